"""The exact integrator's transition and work integrals, compiled mode by mode.

The crossing locator asks the exact solution at many step lengths that are used once (a root
finder's trials, the two parts of a step split at an impact), besides the grid step. Vectorised
numpy (stacked matrix products, one Python call per array operation) took ~0.2 ms and ~0.6 ms per
step length for the paper pair; here the mathematics runs mode by mode compiled:

* :func:`exact_transition`: the integrator's transition, every step length
  (:meth:`pounding.solvers.exact.Exact.transition`): ``omega dt <= 1/2``, the exponential of the 4x4
  augmented matrix by scaling and squaring (the modes of that route scaled together by the largest
  norm among them, and summed with 16 Taylor terms, or 20 when one of them has zeta omega dt > 1/2:
  :data:`_TRANSITION_TERMS`); above, the closed form of the damped oscillator; then A and B assembled.
* :func:`work_maps_small`: the work integrals of :func:`pounding.solvers.exact_work.work_maps` in its
  regime (A) (``omega h <= max(3, 1.5 zeta)``, time unit h, the 4x4 augmented system), from the scaled
  interval ``t0 = 2**-k`` and ``k`` doubling identities; on ``t0`` the blocks of Van Loan's
  exponentials are summed as their Taylor series directly (Phi = sum X^j / j!, J0 = t0 sum X^j / (j+1)!,
  int (t0 - u) Phi = t0^2 sum X^j / (j+2)!, W = t0 sum_ij R_i^T R_j / (i + j + 1) with R_j = e2^T X^j / j!,
  X = t0 F, ||X||_1 <= 1: 21 terms leave < 1/21! ~ 2e-20) instead of exponentiating the 8x8 and
  12x12 block matrices. It is the one implementation of that regime: ``work_maps`` calls it for
  every step length (the grid's energy audit and contact events' partial steps), and computes the
  modes it leaves (regime (B)) itself.

With the compiler off both run as the same functions in Python.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit

_SPLIT = 0.5  # omega dt at which the closed form takes over from expm (as pounding.solvers.exact)
#: Taylor terms after the first: of the work integrals (||X||_1 <= 1: 1/21! ~ 2e-20), and of the
#: transition's exponential when a mode of the batch has zeta omega dt > 1/2
_TERMS = 20
#: Taylor terms after the first of the transition's exponential when its unscaled 1-norm is <= 2 (every
#: mode of the batch with zeta omega dt <= 1/2, all but the most heavily damped): scaled by 2**j <= 4 to
#: ||M||_1 <= 1/2, the terms left out are < 2.3e-20 in every entry. That is far below an ulp of each
#: entry the maps take: the ramp's, about (1 / scale)^3 / 6 >= 2.6e-3, and the entries that scale with
#: omega dt (every term of theirs carries the factor M[1, 0] = -s^2 / scale, so their error is relative
#: too); the j <= 2 squarings after it each at most double a relative error
_TRANSITION_TERMS = 16


@njit(borrowed=True)
def _matmul4(X, Y, out):
    for i in range(X.shape[0]):
        for j in range(Y.shape[1]):
            acc = 0.0
            for k in range(X.shape[1]):
                acc += X[i, k] * Y[k, j]
            out[i, j] = acc


@njit(borrowed=True)
def _congruence4(W, X, tmp, out):
    """out = X^T W X (4, 4), with tmp = W X: the energy form W carried through the map X."""
    _matmul4(W, X, tmp)
    for r in range(4):
        for c in range(4):
            acc = 0.0
            for m in range(4):
                acc += X[m, r] * tmp[m, c]
            out[r, c] = acc


@njit(borrowed=True)
def _times_f(P, X, out, rows):
    """out[:rows] = (P X)[:rows] for X with the pattern of the augmented oscillator matrix [[0, x01, 0,
    0], [x10, x11, x12, 0], [0, 0, 0, x23], [0, 0, 0, 0]] (its other entries are zero): 5 products a
    row, not 16. From the square on, the last two rows of X's powers are zero: the callers skip
    their sums (adding a zero leaves every sum as it was)."""
    for r in range(rows):
        out[r, 0] = P[r, 1] * X[1, 0]
        out[r, 1] = P[r, 0] * X[0, 1] + P[r, 1] * X[1, 1]
        out[r, 2] = P[r, 1] * X[1, 2]
        out[r, 3] = P[r, 2] * X[2, 3]


@njit
def exact_transition(omega, zeta, dt):
    """Per-mode transition (A (n, 3, 3), B (n, 3, 2)) of the exact integrator for a step of dt [s]
    (:meth:`pounding.solvers.exact.Exact.transition`, compiled; see the module docstring)."""
    n = omega.shape[0]
    A = np.zeros((n, 3, 3))
    B = np.zeros((n, 3, 2))
    # the batch's scaling of the small route: its largest column sum of M
    norm = 0.0
    for i in range(n):
        s = omega[i] * dt
        if s <= _SPLIT and dt > 0.0:
            norm = max(norm, s * s, 1.0 + 2.0 * zeta[i] * s, 1.0)
    j = 0
    if norm > 0.5:
        j = max(0, int(np.ceil(np.log2(norm / 0.5))))
    scale = 2.0 ** j
    terms = _TRANSITION_TERMS if norm <= 2.0 else _TERMS
    M = np.zeros((4, 4))
    E = np.empty((4, 4))
    term = np.empty((4, 4))
    tmp = np.empty((4, 4))
    for i in range(n):
        s = omega[i] * dt
        z = zeta[i]
        p00, p01, p10, p11 = 1.0, 0.0, 0.0, 1.0  # dt = 0: identity
        g00, g01, g10, g11 = 0.0, 0.0, 0.0, 0.0
        kappa = 1.0
        if s <= _SPLIT and dt > 0.0:
            M[:, :] = 0.0
            M[0, 1] = 1.0 / scale
            M[1, 0] = -s * s / scale
            M[1, 1] = -2.0 * z * s / scale
            M[1, 2] = 1.0 / scale
            M[2, 3] = 1.0 / scale
            E[:, :] = 0.0
            term[:, :] = 0.0
            for r in range(4):
                E[r, r] = 1.0
                term[r, r] = 1.0
            for k in range(1, terms + 1):
                rows = 4 if k <= 2 else 2  # M^k / k! has zero rows 2 and 3 from k = 2 on
                _times_f(term, M, tmp, rows)
                rk = 1.0 / k  # (one division a term, not eight: the series' last bit is rounding anyway)
                for a in range(rows):
                    for b in range(4):
                        term[a, b] = tmp[a, b] * rk
                        E[a, b] += term[a, b]
            for _ in range(j):
                _matmul4(E, E, tmp)
                E[:, :] = tmp
            p00, p01, p10, p11 = E[0, 0], E[0, 1], E[1, 0], E[1, 1]
            r0, r1 = E[0, 3], E[1, 3]
            g00, g10, g01, g11 = E[0, 2] - r0, E[1, 2] - r1, r0, r1
            kappa = 1.0 / dt
        elif s > _SPLIT:
            d = z * z - 1.0
            r = np.sqrt(abs(d))
            x = r * s
            if d < 0.0:
                e = np.exp(-z * s)
                C = e * np.cos(x)
                S = e * s * (np.sin(x) / x)
            elif x > 1.0:
                slow = np.exp(-s / (z + r))
                fast = np.exp(-(z + r) * s)
                C = 0.5 * (slow + fast)
                S = 0.5 * (slow - fast) / r
            else:
                e = np.exp(-z * s)
                C = e * np.cosh(x)
                S = e * s * (np.sinh(x) / x if x > 0.0 else 1.0)
            p00, p01, p10, p11 = C + z * S, S, -S, C - z * S
            step0 = (1.0 - C - z * S) / s
            step1 = S / s
            ramp0 = (1.0 - step1 - 2.0 * z * step0) / s
            ramp1 = step0 / s
            g00, g10, g01, g11 = step0 - ramp0, step1 - ramp1, ramp0, ramp1
            kappa = omega[i]
        A[i, 0, 0] = p00
        A[i, 0, 1] = p01 / kappa
        A[i, 1, 0] = p10 * kappa
        A[i, 1, 1] = p11
        B[i, 0, 0] = g00 * (dt / kappa)
        B[i, 0, 1] = g01 * (dt / kappa)
        B[i, 1, 0] = g10 * dt
        B[i, 1, 1] = g11 * dt
        c = 2.0 * z * omega[i]
        kk = omega[i] * omega[i]
        for col in range(3):
            A[i, 2, col] = -kk * A[i, 0, col] - c * A[i, 1, col]
        for col in range(2):
            B[i, 2, col] = -kk * B[i, 0, col] - c * B[i, 1, col]
        B[i, 2, 1] += 1.0
    return A, B


@njit
def work_maps_small(w, zeta, h, a1, a2, Mq, done):
    """The work integrals of :func:`pounding.solvers.exact_work.work_maps` for the modes in its regime (A)
    (``w h <= max(3, 1.5 zeta)``; w (n,) [rad/s], zeta (n,), h [s]), written into a1, a2 (n, 4) and Mq
    (n, 4, 4) in the units of ``work_maps``; done (n,) bool marks them, the other modes' rows are left
    as they were (see the module docstring). Returns how many modes it left (regime (B)), or -1 without
    writing anything when a mode has not w > 0, zeta >= 0 (``work_maps``, which has checked 0 < h < inf,
    says so: as numpy reductions the modes' checks cost more than the arithmetic of a mode)."""
    n = w.shape[0]
    for i in range(n):
        if not (w[i] > 0.0 and zeta[i] >= 0.0):
            return -1
    left = 0
    F = np.zeros((4, 4))
    X = np.empty((4, 4))
    P = np.empty((4, 4))  # X^j / j!
    tmp = np.empty((4, 4))
    Phi = np.empty((4, 4))
    J0 = np.empty((4, 4))
    Y = np.empty((4, 4))
    J1 = np.empty((4, 4))
    W = np.empty((4, 4))
    R = np.empty((_TERMS + 1, 4))
    S = np.empty((_TERMS + 1, 4))
    inv = np.empty(2 * _TERMS + 1)
    for m in range(2 * _TERMS + 1):
        inv[m] = 1.0 / (m + 1)
    G = np.zeros((4, 4))
    t1 = np.empty((4, 4))
    t2 = np.empty((4, 4))
    for i in range(n):
        Om = w[i] * h
        if not Om <= max(3.0, 1.5 * zeta[i]):
            done[i] = False
            left += 1
            continue
        done[i] = True
        a = Om
        b = 2.0 * zeta[i] * a
        F[:, :] = 0.0
        F[0, 1] = 1.0
        F[1, 0] = -a * a
        F[1, 1] = -b
        F[1, 2] = 1.0
        F[2, 3] = 1.0
        ninf = 0.0
        n1 = 0.0
        for r in range(4):
            rs = 0.0
            cs = 0.0
            for c in range(4):
                rs += abs(F[r, c])
                cs += abs(F[c, r])
            ninf = max(ninf, rs)
            n1 = max(n1, cs)
        nrm = max(ninf, 1.0 + n1)
        k = int(np.ceil(np.log2(max(nrm, 1.0))))
        k = max(k, 0)
        t0 = np.ldexp(1.0, -k)
        for r in range(4):
            for c in range(4):
                X[r, c] = t0 * F[r, c]
        # Taylor sums on t0: P_j = X^j / j!
        Phi[:, :] = 0.0
        J0[:, :] = 0.0
        Y[:, :] = 0.0
        P[:, :] = 0.0
        for r in range(4):
            P[r, r] = 1.0
        for jj in range(_TERMS + 1):
            rows = 4 if jj <= 2 else 2  # X^j / j! has zero rows 2 and 3 from j = 2 on
            if jj > 0:
                _times_f(P, X, tmp, rows)
                for r in range(rows):
                    for c in range(4):
                        P[r, c] = tmp[r, c] / jj
            f1 = 1.0 / (jj + 1)
            f2 = f1 / (jj + 2)
            for r in range(rows):
                for c in range(4):
                    Phi[r, c] += P[r, c]
                    J0[r, c] += P[r, c] * f1
                    Y[r, c] += P[r, c] * f2
            for c in range(4):
                R[jj, c] = P[1, c]
        for r in range(4):
            for c in range(4):
                J0[r, c] *= t0
                Y[r, c] *= t0 * t0
                J1[r, c] = t0 * J0[r, c] - Y[r, c]
        # W = t0 sum_i R_i^T S_i with S_i = sum_j R_j / (i + j + 1)
        for ii in range(_TERMS + 1):
            for c in range(4):
                acc = 0.0
                for jj in range(_TERMS + 1):
                    acc += R[jj, c] * inv[ii + jj]
                S[ii, c] = acc
        for p in range(4):
            for q in range(4):
                acc = 0.0
                for ii in range(_TERMS + 1):
                    acc += R[ii, p] * S[ii, q]
                tmp[p, q] = acc
        for p in range(4):
            for q in range(4):
                W[p, q] = t0 * (0.5 * (tmp[p, q] + tmp[q, p]))
        t = t0
        for _ in range(k):
            # J1(2t) = J1 + Phi (J1 + t J0), J0(2t) = J0 + Phi J0, W(2t) = W + Phi^T W Phi, Phi(2t) = Phi Phi
            for r in range(4):
                for c in range(4):
                    t1[r, c] = J1[r, c] + t * J0[r, c]
            _matmul4(Phi, t1, t2)
            for r in range(4):
                for c in range(4):
                    J1[r, c] += t2[r, c]
            _matmul4(Phi, J0, t2)
            for r in range(4):
                for c in range(4):
                    J0[r, c] += t2[r, c]
            _congruence4(W, Phi, t1, t2)
            for r in range(4):
                for c in range(4):
                    tmp[r, c] = W[r, c] + 0.5 * (t2[r, c] + t2[c, r])
            W[:, :] = tmp
            _matmul4(Phi, Phi, tmp)
            Phi[:, :] = tmp
            t = 2.0 * t
        # back to physical inputs x = (q0, v0, p0, p1): y0 = G x, T = h
        T = h
        G[0, 0] = 1.0
        G[1, 1] = T
        G[2, 2] = T * T
        T3h = T * T * (T / h)
        G[3, 2] = -T3h
        G[3, 3] = T3h
        for c in range(4):
            s1 = 0.0
            s2 = 0.0
            for m in range(4):
                s1 += J0[1, m] * G[m, c]
                s2 += J1[1, m] * G[m, c]
            a1[i, c] = s1
            a2[i, c] = T * s2
        _congruence4(W, G, t1, t2)
        for r in range(4):
            for c in range(4):
                Mq[i, r, c] = 0.5 * (t2[r, c] / T + t2[c, r] / T)
    return left


@njit
def exact_maps(omega, zeta, dt, params):
    """:func:`exact_transition` in the form the compiled impact search takes an integrator's maps,
    ``(omega, zeta, dt, params) -> (A, B)`` (``params`` unused: :meth:`pounding.solvers.exact.Exact.search_maps`)."""
    return exact_transition(omega, zeta, dt)
