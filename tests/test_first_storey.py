"""Elements that stand on a floor above the ground (``first_storey``): a base-isolated building.

An element with ``first_storey = s`` spans the building's storeys s, s + 1, ... and stands on floor
s - 1: it resists its floors' displacements relative to that floor. A base-isolated building is its
isolators as storey 1 (one-storey storey springs between the ground and the base slab) and its
superstructure from ``first_storey = 2``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding.framework.model.assembly import assemble
from pounding.io.scene import parse_scene

EPS = np.finfo(float).eps
E_RC = 30e9  # [Pa]
SLAB = [[0.0, 0.0], [12.0, 0.0], [12.0, 8.0], [0.0, 8.0]]  # [m], centre of mass (6, 4)


# --------------------------------------------------------------------------- scenes
def isolators(yield_force=None, *, stiffness=(4.0e7, 3.0e7, 3.5e7, 3.5e7)) -> list[dict]:
    """Four lines of isolators in storey 1 (``storeys = 1``): along x at y = 0 and y = 8, along y at
    x = 0 and x = 12 [N/m per line]; the y = 0 line stiffer, so the base slab twists under x shaking.
    With ``yield_force`` [N] bilinear (lead-rubber: 10 % post-yield stiffness)."""
    lines = [([0.0, 0.0], [12.0, 0.0]), ([0.0, 8.0], [12.0, 8.0]), ([0.0, 0.0], [0.0, 8.0]), ([12.0, 0.0], [12.0, 8.0])]
    out = []
    for (start, end), k in zip(lines, stiffness):
        table = {"type": "storey_springs", "start": start, "end": end, "storeys": 1, "stiffness": k}
        if yield_force is not None:
            table.update(yield_force=yield_force, hardening=0.1, hysteresis="bilinear")
        out.append(table)
    return out


def superstructure_frames(first_storey: int = 2) -> list[dict]:
    """Two frames along x, two along y, standing on floor first_storey - 1 (``storeys`` omitted: up to the top)."""
    frame = lambda start, end, columns, b: {  # noqa: E731
        "type": "frame", "first_storey": first_storey, "start": start, "end": end, "columns": columns,
        "column": {"E": E_RC, "b": b, "h": b}, "beam": {"E": E_RC, "b": 0.3, "h": 0.55}}
    return [frame([0.0, 0.0], [12.0, 0.0], [0.0, 6.0, 12.0], 0.50), frame([0.0, 8.0], [12.0, 8.0], [0.0, 6.0, 12.0], 0.40),
            frame([0.0, 0.0], [0.0, 8.0], [0.0, 8.0], 0.45), frame([12.0, 0.0], [12.0, 8.0], [0.0, 8.0], 0.45)]


def isolated(elements: list[dict]) -> dict:
    """The issue's isolated building: storey 1 (1.0 m) the isolation layer, slab 1 the base slab, four storeys above."""
    return {"name": "isolated", "storey_heights": [1.0, 3.2, 3.2, 3.2, 3.2], "slab": SLAB,
            "mass": [150000.0, 135000.0, 135000.0, 135000.0, 120000.0],
            "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]}, "element": elements}


def scene_of(building: dict, *, duration: float = 3.0, angle: float = 0.0) -> dict:
    return {"building": [building], "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": angle},
            "analysis": {"integrator": "newmark", "dt": 0.01, "duration": duration, "contact": "none"}}


# --------------------------------------------------------------------------- 1. placement, closed form
def _row(point, direction, floor: int, centre) -> np.ndarray:
    """Displacement along ``direction`` at ``point`` of floor ``floor`` (1-based) over the 6 DOFs of a
    2-storey building: (d_x, d_y, (p - c) x d) in the floor's columns; the ground (0) is a zero row."""
    r = np.zeros(6)
    if floor:
        p, d = np.asarray(point, float) - centre, np.asarray(direction, float)
        r[3 * (floor - 1): 3 * floor] = (d[0], d[1], p[0] * d[1] - p[1] * d[0])
    return r


