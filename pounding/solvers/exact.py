"""Exact integration of each mode under a load linear in the step.

The unit-mass oscillator ``q'' + 2 zeta omega q' + omega**2 q = p(t)`` with
``p`` linear between ``p0`` and ``p1`` has a closed-form solution
(Nigam & Jennings, 1969, Bull. Seismol. Soc. Am. 59, 909-922). Written
naively its coefficients cancel catastrophically for small ``omega dt``;
written as matrix exponentials they do not, so each mode takes one of two
routes, both accurate to ~1e-14 of the natural scale of each entry
(checked against 50-digit arithmetic for ``omega dt`` in [1e-4, 1e4],
``zeta`` in [0, 10]):

* ``omega dt <= 1/2``: the exponential (scaling and squaring, Taylor) of a 4x4 augmented matrix
  (Van Loan, 1978, IEEE Trans. Autom. Control 23, 395-404). Its norm is
  small, so no squaring is needed and rounding stays at the ulp level.
* ``omega dt > 1/2``: the closed form of ``exp(F)``, ``F = omega dt [[0, 1],
  [-1, -2 zeta]]``, and the load responses ``F^-1 (exp(F) - I)`` and
  ``F^-2 (exp(F) - I - F)``. There ``expm`` would square many times and lose
  up to 1e-12 on lightly damped modes; the closed form loses nothing.
"""

from __future__ import annotations

import numpy as np

from pounding.solvers.base import Integrator, Transition

_SPLIT = 0.5  # omega dt at which the closed form takes over from expm


def _expm_batched(M):
    """exp of a stack of small matrices (n, k, k) by scaling and squaring with a Taylor series.

    The matrices are scaled by 2**-j until their 1-norm is <= 1/2; 20 Taylor
    terms then leave a truncation below 0.5**21/21! ~ 1e-26 relative, and j
    squarings restore the exponential. Vectorised over the stack, so a
    root finder's trial step sizes cost microseconds instead of one
    scipy.linalg.expm call per batch.
    """
    norm = float(np.max(np.sum(np.abs(M), axis=1))) if M.size else 0.0
    j = max(0, int(np.ceil(np.log2(norm / 0.5)))) if norm > 0.5 else 0
    A = M / 2.0**j
    E = np.broadcast_to(np.eye(M.shape[-1]), M.shape).copy()
    term = E.copy()
    for k in range(1, 21):
        term = term @ A / k
        E += term
    for _ in range(j):
        E = E @ E
    return E


def _small(s, zeta):
    """Scaled one-step maps for ``s = omega dt <= 1/2``.

    In ``tau = t/dt`` with ``y = (q/dt, q')`` and ``u = dt p = u0 + tau du``,
    ``d/dtau (y, u, du) = M (y, u, du)`` with
    ``M = [[0, 1, 0, 0], [-s**2, -2 zeta s, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]``,
    all entries O(1) (valid also for ``omega = 0``).
    """
    M = np.zeros((s.shape[0], 4, 4))
    M[:, 0, 1] = 1.0
    M[:, 1, 0] = -s * s
    M[:, 1, 1] = -2.0 * zeta * s
    M[:, 1, 2] = 1.0
    M[:, 2, 3] = 1.0
    E = _expm_batched(M)
    ramp = E[:, :2, 3]  # response to u rising 0 -> 1
    return E[:, :2, :2], np.stack([E[:, :2, 2] - ramp, ramp], axis=2)


