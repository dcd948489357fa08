"""The storey_springs element: its stiffness in closed form, its place in the elastic model, and bad input."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.model.assembly import assemble
from pounding.io.scene import load_scene, parse_scene
from tests.rounding import EPS, sym_eig_rel

from inelastic_scenes import eccentric_building, single, springs


def test_lateral_stiffness_is_the_tridiagonal_chain_of_storey_springs():
    """Springs k_1..k_n in series from the ground: K[f, f] = k_f + k_(f+1), K[f, f+1] = -k_(f+1)."""
    scene = parse_scene(single(eccentric_building()))
    e = scene.buildings[0].elements[0]
    k1, k2, k3 = 1.2e8, 1.0e8, 0.8e8
    expected = np.array([[k1 + k2, -k2, 0.0], [-k2, k2 + k3, -k3], [0.0, -k3, k3]])
    assert np.array_equal(e.lateral_stiffness(), expected)
    assert e.floors == (1, 2, 3)


def test_uniform_shear_building_frequencies():
    """N equal masses m on N equal springs k (a uniform shear building, springs through the centre of
    mass in x and y, torsion resisted by lines at the edges): omega_j = 2 sqrt(k/m) sin((2j-1) pi / (2(2N+1)))
    along x (Chopra, Dynamics of Structures, eq. for the uniform shear beam), to the eigensolver's rounding."""
    n, k = 4, 2.0e8
    b = {
        "name": "uniform",
        "storey_heights": [3.0] * n,
        "slab": [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
        "mass": 1.0e5,
        "element": [springs([0.0, 5.0], [10.0, 5.0], k), springs([5.0, 0.0], [5.0, 10.0], 3.0 * k),
                    springs([0.0, 0.0], [0.0, 10.0], 2.0 * k), springs([10.0, 0.0], [10.0, 10.0], 2.0 * k)],
    }
    system = assemble(parse_scene(single(b)).buildings[0])
    ux = np.abs(system.modes[0::3, :]).sum(axis=0) > 1e-6 * np.abs(system.modes).max()
    omega_x = np.sort(system.omega[ux])
    j = np.arange(1, n + 1)
    exact = 2.0 * np.sqrt(k / 1.0e5) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1)))
    # omega = sqrt(lam): half the eigen-solve's relative bound on lam (rounding.sym_eig_rel), plus a few ulps
    np.testing.assert_allclose(omega_x, exact, rtol=0.5 * sym_eig_rel(system.omega**2)[ux].max() + 8 * EPS)


def test_eccentric_springs_couple_translation_and_torsion():
    """Unequal lines along x put the centre of rigidity off the centre of mass: the first mode has both
    a u and a phi component (placement as for frames and walls)."""
    system = assemble(parse_scene(single(eccentric_building())).buildings[0])
    first = system.modes[:, 0].reshape(3, 3)
    assert np.abs(first[:, 2]).max() * 5.0 > 1e-3 * np.abs(first[:, :2]).max()


BASE = """
[ground_motion]
record = "elcentro"
pga = 0.32

[analysis]
dt = 0.01
duration = 1.0
integrator = "newmark"
contact = "none"

[[building]]
name = "A"
storey_heights = [3.0, 3.0]
slab = [[0, 0], [10, 0], [10, 8], [0, 8]]
mass = 80000.0
  [[building.element]]
  type = "storey_springs"
  start = [0, 0]
  end = [10, 0]
  stiffness = [6.0e7, 5.0e7]
  yield_force = [3.0e5, 2.5e5]
  hardening = 0.02
  hysteresis = "bilinear"
  [[building.element]]
  type = "storey_springs"
  start = [0, 8]
  end = [10, 8]
  stiffness = 5.0e7
  yield_force = 2.5e5
  hardening = 0.02
  hysteresis = { name = "bouc_wen", n = 2, beta = 0.5, gamma = 0.5 }
  [[building.element]]
  type = "storey_springs"
  start = [0, 0]
  end = [0, 8]
  stiffness = 5.0e7
  [[building.element]]
  type = "storey_springs"
  start = [10, 0]
  end = [10, 8]
  stiffness = 5.0e7
"""

E1 = "building[0].element[0]"
E2 = "building[0].element[1]"
CASES = [
    ("zero yield force", "yield_force = [3.0e5, 2.5e5]", "yield_force = [3.0e5, 0.0]", E1 + ".yield_force[1]", "> 0"),
    ("negative yield force", "yield_force = 2.5e5", "yield_force = -2.5e5", E2 + ".yield_force", "> 0"),
    ("hardening 1", "hardening = 0.02\n  hysteresis = \"bilinear\"", "hardening = 1.0\n  hysteresis = \"bilinear\"", E1 + ".hardening", "[0, 1)"),
    ("negative hardening", "hardening = 0.02\n  hysteresis = \"bilinear\"", "hardening = -0.1\n  hysteresis = \"bilinear\"", E1 + ".hardening", "[0, 1)"),
    ("yield list length", "yield_force = [3.0e5, 2.5e5]", "yield_force = [3.0e5, 2.5e5, 2.0e5]", E1 + ".yield_force", "list of 2"),
    ("stiffness list length", "stiffness = [6.0e7, 5.0e7]", "stiffness = [6.0e7]", E1 + ".stiffness", "list of 2"),
    ("zero stiffness", "stiffness = [6.0e7, 5.0e7]", "stiffness = [6.0e7, 0.0]", E1 + ".stiffness[1]", "> 0"),
    ("bouc-wen n below 1", "n = 2, beta", "n = 0.5, beta", E2 + ".hysteresis.n", ">= 1"),
    ("bouc-wen gamma above beta", "beta = 0.5, gamma = 0.5", "beta = 0.5, gamma = 0.7", E2 + ".hysteresis.gamma", "-beta < gamma <= beta"),
    ("bouc-wen beta not positive", "beta = 0.5, gamma = 0.5", "beta = -0.5, gamma = 0.5", E2 + ".hysteresis.beta", "> 0"),
    ("unknown law parameter", "n = 2, beta", "m = 2, beta", E2 + ".hysteresis", "m"),
    ("unknown law", "hysteresis = \"bilinear\"", "hysteresis = \"takeda\"", E1 + ".hysteresis", "known: bilinear, bouc_wen"),
    ("hysteresis without yield force", "stiffness = 5.0e7\n  [[building.element]]\n  type = \"storey_springs\"\n  start = [10, 0]",
     "stiffness = 5.0e7\n  hardening = 0.1\n  [[building.element]]\n  type = \"storey_springs\"\n  start = [10, 0]", "building[0].element[2].hardening", "yield_force"),
]