def test_frame_on_floor_1_is_placed_between_floors_1_and_2():
    """Two storeys: storey-1 springs (k_i along x at y = 0, 8 and along y at x = 0, 12) and four
    one-column frames with ``first_storey = 2`` (columns at (6, 0), (6, 8) in x and (0, 4), (12, 4)
    in y). A column fixed at its base with its top rotation free (condensed out) has the lateral
    stiffness k_c = 3 E I / h^3; standing on floor 1 it resists u_2 - u_1 along its line. By hand,
    K = sum_i k_i r_i^T r_i (r_i the spring's row at floor 1) + sum_c k_c (r_c,2 - r_c,1)^T (r_c,2 - r_c,1).
    The assembled K equals it to the rounding of its few additions (8 eps of its largest entry).

    Symmetric about the centre of mass, x translation decouples: M = diag(m1, m2),
    K_x = [[k1 + k2, -k2], [-k2, k2]] (k1 the x springs, k2 = 2 k_c), and the two x periods are the
    roots of m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0; the eigen-solver's rounding is
    below 10 n eps of the largest eigenvalue (backward stable), relative to each one compared."""
    h1, h2, m1, m2 = 1.0, 3.0, 90000.0, 80000.0
    b_col = 0.5
    I = b_col**4 / 12.0
    k_c = 3.0 * E_RC * I / h2**3
    springs = [({"start": [0.0, 0.0], "end": [12.0, 0.0]}, 2.0e7), ({"start": [0.0, 8.0], "end": [12.0, 8.0]}, 2.0e7),
               ({"start": [0.0, 0.0], "end": [0.0, 8.0]}, 3.0e7), ({"start": [12.0, 0.0], "end": [12.0, 8.0]}, 3.0e7)]
    columns = [([6.0, 0.0], [1.0, 0.0]), ([6.0, 8.0], [1.0, 0.0]), ([0.0, 4.0], [0.0, 1.0]), ([12.0, 4.0], [0.0, 1.0])]
    elements = [{"type": "storey_springs", "storeys": 1, "stiffness": k, **line} for line, k in springs]
    elements += [{"type": "frame", "first_storey": 2, "start": p, "end": list(np.add(p, d)), "columns": [0.0],
                  "column": {"E": E_RC, "b": b_col, "h": b_col}} for p, d in columns]
    building = {"name": "two", "storey_heights": [h1, h2], "slab": SLAB, "mass": [m1, m2], "element": elements}
    b = parse_scene({"building": [building], "ground_motion": {"record": "elcentro"}}).buildings[0]
    system = assemble(b)
    c = np.array([6.0, 4.0])

    K = np.zeros((6, 6))
    for line, k in springs:
        d = np.subtract(line["end"], line["start"]) / np.hypot(*np.subtract(line["end"], line["start"]))
        r = _row(line["start"], d, 1, c) - _row(line["start"], d, 0, c)
        K += k * np.outer(r, r)
    for p, d in columns:
        r = _row(p, d, 2, c) - _row(p, d, 1, c)
        K += k_c * np.outer(r, r)
    assert np.abs(system.K - K).max() <= 8 * EPS * np.abs(K).max()

    k1, k2 = 2 * 2.0e7, 2 * k_c
    a, bq, cq = m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2
    w2 = np.array([(-bq - np.sqrt(bq * bq - 4 * a * cq)) / (2 * a), (-bq + np.sqrt(bq * bq - 4 * a * cq)) / (2 * a)])
    x_modes = [j for j in range(6) if np.abs(system.modes[0::3, j]).max() > 1e-6 * np.abs(system.modes[:, j]).max()]
    assert len(x_modes) == 2
    lam = system.omega[x_modes] ** 2
    tol = 10 * 6 * EPS * system.omega.max() ** 2 / lam
    assert np.all(np.abs(np.sort(lam) - np.sort(w2)) <= tol * lam)


