"""Bumpers: a rubber layer of thickness t on one building's facing faces, declared in a ``[[contact]]`` table.

The physics checks use two box slabs side by side (a bare gap G along x) on columns so soft (periods
of ~12 s) that during a contact of ~0.02 s they are nearly free, the left one moving at v0 towards
the right one with no ground motion and no damping: the closed forms of two free bodies meeting
apply, up to the columns' share (bounded as in tests/test_contact_law_contract.py). The layer is on
the right slab's face.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from scenes_for_tests import box_building, contact_momentum_changes, modal_from_physical, physical, pulse, scene
from test_bad_input import BASE
from pounding.contact.bumper import BumperLaw
from pounding.contact.kelvin import Kelvin
from pounding.contact.rebound import rebound
from pounding.contact.rubber import Rubber
from pounding.errors import InputError
from pounding.framework.engine.driver import Driver
from pounding.framework.engine.stacked_model import Model
from pounding.io.scene import load_scene

G = 0.05  # [m] bare gap at rest
T = 0.02  # [m] the layer's thickness
C = 0.8  # its compressible fraction: the slabs' law acts beyond C T = 0.016 m
DT = 1e-4  # [s] >= 150 steps per contact below
K_LAYER = 1e10  # [N/m^1.5] an elastic Hertz layer: delta_max = 0.0077 m at 1 m/s (m_eff = 4.5e4 kg)
K_SLABS = 1e11  # [N/m^1.5] the slabs' Hertz law


def pair_data(layer: dict, *, slabs: dict | None = None, gap: float = G, duration: float = 0.08) -> dict:
    """Two 10 m box slabs [0, 10] and [10 + gap, 20 + gap] x [0, 10] on soft undamped columns,
    a bumper of T on the right slab's face (C T compressible), ``layer`` its law and ``slabs`` the
    slabs' law (default: [analysis] contact, an elastic Hertz law of K_SLABS)."""
    buildings = [box_building("left", 0.0, 10.0, 10.0, 1, 0.05, 0.05, damping={"type": "modal", "ratio": 0.0}),
                 box_building("right", 10.0 + gap, 10.0, 10.0, 1, 0.05, 0.05, damping={"type": "modal", "ratio": 0.0})]
    rule = {"between": ["left", "right"], "bumper": {"on": "right", "storeys": [1], "thickness": T, "compressible": C, "law": layer}}
    if slabs is not None:
        rule["law"] = slabs
    return {"building": buildings, "ground_motion": {"record": "elcentro", "pga": 0.1},
            "analysis": {"integrator": "newmark", "dt": DT, "duration": duration,
                         "contact": {"name": "hertz", "stiffness": K_SLABS}},
            "contact": [rule]}


def free_slabs(layer: dict, v0: float, **kw) -> Driver:
    """A Driver of :func:`pair_data` with no ground motion, the left slab moving at v0 [m/s] towards the right one."""
    sc = scene(pair_data(layer, **kw)).with_ground_motion(pulse(0.2, 0.0))
    d = Driver(sc)
    d.z[:, 1] = modal_from_physical(d.model, {(0, 0): (v0, 0.0, 0.0)})
    return d


def slab_mass(d) -> float:
    return float(d.model.systems[0].mass[0])


def column_share(d, v0: float, duration: float, impulse: float) -> float:
    """Bound on the columns' impulse over a contact of ``duration`` [s] that begins after the slab has
    travelled G - T, relative to ``impulse`` [N s]: each slab moves at most v0 (t0 + t) from rest, so its
    columns push at most k v0 (t0 + t); over the contact that is k v0 (t0 duration + duration^2 / 2)."""
    k = max(s.K[0, 0] for s in d.model.systems)
    t0 = (G - T) / v0
    return 2.0 * k * v0 * (t0 * duration + duration**2 / 2.0) / impulse


def hertz_duration(k: float, m_eff: float, v0: float) -> tuple[float, float]:
    """(delta_max [m], duration [s]) of an elastic Hertz contact k delta^1.5 of two free bodies."""
    delta = (5.0 * m_eff * v0**2 / (4.0 * k)) ** 0.4
    return delta, 2.943 * delta / v0


