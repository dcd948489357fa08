"""Assembly of a building over slab DOFs, against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.model.assembly import assemble
from pounding.io.scene import parse_scene

E = 30e9


def square_building(n=1, *, angle=0.0, side=8.0, heights=None, mass=60000.0, x_frames=(0.0, 8.0), y_frames=(0.0, 8.0), rigid=True, centre=(4.0, 4.0)):
    """A square building rotated by ``angle`` [deg] about ``centre``, two-column frames on its sides."""
    heights = heights or [3.0] * n
    a = np.deg2rad(angle)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    c = np.asarray(centre)

    def rot(p):
        return (c + R @ (np.asarray(p, float) - c)).tolist()

    col = {"E": E, "A": 0.25 * (1e6 if rigid else 1.0), "I": 0.25**2 / 12 * 0.25 / 0.25 * 0.25}
    beam = {"E": E, "A": 0.2, "I": (1e6 if rigid else 1.0) * 0.3 * 0.6**3 / 12}
    els = []
    for y in x_frames:
        els.append({"type": "frame", "start": rot([0.0, y]), "angle": angle, "columns": [0.0, side], "column": col, "beam": beam})
    for x in y_frames:
        els.append({"type": "frame", "start": rot([x, 0.0]), "angle": angle + 90.0, "columns": [0.0, side], "column": col, "beam": beam})
    slab = [rot(p) for p in ([0, 0], [side, 0], [side, side], [0, side])]
    return {"name": "sq", "storey_heights": heights, "slab": slab, "mass": mass, "element": els}


def build(table):
    return parse_scene({"building": [table]}).buildings[0]


def test_uniform_shear_building_frequencies():
    """N equal storeys (stiffness k, mass m) with rigid beams: omega_j = 2 sqrt(k/m) sin((2j - 1) pi / (2 (2N + 1))).

    Members 1e6 times stiffer axially and in the beams than the columns in bending
    leave ~1e-6 of flexibility the closed form does not have: rtol 1e-5.
    """
    N = 5
    sys_ = assemble(build(square_building(N)))
    col_I = 0.25**2 / 12 * 0.25
    k = 2 * 2 * 12 * E * col_I / 3.0**3  # two x-frames, two columns each, fixed-fixed
    m = 60000.0
    j = np.arange(1, N + 1)
    expected = 2 * np.sqrt(k / m) * np.sin((2 * j - 1) * np.pi / (2 * (2 * N + 1)))
    # the layout is the same along x and y and symmetric: translational modes come in x/y pairs
    translational = [i for i in range(3 * N) if np.abs(sys_.modes[2::3, i]).max() < 1e-9]
    got = np.sort(sys_.omega[translational])
    assert got == pytest.approx(np.repeat(expected, 2), rel=1e-5)


def test_frame_at_an_angle_gives_the_rotated_stiffness():
    """Rotating the whole building by theta about its centre of mass turns K into G K G^T,
    G = diag(R(theta), 1) per floor (rotation DOFs are invariant)."""
    theta = 27.0
    K0 = assemble(build(square_building(2, x_frames=(0.0, 3.0), y_frames=(1.0, 8.0)))).K
    K1 = assemble(build(square_building(2, angle=theta, x_frames=(0.0, 3.0), y_frames=(1.0, 8.0)))).K
    a = np.deg2rad(theta)
    g = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1.0]])
    G = np.kron(np.eye(2), g)
    assert np.allclose(K1, G @ K0 @ G.T, rtol=0, atol=1e-9 * np.abs(K0).max())


def test_symmetric_building_has_uncoupled_torsion():
    """A doubly symmetric layout: no coupling between translations and rotation in K, and pure modes."""
    sys_ = assemble(build(square_building(3, rigid=False)))
    K = sys_.K
    scale = np.abs(K).max()
    for f in range(3):
        for g in range(3):
            assert abs(K[3 * f, 3 * g + 2]) < 1e-12 * scale
            assert abs(K[3 * f + 1, 3 * g + 2]) < 1e-12 * scale
    # every mode is a pure translation (any mix of x and y: they share frequencies) or a pure rotation
    R = 4.0 * np.sqrt(2)  # the slab's radius turns rotations into displacements at its corners
    for i in range(9):
        phi = sys_.modes[:, i].reshape(3, 3)
        trans, rot = np.abs(phi[:, :2]).max(), R * np.abs(phi[:, 2]).max()
        assert min(trans, rot) < 1e-9 * max(trans, rot)


def test_eccentric_stiffness_couples_translation_and_torsion():
    """Moving one y-frame inward makes the centre of rigidity leave the centre of mass: e_x != 0."""
    sys_ = assemble(build(square_building(1, y_frames=(0.0, 4.0))))
    cr = sys_.centres_of_rigidity()[0]
    # the two equal y-frames sit at x = 0 and x = 4, so the centre of rigidity is at x = 2 (closed form)
    assert cr[0] == pytest.approx(2.0, rel=1e-9)
    assert cr[1] == pytest.approx(4.0, rel=1e-9)


def test_modes_are_mass_normalised_and_periods_sorted():
    """Phi^T M Phi = I, Phi^T K Phi = diag(omega^2), periods descending."""
    s = assemble(build(square_building(3, y_frames=(0.0, 5.0), rigid=False)))
    assert np.allclose(s.modes.T @ s.M @ s.modes, np.eye(9), atol=1e-12)
    assert np.allclose(s.modes.T @ s.K @ s.modes, np.diag(s.omega**2), rtol=0, atol=1e-9 * s.omega.max() ** 2)
    assert np.all(np.diff(s.periods) <= 0)


def test_rayleigh_damping_gives_the_ratio_at_modes_1_and_3():
    """Default damping: 5 % Rayleigh on modes 1 and 3, and C = a0 M + a1 K."""
    from pounding.framework.model.assembly import rayleigh_coefficients

    b = build(square_building(3, y_frames=(0.0, 5.0), rigid=False))
    s = assemble(b)
    assert s.zeta[0] == pytest.approx(0.05, rel=1e-12) and s.zeta[2] == pytest.approx(0.05, rel=1e-12)
    a0, a1 = rayleigh_coefficients(b.damping, s.omega, b.name)
    assert np.allclose(s.C, a0 * s.M + a1 * s.K, rtol=0, atol=1e-9 * np.abs(a1 * s.K).max())


@pytest.mark.parametrize(
    "damping, check",
    [
        ({"type": "modal", "ratio": 0.03}, lambda z, w: np.allclose(z, 0.03)),
        ({"type": "stiffness", "ratio": 0.02, "modes": [1]}, lambda z, w: np.allclose(z, 0.02 * w / w[0])),
        ({"type": "rayleigh", "ratio": 0.04, "periods": [1.0, 0.1]}, lambda z, w: True),
    ],
)
def test_other_damping_models(damping, check):
    """Modal ratios are as given; stiffness-proportional damping grows as omega; periods form accepted."""
    t = square_building(3, y_frames=(0.0, 5.0), rigid=False)
    t["damping"] = damping
    s = assemble(build(t))
    assert check(s.zeta, s.omega)
    if "periods" in damping:
        w1, w2 = 2 * np.pi / 1.0, 2 * np.pi / 0.1
        a0, a1 = 2 * 0.04 * w1 * w2 / (w1 + w2), 2 * 0.04 / (w1 + w2)
        assert np.allclose(s.zeta, a0 / (2 * s.omega) + a1 * s.omega / 2, rtol=1e-12)