def test_storey_shears_of_an_isolated_building():
    """Statics of a structure standing on a slab: a frame that stands on floor 1 pushes that floor with
    the reaction of its floor forces (its base row), so its shear in storey 1, below it, is zero
    (to the rounding of the product and sum of its floor forces), and the building's
    storey-1 shear is the isolators' alone: sum_i k_i (r_i . x) d_i over the lines (elastic isolators,
    r_i the line's row at the base slab), to the frames' rounding and 40 eps of the isolators' shear.
    Checked on 1.5 s of El Centro at 30 degrees."""
    from pounding.framework.post.response import storey_forces
    from pounding.framework.post.run import run

    scene = parse_scene(scene_of(isolated(isolators() + superstructure_frames()), duration=1.5, angle=30.0))
    result = run(scene)
    system = result.systems[0]
    cm = result.cm("isolated")
    forces = storey_forces(system, cm)
    frames = forces.element_shear[:, 4:, :]  # (nt, 4 frames, 5 storeys)
    x = cm.reshape(len(cm), -1)
    frame_rounding = np.zeros(len(cm))
    for j, placed in enumerate(system.elements[4:]):
        # floor forces k (T x) summed over 5 floors: rounding <= 2 n eps sum_i sum_j |k_ij| |(T x)_j|
        bound = 2 * 5 * EPS * (np.abs(x @ placed.T.T) @ np.abs(placed.k)).sum(axis=1)
        assert np.all(np.abs(frames[:, j, 0]) <= bound) and np.abs(frames[:, j, 1]).max() > 1e3
        frame_rounding += bound
    expected = np.zeros((len(cm), 2))
    for e, placed in zip(scene.buildings[0].elements[:4], system.elements[:4]):
        expected += (x @ placed.T[0]) [:, None] * e.stiffness[0] * np.asarray(e.direction)
    err = np.abs(forces.shear[:, 0, :] - expected).max(axis=1)
    assert np.all(err <= frame_rounding + 40 * EPS * np.abs(expected).max())
    assert np.abs(expected).max() > 1e4  # [N]: the isolators do carry the building


# --------------------------------------------------------------------------- 2. against OpenSees
OUT_OF_PLANE = 1e-9


@pytest.mark.opensees
def test_isolated_building_periods_match_opensees(opensees):
    """The isolated building (elastic isolators in storey 1, frames from storey 2) in OpenSees' 3-D
    model of :mod:`pounding.peer.opensees`: the frames' base nodes on the base slab's diaphragm, fixed in
    uz, rx, ry; the isolators ``twoNodeLink`` s from the ground to it. Periods to 1e-6 relative, as
    tests/test_opensees_modal.py: the difference is the out-of-plane stiffness OpenSees needs
    (0.68 x ``out_of_plane`` relative for frames; out_of_plane = 1e-9 leaves a factor ~1000; measured 7e-10)."""
    from pounding.peer.opensees import build_building, eigen_periods

    b = parse_scene(scene_of(isolated(isolators() + superstructure_frames()))).buildings[0]
    ours = assemble(b).periods
    opensees.wipe()
    build_building(opensees, b, out_of_plane=OUT_OF_PLANE)
    peer = eigen_periods(opensees, len(ours))
    opensees.wipe()
    assert ours[0] > 2.5 * ours[3]  # the isolation modes (x, y, twist) are well apart from the superstructure's
    np.testing.assert_allclose(peer, ours, rtol=1e-6)


@pytest.mark.opensees
def test_isolated_building_history_matches_opensees(opensees):
    """Contact-free, elastic isolators, El Centro NS at 0.32 g along 30 degrees for 3 s, Newmark average
    acceleration, dt = 0.01 s (it divides the record's 0.02 s), each building's Rayleigh damping:
    every slab's u, v, phi within 1e-6 of its peak, as tests/test_opensees_transient.py (the difference
    is proportional to out_of_plane; measured 2e-10 to 9e-10)."""
    from pounding.framework.post.run import run
    from pounding.peer.opensees import run_transient

    scene = parse_scene(scene_of(isolated(isolators() + superstructure_frames()), angle=30.0))
    result = run(scene)
    peer = run_transient(opensees, scene, scene.ground_motion, result.dt, result.steps, out_of_plane=OUT_OF_PLANE)["isolated"]
    ours = result.cm("isolated")
    for c in range(3):
        peak = np.abs(ours[:, :, c]).max()
        assert peak > 0 and np.abs(ours[:, :, c] - peer[:, :, c]).max() <= 1e-6 * peak