def _large(s, zeta):
    """Scaled one-step maps for ``s = omega dt > 1/2``, in closed form.

    With ``y = (omega q, q')`` and ``tau = t/dt``, ``y' = F y + (0, u)``,
    ``F = s (-zeta I + K)``, ``K = [[zeta, 1], [-1, -zeta]]``,
    ``K**2 = (zeta**2 - 1) I``, so ``exp(F) = C I + S K`` with
    ``C = e^(-zeta s) cosh(r s)``, ``S = e^(-zeta s) sinh(r s)/r``,
    ``r = sqrt(zeta**2 - 1)`` (cos/sin with ``sqrt(1 - zeta**2)`` below critical).
    """
    n = s.shape[0]
    C = np.empty(n)
    S = np.empty(n)
    d = zeta * zeta - 1.0
    r = np.sqrt(np.abs(d))
    x = r * s
    under = d < 0.0
    # Underdamped: S = e^(-zeta s) s sin(x)/x, continuous at critical damping
    # (x > 0 here; np.sinc would round x/pi and lose ~x*eps in the phase).
    e = np.exp(-zeta[under] * s[under])
    xu = x[under]
    C[under] = e * np.cos(xu)
    S[under] = e * s[under] * (np.sin(xu) / xu)
    # Overdamped, well apart from critical: separate exponentials (no overflow;
    # zeta - r written as 1/(zeta + r) to avoid cancellation at large zeta).
    far = ~under & (x > 1.0)
    slow = np.exp(-s[far] / (zeta[far] + r[far]))
    fast = np.exp(-(zeta[far] + r[far]) * s[far])
    C[far] = 0.5 * (slow + fast)
    S[far] = 0.5 * (slow - fast) / r[far]
    # Overdamped near critical: sinh(x)/x -> 1 without cancellation.
    near = ~under & ~far
    e = np.exp(-zeta[near] * s[near])
    xn = x[near]
    C[near] = e * np.cosh(xn)
    S[near] = e * s[near] * np.where(xn > 0.0, np.sinh(xn) / np.where(xn > 0.0, xn, 1.0), 1.0)

    phi = np.empty((n, 2, 2))
    phi[:, 0, 0] = C + zeta * S
    phi[:, 0, 1] = S
    phi[:, 1, 0] = -S
    phi[:, 1, 1] = C - zeta * S
    # F^-1 = [[-2 zeta, -1], [1, 0]]/s; g = (0, 1) is where u enters.
    step0 = (1.0 - C - zeta * S) / s  # F^-1 (exp(F) - I) g: response to constant u = 1
    step1 = S / s
    ramp0 = (1.0 - step1 - 2.0 * zeta * step0) / s  # F^-1 (step - g): response to u = tau
    ramp1 = step0 / s
    gamma = np.empty((n, 2, 2))
    gamma[:, 0, 0] = step0 - ramp0
    gamma[:, 1, 0] = step1 - ramp1
    gamma[:, 0, 1] = ramp0
    gamma[:, 1, 1] = ramp1
    return phi, gamma


