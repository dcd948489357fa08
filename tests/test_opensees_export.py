"""``pounding export opensees``: the exported script, run by OpenSeesPy in its own process, is the tool's model.

The script is the peer builders' commands written down (:mod:`pounding.peer.export`), so what it
computes is what the in-memory cross-checks compute (tests/test_opensees_transient.py,
tests/test_opensees_pounding.py): same structure, same damping, same load, same Newmark scheme.
What separates it from the tool is the model difference those tests measure, the out-of-plane
stiffness OpenSees' planar frames need (``OUT_OF_PLANE`` = 1e-9 of the in-plane inertia): a
relative stiffness perturbation of that size moves periods and histories by the same order
(measured there: 1e-9 to 2e-9 of the peaks), plus the Newton tolerance (1e-12 m, against peaks of
centimetres: 1e-10 relative). Every comparison below allows 1e-6 relative, three orders above
both, and far below what a wrong mass, stiffness, damping or load would change (the checks that
the comparisons discriminate are in the transient cross-check). Measured: periods 2.4e-10,
contact-free histories 0.9e-9 to 2.2e-9, the pounding pair 3.3e-9 (of the peaks).
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.framework.model.assembly import assemble
from pounding.io.scene import load_scene, parse_scene

pytestmark = pytest.mark.opensees

ROOT = Path(__file__).resolve().parents[1]
PAIR = ROOT / "examples" / "paper" / "pair_gap_0.5.toml"
RTOL = 1e-6  # see the module docstring
MODES = 6


def _run_script(scene, folder: Path, modes: int = MODES) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Export ``scene``, run the script with this interpreter; (periods [s], name -> (steps + 1, storeys, 3))."""
    from pounding.peer.export import write_script

    script = folder / "model.py"
    write_script(scene, script)
    history = folder / "history.csv"
    done = subprocess.run([sys.executable, str(script), "--history", str(history), "--modes", str(modes)],
                          capture_output=True, text=True, timeout=600, cwd=folder)
    assert done.returncode == 0, done.stderr[-2000:]
    printed = [json.loads(line)["periods [s]"] for line in done.stdout.splitlines() if line.startswith("{")]
    periods = printed[0] if modes > 0 else []
    with open(history, newline="") as fh:
        rows = list(csv.reader(fh))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    out = {}
    for b in scene.buildings:
        cols = [header.index(f"{b.name}.{f + 1}.{dof}") for f in range(b.n_storeys) for dof in ("u [m]", "v [m]", "phi [rad]")]
        out[b.name] = data[:, cols].reshape(len(data), b.n_storeys, 3)
    return np.asarray(periods), out


@pytest.fixture(scope="module")
def paper_pair(tmp_path_factory):
    """The paper pair (non-symmetric, each building its own Rayleigh a0, a1), no contact, Newmark, dt 0.01 s, 6 s
    (the strong motion and the low building's peak at 2.3 s)."""
    scene = load_scene(PAIR).with_analysis(integrator="newmark", integrator_params={}, contact="none", contact_params={},
                                           dt=0.01, duration=6.0)
    result = run(scene)
    periods, peer = _run_script(scene, tmp_path_factory.mktemp("export"))
    return scene, result, periods, peer


def test_exported_periods_are_the_tools(paper_pair):
    """The script's first six periods (both buildings in one domain) are the union of each building's, longest
    first, to 1e-6."""
    scene, _, periods, _ = paper_pair
    ours = np.sort(np.concatenate([assemble(b).periods for b in scene.buildings]))[::-1][:MODES]
    np.testing.assert_allclose(periods, ours, rtol=RTOL)


