"""Independent cross-check against a full 3-D OpenSeesPy model.

The project's issue asks for "a full 3D OpenSeesPy model (rigid diaphragms,
elastic beam-columns, frames modelled as independent planar structures) of a
non-symmetric 3-storey building with frames of different stiffness in both
directions [that] gives the same periods to 1e-6 relative".

The OpenSees model (:mod:`pounding.peer.opensees`) shares nothing with
pounding's condensation but the scene: every frame is a real planar structure
of ``elasticBeamColumn`` members with its own nodes, every floor a
``rigidDiaphragm`` with the slab mass at its centre of mass, every wall a chain
of ``ElasticTimoshenkoBeam`` elements. The only modelling difference is the
out-of-plane bending and torsional stiffness OpenSees needs to keep the planar
frames stable: ``out_of_plane`` times the in-plane inertia. It adds stiffness
the condensed model does not have, so the periods differ by a relative amount
proportional to it (measured: 0.68 x out_of_plane for the frame building,
63 x for the wall building, whose walls have a large in-plane inertia
t L^3 / 12 and so a larger out-of-plane stiffness for the same fraction).
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.model.assembly import assemble, rayleigh_coefficients
from pounding.io.scene import load_scene

pytestmark = pytest.mark.opensees

RTOL = 1e-6  # the requirement

# Non-symmetric 3-storey building: three x-frames at uneven spacing with
# different columns (the strong one on y = 0), four y-frames at uneven
# spacing with different columns and bays, sections changing with height.
FRAME_BUILDING = """
[[building]]
name = "frames"
storey_heights = [3.6, 3.2, 3.2]
slab = [[0.0, 0.0], [15.0, 0.0], [15.0, 10.0], [0.0, 10.0]]
mass_per_area = [950.0, 900.0, 700.0]

  [[building.element]]
  type = "frame"
  start = [0.0, 0.0]
  angle = 0.0
  columns = [0.0, 4.0, 10.0, 15.0]
  column = [{ E = 30e9, b = 0.55, h = 0.55 }, { E = 30e9, b = 0.50, h = 0.50 }, { E = 30e9, b = 0.45, h = 0.45 }]
  beam = { E = 30e9, b = 0.30, h = 0.60 }

  [[building.element]]
  type = "frame"
  start = [0.0, 6.5]
  angle = 0.0
  columns = [0.0, 6.0, 15.0]
  column = { E = 30e9, b = 0.40, h = 0.40 }
  beam = { E = 30e9, b = 0.30, h = 0.50 }

  [[building.element]]
  type = "frame"
  start = [0.0, 10.0]
  end = [15.0, 10.0]
  columns = [0.0, 7.5, 15.0]
  column = { E = 28e9, A = 0.09, I = 6.75e-4 }
  beam = { E = 28e9, A = 0.12, I = 1.6e-3 }

  [[building.element]]
  type = "frame"
  start = [0.0, 0.0]
  angle = 90.0
  columns = [0.0, 3.5, 10.0]
  column = { E = 30e9, b = 0.45, h = 0.45 }
  beam = { E = 30e9, b = 0.30, h = 0.50 }

  [[building.element]]
  type = "frame"
  start = [4.0, 0.0]
  angle = 90.0
  columns = [0.0, 10.0]
  column = { E = 30e9, b = 0.35, h = 0.35 }
  beam = { E = 30e9, b = 0.30, h = 0.45 }

  [[building.element]]
  type = "frame"
  start = [11.0, 0.0]
  angle = 90.0
  columns = [0.0, 6.5, 10.0]
  column = { E = 30e9, b = 0.40, h = 0.40 }
  beam = { E = 30e9, b = 0.30, h = 0.50 }

  [[building.element]]
  type = "frame"
  start = [15.0, 0.0]
  angle = 90.0
  columns = [0.0, 4.0, 10.0]
  column = [{ E = 30e9, b = 0.60, h = 0.60 }, { E = 30e9, b = 0.60, h = 0.60 }, { E = 30e9, b = 0.50, h = 0.50 }]
  beam = { E = 30e9, b = 0.35, h = 0.60 }
