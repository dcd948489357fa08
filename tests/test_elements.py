"""Planar elements against closed forms.

Frames are checked with near-rigid members where the closed form assumes
rigidity: with areas and beam inertias 1e6 times the real ones, the neglected
flexibility is ~1e-6 of the total, so those comparisons use rtol = 1e-5.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.elements.frame import Frame, condense
from pounding.elements.shear_wall import ShearWall
from tests.rounding import solve_rel

E, H = 30e9, 3.2
COL = {"E": E, "b": 0.4, "h": 0.5}
I_COL = 0.4 * 0.5**3 / 12
RIGID = 1e6


def frame(columns, heights, column, beam=None, angle=0.0, start=(0.0, 0.0)):
    table = {"start": list(start), "angle": angle, "columns": columns, "column": column}
    if beam is not None:
        table["beam"] = beam
    return Frame.from_table(table, storey_heights=heights)


def test_cantilever_column_is_3EI_over_h3():
    """A single column fixed at the base and free to rotate at the top: k = 3 E I / h^3."""
    k = frame([0.0], [H], COL).lateral_stiffness()
    # condensation by a Cholesky solve of the column's end rotations and axial DOF: n eps cond ~ 1e-13
    # (cond(K_oo) ~ A h^2 / I ~ 1e2 for this column), so 1e-12 bounds it on any LAPACK
    assert k[0, 0] == pytest.approx(3 * E * I_COL / H**3, rel=1e-12)


def test_fixed_fixed_column_is_12EI_over_h3():
    """Two columns under a rigid beam (rotation restrained at both ends): k = 2 x 12 E I / h^3."""
    col = {"E": E, "A": 0.2 * RIGID, "I": I_COL}
    beam = {"E": E, "A": 0.2, "I": I_COL * RIGID}
    k = frame([0.0, 6.0], [H], col, beam).lateral_stiffness()
    assert k[0, 0] == pytest.approx(2 * 12 * E * I_COL / H**3, rel=1e-5)


@pytest.mark.parametrize("ib_over_ic", [0.25, 1.0, 4.0])
def test_portal_frame_with_flexible_beam(ib_over_ic):
    """Chopra, Dynamics of Structures, eq. (1.3.5): k = 24 E Ic / h^3 (12 rho + 1) / (12 rho + 4),
    rho = (E Ib / L) / (2 E Ic / h) = Ib h / (2 Ic L), for axially rigid members."""
    L = 6.0
    col = {"E": E, "A": 0.2 * RIGID, "I": I_COL}
    beam = {"E": E, "A": 0.2, "I": I_COL * ib_over_ic}
    k = frame([0.0, L], [H], col, beam).lateral_stiffness()[0, 0]
    rho = ib_over_ic * H / (2 * L)
    assert k == pytest.approx(24 * E * I_COL / H**3 * (12 * rho + 1) / (12 * rho + 4), rel=1e-5)


def test_frame_stiffness_is_symmetric_positive_definite():
    """Any stable frame gives a symmetric positive-definite condensed stiffness."""
    k = frame([0.0, 5.0, 11.0], [4.0, 3.2, 3.2, 3.0], COL, {"E": E, "b": 0.3, "h": 0.6}).lateral_stiffness()
    assert np.allclose(k, k.T, rtol=0, atol=1e-9 * np.abs(k).max())
    assert np.all(np.linalg.eigvalsh(k) > 0)


def test_condense_matches_schur_complement():
    """Static condensation equals K_ll - K_lo K_oo^-1 K_ol computed with a dense inverse."""
    rng = np.random.default_rng(1)
    a = rng.normal(size=(6, 6))
    K = a @ a.T + 6 * np.eye(6)
    expected = K[:2, :2] - K[:2, 2:] @ np.linalg.inv(K[2:, 2:]) @ K[2:, :2]
    # a Cholesky solve against a LU inverse: each within n eps cond(K_oo) of K_oo^-1 (rounding.solve_rel),
    # times the size of the product it enters (|K| max squared over K_oo's smallest eigenvalue <= |K|)
    tol = 2 * solve_rel(K[2:, 2:]) * np.abs(K).max()
    assert np.allclose(condense(K, 2), expected, rtol=0, atol=tol)


def wall(heights, **kw):
    table = {"start": [0.0, 0.0], "end": [4.0, 0.0], "thickness": 0.25, "E": E, "nu": 0.2, **kw}
    return ShearWall.from_table(table, storey_heights=heights)


def test_timoshenko_cantilever_tip_flexibility():
    """Tip flexibility of a cantilever wall: h^3 / (3 E I) + h / (G A_s), A_s = 5/6 t L, I = t L^3 / 12."""
    heights = [3.0, 3.0, 3.0, 3.0]
    w = wall(heights)
    Htot, t, L = 12.0, 0.25, 4.0
    G = E / (2 * 1.2)
    expected = Htot**3 / (3 * E * t * L**3 / 12) + Htot / (G * 5 / 6 * t * L)
    flex = np.linalg.inv(w.lateral_stiffness())
    # the model is exact for Timoshenko members; what is left is the inverse's rounding, n eps cond(K)
    # (rounding.solve_rel: 3e-12 here, the storey stiffnesses of a slender wall differ widely)
    assert flex[-1, -1] == pytest.approx(expected, rel=solve_rel(w.lateral_stiffness()))


def test_wall_shear_area_can_be_given():
    """A given shear area replaces 5/6 of the gross area in the shear term."""
    w = wall([3.0], shear_area=0.5)
    G = E / 2.4
    expected = 27.0 / (3 * E * 0.25 * 64 / 12) + 3.0 / (G * 0.5)
    # one storey: a 1 x 1 inverse is one division; the formulas a few ulps each: 1e-12 is far above
    assert np.linalg.inv(w.lateral_stiffness())[0, 0] == pytest.approx(expected, rel=1e-12)
