"""Compiled transitions and work integrals against the integrators' numpy definitions.

* Newmark, HHT and generalized-alpha build their per-mode transition by running ``alpha_step`` on the five
  unit probes (:meth:`pounding.solvers.base.Integrator.transition`). The compiled
  :func:`pounding.solvers.newmark.alpha_transition` performs the same IEEE operations in the same order on
  the same numbers (no fast-math, so no fused or reordered operations): the same transition to the bit.
* ``exact`` gives the crossing locator's one-off step lengths a compiled transition and compiled work
  integrals (:mod:`pounding.solvers.exact_partial`), the same mathematics summed in another order: equal
  to rounding, with the bounds derived in each test.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.solvers.base import Integrator
from pounding.solvers.exact import Exact
from pounding.solvers.exact_work import work_maps
from pounding.solvers.generalized_alpha import GeneralizedAlpha
from pounding.solvers.hht import HHT
from pounding.solvers.newmark import Newmark

EPS = float(np.finfo(float).eps)


def _modes(seed=3, n=300):
    """Frequencies over seven decades (a rigid-body mode included) and damping ratios up to 3."""
    rng = np.random.default_rng(seed)
    omega = np.concatenate([[0.0], 10 ** rng.uniform(-3, 4, n)])
    zeta = rng.uniform(0.0, 3.0, omega.size)
    zeta[: n // 4] = 0.05
    return omega, zeta


@pytest.mark.parametrize("integrator", [Newmark(), HHT(), HHT(alpha=-1.0 / 3.0), GeneralizedAlpha(), GeneralizedAlpha(rho_inf=0.0)],
                         ids=lambda i: f"{i.name}{vars(i)}")
@pytest.mark.parametrize("dt", [1e-5, 0.0025, 0.0137, 0.02, 0.5])
def test_alpha_family_transition_is_the_probed_one_to_the_bit(integrator, dt):
    """Compiled transition == alpha_step on unit probes, bit for bit (signed zeros included)."""
    omega, zeta = _modes()
    fast = integrator.transition(omega, zeta, dt)
    probed = Integrator.transition(integrator, omega, zeta, dt)
    assert fast.A.tobytes() == probed.A.tobytes()
    assert fast.B.tobytes() == probed.B.tobytes()


def test_a_subclass_with_its_own_step_is_probed():
    """The compiled shortcut is taken only for the step it reproduces: a subclass's own step is probed."""
    class Damped(Newmark):
        def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
            q1, v1, a1 = super().step(q, qd, qdd, p0, p1, omega, zeta, dt)
            return q1, 0.5 * v1, a1

    omega, zeta = _modes(n=20)
    tr = Damped().transition(omega, zeta, 0.01)
    assert np.array_equal(tr.A[:, 1], 0.5 * Newmark().transition(omega, zeta, 0.01).A[:, 1])


@pytest.mark.parametrize("dt", [1e-6, 1e-4, 0.0025, 0.01, 0.0137, 0.3])
def test_exact_partial_transition_equals_transition_to_rounding(dt):
    """Both build the same maps: for omega dt > 1/2 the same closed form (same operations), for omega dt <=
    1/2 the exponential of the 4x4 augmented matrix M (||M||_1 <= 1 + 2 zeta omega dt <= 4, scaled by 2^-j,
    j <= 3) by 20 Taylor terms and j squarings, in another summation order. Each Taylor sum is exact to a
    few ulps of its O(1) entries, and each squaring at most doubles the relative error, so the two agree
    within 2 x 20 x 2^3 eps ~ 3.6e-14 of the scale of the (q, q') rows of the maps (scaled by kappa:
    A[0, 1] kappa, A[1, 0] / kappa, B / dt with kappa = 1/dt or omega). The acceleration row follows from
    equilibrium, -omega^2 row0 - 2 zeta omega row1, and inherits those errors times its factors."""
    omega, zeta = _modes()
    omega = omega[1:]  # the small route handles omega = 0 too; kappa scaling below needs omega > 0
    zeta = zeta[1:]
    ex = Exact()
    ref, fast = ex.transition(omega, zeta, dt), ex.partial_transition(omega, zeta, dt)
    s = omega * dt
    kappa = np.where(s <= 0.5, 1.0 / dt, omega)
    bound = 2 * 20 * 8 * EPS

    def scaled(tr):  # the maps of y = (kappa q, q') and u = dt p: O(1) entries
        A, B = tr.A, tr.B
        return np.stack([A[:, 0, 0], A[:, 0, 1] * kappa, A[:, 1, 0] / kappa, A[:, 1, 1],
                         B[:, 0, 0] * kappa / dt, B[:, 0, 1] * kappa / dt, B[:, 1, 0] / dt, B[:, 1, 1] / dt], axis=1)

    R, F = scaled(ref), scaled(fast)
    scale = np.max(np.abs(R), axis=1)
    assert np.all(np.abs(R - F) <= bound * scale[:, None])
    # the acceleration row: -omega^2 (row q) - 2 zeta omega (row q'), with the rows' bounds unscaled, plus
    # the rounding of that combination itself
    c, k = 2.0 * zeta * omega, omega * omega
    dq = bound * scale[:, None] * np.stack([np.ones_like(kappa), 1.0 / kappa], axis=1)  # |d A[0, :2]|
    dv = bound * scale[:, None] * np.stack([kappa, np.ones_like(kappa)], axis=1)  # |d A[1, :2]|
    tol = k[:, None] * dq + c[:, None] * dv + 4 * EPS * (k[:, None] * np.abs(ref.A[:, 0, :2]) + c[:, None] * np.abs(ref.A[:, 1, :2]))
    assert np.all(np.abs(ref.A[:, 2, :2] - fast.A[:, 2, :2]) <= tol)


@pytest.mark.parametrize("dt", [1e-6, 1e-4, 0.0025, 0.01, 0.0137, 0.3])
def test_exact_partial_work_maps_equal_work_maps_to_rounding(dt):
    """Regime (A) of the work integrals (omega h <= max(3, 1.5 zeta)) is summed from the Taylor series of
    the blocks of Van Loan's exponentials instead of the exponentials of the 8x8 and 12x12 block
    matrices; both are exact to ~1e-15 of each map's natural (Cauchy-Schwarz) scale on the scaled interval
    (||t0 F||_1 <= 1, 21 terms: truncation < 1/21!), and k <= 4 doubling steps, each a sum of products of
    bounded factors, add a few ulps each. Bound: 100 eps of the largest entry of each mode's map
    (exact_work states 3e-14 for its own accuracy). Modes of regime (B) are the numpy maps themselves."""
    omega, zeta = _modes()
    omega, zeta = omega[1:], zeta[1:]
    ex = Exact()
    ref = work_maps(omega, zeta, dt)
    fast = ex.partial_work_maps(omega, zeta, dt)
    for R, F in zip(ref, fast):
        axes = tuple(range(1, R.ndim))
        scale = np.max(np.abs(R), axis=axes, keepdims=True)
        assert np.all(np.abs(R - F) <= 100 * EPS * scale)