def test_exported_contact_free_history_is_the_tools(paper_pair):
    """Every floor's u, v, phi over the whole run: max |difference| <= 1e-6 of the peak of each kind (m, m, rad).
    The two buildings' damping differs (two ``region``s), so this also checks the damping of each building."""
    scene, result, _, peer = paper_pair
    a, b = (assemble(x) for x in scene.buildings)
    assert not np.allclose(a.zeta, b.zeta[: len(a.zeta)])  # per-building damping is really exercised
    for bld in scene.buildings:
        ours = result.cm(bld.name)
        assert peer[bld.name].shape == ours.shape
        scale = np.max(np.abs(ours), axis=(0, 1))
        assert np.all(scale[:2] > 1e-3)  # the response is well above rounding (>= 1 mm)
        np.testing.assert_array_less(np.max(np.abs(peer[bld.name] - ours), axis=(0, 1)), RTOL * scale, err_msg=bld.name)


def test_exported_gap_springs_pound_as_the_tools_penalty_law(tmp_path):
    """Contact: the symmetric pair of tests/test_opensees_pounding.py with a penalty law of restitution 1 (a linear
    spring in compression only) exports as ElasticPPGap springs; over 4 s (every storey pounds) the script's
    floor displacements are the tool's to 1e-6 of the peak (that test measured 3e-8 over 10 s at this
    out-of-plane stiffness, the impacts amplifying the model difference)."""
    from test_opensees_pounding import _penalty, _scene_dict

    scene = parse_scene(_scene_dict(_penalty(), duration=4.0))
    result = run(scene)
    _, peer = _run_script(scene, tmp_path, modes=0)
    for bld in scene.buildings:
        ours = result.cm(bld.name)[:, :, 0]
        peak = np.abs(ours).max()
        assert np.abs(peer[bld.name][:, :, 0] - ours).max() <= RTOL * peak, bld.name
    text = (tmp_path / "model.py").read_text()
    assert "ElasticPPGap" in text and "zeroLength" in text


@pytest.mark.parametrize("integrator", ["newmark", {"name": "hht", "alpha": -0.05}], ids=["newmark", "hht"])
def test_exported_yielding_springs_are_the_tools(tmp_path, integrator):
    """Storey springs that yield (tests/inelastic_scenes.eccentric_building: five bilinear lines, eccentric in
    strength and stiffness, shaken at 30 degrees) export as twoNodeLink elements with Steel01; over 4 s the
    script's floor histories are the tool's within 1e-5 of the peak (the requirement of
    tests/test_opensees_inelastic.py, whose in-memory model this is). pounding's hht is exported as OpenSees'
    HHT_TP with alpha 1 + Hilber's (the yielding forces weighted as pounding blends them). Measured 2.6e-13
    for both: the Newton tolerance."""
    from inelastic_scenes import eccentric_building, single

    scene = parse_scene(single(eccentric_building(), duration=4.0, integrator=integrator))
    result = run(scene)
    _, peer = _run_script(scene, tmp_path, modes=0)
    assert "Steel01" in (tmp_path / "model.py").read_text()
    ours = result.cm("tower")
    for c in range(3):
        peak = np.abs(ours[:, :, c]).max()
        assert np.abs(peer["tower"][:, :, c] - ours[:, :, c]).max() <= 1e-5 * peak


def test_an_impulse_scene_exports_without_contact_and_says_so(tmp_path):
    """The rigid impulse law has no OpenSees material: the script has no gap element and the note says why."""
    from pounding.peer.export import write_script

    notes = write_script(load_scene(PAIR), tmp_path / "model.py")
    text = (tmp_path / "model.py").read_text()
    assert any("impulse" in n for n in notes) and "zeroLength" not in text
    assert "Left out: contact law 'impulse'" in text


