"""Rows of buildings: what the scene reader refuses and what it warns about.

A storey is the prism of its slab between the floor below and its own level;
two buildings may not claim the same space at rest, whether or not their slabs
are at a common level. Buildings with no slabs at a common level are valid but
nothing is checked between them: one warning says so, naming every such pair.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from pounding.errors import InputError
from pounding.framework.plausibility import findings
from pounding.io.scene import load_scene

from test_bad_input import BASE


def _scene_text(b_heights: str, b_slab_x0: float, extra: str = "") -> str:
    old = 'storey_heights = [3.0]\nslab = [[10.1, 0], [20, 0], [20, 8], [10.1, 8]]'
    assert old in BASE, "B's block changed: these scenes would not be what they say"
    return BASE.replace(old, f'storey_heights = {b_heights}\nslab = [[{b_slab_x0}, 0], [20, 0], [20, 8], [{b_slab_x0}, 8]]', 1) + extra


def _third(name: str, heights: str, x0: float) -> str:
    """A three-wall building standing on [x0, x0 + 10] x [0, 8]."""
    return f"""
[[building]]
name = "{name}"
storey_heights = {heights}
slab = [[{x0}, 0], [{x0 + 10}, 0], [{x0 + 10}, 8], [{x0}, 8]]
mass_per_area = 800.0
  [[building.element]]
  type = "shear_wall"
  start = [{x0}, 0]
  end = [{x0 + 10}, 0]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [{x0}, 8]
  end = [{x0 + 10}, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [{x0 + 5}, 0]
  end = [{x0 + 5}, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
"""


def test_overlap_at_different_levels_is_refused_with_exit_2_and_one_line(tmp_path):
    """B (one 3.5 m storey) reaches 0.6 m into A (3 m storeys): no slabs share a level, yet the
    storeys 0-3 m and 0-3.5 m share height and plan: `pounding check` exits 2 with one line."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 9.4))
    with pytest.raises(InputError, match=r"storey 1 of 'A' \(0-3 m\) and storey 1 of 'B' \(0-3.5 m\).*overlap by 0.6 m"):
        load_scene(path)
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "building[1].slab" in proc.stderr


def test_a_storey_above_a_lower_neighbours_roof_may_overhang_it(tmp_path):
    """C's second storey (3-6 m) overhangs B's roof (B is one 3 m storey) by 2 m in plan: the
    storeys share no height, so the scene is valid (a setback over a low neighbour)."""
    path = tmp_path / "scene.toml"
    # C's first storey stands clear of B (x >= 20.1), its second slab reaches back over B to x = 18
    extra = _third("C", "[3.0, 3.0]", 20.1).replace(
        "slab = [[20.1, 0], [30.1, 0], [30.1, 8], [20.1, 8]]",
        "slabs = [[[20.1, 0], [30.1, 0], [30.1, 8], [20.1, 8]], [[18, 0], [30.1, 0], [30.1, 8], [18, 8]]]")
    path.write_text(_scene_text("[3.0]", 10.1, extra))
    scene = load_scene(path)
    assert [b.name for b in scene.buildings] == ["A", "B", "C"]


def test_no_common_level_is_said_once_naming_every_pair(tmp_path):
    """A has 3 m storeys, B one of 3.5 m, C 3.7 m: no two share a level; one warning names the
    three pairs, and none is given when B and C share A's levels."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 10.1, _third("C", "[3.7]", 20.2)))
    found = [f for f in findings(load_scene(path)) if f.check == "no_common_level"]
    assert len(found) == 1
    for pair in ("'A' and 'B'", "'A' and 'C'", "'B' and 'C'"):
        assert pair in found[0].message
    path.write_text(_scene_text("[3.0]", 10.1, _third("C", "[3.0]", 20.2)))
    assert [f for f in findings(load_scene(path)) if f.check == "no_common_level"] == []


def test_no_common_level_warning_reaches_stderr_once_and_is_silenced(tmp_path):
    """`pounding info` on the A (3 m) / B (3.5 m) scene prints exactly one no_common_level warning
    line (exit 0), and none with --silence no_common_level."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 10.1))
    proc = subprocess.run([sys.executable, "-m", "pounding", "info", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if "no_common_level" in ln]
    assert len(lines) == 1 and "'A' and 'B'" in lines[0]
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path), "--silence", "no_common_level"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "no_common_level" not in proc.stderr
