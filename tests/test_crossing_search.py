"""The crossing locator's compiled search on a step's cubic Hermite interpolant (pounding.framework.engine.crossing).

The problem. Two symmetric one-storey box buildings side by side along x (the left slab's face at
x = 10 m, the right one's ``GAP`` further), moved by pure x translations u_a, u_b of their slabs: the
clear distance between the parallel faces is g = GAP - u_a + u_b, linear in the modal state. Along the
cubic Hermite interpolant of a step's end displacements and velocities the slabs' translations are the
Hermite cubics of their end values and rates, so the interpolant's gap is the Hermite cubic

    g(s) = g0 + m0 s + c2 s^2 + c3 s^3,  s = x / h,  m = h g',  c2 = 3 (g1 - g0) - 2 m0 - m1,  c3 = 2 (g0 - g1) + m0 + m1

of the end gaps g0, g1 and gap rates g0', g1': its minimum and its zeros are known in closed form.
What is asserted: the compiled minimiser finds that minimum, the compiled zero finder that zero, and the
minimiser is scipy's bounded Brent method (``minimize_scalar(method="bounded")``) step for step.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding import compiler
from pounding.framework.engine import crossing as cr
from pounding.framework.engine.stacked_model import Model
from scenes_for_tests import modal_from_physical, scene, side_by_side

GAP = 0.1  # [m] clear distance at rest
H = 0.01  # [s] the step


@pytest.fixture(scope="module")
def model():
    return Model(scene(side_by_side(GAP, storeys=(1, 1))))


def _ends(model, g0, r0, g1, r1):
    """Interpolant data (q0, v0, q1, v1, h) whose gap has end values g0, g1 [m] and rates r0, r1 [m/s]:
    the left slab still, the right one translated along x by g - GAP."""
    def q(u_right):
        return np.ascontiguousarray(modal_from_physical(model, {(0, 0): (0.0, 0.0, 0.0), (1, 0): (u_right, 0.0, 0.0)}))

    return q(g0 - GAP), q(r0), q(g1 - GAP), q(r1), H


def _cubic(g0, r0, g1, r1):
    m0, m1 = H * r0, H * r1
    c2 = 3.0 * (g1 - g0) - 2.0 * m0 - m1
    c3 = 2.0 * (g0 - g1) + m0 + m1
    return np.polynomial.Polynomial([g0, m0, c2, c3])  # in s = x / H


PLIST = np.array([0], dtype=np.int64)


def test_the_interpolants_gap_is_the_hermite_cubic_of_the_end_gaps(model):
    """The premise: hermite_gap along a step of pure x translations is the cubic of the module docstring.
    Rounding: the modal round trip and the polygon distance, ~1e-16 of the slab coordinates (22 m)."""
    ends = (0.004, -1.0, 0.003, 1.2)
    herm, g = _ends(model, *ends), _cubic(*ends)
    for s in np.linspace(0.0, 1.0, 11):
        assert cr.hermite_gap(*herm, s * H, PLIST, model.geo) == pytest.approx(g(s), abs=1e-13)


def test_bounded_minimum_finds_the_minimum_of_the_cubic(model):
    """A graze: both end gaps positive, closing then opening. The minimum of the cubic is at the root of
    its derivative in (0, 1). Brent's method stops with the bracket within 2 (sqrt(eps) |x| + xatol / 3)
    of x (xatol = 1e-7 h), so |x - x*| <= 3 xatol + 1.5e-8 x* plus the flat bottom's resolution
    sqrt(2 d / g''), d ~ 1e-13 m the gap's rounding; the value is then within g'' / 2 (x - x*)^2 + d of
    the minimum."""
    ends = (0.004, -1.0, 0.003, 1.2)
    herm, g = _ends(model, *ends), _cubic(*ends)
    s_star = [s.real for s in g.deriv().roots() if abs(s.imag) < 1e-12 and 0.0 < s.real < 1.0]
    assert len(s_star) == 1
    x_star = s_star[0] * H
    curvature = g.deriv(2)(s_star[0]) / H**2  # [m/s^2]
    xatol = 1e-7 * H
    x, value = cr.bounded_minimum(*herm, 0.0, H, xatol, PLIST, model.geo)
    resolution = np.sqrt(2.0 * 1e-13 / curvature)
    assert abs(x - x_star) <= 3.0 * xatol + 1.5e-8 * x_star + resolution
    assert value == pytest.approx(g(s_star[0]), abs=0.5 * curvature * (x - x_star) ** 2 + 1e-13)
    assert value < min(ends[0], ends[2])  # it is inside the step, below both ends


def test_bounded_minimum_is_scipys_bounded_brent(model):
    """The minimiser is a port of scipy's ``minimize_scalar(method="bounded")``: run interpreted on the
    same objective (the interpolant's gap), both take the same steps and stop at the same x, to the bit."""
    from scipy.optimize import minimize_scalar

    ends = (0.002, -0.7, 0.0025, 0.4)
    herm = _ends(model, *ends)
    with compiler.interpreted():
        x, value = cr.bounded_minimum.py_func(*herm, 0.0, H, 1e-7 * H, PLIST, model.geo)
        res = minimize_scalar(lambda y: cr.hermite_gap.py_func(*herm, y, PLIST, model.geo), bounds=(0.0, H), method="bounded",
                              options={"xatol": 1e-7 * H})
    assert x == res.x
    assert value == res.fun


def test_hermite_zero_finds_the_first_zero_of_the_cubic(model):
    """A step that ends overlapping: g0 > 0 > g1. The zero finder stops at a point where the gap is within
    eps [m] of zero; the cubic's root x* is then within eps / |g'(x*)| of it (the gap rate is bounded
    away from zero there), plus rounding of the gap (1e-13 m) over the same rate."""
    ends = (0.003, -0.9, -0.004, -1.1)
    herm, g = _ends(model, *ends), _cubic(*ends)
    roots = sorted(s.real for s in g.roots() if abs(s.imag) < 1e-12 and 0.0 < s.real < 1.0)
    assert len(roots) == 1
    x_star = roots[0] * H
    rate = abs(g.deriv()(roots[0]) / H)
    eps = 1e-11
    x = cr.hermite_zero(*herm, 0.0, H, eps, 1e-14, True, PLIST, model.geo)
    assert abs(cr.hermite_gap(*herm, x, PLIST, model.geo)) <= eps
    assert abs(x - x_star) <= (eps + 1e-13) / rate


def test_hermite_search_brackets_the_first_negative_sample_or_returns_the_minimum(model):
    """A graze that dips below zero: the search returns the first of its samples h j / 17 where the cubic
    is below -eps, and its left neighbour; a graze that stays above zero returns the minimiser's x."""
    eps = 1e-11
    dip = (0.001, -1.0, 0.001, 1.0)  # the cubic falls to about -1.5 mm mid-step
    herm, g = _ends(model, *dip), _cubic(*dip)
    found, lo, hi = cr.hermite_search(*herm, dip[0], dip[2], eps, PLIST, model.geo)
    m = cr.GRAZE_SAMPLES
    first = next(j for j in range(1, m + 1) if g(j / (m + 1)) < -eps)
    assert found
    assert hi == pytest.approx(H * first / (m + 1), rel=1e-15)
    assert lo == pytest.approx(H * (first - 1) / (m + 1), rel=1e-15, abs=1e-300)
    above = (0.004, -1.0, 0.003, 1.2)
    herm, g = _ends(model, *above), _cubic(*above)
    found, _, x = cr.hermite_search(*herm, above[0], above[2], eps, PLIST, model.geo)
    s_star = next(s.real for s in g.deriv().roots() if abs(s.imag) < 1e-12 and 0.0 < s.real < 1.0)
    assert not found
    assert abs(x - s_star * H) <= 1e-6 * H
