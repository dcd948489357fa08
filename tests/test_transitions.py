"""Compiled transitions against the integrators' definitions (probed steps, scipy's exponential).

* Newmark, HHT and generalized-alpha build their per-mode transition by running ``alpha_step`` on the five
  unit probes (:meth:`pounding.solvers.base.Integrator.transition`). The compiled
  :func:`pounding.solvers.newmark.alpha_transition` performs the same IEEE operations in the same order on
  the same numbers (no fast-math, so no fused or reordered operations): the same transition to the bit.
* ``exact``'s one transition (:func:`pounding.solvers.exact_partial.exact_transition`) against scipy's
  exponential of the augmented system: equal to rounding, with the bound derived in the test. (Its work
  integrals, one implementation too, are checked in tests/test_exact_work.py.)
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.solvers.base import Integrator
from pounding.solvers.exact import Exact
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
def test_exact_transition_is_scipys_exponential_of_the_augmented_system(dt):
    """The exact step is the exponential of the augmented system (Van Loan): in tau = t / dt, with
    y = (q / dt, q') and the load u = dt p rising linearly by du, d(y, u, du)/dtau = M (y, u, du),
    M = [[0, 1, 0, 0], [-s^2, -2 zeta s, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]], s = omega dt, all entries
    O(1) for s <= 4. scipy.linalg.expm (Pade with scaling and squaring) gives exp(M) independently of
    the integrator's two routes (a Taylor series below s = 1/2, the closed form above). Both are exact
    to a few ulps of their O(1) entries before squarings (||M||_1 <= 1 + 16 + 24 = 41: at most 6 of
    expm's, 3 of the Taylor route's), each at most doubling the relative error: bound 2 x 20 x 2^6 eps
    of each mode's largest entry (measured: at most 180 eps)."""
    from scipy.linalg import expm

    omega, zeta = _modes()
    keep = omega * dt <= 4.0
    omega, zeta = omega[keep], zeta[keep]
    tr = Exact().transition(omega, zeta, dt)
    for i in range(omega.size):
        s = omega[i] * dt
        E = expm(np.array([[0.0, 1.0, 0.0, 0.0], [-s * s, -2.0 * zeta[i] * s, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [0.0] * 4]))
        # from (q0, q'0, p0, p1): y0 = (q0 / dt, q'0), u0 = dt p0, du = dt (p1 - p0)
        ref = np.array([E[0, 0], E[0, 1], E[1, 0], E[1, 1], E[0, 2] - E[0, 3], E[0, 3], E[1, 2] - E[1, 3], E[1, 3]])
        A, B = tr.A[i], tr.B[i]
        got = np.array([A[0, 0], A[0, 1] / dt, A[1, 0] * dt, A[1, 1], B[0, 0] / dt**2, B[0, 1] / dt**2, B[1, 0] / dt, B[1, 1] / dt])
        assert np.all(np.abs(got - ref) <= 2 * 20 * 64 * EPS * np.max(np.abs(ref))), (s, zeta[i])