@pytest.mark.parametrize("args, message", [
    (["export", "opensee", str(PAIR)], "did you mean 'opensees'"),
    (["export", "opensees", "missing.toml"], "cannot read the scene file"),
])
def test_bad_export_input_exits_2_and_writes_nothing(tmp_path, args, message):
    """An unknown format or an unreadable scene: one message naming the problem, exit 2, no file written."""
    out = tmp_path / "model.py"
    done = subprocess.run([sys.executable, "-m", "pounding", *args, "--out", str(out)], capture_output=True, text=True,
                          cwd=tmp_path, timeout=300)
    assert done.returncode == 2
    assert message in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_exported_force_law_pounds_as_the_tools_law(tmp_path):
    """A force law exports as zeroLength elements with OpenSees' material of the same name: jankowski as
    JankowskiImpact (half the law at each end of a face, at its point's effective mass), on the two shear
    buildings of tests/test_opensees_contact_buildings.py; the script's floor displacements are the tool's
    to 1e-6 of the peak (the in-memory model, which this script writes down, measured 3.3e-10 there)."""
    from contact_pair import pair_scene

    scene = pair_scene({"name": "jankowski", "restitution": 0.5}, 1e-3, 0.85)
    result = run(scene)
    _, peer = _run_script(scene, tmp_path, modes=0)
    assert "JankowskiImpact" in (tmp_path / "model.py").read_text()
    for bld in scene.buildings:
        ours = result.cm(bld.name)[:, :, 0]
        assert np.abs(peer[bld.name][:, :, 0] - ours).max() <= RTOL * np.abs(ours).max(), bld.name


def test_kelvin_without_tension_exports_its_material_and_says_how_it_differs(tmp_path):
    """kelvin's default (tension = false, never pulling) exports as ViscoelasticGap, which may pull: the note says so."""
    from contact_pair import pair_scene
    from pounding.peer.export import write_script

    notes = write_script(pair_scene({"name": "kelvin", "restitution": 0.5}, 1e-3, 0.85), tmp_path / "model.py")
    text = (tmp_path / "model.py").read_text()
    assert "ViscoelasticGap" in text and "zeroLength" in text
    assert any("tension = false" in n for n in notes) and "Left out: contact law 'kelvin'" in text


def test_exported_moat_wall_strikes_as_the_tools_kelvin_wall(tmp_path):
    """A retaining wall exports as tests/test_walls.py's peer model builds it (the same function,
    :func:`pounding.peer.opensees_walls.scene_walls`): the base-isolated building of that test beside a moat
    wall with a Kelvin law of its own (tension: OpenSees' ViscoelasticGap), struck once at 2.79 s. Both step the
    same discrete equations (Newmark average acceleration, the same dt; the script builds storey springs only,
    so no out-of-plane stiffness enters), so the agreement is that test's: every step within the Newton
    tolerance (1e-12 m) of its solution, summed over the steps by a stable scheme, n x 1e-12 m on every floor.
    Measured: 2.9e-12 m (peak 0.12 m), against 1.5e-9 m."""
    from test_walls import _isolated_beside_a_moat

    scene = parse_scene(_isolated_beside_a_moat())
    result = run(scene)
    _, peer = _run_script(scene, tmp_path, modes=0)
    text = (tmp_path / "model.py").read_text()
    assert text.count("'zeroLength'") == 2 and "ViscoelasticGap" in text  # the two ends of the base slab's edge
    ours = result.cm("isolated")[:, :, 0]
    assert ours[:, 0].min() < -0.05  # the base slab passed the face (0.05 m away): the wall was struck
    assert np.abs(peer["isolated"][:, :, 0] - ours).max() <= result.steps * 1e-12