"""

# 4 storeys: two Timoshenko walls (one with its own G and shear area,
# spanning 3 storeys only), frames along x and y and one inclined frame.
WALL_BUILDING = """
[[building]]
name = "walls"
storey_heights = [3.5, 3.0, 3.0, 3.0]
slab = [[0.0, 0.0], [15.0, 0.0], [15.0, 10.0], [0.0, 10.0]]
mass_per_area = 800.0
damping = { type = "rayleigh", ratio = 0.03, modes = [1, 2] }

  [[building.element]]
  type = "shear_wall"
  start = [0.0, 0.0]
  end = [5.0, 0.0]
  thickness = 0.25
  E = 30e9
  nu = 0.2

  [[building.element]]
  type = "shear_wall"
  start = [15.0, 2.0]
  end = [15.0, 8.0]
  thickness = 0.30
  E = 25e9
  G = 10e9
  shear_area = 1.2
  storeys = 3

  [[building.element]]
  type = "frame"
  start = [0.0, 10.0]
  angle = 0.0
  columns = [0.0, 6.0, 15.0]
  column = { E = 30e9, b = 0.40, h = 0.40 }
  beam = { E = 30e9, b = 0.30, h = 0.50 }

  [[building.element]]
  type = "frame"
  start = [0.0, 0.0]
  angle = 90.0
  columns = [0.0, 4.0, 10.0]
  column = { E = 30e9, b = 0.45, h = 0.45 }
  beam = { E = 30e9, b = 0.30, h = 0.50 }

  [[building.element]]
  type = "frame"
  start = [8.0, 2.0]
  end = [12.0, 9.0]
  columns = [0.0, 4.0, 8.0]
  column = { E = 30e9, b = 0.35, h = 0.35 }
  beam = { E = 30e9, b = 0.30, h = 0.45 }
"""


def _building(tmp_path, text: str):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    (building,) = load_scene(path).buildings
    return building


def _opensees_periods(ops, building, out_of_plane: float) -> np.ndarray:
    from pounding.peer.opensees import build_building, eigen_periods

    ops.wipe()
    masters = build_building(ops, building, out_of_plane=out_of_plane)
    assert len(masters) == building.n_storeys
    periods = eigen_periods(ops, 3 * building.n_storeys)
    ops.wipe()
    return periods


def test_frame_building_periods_match_opensees(opensees, tmp_path):
    """All 9 periods of the non-symmetric 3-storey frame building agree to 1e-6.

    out_of_plane = 1e-8: the measured deviation is 0.68 x out_of_plane
    (6.8e-7 at 1e-6, 6.8e-9 at 1e-8), so 1e-8 leaves a factor of ~150 of
    margin below the required 1e-6; what is left is the modelling difference,
    not round-off (it keeps scaling with out_of_plane down to 1e-9 and beyond).
    """
    building = _building(tmp_path, FRAME_BUILDING)
    expected = assemble(building).periods
    periods = _opensees_periods(opensees, building, out_of_plane=1e-8)
    assert periods.shape == (9,)
    np.testing.assert_allclose(periods, expected, rtol=RTOL, atol=0)


def test_frame_building_deviation_follows_out_of_plane_stiffness(opensees, tmp_path):
    """The residual difference is the out-of-plane stiffness: 100x more of it, ~100x the deviation."""
    building = _building(tmp_path, FRAME_BUILDING)
    expected = assemble(building).periods
    d6 = np.max(np.abs(_opensees_periods(opensees, building, 1e-6) / expected - 1))
    d8 = np.max(np.abs(_opensees_periods(opensees, building, 1e-8) / expected - 1))
    assert 1e-8 < d6 < 1e-5
    assert d6 / d8 == pytest.approx(100.0, rel=0.05)


def test_wall_building_periods_match_opensees(opensees, tmp_path):
    """Timoshenko walls (bending + shear with As), frames and an inclined frame: all 12 periods to 1e-6.

    ElasticTimoshenkoBeam is exact for a prismatic member under end loads, so
    the chain reproduces ShearWall.flexibility exactly. The walls' in-plane
    inertia is large, so their out-of-plane stiffness for a given fraction is
    too: the deviation is 63 x out_of_plane here (6.3e-7 at 1e-8). Hence
    out_of_plane = 1e-9: 6.3e-8, a factor of ~16 of margin.
    """
    building = _building(tmp_path, WALL_BUILDING)
    expected = assemble(building).periods
    periods = _opensees_periods(opensees, building, out_of_plane=1e-9)
    np.testing.assert_allclose(periods, expected, rtol=RTOL, atol=0)


def _newmark(system, ground_motion, dt, n, a0, a1, beta=0.25, gamma=0.5):
    """Newmark on pounding's own M, K with C = a0 M + a1 K: displacements (n+1, N, 3)."""
    M, K = system.M, system.K
    C = a0 * M + a1 * K
    load = -np.outer(ground_motion.at(np.arange(n + 1) * dt), M @ system.influence(ground_motion.direction()))
    x = np.zeros(system.n_dof)
    v = np.zeros_like(x)
    a = np.linalg.solve(M, load[0])
    keff = K + gamma / (beta * dt) * C + M / (beta * dt**2)
    out = [x]
    for k in range(1, n + 1):
        rhs = (
            load[k]
            + M @ (x / (beta * dt**2) + v / (beta * dt) + (1 / (2 * beta) - 1) * a)
            + C @ (gamma / (beta * dt) * x + (gamma / beta - 1) * v + dt * (gamma / (2 * beta) - 1) * a)
        )
        xn = np.linalg.solve(keff, rhs)
        an = (xn - x) / (beta * dt**2) - v / (beta * dt) - (1 / (2 * beta) - 1) * a
        v = v + dt * ((1 - gamma) * a + gamma * an)
        x, a = xn, an
        out.append(x)
    return np.array(out).reshape(n + 1, system.n_storeys, 3)