# --------------------------------------------------------------------------- (a) the offset geometry
@pytest.mark.parametrize("right_y0", [0.0, 3.0])
def test_the_bumper_pairs_rest_gap_is_the_bare_gap_minus_the_thickness(right_y0):
    """The bumper slab is the right slab with its face towards the left one (x = 10 + G) moved out by
    T, its other faces in place: the pair's rest gap is G - T, to rounding of coordinates ~20 m
    (1e-12 m), whether the slabs meet face to face or along part of a face (shifted along y)."""
    data = pair_data({"name": "rubber", "stiffness": 1e8})
    data["building"][1] = box_building("right", 10.0 + G, 10.0, 10.0, 1, 0.05, 0.05, y0=right_y0)
    m = Model(scene(data))
    assert list(m.bumpers) == [0]
    assert m.pairs[0][4] == pytest.approx(G - T, abs=1e-12)
    assert m.geo.rest[0] == pytest.approx(G - T, abs=1e-12)
    s = m.geo.off[m.geo.pb[0, 0]] + m.geo.pb[0, 1]  # the bumper slab
    poly = m.geo.verts[s, : m.geo.nvert[s]]
    xs = np.sort(np.unique(np.round(poly[:, 0], 12)))
    assert xs == pytest.approx([10.0 + G - T, 20.0 + G], abs=1e-12)  # only the facing face moved
    assert np.ptp(poly[:, 1]) == pytest.approx(10.0, abs=1e-12)
    assert m.geo.floors[s, 0] == m.slab_index(1, 0) and m.geo.weights[s, 0] == 1.0  # the real slab's rigid motion


# --------------------------------------------------------------------------- (b) two free slabs on a bumper
def test_an_elastic_layer_meets_the_hertz_closed_forms_and_contact_begins_at_the_layer():
    """An elastic Hertz layer k delta^1.5, delta = T - bare gap, struck at v0 = 1 m/s: delta_max =
    (5 m_eff v0^2 / (4 k))^(2/5) < C T (the slabs' law never acts), impulse 2 m_eff v0 (rebound 1),
    duration 2.943 delta_max / v0; the contact begins where the bare gap is T, at t0 with
    v0 sin(w t0) / w = G - T (the left slab's free swing on its columns, w^2 = k_x / m).

    Tolerances: the columns' share (:func:`column_share`) plus Newmark's second-order error
    (dt / duration)^2, as in the contract tests; the start is interpolated linearly in its step,
    whose error is the gap's curvature w^2 (G - T) dt^2 / 8 over v0, far below 1e-9 s."""
    v0 = 1.0
    d = free_slabs({"name": "hertz", "stiffness": K_LAYER}, v0)
    r = d.run()
    assert len(r.contacts) == 1
    e = r.contacts[0]
    m_eff = slab_mass(d) / 2.0
    delta, duration = hertz_duration(K_LAYER, m_eff, v0)
    assert delta < C * T
    tol = column_share(d, v0, duration, 2.0 * m_eff * v0) + (DT / duration) ** 2
    assert e.peak_penetration == pytest.approx(delta, rel=tol)
    assert e.impulse == pytest.approx(2.0 * m_eff * v0, rel=tol)
    assert e.duration == pytest.approx(duration, rel=tol + 2e-4)  # 2.943 is given to 4 digits
    assert e.peak_force == pytest.approx(K_LAYER * e.peak_penetration**1.5, rel=1e-12)  # the layer alone
    w = math.sqrt(d.model.systems[0].K[0, 0] / slab_mass(d))
    t0 = brentq(lambda t: v0 * math.sin(w * t) / w - (G - T), 0.0, 1.0)
    assert e.start == pytest.approx(t0, abs=1e-9)


def test_momentum_is_conserved_across_a_bumper_contact():
    """The contact's equal and opposite forces change the slabs' x momentum by -I and +I (the episode's
    impulse) and their total only by the columns' impulse: to rounding of ~1e3 trapezoidal sums
    (1e-9 of the impulse), as in the contract tests."""
    d = free_slabs({"name": "rubber", "stiffness": K_LAYER, "restitution": 0.6}, 1.0)
    r = d.run()
    e = r.contacts[0]
    change = contact_momentum_changes(d.model, r)
    assert change[0] == pytest.approx(-e.impulse, rel=1e-9)
    assert change[1] == pytest.approx(e.impulse, rel=1e-9)
    assert abs(change[0] + change[1]) <= 1e-9 * e.impulse