def test_exported_viscous_link_converges_to_the_tools_link(tmp_path, opensees):
    """A link between slabs exports as tests/test_links_between.py's peer model builds it (the same function,
    :func:`pounding.peer.opensees_links.scene_links`): a linear dashpot (zeroLength with ``Viscous``) between
    a one- and a two-storey building, eccentric. OpenSees' Viscous takes the end rate of Newmark's step,
    pounding's law the step's mean rate, a first-order difference (that test's derivation): from 10 ms to 5 ms
    the displacements' difference halves (ratio within [1.7, 2.3]), and at 5 ms it stays below the link
    force's largest change in one step, over its peak (the size of the half-step lag). Measured: 3.5 % and
    1.74 % of the peaks (ratio 2.01; 0.87 % at 2.5 ms), against a lag of 12 %. The script is also the
    in-memory peer (:func:`pounding.peer.opensees_springs.run_linked_transient`) to the two Newton
    tolerances summed over the steps, n x (1e-12 + 1e-13) m (measured: identical, 0 m)."""
    from pounding.peer.opensees_springs import run_linked_transient
    from test_links_between import linked_pair

    law = {"name": "viscous", "coefficient": 4.0e6, "exponent": 1.0}
    worst, lag = [], 0.0
    for dt in (0.01, 0.005):
        scene = parse_scene(linked_pair(law, storeys=(1, 2), kx_a=(0.8e8, 1.2e8), kx_b=(2.0e8, 1.4e8), y=3.0, dt=dt,
                                        damping={"type": "rayleigh", "ratio": 0.02, "modes": [1, 2]}))
        result = run(scene)
        folder = tmp_path / f"dt{dt:g}"
        folder.mkdir()
        _, peer = _run_script(scene, folder, modes=0)
        assert "'Viscous'" in (folder / "model.py").read_text()
        in_memory, _ = run_linked_transient(opensees, scene, result.dt, result.steps)
        for n in result.names:
            assert np.abs(in_memory[n] - peer[n]).max() <= result.steps * 1.1e-12, n
        worst.append(max(np.abs(result.cm(n)[:, :, c] - peer[n][:, :, c]).max() / np.abs(peer[n][:, :, c]).max()
                         for n in result.names for c in (0, 2)))  # u and phi (v is not excited)
        force = result.links["l1"]["force"]
        lag = np.abs(np.diff(force)).max() / np.abs(force).max()
    assert 1.7 <= worst[0] / worst[1] <= 2.3
    assert worst[1] <= lag


def test_a_wall_without_an_opensees_material_is_left_out_and_the_note_names_it(tmp_path):
    """A wall taking the rigid impulse law ([analysis] contact's, as by default) has no OpenSees material: the
    script has no wall element, and one note names the wall and why (the warning the command prints)."""
    from test_walls import _isolated_beside_a_moat
    from pounding.peer.export import write_script

    data = _isolated_beside_a_moat()
    data["analysis"]["contact"] = {"name": "impulse", "restitution": 0.5}
    del data["wall"][0]["contact"]
    notes = write_script(parse_scene(data), tmp_path / "model.py")
    text = (tmp_path / "model.py").read_text()
    assert "'zeroLength'" not in text
    assert [n for n in notes if "wall 'moat'" in n and "'impulse' has no OpenSees material" in n]


def test_a_link_law_without_an_opensees_material_is_one_message_naming_it(tmp_path):
    """A link whose law OpenSees has no material for (a friction pendulum with velocity-dependent friction)
    cannot be exported: one InputError naming the law, and no file written."""
    from test_links_between import linked_pair
    from pounding.errors import InputError
    from pounding.peer.export import write_script

    law = {"name": "friction_pendulum", "weight": 1e6, "radius": 2.0, "friction": 0.06, "friction_slow": 0.03, "rate": 30.0}
    scene = parse_scene(linked_pair(law, damping={"type": "rayleigh", "ratio": 0.02, "modes": [1, 2]}))
    with pytest.raises(InputError, match="cannot export to OpenSees: no OpenSees material for hysteresis law "
                                         "'friction_pendulum' with velocity-dependent friction"):
        write_script(scene, tmp_path / "model.py")
    assert list(tmp_path.iterdir()) == []


def test_a_step_too_coarse_for_the_contact_is_noted_in_the_script():
    """A scene's own dt that spans a force law's shortest contact in fewer steps than the default takes
    (the paper's pair with kelvin, k = 1e9, at dt = 0.005 s: about 2.5 steps) gets a note naming the law,
    the steps and the step that resolves it (OpenSees' Newton failed inside such a contact); the default
    step gets none."""
    from pounding.peer.export import opensees_script

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(
        contact="kelvin", contact_params={"stiffness": 1e9, "restitution": 0.5}, integrator="newmark", integrator_params={})
    _, notes = opensees_script(scene.with_analysis(dt=0.005))
    coarse = [n for n in notes if "spans the shortest kelvin contact" in n]
    assert len(coarse) == 1 and "resolves it" in coarse[0]
    _, notes = opensees_script(scene.with_analysis(dt=None))
    assert not any("spans the shortest" in n for n in notes)