def spring_superstructure(yield_force: float) -> list[dict]:
    """Storey springs from storey 2 to the top (``first_storey = 2``, ``storeys`` omitted), 2e8 N/m per line
    and storey, yielding at ``yield_force`` [N]."""
    lines = [([0.0, 0.0], [12.0, 0.0]), ([0.0, 8.0], [12.0, 8.0]), ([0.0, 0.0], [0.0, 8.0]), ([12.0, 0.0], [12.0, 8.0])]
    return [{"type": "storey_springs", "first_storey": 2, "start": s, "end": e, "stiffness": 2.0e8,
             "yield_force": yield_force, "hardening": 0.02} for s, e in lines]


@pytest.mark.opensees
def test_yielding_isolators_and_storeys_above_match_opensees(opensees):
    """Yielding isolators under yielding storey springs that stand on the base slab: pounding's spring
    rows (floor s minus floor s - 1, from the base slab up) against OpenSees' ``twoNodeLink`` s with
    ``Steel01`` between the diaphragms (:mod:`pounding.peer.opensees_springs`), El Centro at 30 degrees
    for 3 s, both layers yielding: slabs and spring forces within 1e-5 of their peaks, as
    tests/test_opensees_inelastic.py (measured here 1e-13 to 5e-13: the Newton tolerances)."""
    from pounding.framework.post.inelastic_run import run_inelastic
    from pounding.peer.opensees_springs import run_springs_transient

    scene = parse_scene(scene_of(isolated(isolators(2.0e5) + spring_superstructure(2.4e5)), angle=30.0))
    b = run_inelastic(scene).buildings[0]
    above = b.springs.storey > 1
    assert b.ductility[~above].min() > 2.0 and b.ductility[above].max() > 1.0
    disp, forces, _ = run_springs_transient(opensees, scene.buildings, scene.ground_motion, scene.analysis.dt, len(b.cm()) - 1)
    ours, peer = b.cm(), disp["isolated"]
    for c in range(3):
        assert np.abs(ours[:, :, c] - peer[:, :, c]).max() <= 1e-5 * np.abs(peer[:, :, c]).max()
    assert np.abs(b.force - forces["isolated"]).max() <= 1e-5 * np.abs(forces["isolated"]).max()


@pytest.mark.opensees
def test_exported_isolated_building_is_the_tools(tmp_path):
    """``pounding export opensees`` of the isolated building (bilinear isolators, frames from storey 2):
    the script, run by OpenSeesPy in its own process, gives pounding's periods and contact-free history
    (El Centro at 30 degrees, 3 s) within 1e-6 of the peaks, as tests/test_opensees_export.py (the
    out-of-plane stiffness 1e-9 and the Newton tolerance set the difference; measured: periods 2e-10,
    histories 6e-11 to 7e-10)."""
    from pounding.framework.post.run import run
    from test_opensees_export import _run_script

    scene = parse_scene(scene_of(isolated(isolators(2.0e5) + superstructure_frames()), angle=30.0))
    periods, peer = _run_script(scene, tmp_path, modes=6)
    np.testing.assert_allclose(periods, assemble(scene.buildings[0]).periods[:6], rtol=1e-6)
    result = run(scene)
    assert (result.springs["isolated"]["peak"] / result.springs["isolated"]["yield_deformation"]).max() > 2.0
    ours = result.cm("isolated")
    assert peer["isolated"].shape == ours.shape
    for c in range(3):
        assert np.abs(ours[:, :, c] - peer["isolated"][:, :, c]).max() <= 1e-6 * np.abs(ours[:, :, c]).max()


