"""The compiled Hermite extremes of the true peaks (pounding.framework.engine.peaks.hermite_extremes).

The extreme of |y| of a cubic Hermite over a step is closed form: the step ends and the roots in (0, 1)
of y'(s) (a quadratic). The compiled loop evaluates it element by element with the operations of the
vectorised numpy form (kept for runs without numba), so both give the same numbers to the bit: IEEE
additions, products, divisions and square roots are correctly rounded, with no fast-math reordering.
"""

from __future__ import annotations

import numpy as np

from pounding.framework.engine import peaks as pk


def test_the_parabola_s_one_minus_s_peaks_at_a_quarter_mid_step():
    """y(s) = s (1 - s): y0 = y1 = 0, slopes m0 = 1, m1 = -1; max |y| = 1/4 at s = 1/2 (exact in binary)."""
    best, where = pk.hermite_extremes(np.array([0.0]), np.array([0.0]), np.array([1.0]), np.array([-1.0]))
    assert best[0] == 0.25 and where[0] == 0.5


def test_compiled_extremes_equal_the_numpy_form_to_the_bit():
    """Random cubics, with the special cases of the formula mixed in (equal ends, opposite slopes, zero
    start slope): values and fractions identical, for |y| and for signed y."""
    rng = np.random.default_rng(0)
    y0, y1, m0, m1 = (rng.normal(size=(4000, 5)) for _ in range(4))
    m1[::3] = -m0[::3]
    y1[::5] = y0[::5]
    m0[::7] = 0.0
    for signed in (False, True):
        best, where = pk.hermite_extremes(y0, y1, m0, m1, signed)
        ref_best, ref_where = pk._hermite_extremes_numpy(y0, y1, m0, m1, signed)
        assert best.tobytes() == ref_best.tobytes()
        assert where.tobytes() == ref_where.tobytes()
