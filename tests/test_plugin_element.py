"""The element plugin mechanism, end to end: an out-of-tree package registers a new type.

examples/plugin_element is a separate distribution ("pounding-brace") whose
only link to pounding is one entry point in the group ``pounding.elements``.
"""

from __future__ import annotations

import importlib.metadata
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

SCENE = """
[[building]]
name = "braced"
storey_heights = [3.0]
slab = [[0, 0], [6, 0], [6, 6], [0, 6]]
mass = 50000.0
  [[building.element]]
  type = "brace"
  start = [0.0, 0.0]
  end = [6.0, 0.0]
  storey = 1
  E = 200e9
  A = 0.002
  [[building.element]]
  type = "brace"
  start = [0.0, 6.0]
  end = [6.0, 6.0]
  storey = 1
  E = 200e9
  A = 0.002
  [[building.element]]
  type = "shear_wall"
  start = [0.0, 0.0]
  end = [0.0, 6.0]
  thickness = 0.2
  E = 30e9
  nu = 0.2
  [[building.element]]
  type = "shear_wall"
  start = [6.0, 0.0]
  end = [6.0, 6.0]
  thickness = 0.2
  E = 30e9
  nu = 0.2
"""


@pytest.fixture(scope="module")
def brace_installed():
    """Install examples/plugin_element into this environment (once), as a user would with pip."""
    if not any(ep.name == "brace" for ep in importlib.metadata.entry_points(group="pounding.elements")):
        subprocess.run(
            [sys.executable, "-m", "pip", "install", "-q", "--no-deps", str(ROOT / "examples" / "plugin_element")],
            check=True,
        )
    return True


def test_brace_is_found_through_its_entry_point(brace_installed):
    """After installation the registry lists "brace" with the built-ins, without any edit to pounding."""
    out = subprocess.run([sys.executable, "-c", "from pounding.framework.model.registry import ELEMENTS; print(ELEMENTS.names())"], capture_output=True, text=True, check=True)
    assert "brace" in out.stdout and "frame" in out.stdout


def test_braced_building_has_the_closed_form_period(brace_installed, tmp_path):
    """Two braces along x on one storey: T_x = 2 pi sqrt(m / (2 E A cos^2(theta) / L)), read back from `pounding info --json`."""
    scene = tmp_path / "braced.toml"
    scene.write_text(SCENE)
    out = subprocess.run([sys.executable, "-m", "pounding", "info", str(scene), "--json"], capture_output=True, text=True, check=True)
    periods = json.loads(out.stdout)["buildings"]["braced"]["periods"]
    L = np.hypot(6.0, 3.0)
    k = 2 * 200e9 * 0.002 * (6.0 / L) ** 2 / L
    T = 2 * np.pi * np.sqrt(50000.0 / k)
    # the x mode is uncoupled (symmetric layout): one of the periods is exactly T
    assert min(abs(p - T) / T for p in periods) < 1e-10