# --------------------------------------------------------------------------- 3. energy
def test_yielding_isolators_dissipate_in_storey_1_only_and_the_account_balances():
    """Bilinear isolators (u_y = 5 mm) under storey springs from storey 2 that yield at 3 MN per line
    (u_y = 15 mm of drift). The storeys above carry little more than the isolators' shear (measured
    drift below 0.1 u_y): they stay elastic and dissipate exactly nothing (a bilinear law's elastic
    branch moves no plastic deformation); were their rows measured from the ground instead of the
    base slab, the isolators' displacement (ductility 3.6 to 6.5: 18 to 33 mm) would yield them.
    The isolators yield and dissipate, and the audit input = kinetic + strain + damping + hysteretic closes to rounding (<= 1e-12 of the input,
    average acceleration's exact identity, as tests/test_inelastic.py)."""
    from pounding.framework.post.inelastic_run import run_inelastic

    scene = parse_scene(scene_of(isolated(isolators(2.0e5) + spring_superstructure(3.0e6)), angle=30.0))
    b = run_inelastic(scene).buildings[0]
    storey = b.springs.storey
    assert set(storey[:4]) == {1} and set(storey[4:]) == {2, 3, 4, 5}
    iso = storey == 1
    assert b.ductility[iso].min() > 2.0 and np.all(b.hysteretic[iso] > 0.0)
    assert np.all(b.ductility[~iso] < 1.0) and np.all(b.hysteretic[~iso] == 0.0)
    e = b.energy
    assert e["hysteretic"] > 0.1 * e["input"]
    assert e["relative_error"] <= 1e-12


# --------------------------------------------------------------------------- plausibility, writer
def test_an_isolation_layer_is_not_a_soft_storey():
    """Storey 1 of one-storey springs with the superstructure standing on floor 1: the isolators'
    low stiffness is the design (no ``soft_storey`` finding). The same soft springs under frames that
    stand on the ground through them are a soft storey (it is reported)."""
    from pounding.framework.post.plausibility import SOFT_RATIO, findings, storey_stiffness

    isolated_scene = parse_scene(scene_of(isolated(isolators() + superstructure_frames())))
    k = storey_stiffness(isolated_scene.buildings[0], (1.0, 0.0))
    assert k[0] < SOFT_RATIO * k[1]  # as soft as a soft storey: the rule, not the numbers, keeps it quiet
    assert not [f for f in findings(isolated_scene) if f.check == "soft_storey"]
    soft = isolated(isolators() + superstructure_frames(first_storey=1))
    soft["element"][4:] = [{**e, "storeys": 4, "first_storey": 2} for e in soft["element"][4:]]
    for e in soft["element"][:4]:  # the soft springs now span every storey: a building on springs
        e.update(storeys=5, stiffness=[e["stiffness"]] + [1e9] * 4)
    assert [f for f in findings(parse_scene(scene_of(soft))) if f.check == "soft_storey"]


def test_written_scene_keeps_first_storey(tmp_path):
    """write_scene writes ``first_storey`` and reading the file back gives the same scene; a scene
    whose frames stand on the ground differs from it exactly at those elements."""
    from pounding.io.scene import load_scene
    from pounding.io.scene_writer import scene_differences, write_scene

    scene = parse_scene(scene_of(isolated(isolators() + superstructure_frames())))
    back = load_scene(write_scene(scene, tmp_path / "isolated.toml"))
    assert "first_storey = 2" in (tmp_path / "isolated.toml").read_text()
    assert scene_differences(scene, back) == []
    assert [e.first_storey for e in back.buildings[0].elements] == [1] * 4 + [2] * 4
    grounded = scene.buildings[0].elements[4].replaced(first_storey=1)
    assert grounded.first_storey == 1 and scene.buildings[0].elements[4].first_storey == 2
    shifted = scene.with_building_shifted("isolated", np.array([1.0, 0.0]))
    assert [e.first_storey for e in shifted.buildings[0].elements] == [1] * 4 + [2] * 4


# --------------------------------------------------------------------------- 4. bad input
BAD = [
    ("zero", "first_storey = 0", "building[0].element[4].first_storey", "expected a number >= 1"),
    ("float", "first_storey = 1.5", "building[0].element[4].first_storey", "expected an integer"),
    ("beyond the top", "first_storey = 6", "building[0].element[4].first_storey", "the building has 5"),
    ("spans beyond the top", "first_storey = 2\nstoreys = 5", "building[0].element[4].storeys", "at most storeys = 4"),
]