def test_transient_matches_newmark_on_condensed_model(opensees, tmp_path):
    """run_transient on a two-building scene, oblique shaking, per-building Rayleigh damping.

    The same linear Newmark (average acceleration) on pounding's condensed
    M, K and C = a0 M + a1 K must give the same slab histories: condensation
    commutes with Newmark and with stiffness-proportional damping, so the only
    difference is the out-of-plane stiffness (1e-9 here).
    """
    from pounding.peer.opensees import run_transient

    walls = WALL_BUILDING.replace("[0.0, 0.0], [15.0, 0.0], [15.0, 10.0], [0.0, 10.0]", "[20.0, 0.0], [35.0, 0.0], [35.0, 10.0], [20.0, 10.0]")
    walls = walls.replace("start = [0.0,", "start = [20.0,").replace("start = [8.0,", "start = [28.0,").replace("start = [15.0,", "start = [35.0,")
    walls = walls.replace("end = [5.0,", "end = [25.0,").replace("end = [15.0,", "end = [35.0,").replace("end = [12.0,", "end = [32.0,")
    text = '[ground_motion]\nrecord = "elcentro"\npga = 0.3\nangle = 30.0\n' + FRAME_BUILDING + walls
    path = tmp_path / "scene.toml"
    path.write_text(text)
    scene = load_scene(path)
    dt, n = 0.01, 500
    result = run_transient(opensees, scene, scene.ground_motion, dt, n, out_of_plane=1e-9)
    assert set(result) == {"frames", "walls"}
    for building in scene.buildings:
        system = assemble(building)
        a0, a1 = rayleigh_coefficients(building.damping, system.omega, building.name)
        expected = _newmark(system, scene.ground_motion, dt, n, a0, a1)
        got = result[building.name]
        assert got.shape == (n + 1, building.n_storeys, 3)
        scale = np.max(np.abs(expected), axis=(0, 1))  # per DOF kind: m, m, rad
        assert np.all(scale > 0)
        np.testing.assert_array_less(np.max(np.abs(got - expected), axis=(0, 1)), 1e-5 * scale)