def test_a_rubber_layer_gives_its_own_peak_and_rebound():
    """The rubber law (Hertz-type, Hunt-Crossley damping, e = 0.6) alone while delta < C T: the run's
    peak compression and rebound (separation over approach speed) are those of two free bodies
    integrated by DOP853 at rtol 1e-12 (:func:`pounding.contact.rebound.rebound`, a converged
    reference good to ~1e-11), to the columns' share plus Newmark's (dt / duration)^2."""
    v0 = 1.0
    layer = Rubber(stiffness=K_LAYER, restitution=0.6)
    d = free_slabs({"name": "rubber", "stiffness": K_LAYER, "restitution": 0.6}, v0)
    r = d.run()
    assert len(r.contacts) == 1
    e = r.contacts[0]
    m = slab_mass(d)
    ref = rebound(layer, approach_speed=v0, m1=m, m2=m)
    assert ref.peak_penetration < C * T
    v = physical(d.model, r.qd[-1])
    ratio = (v[(1, 0)][0] - v[(0, 0)][0]) / v0
    tol = column_share(d, v0, ref.duration, e.impulse) + (DT / ref.duration) ** 2
    assert e.peak_penetration == pytest.approx(ref.peak_penetration, rel=tol)
    assert ratio == pytest.approx(ref.ratio, rel=tol)
    assert 0.0 < ratio < 1.0


def test_a_faster_approach_reaches_the_slabs_law():
    """At v0 = 3 m/s the elastic layer alone would compress 0.0119 m > C T: beyond C T the slabs' law
    k_s (delta - C T)^1.5 acts with the layer. Energy then gives the peak: m_eff v0^2 / 2 =
    (2/5) k_b delta^2.5 + (2/5) k_s (delta - C T)^2.5, the force there is the sum of the two laws,
    and the rebound stays 1 (impulse 2 m_eff v0: both laws elastic). Tolerance as above, with the
    contact's duration bounded below by the stiffer law alone's."""
    v0 = 3.0
    d = free_slabs({"name": "hertz", "stiffness": K_LAYER}, v0)
    r = d.run()
    assert len(r.contacts) == 1
    e = r.contacts[0]
    m_eff = slab_mass(d) / 2.0
    reach = C * T

    def energy(x):
        return 0.4 * K_LAYER * x**2.5 + 0.4 * K_SLABS * max(x - reach, 0.0) ** 2.5 - 0.5 * m_eff * v0**2

    delta = brentq(energy, 0.0, T)
    assert delta > reach
    tol = column_share(d, v0, e.duration, 2.0 * m_eff * v0) + (DT / e.duration) ** 2
    assert e.peak_penetration == pytest.approx(delta, rel=tol)
    assert e.impulse == pytest.approx(2.0 * m_eff * v0, rel=tol)
    p = e.peak_penetration
    assert e.peak_force == pytest.approx(K_LAYER * p**1.5 + K_SLABS * (p - reach) ** 1.5, rel=1e-12)


def test_the_force_jumps_by_the_slabs_law_at_the_compressible_fraction():
    """F(delta) = F_b(delta) + F_s(delta - C T): across delta = C T at rate delta' the bumper's force
    jumps by the slabs' Kelvin law at zero penetration, its dashpot c_s delta' (c_s = 2 xi sqrt(k m)),
    to rounding of the forces (1e-9 of them over a step of 1e-12 m in delta)."""
    layer, slabs = Rubber(stiffness=1e8, restitution=0.5), Kelvin(stiffness=2e9, restitution=0.5)
    law = BumperLaw(layer=layer, slabs=slabs, thickness=T, compressible=C)
    m_eff, rate, eps = 4.5e4, 0.7, 1e-12
    below = law.point_force(C * T - eps, rate, 1.0, m_eff)[0]
    above = law.point_force(C * T + eps, rate, 1.0, m_eff)[0]
    assert below == pytest.approx(layer.point_force(C * T, rate, 1.0, m_eff)[0], rel=1e-9)
    c_s = 2.0 * slabs.damping_ratio * math.sqrt(slabs.stiffness * m_eff)
    assert above - below == pytest.approx(c_s * rate, rel=1e-6)