@pytest.mark.parametrize("text, field, words", [c[1:] for c in BAD], ids=[c[0] for c in BAD])
def test_bad_first_storey_is_one_message_exit_2_nothing_written(tmp_path, text, field, words):
    """A first_storey that is not a storey of the building (0, a fraction, above the top) or that makes
    the element end above the top: ``pounding run`` prints one line naming the file and the field, exits
    with 2 and writes nothing."""
    from pounding.io.scene_writer import to_toml

    data = scene_of(isolated(isolators() + superstructure_frames()), duration=0.1)
    text_scene = to_toml(data).replace("first_storey = 2", text, 1)
    assert text_scene.count(text) == 1  # the first frame edited, the others as they were
    path, out = tmp_path / "bad.toml", tmp_path / "out"
    path.write_text(text_scene)
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and field in lines[0] and words in lines[0], lines
    assert not out.exists()


def test_first_storey_from_the_api_is_checked_too():
    """:meth:`PlanarElement.build` (the template every element type inherits) refuses a float, a bool or a
    storey out of range, with ``field = "first_storey"``."""
    from pounding.elements.storey_springs import StoreySprings
    from pounding.errors import InputError

    table = {"start": [0.0, 0.0], "end": [12.0, 0.0], "stiffness": 1e7}
    for bad in (2.0, True, 0, 4):
        with pytest.raises(InputError) as err:
            StoreySprings.build(table, storey_heights=[3.0, 3.0, 3.0], first_storey=bad)
        assert err.value.field == "first_storey"
    e = StoreySprings.build(table, storey_heights=[1.0, 3.0, 3.5], first_storey=2)
    assert e.building_floors == (2, 3) and e.heights == (3.0, 3.5) and e.storey_floors() == [(1, 2), (2, 3)]


# --------------------------------------------------------------------------- isolator outputs
def test_a_bilinear_loop_dissipates_4_q_d_minus_dy():
    """A bilinear law (k0, F_y, b) cycled quasi-statically between +-D > u_y dissipates the loop's area
    E_D = 4 Q (D - u_y), Q = F_y (1 - b) (AASHTO's form); the law is exact for any increment, so the
    only error is the rounding of summing 3 x 2000 increments (3 x 2000 eps of E_D)."""
    from pounding.framework.post.isolators import CYCLE_STEPS, cycle_energy
    from pounding.hysteresis.bilinear import Bilinear

    k0, fy, b = 4.0e7, 2.0e5, 0.1
    law = Bilinear()
    for D in (0.01, 0.05, 0.2):
        expected = 4 * fy * (1 - b) * (D - fy / k0)
        assert abs(cycle_energy(law, law.pack(k0, fy, b), D) - expected) <= 3 * CYCLE_STEPS * EPS * expected
    assert cycle_energy(law, law.pack(k0, fy, b), 0.5 * fy / k0) == 0.0  # within the elastic range: no loop


def test_summary_reports_the_isolators_per_line(tmp_path):
    """summary.json of the isolated building (bilinear isolators, frames from storey 2), per line (all yield): the
    peak force is the bilinear envelope at the peak displacement, F_y (1 - b) + b k0 D (kinematic
    hardening bounds |r| by it, reached when loading at the peak; to 10 eps of F), so
    K_eff = F / D, and beta_eff = 4 Q (D - u_y) / (2 pi K_eff D^2). Along x (two x lines, the y lines
    count (d . e)^2 = 0): T_eff = 2 pi sqrt(M / (K_eff,1 + K_eff,2)), longer than with the isolators'
    initial stiffness (the secant is softer)."""
    import json

    from pounding.framework.post.isolators import CYCLE_STEPS
    from pounding.framework.post.run import run
    from pounding.io.results import write_results

    scene = parse_scene(scene_of(isolated(isolators(2.0e5) + superstructure_frames()), angle=30.0))
    write_results(run(scene), tmp_path / "out")
    iso = json.loads((tmp_path / "out" / "summary.json").read_text())["buildings"]["isolated"]["isolators"]
    k0s, fy, b = (4.0e7, 3.0e7, 3.5e7, 3.5e7), 2.0e5, 0.1
    assert [line["element"] for line in iso["lines"]] == [0, 1, 2, 3]
    for line, k0 in zip(iso["lines"], k0s):
        D, F = line["peak_displacement"], line["peak_force"]
        assert D > fy / k0  # they yield
        assert abs(F - (fy * (1 - b) + b * k0 * D)) <= 10 * EPS * F
        assert line["effective_stiffness"] == pytest.approx(F / D, rel=4 * EPS)
        beta = 4 * fy * (1 - b) * (D - fy / k0) / (2 * np.pi * (F / D) * D * D)
        assert line["effective_damping"] == pytest.approx(beta, rel=3 * CYCLE_STEPS * EPS + 20 * EPS)  # the loop's sum
    M = 675000.0
    Kx = iso["lines"][0]["effective_stiffness"] + iso["lines"][1]["effective_stiffness"]
    assert iso["mass"] == M and iso["effective_period"]["x"] == pytest.approx(2 * np.pi * np.sqrt(M / Kx), rel=4 * EPS)
    assert iso["effective_period"]["x"] > 2 * np.pi * np.sqrt(M / (k0s[0] + k0s[1]))