class Exact(Integrator):
    """Free of integration error for piecewise-linear modal loads.

    ``(q, q')`` at the end of the step is the exact solution; ``q''`` at the
    end follows from equilibrium, ``q''1 = p1 - 2 zeta omega q'1 - omega**2 q1``,
    so the start acceleration is not an input (its column of ``A`` is zero).
    ``order`` is 2 because a sampled record is followed to second order by
    its linear interpolation.
    """

    name = "exact"
    order = 2
    # Only when work_maps cannot serve (a mode with omega = 0): 4 Gauss points on the exact
    # trajectory integrate the work to ~(omega dt)^8 / 1e9 relative per step.
    energy_nodes = 4
    exact_within_step = True

    def work_maps(self, omega, zeta, dt):
        """Exact work integrals of a step on the exact trajectory, for the energy audit.

        Returns a1, a2 (n, 4) and M (n, 4, 4): for x = (q0, q'0, p0, p1),
        int q' ds = a1 x, int s q' ds = a2 x, int q'^2 ds = x M x over the step
        (:func:`pounding.solvers.exact_work.work_maps`; to ~1e-14 of their scale for
        omega dt up to 1e5 and zeta up to 10, also at critical damping).
        """
        from pounding.solvers.exact_work import work_maps

        return work_maps(np.asarray(omega, dtype=float), np.asarray(zeta, dtype=float), float(dt))

    def partial_transition(self, omega, zeta, dt):
        """:meth:`transition` compiled mode by mode (:func:`pounding.solvers.exact_partial.exact_transition`;
        equal to rounding), for the crossing locator's one-off step lengths."""
        from pounding.compiler import Kernel
        from pounding.solvers.exact_partial import exact_transition

        if not isinstance(exact_transition, Kernel):  # without numba the numpy form is the fast one
            return self.transition(omega, zeta, dt)
        omega, zeta = _modes_flat(omega, zeta)
        A, B = exact_transition(omega, zeta, float(dt))
        return Transition(A=A, B=B, dt=float(dt))

    def search_maps(self):
        """(:func:`pounding.solvers.exact_partial.exact_maps`, no parameters): the compiled
        :meth:`partial_transition`; None without the compiler."""
        from pounding.compiler import Kernel
        from pounding.solvers.exact_partial import exact_maps

        return (exact_maps, np.zeros(0)) if isinstance(exact_maps, Kernel) else None

    def partial_work_maps(self, omega, zeta, dt):
        """:meth:`work_maps` compiled mode by mode in its regime (A) (:func:`pounding.solvers.exact_partial.work_maps_small`;
        equal to rounding), the other modes by :meth:`work_maps`."""
        from pounding.compiler import Kernel
        from pounding.solvers.exact_partial import work_maps_small

        omega, zeta = _modes_flat(omega, zeta)
        if not isinstance(work_maps_small, Kernel) or not (dt > 0 and np.all(omega > 0) and np.all(zeta >= 0)):
            return self.work_maps(omega, zeta, dt)
        n = omega.shape[0]
        a1, a2, M = np.zeros((n, 4)), np.zeros((n, 4)), np.zeros((n, 4, 4))
        done = np.zeros(n, dtype=np.bool_)
        work_maps_small(omega, zeta, float(dt), a1, a2, M, done)
        if not done.all():
            rest = ~done
            a1[rest], a2[rest], M[rest] = self.work_maps(omega[rest], zeta[rest], dt)
        return a1, a2, M

    def transition(self, omega, zeta, dt):
        omega = np.asarray(omega, dtype=float).reshape(-1)
        zeta = np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape)
        dt = float(dt)
        n = omega.shape[0]
        s = omega * dt
        # Both routes work with y = (kappa q, q') and the load as u = dt p.
        phi = np.broadcast_to(np.eye(2), (n, 2, 2)).copy()  # dt = 0: identity
        gamma = np.zeros((n, 2, 2))
        kappa = np.ones(n)
        small = (s <= _SPLIT) & (dt > 0.0)
        if small.any():
            phi[small], gamma[small] = _small(s[small], zeta[small])
            kappa[small] = 1.0 / dt
        large = s > _SPLIT
        if large.any():
            phi[large], gamma[large] = _large(s[large], zeta[large])
            kappa[large] = omega[large]

        A = np.zeros((n, 3, 3))
        B = np.zeros((n, 3, 2))
        A[:, 0, 0] = phi[:, 0, 0]
        A[:, 0, 1] = phi[:, 0, 1] / kappa
        A[:, 1, 0] = phi[:, 1, 0] * kappa
        A[:, 1, 1] = phi[:, 1, 1]
        B[:, 0, :] = gamma[:, 0, :] * (dt / kappa)[:, None]
        B[:, 1, :] = gamma[:, 1, :] * dt
        # End acceleration from equilibrium at the end of the step.
        c = (2.0 * zeta * omega)[:, None]
        k = (omega * omega)[:, None]
        A[:, 2, :] = -k * A[:, 0, :] - c * A[:, 1, :]
        B[:, 2, :] = -k * B[:, 0, :] - c * B[:, 1, :]
        B[:, 2, 1] += 1.0
        return Transition(A=A, B=B, dt=dt)

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        omega = np.asarray(omega, dtype=float)
        zeta = np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape)
        tr = self.transition(omega.reshape(-1), zeta.reshape(-1), dt)
        z = np.stack(np.broadcast_arrays(q, qd, qdd), axis=1)  # (n, 3) or (n, 3, k)
        u = np.stack(np.broadcast_arrays(p0, p1), axis=1)  # (n, 2) or (n, 2, k)
        z1 = np.einsum("nij,nj...->ni...", tr.A, z) + np.einsum("nij,nj...->ni...", tr.B, u)
        return z1[:, 0], z1[:, 1], z1[:, 2]


def _modes_flat(omega, zeta):
    """omega, zeta as writable contiguous float arrays (n,) for the compiled one-off maps (one argument
    type, so one compilation); the driver's (:class:`pounding.solvers.base.TransitionCache`) already
    are, and pass through untouched: these maps are built a few times per contact event."""
    if (type(omega) is np.ndarray and type(zeta) is np.ndarray and omega.ndim == 1 and omega.shape == zeta.shape
            and omega.dtype == np.float64 and zeta.dtype == np.float64 and omega.flags.c_contiguous and zeta.flags.c_contiguous
            and omega.flags.writeable and zeta.flags.writeable):
        return omega, zeta
    omega = np.array(omega, dtype=float).reshape(-1)
    return omega, np.array(np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape))