# --------------------------------------------------------------------------- (c) the energy account
def test_the_energy_account_closes_and_the_contact_takes_energy():
    """Undamped, unforced: the kinetic energy at the start is what the buildings hold at the end plus what
    the bumper's contact took (average acceleration conserves the energy of the linear part), to the
    rounding of ~1e3 steps (1e-9); the contact work is <= 0 (a passive layer and slabs' law) and is the
    episode's dissipation. The approach at 3 m/s reaches the slabs' law too."""
    d = free_slabs({"name": "rubber", "stiffness": K_LAYER, "restitution": 0.5},
                   3.0, slabs={"name": "kelvin", "stiffness": 2e9, "restitution": 0.5})
    r = d.run()
    assert len(r.contacts) == 1
    e = r.contacts[0]
    assert e.peak_penetration > C * T
    e0 = 0.5 * float(np.sum(r.qd[0] ** 2))
    held = sum(x["kinetic"] + x["strain"] for x in r.energy.values())
    work = sum(x["contact_forces"] for x in r.energy.values())
    assert work <= 0.0 < e.energy_dissipated
    assert e.energy_dissipated == pytest.approx(e0 - held, rel=1e-9)
    assert -work == pytest.approx(e.energy_dissipated, rel=1e-9)


# --------------------------------------------------------------------------- (d) bad input
FORCE = 'contact = "kelvin"\nrestitution = 0.5'
GOOD_BUMPER = 'on = "B", storeys = [1], thickness = 0.02, compressible = 0.8, law = { name = "rubber", stiffness = 1e8 }'


def bumper_scene(bumper: str = GOOD_BUMPER, analysis: str = FORCE) -> str:
    """tests/test_bad_input.py's scene (A: 2 storeys, B: 1, gap 0.1 m) with a [[contact]] bumper."""
    return BASE.replace('contact = "impulse"\nrestitution = 0.5', analysis, 1) + \
        f'\n[[contact]]\nbetween = ["A", "B"]\nbumper = {{ {bumper} }}\n'


BAD = [
    ("unknown building in on", GOOD_BUMPER.replace('on = "B"', 'on = "C"'), FORCE, "contact[0].bumper.on", "got 'C'"),
    ("storey that does not exist", GOOD_BUMPER.replace('on = "B", storeys = [1]', 'on = "A", storeys = [3]'), FORCE,
     "contact[0].bumper.storeys[0]", "storeys 1 to 2"),
    ("storey with no pair", GOOD_BUMPER.replace('on = "B", storeys = [1]', 'on = "A", storeys = [2]'), FORCE,
     "contact[0].bumper.storeys[0]", "no slab of 'B' at its level"),
    ("zero thickness", GOOD_BUMPER.replace("thickness = 0.02", "thickness = 0.0"), FORCE, "contact[0].bumper.thickness", ""),
    ("thickness of the whole gap", GOOD_BUMPER.replace("thickness = 0.02", "thickness = 0.1"), FORCE,
     "contact[0].bumper.thickness", "does not fit in the rest gap"),
    ("compressible zero", GOOD_BUMPER.replace("compressible = 0.8", "compressible = 0.0"), FORCE, "contact[0].bumper.compressible", ""),
    ("compressible above one", GOOD_BUMPER.replace("compressible = 0.8", "compressible = 1.5"), FORCE,
     "contact[0].bumper.compressible", ""),
    ("rubber without stiffness", GOOD_BUMPER.replace(", stiffness = 1e8", ""), FORCE, "contact[0].bumper.law.stiffness",
     "needs its stiffness"),
    ("rubber restitution out of range", GOOD_BUMPER.replace("stiffness = 1e8", "stiffness = 1e8, restitution = 1.5"), FORCE,
     "contact[0].bumper.law.restitution", "[0, 1]"),
    ("impulse layer", GOOD_BUMPER.replace('law = { name = "rubber", stiffness = 1e8 }', 'law = "impulse"'), FORCE,
     "contact[0].bumper.law", "a bumper needs a force law"),
    ("impulse run", GOOD_BUMPER, 'contact = "impulse"\nrestitution = 0.5', "contact[0].bumper", "a bumper needs a force law"),
]


def test_a_good_bumper_loads(tmp_path):
    """The scene every case below edits loads, with its bumper (so each case tests only its own defect)."""
    sc = load_scene(_write(tmp_path, bumper_scene()))
    assert sc.contacts[0].bumper.thickness == 0.02 and sc.contacts[0].law == "kelvin"


def _write(folder: Path, text: str) -> Path:
    path = folder / "scene.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_a_bad_bumper_gets_one_message_naming_its_field(tmp_path, case):
    """load_scene raises one InputError naming the file, the bumper's field and what was wrong."""
    _, bumper, analysis, field, words = case
    path = _write(tmp_path, bumper_scene(bumper, analysis))
    with pytest.raises(InputError) as exc:
        load_scene(path)
    text = str(exc.value)
    assert str(path) in text and field in text and words in text, text