def test_a_third_party_element_stands_on_a_floor_for_free():
    """The example plugin ``Brace`` (examples/plugin_element, written before ``first_storey`` existed)
    braces its own storey 1; built with ``first_storey = 3`` in a building of storey heights
    (3.0, 3.0, 3.5) it braces storey 3: its height is 3.5 m, and placed it acts on the relative drift
    of floors 2 and 3 with k [[1, -1], [-1, 1]], k = E A cos^2(theta) / L, L = sqrt(b^2 + h^2)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples" / "plugin_element"))
    try:
        from pounding_brace import Brace
    finally:
        sys.path.pop(0)
    E, A, b, h = 200e9, 0.002, 6.0, 3.5
    brace = Brace.build({"start": [0.0, 0.0], "end": [b, 0.0], "storey": 1, "E": E, "A": A},
                        storey_heights=[3.0, 3.0, h], first_storey=3)
    L = np.hypot(b, h)
    k = E * A * (b / L) ** 2 / L
    floors, K = brace.placed_stiffness()
    assert brace.building_floors == (3,) and floors == (2, 3)
    np.testing.assert_allclose(K, k * np.array([[1.0, -1.0], [-1.0, 1.0]]), rtol=4 * EPS)


def test_walls_on_soft_isolators_are_not_a_unit_slip():
    """Three shear walls (12 m and 8 m long, 0.25 m thick) standing on the base slab over four lines of
    isolators (1e7 N/m each): the walls are over 2000 times stiffer than the isolators, whose median would flag them as a
    unit slip (``stiff_element``: 1000 x the median). An isolation layer's lines are soft by design and
    stay out of that median; the same walls on the ground beside soft springs in every storey are flagged."""
    from pounding.framework.model.stiffness_scale import STIFF_RATIO, element_stiffness
    from pounding.framework.post.plausibility import findings

    wall = lambda start, end, first: {"type": "shear_wall", "first_storey": first, "start": start, "end": end,  # noqa: E731
                                      "thickness": 0.25, "E": E_RC, "nu": 0.2}
    walls = [wall([0.0, 0.0], [12.0, 0.0], 2), wall([0.0, 0.0], [0.0, 8.0], 2), wall([12.0, 0.0], [12.0, 8.0], 2)]
    soft = (1.0e7,) * 4  # [N/m] per line
    scene = parse_scene(scene_of(isolated(isolators(stiffness=soft) + walls)))
    b = scene.buildings[0]
    k = [element_stiffness(e) for e in b.elements]
    assert min(k[4:]) > STIFF_RATIO * np.median(k)  # what the median with the isolators would say
    assert not [f for f in findings(scene) if f.check == "stiff_element"]
    on_springs = isolated([{**t, "storeys": 5, "stiffness": [t["stiffness"]] * 5} for t in isolators(stiffness=soft)]
                          + [{**w, "first_storey": 1} for w in walls])
    assert [f for f in findings(parse_scene(scene_of(on_springs))) if f.check == "stiff_element"]