def _write(tmp_path, old, new):
    text = BASE.replace(old, new, 1)
    assert text != BASE, "the case does not change the scene"
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_base_scene_is_valid(tmp_path):
    """The scene every case edits loads: two yielding lines (bilinear, Bouc-Wen) and two elastic ones."""
    path = tmp_path / "scene.toml"
    path.write_text(BASE)
    elements = load_scene(path).buildings[0].elements
    assert [e.law.name if e.law else None for e in elements] == ["bilinear", "bouc_wen", None, None]
    assert elements[1].yield_force == (2.5e5, 2.5e5) and elements[1].law.n == 2.0


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_bad_spring_input_names_file_key_and_expectation(tmp_path, case):
    """One InputError naming the file, the key path (0-based) and what was expected."""
    _, old, new, field, words = case
    path = _write(tmp_path, old, new)
    with pytest.raises(InputError) as exc:
        load_scene(path)
    text = str(exc.value)
    assert str(path) in text
    assert field in text
    assert words in text


def test_cli_exit_code_2_for_a_bad_yield_force(tmp_path):
    """The command line: one line on stderr naming the key, exit code 2, nothing written."""
    path = _write(tmp_path, "yield_force = [3.0e5, 2.5e5]", "yield_force = [3.0e5, -1.0]")
    proc = subprocess.run([sys.executable, "-m", "pounding", "info", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1
    assert E1 + ".yield_force[1]" in proc.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["scene.toml"]


def test_pounding_run_steps_a_building_mixing_laws(tmp_path):
    """`pounding run` steps yielding springs (with or without contact) and any mix of hysteresis
    laws in a building (here bilinear and Bouc-Wen lines): it runs and reports ductility for every
    spring."""
    import json

    path = tmp_path / "scene.toml"
    path.write_text(BASE)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    lines = summary["buildings"]["A"].get("yielding_springs")
    assert lines is not None and len(lines) == 2  # both lines, one bilinear and one Bouc-Wen
    assert all(len(line["ductility"]) == 2 and min(line["ductility"]) > 0.0 for line in lines)


PAIR = BASE.replace('contact = "none"', 'contact = "impulse"').replace("duration = 1.0", "duration = 4.0") + """
[[building]]
name = "B"
storey_heights = [3.0, 3.0]
slab = [[10.02, 0], [16.02, 0], [16.02, 8], [10.02, 8]]
mass = 50000.0
  [[building.element]]
  type = "storey_springs"
  start = [10.02, 0]
  end = [16.02, 0]
  stiffness = 2.0e7
  yield_force = 1.2e5
  hysteresis = "bilinear"
  [[building.element]]
  type = "storey_springs"
  start = [10.02, 8]
  end = [16.02, 8]
  stiffness = 2.0e7
  yield_force = 1.2e5
  hysteresis = "bilinear"
  [[building.element]]
  type = "storey_springs"
  start = [10.02, 0]
  end = [10.02, 8]
  stiffness = 2.0e7
"""


def test_pounding_gap_on_yielding_buildings_is_checked_by_full_yielding_runs(tmp_path):
    """`pounding gap` on two yielding buildings: without contact the buildings are independent
    whatever their springs do, so the smallest gap that avoids contact comes from one contact-free
    run as for elastic buildings; its check, two full yielding runs with impulse contact at 0.99x
    (impacts) and 1.01x (none) of the answer, passes (exit 0)."""
    import json

    path = tmp_path / "pair.toml"
    path.write_text(PAIR)
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(path), "--json"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    report = json.loads(proc.stdout)
    assert report["min_gap"] > 0.01  # the buildings sway by centimetres
    assert report["check"]["ok"]


def test_pounding_sweep_on_yielding_buildings(tmp_path):
    """`pounding sweep --gaps` on two yielding buildings runs every case with the springs (one row
    per gap): impacts at a gap they close, none at a gap wider than any approach."""
    from pounding.framework.studies.sweep import read_table

    path = tmp_path / "pair.toml"
    path.write_text(PAIR)
    out = tmp_path / "sweep"
    proc = subprocess.run([sys.executable, "-m", "pounding", "sweep", str(path), "--gaps", "0.002,0.5", "--out", str(out), "--quiet"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rows = read_table(out / "sweep.csv")
    by_gap = {r["gap"]: r["n_impacts"] for r in rows}
    assert by_gap[0.002] > 0 and by_gap[0.5] == 0