def test_the_cli_refuses_a_bad_bumper_in_one_line_exit_2_nothing_written(tmp_path):
    """``pounding run`` of a scene whose layer fills the gap: one line on stderr, exit code 2, no output folder."""
    path = _write(tmp_path, bumper_scene(GOOD_BUMPER.replace("thickness = 0.02", "thickness = 0.1")))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "contact[0].bumper.thickness" in proc.stderr
    assert not out.exists()


def test_a_bumper_round_trips_through_the_scene_writer(tmp_path):
    """write_scene writes the bumper back, and the written scene loads equal (scene_differences: none)."""
    from pounding.io.scene_writer import scene_differences, write_scene

    sc = load_scene(_write(tmp_path, bumper_scene()))
    again = load_scene(write_scene(sc, tmp_path / "again.toml"))
    assert again.contacts[0].bumper == sc.contacts[0].bumper
    assert scene_differences(sc, again) == []


# --------------------------------------------------------------------------- the gap study
def test_the_gap_study_gives_the_gap_that_keeps_the_layer_untouched():
    """``pounding gap`` measures the bare slabs (its min_gap ignores the layer) and adds, per bumper
    storey, the bare gap that keeps the layer untouched: the storey's required gap plus T. A run
    with contact at 1.01 times it sees no contact; at 0.99 times it the other slab strikes the layer
    (the 1 % margin is 2e-4 m here, above the law's 1e-4 m contact tolerance)."""
    from pounding.framework.post.run import run
    from pounding.framework.studies.gap import minimum_gap

    data = pair_data({"name": "rubber", "stiffness": 1e8}, duration=2.0)
    data["building"][0] = box_building("left", 0.0, 10.0, 10.0, 1, 0.3, 0.3)
    data["building"][1] = box_building("right", 10.0 + G, 10.0, 10.0, 1, 0.5, 0.5)
    data["ground_motion"] = {"record": "elcentro", "pga": 0.3, "angle": 0.0}
    data["analysis"]["dt"] = 0.0005  # resolves the grazing contact at 0.99 (its energy is then <= 0 to rounding)
    sc = scene(data)
    report = minimum_gap(sc, "x")
    assert [(b["on"], b["storey"]) for b in report.bumpers] == [("right", 1)]
    need = report.bumpers[0]["gap"]
    assert report.required[0][2] > 0.0  # the slabs approach: the layer decides the gap, not the rest position
    assert need == pytest.approx(report.required[0][2] + T, abs=1e-15)
    runs = [run(sc.with_gap(f * need, report.direction)) for f in (0.99, 1.01)]
    assert len(runs[0].contacts) > 0 and len(runs[1].contacts) == 0
    assert sum(x["contact_forces"] for x in runs[0].energy.values()) <= 0.0


def test_a_layer_moved_into_its_neighbour_is_refused():
    """A scene moved in Python (with_gap) so that the layer no longer fits in the gap: the run refuses it
    (the layer would start compressed, its stored energy outside the account), naming the bumper."""
    sc = scene(pair_data({"name": "rubber", "stiffness": 1e8})).with_gap(0.5 * T, "x")
    with pytest.raises(ValueError, match="does not fit in the rest gap"):
        Model(sc)


def test_contacts_csv_names_the_bumper_as_the_pairs_law(tmp_path):
    """The law column of contacts.csv names a bumper's pair's law "bumper" (its layer and the slabs' law:
    summary.json's contact.between[...].bumper), not the slabs' law alone: the run records each pair's
    law as it resolved it, and a run folder read back resolves the same by the same rule."""
    from pounding.io.results import contact_rows, load_result, write_results

    d = free_slabs({"name": "rubber", "stiffness": K_LAYER}, 1.0)
    r = d.run()
    assert r.pair_law_names == ["bumper"]
    assert [row[2] for row in contact_rows(r)] == ["bumper"]
    assert load_result(write_results(r, tmp_path / "run"))[1].pair_law_names == ["bumper"]
    assert r.contact["between"][0]["bumper"]["layer"]["name"] == "rubber"


def test_pounding_check_describes_the_bumper(tmp_path):
    """``pounding check`` prints the bumper under its [[contact]] line: building, storey, thickness, fraction, layer law."""
    path = _write(tmp_path, bumper_scene())
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    line = next(x for x in proc.stdout.splitlines() if x.strip().startswith("bumper on"))
    assert "'B' storey 1" in line and "0.02 m thick" in line and "80 %" in line and "layer rubber" in line
