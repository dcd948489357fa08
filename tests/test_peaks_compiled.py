"""The compiled Hermite extremes of the true peaks (pounding.framework.engine.peaks.hermite_extremes).

The extreme of |y| of a cubic Hermite over a step is closed form: the step ends and the roots in (0, 1)
of y'(s) (a quadratic). One function computes it, compiled or (without numba) the same loop as Python.
"""

from __future__ import annotations

import numpy as np

from pounding.framework.engine import peaks as pk


def test_the_parabola_s_one_minus_s_peaks_at_a_quarter_mid_step():
    """y(s) = s (1 - s): y0 = y1 = 0, slopes m0 = 1, m1 = -1; max |y| = 1/4 at s = 1/2 (exact in binary)."""
    best, where = pk.hermite_extremes(np.array([0.0]), np.array([0.0]), np.array([1.0]), np.array([-1.0]))
    assert best[0] == 0.25 and where[0] == 0.5


def _hermite(y0, y1, m0, m1, s):
    """The cubic Hermite y(s) on [0, 1] from its end values y0, y1 and end slopes m0, m1 (per unit s)."""
    c2 = 3.0 * (y1 - y0) - 2.0 * m0 - m1
    c3 = 2.0 * (y0 - y1) + m0 + m1
    return y0 + s * (m0 + s * (c2 + s * c3))


def test_the_extremes_bound_the_cubic_and_are_its_value_at_their_fraction():
    """Random cubics, with the special cases of the formula mixed in (equal ends, opposite slopes, zero
    start slope): the extreme is the cubic's value at its fraction, and no point of a fine sampling of
    the step exceeds it. Tolerance: the cubic's evaluation rounds each of its ~10 operations, a few eps
    of the largest term (|y0| + |m0| + |c2| + |c3| bounds them on [0, 1]): 16 eps of that."""
    rng = np.random.default_rng(0)
    y0, y1, m0, m1 = (rng.normal(size=(4000, 5)) for _ in range(4))
    m1[::3] = -m0[::3]
    y1[::5] = y0[::5]
    m0[::7] = 0.0
    scale = np.abs(y0) + np.abs(m0) + np.abs(3.0 * (y1 - y0) - 2.0 * m0 - m1) + np.abs(2.0 * (y0 - y1) + m0 + m1)
    tol = 16 * np.finfo(float).eps * scale
    samples = np.linspace(0.0, 1.0, 401)
    for signed in (False, True):
        mag = (lambda x: x) if signed else np.abs
        best, where = pk.hermite_extremes(y0, y1, m0, m1, signed)
        assert np.all((where >= 0.0) & (where <= 1.0))
        assert np.all(np.abs(best - mag(_hermite(y0, y1, m0, m1, where))) <= tol)
        for s in samples:
            assert np.all(mag(_hermite(y0, y1, m0, m1, s)) <= best + tol)
