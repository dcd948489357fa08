"""Exact one-step work integrals of damped unit-mass SDOF oscillators (batched).

Used by the ``exact`` integrator's energy audit, for the grid step and the partial steps of contact
events alike (:meth:`pounding.solvers.exact.Exact.work_maps`).

Problem (per mode i, time step of length h, local time s in [0, h]):

    q'' + c q' + w^2 q = p(s),      c = 2 zeta w,
    p(s) = p0 + (p1 - p0) s / h,    q(0) = q0, q'(0) = v0.

For x = (q0, v0, p0, p1) the step integrals of the exact solution are

    Iv0 = int_0^h v(s) ds      = a1 . x        (linear)
    Iv1 = int_0^h s v(s) ds    = a2 . x        (linear)
    Ivv = int_0^h v(s)^2 ds    = x^T M x       (quadratic form, M symmetric PSD)

so the work of any linear-in-time force f(s) = f0 + (f1 - f0) s/h is
int v f ds = f0 * Iv0 + (f1 - f0)/h * Iv1, the load work is
I_p = p0*Iv0 + (p1 - p0)/h * Iv1, and the damping work is I_d = c * Ivv.

Units: w [rad/time], zeta [-], h [time]; q in displacement units u, v in
u/time, p in u/time^2 (unit mass).  Coefficients carry the matching units:
a1 = (1, time, time^2, time^2) for (q0, v0, p0, p1), a2 = time * that, and
x^T M x is in u^2/time.

Method
------
The load is made part of the state: y = (q, v, p, r) with p' = r, r' = 0,
r = (p1 - p0)/h, so y' = F y with a constant 4x4 F.  Work is done in
dimensionless variables tau = s/T, y_hat = (q, T v, T^2 p, T^3 r) with a
per-mode time unit T, horizon H = h/T.  Needed are, for the velocity row
(index 1) of Phi(t) = expm(F_hat t):
    J0(H) = int_0^H Phi,  J1(H) = int_0^H u Phi(u) du,
    W(H)  = int_0^H Phi^T e2 e2^T Phi du
(Iv0 = e2.J0 y0, Iv1 = T e2.J1 y0, Ivv = y0.W y0 / T, y0 = G x).
They are computed on a short sub-interval t0 = H / 2^k (block 1-norms
<= 1) from the blocks of two block matrix exponentials (Van Loan 1978,
"Computing integrals involving the matrix exponential", IEEE TAC 23(3)):
    expm(t0 [[-F^T, e2 e2^T], [0, F]]) = [[., G12], [0, Phi]],   W = Phi^T G12
    expm(t0 [[F, I, 0], [0, 0, I], [0, 0, 0]]) = [[Phi, J0, Y], ...],
                                                       J1 = t0 J0 - Y
and carried to the full horizon by k exact doubling identities
    J1(2t) = J1 + Phi (J1 + t J0),   J0(2t) = J0 + Phi J0,
    W(2t)  = W + Phi^T W Phi,        Phi(2t) = Phi Phi (or closed form),
which only ever use the bounded/decaying propagator (never e^{+c h}): no
overflow and no cancellation for stiff, heavily damped modes.  Critical
damping (zeta = 1, 1 +- 1e-8) is not special for the matrix exponential.

Two regimes (chosen per mode, by the compiled function of regime A, which marks its modes):
 (A) w h <= max(3, 1.5 zeta): T = h, H = 1, the full 4x4 augmented system;
     F_hat = [[0,1,0,0],[-(wh)^2,-2 zeta wh,1,0],[0,0,0,1],[0,0,0,0]].
     No 1/w^2 particular solutions, so w h -> 0 (1e-6 and below) is exact.
     Computed mode by mode by the compiled
     :func:`pounding.solvers.exact_partial.work_maps_small` (with the compiler off, the same
     function as Python): the blocks of Van Loan's exponentials on t0 summed as their Taylor
     series, then the doublings with Phi(2t) = Phi Phi.
 (B) w h >  max(3, 1.5 zeta): T = 1/w, H = w h, here, batched numpy.  The exact particular
     solution of the linear load (scaled: q_p = p_hat - 2 zeta r_hat,
     v_p = r_hat) is split off and its polynomial contributions are
     integrated analytically; only the 2x2 homogeneous oscillator
     A = [[0,1],[-1,-2 zeta]] goes through Van Loan + doubling, and inside
     the doubling Phi(t) is the closed form (cos/sin, or the two decaying
     exponentials with the stable slow rate 1/(zeta + sqrt(zeta^2-1))).
     This avoids (i) mixing O(H^3) polynomial terms with O(1) oscillatory
     ones (error ~ eps*H) and (ii) the eps*2^k amplitude drift of repeated
     squaring for undamped modes and the eps*zeta^2 error of the slow
     overdamped eigenvalue under squaring.

Shapes: w, zeta array-like broadcastable to (n,); h a positive scalar.
Returns a1 (n, 4), a2 (n, 4), M (n, 4, 4).

Cost: regime A compiled, ~1.5 us a mode (0.03 ms for the paper pair's 24 modes, 0.5 ms for 360);
as Python with the compiler off ~1-2 ms a mode. Regime B: the sub-interval block exponentials (4x4
and 6x6) have 1-norm <= 1 by construction, so a degree-20 Taylor polynomial (truncation ~2e-20)
evaluated with stacked numpy matmuls is used instead of scipy.linalg.expm (same accuracy; scipy
loops over the batch in Python), then <= ~30 vectorised 2x2 doubling steps: a few ms for hundreds
of modes. Call once per distinct h and reuse the maps every step.

Accuracy: every coefficient to <= 4e-14 (typically a few 1e-16) of its natural (Cauchy-Schwarz)
scale for w h in [1e-7, 1e5], zeta in [0, 10] incl. zeta = 1, 1 +- 1e-8, against references in
40 to 90 digits; heavier damping in regime A costs more doublings (zeta = 45 at w h = 68: 3e-13).
tests/test_exact_work.py checks regime A against a quadrature of scipy's exponential, and both
regimes against closed forms and the energy theorem of the exact step.
"""
import numpy as np

from pounding.solvers.exact_partial import work_maps_small

__all__ = ["work_maps"]

_TAYLOR_DEG = 20  # degree of the Taylor polynomial for ||X||_1 <= 1
_DOMAIN = "need h > 0, w > 0, zeta >= 0"  # where the maps are defined (a finite step)


def work_maps(w, zeta, h):
    """Per-mode linear/bilinear maps of the exact one-step work integrals.

    Parameters
    ----------
    w : array_like (n,)   circular frequencies [rad/time], > 0
    zeta : array_like (n,) or scalar   damping ratios >= 0 (c = 2 zeta w)
    h : float   step length [time], > 0

    Returns
    -------
    a1 : (n, 4)    Iv0 = int_0^h v ds   = a1[i] @ x
    a2 : (n, 4)    Iv1 = int_0^h s v ds = a2[i] @ x
    M  : (n, 4, 4) Ivv = int_0^h v^2 ds = x @ M[i] @ x (symmetric)
    where x = (q0, v0, p0, p1) is the state at the start of the step and the
    load values at both ends (load linear in time, unit mass).
    """
    w, zeta = _flat(w, zeta)
    h = float(h)
    n = w.size
    if not 0.0 < h < np.inf:
        raise ValueError(_DOMAIN)
    a1, a2, M = np.zeros((n, 4)), np.zeros((n, 4)), np.zeros((n, 4, 4))
    if n == 0:
        return a1, a2, M
    done = np.zeros(n, dtype=np.bool_)
    left = work_maps_small(w, zeta, h, a1, a2, M, done)  # regime (A), marking its modes; -1: a mode outside the domain
    if left < 0:
        raise ValueError(_DOMAIN)
    if left:
        rest = np.flatnonzero(~done)
        a1[rest], a2[rest], M[rest] = _oscillator_maps(w[rest], zeta[rest], h)
    return a1, a2, M


def _flat(w, zeta) -> tuple[np.ndarray, np.ndarray]:
    """w, zeta as writable contiguous float arrays (n,), one argument type for the compiled regime A
    whatever the caller passes; the driver's (its modes') already are and pass through untouched
    (the crossing locator asks the maps of a one-off step length at every located impact)."""
    if (type(w) is np.ndarray and type(zeta) is np.ndarray and w.ndim == 1 and w.shape == zeta.shape
            and w.dtype == np.float64 and zeta.dtype == np.float64 and w.flags.c_contiguous and zeta.flags.c_contiguous
            and w.flags.writeable and zeta.flags.writeable):
        return w, zeta
    return tuple(np.array(x, dtype=float).reshape(-1) for x in np.broadcast_arrays(np.asarray(w, dtype=float),
                                                                                  np.asarray(zeta, dtype=float)))


def _oscillator_maps(w, zeta, h):
    """Regime (B) of the module docstring, w h > max(3, 1.5 zeta): a1, a2 (n, 4), M (n, 4, 4) in
    time unit T = 1/w, horizon H = w h, the particular solution of the linear load split off."""
    n = w.size
    T = 1.0 / w
    H = w * h
    b = 2.0 * zeta                           # c T
    A = np.zeros((n, 2, 2))
    A[:, 0, 1] = 1.0
    A[:, 1, 0] = -1.0
    A[:, 1, 1] = -b
    JA0, JA1, WA = _integrals(A, H, lambda t: _phi_osc(zeta, t))
    # z0 = L y0: homogeneous initial state (q - q_p(0), v - v_p)
    L = np.zeros((n, 2, 4))
    L[:, 0, 0] = 1.0
    L[:, 0, 2] = -1.0
    L[:, 0, 3] = b
    L[:, 1, 1] = 1.0
    L[:, 1, 3] = -1.0
    J0r = np.einsum("nj,njk->nk", JA0[:, 1, :], L)  # velocity row of J0
    J1r = np.einsum("nj,njk->nk", JA1[:, 1, :], L)  # velocity row of J1
    W = np.swapaxes(L, 1, 2) @ WA @ L
    W[:, :, 3] += J0r
    W[:, 3, :] += J0r
    W[:, 3, 3] += H
    J0r[:, 3] += H
    J1r[:, 3] += 0.5 * H * H

    # --- back to physical inputs x = (q0, v0, p0, p1) --------------------
    # y_hat0 = G x,  G = diag(1, T, T^2, T^3) @ S,  S: p1 -> r = (p1-p0)/h
    G = np.zeros((n, 4, 4))
    G[:, 0, 0] = 1.0
    G[:, 1, 1] = T
    G[:, 2, 2] = T * T
    T3h = T * T * (T / h)
    G[:, 3, 2] = -T3h
    G[:, 3, 3] = T3h

    a1 = np.einsum("nj,njk->nk", J0r, G)
    a2 = T[:, None] * np.einsum("nj,njk->nk", J1r, G)
    M = np.swapaxes(G, 1, 2) @ W @ G / T[:, None, None]
    M = 0.5 * (M + np.swapaxes(M, 1, 2))
    return a1, a2, M


def _phi_osc(zeta, t):
    """Closed-form expm(A t) for A = [[0, 1], [-1, -2 zeta]] (scaled
    oscillator, time unit 1/w), t >= 0; (n, 2, 2).  Only decaying exponentials;
    stable for zeta -> 1 (sin(wd t)/wd, sinh(mu t)/mu) and large zeta."""
    z = zeta
    n = z.size
    P = np.empty((n, 2, 2))
    E = np.exp(-z * t)
    under = z < 1.0
    over = z > 1.0
    C = np.ones(n)
    S = t.astype(float).copy()               # critical: C = 1, S = t
    if np.any(under):
        zu, tu = z[under], t[under]
        wd = np.sqrt((1.0 - zu) * (1.0 + zu))
        C[under] = np.cos(wd * tu)
        S[under] = np.sin(wd * tu) / wd
    P11 = E * (C + z * S)
    P12 = E * S
    P22 = E * (C - z * S)
    if np.any(over):
        io = np.flatnonzero(over)
        zo, to = z[io], t[io]
        mu = np.sqrt((zo - 1.0) * (zo + 1.0))
        near = mu * to <= 1.0
        jn = io[near]
        if jn.size:
            x = mu[near] * to[near]
            Ch = np.cosh(x)
            Sh = np.sinh(x) / mu[near]
            En = E[jn]
            P11[jn] = En * (Ch + z[jn] * Sh)
            P12[jn] = En * Sh
            P22[jn] = En * (Ch - z[jn] * Sh)
        jf = io[~near]
        if jf.size:
            m, zf, tf = mu[~near], z[jf], t[jf]
            f = zf + m                          # fast rate
            sl = 1.0 / f                        # slow rate = zeta - mu
            es = np.exp(-sl * tf)
            ef = np.exp(-f * tf)
            P11[jf] = (es * f - ef * sl) / (2.0 * m)
            P12[jf] = (es - ef) / (2.0 * m)
            P22[jf] = (ef * f - es * sl) / (2.0 * m)
    P[:, 0, 0] = P11
    P[:, 0, 1] = P12
    P[:, 1, 0] = -P12
    P[:, 1, 1] = P22
    return P


def _expm_small(X):
    """Batched expm for ||X||_1 <= 1 (guaranteed by the caller): Taylor
    polynomial of degree 20 in Horner form (truncation <= 1.1/21! ~ 2e-20).
    Pure numpy stacked matmuls: no per-matrix Python loop, no BLAS calls on
    tiny matrices (scipy.linalg.expm loops over the batch and can be hit hard
    by BLAS thread oversubscription)."""
    I = np.eye(X.shape[-1])
    P = np.broadcast_to(I, X.shape).copy()
    for j in range(_TAYLOR_DEG, 0, -1):
        P = I + (X @ P) * (1.0 / j)
    return P


def _integrals(F, H, phi):
    """J0, J1, W (velocity = index 1) of y' = F y over [0, H], batched.

    F (n, m, m), H (n,); phi(t) (t (n,) -> (n, m, m)) the closed form of expm(F t).  Van Loan block
    exponentials on t0 = H / 2^k, chosen so that both block matrices have 1-norm <= 1, then k
    doublings with Phi from phi (only bounded/decaying factors, no repeated squaring).
    """
    n, m, _ = F.shape
    aF = np.abs(F)
    nrm = np.maximum(aF.sum(axis=2).max(axis=1),          # ||F||_inf
                     1.0 + aF.sum(axis=1).max(axis=1))    # 1 + ||F||_1
    k = np.ceil(np.log2(np.maximum(H * nrm, 1.0))).astype(int)
    k = np.maximum(k, 0)
    t0 = np.ldexp(H, -k)                     # exact: H / 2^k
    tt = t0[:, None, None]
    eye = np.eye(m)
    # block 1: expm(t0 [[-F^T, e2 e2^T], [0, F]]) = [[., G12], [0, Phi]]
    C1 = np.zeros((n, 2 * m, 2 * m))
    C1[:, :m, :m] = -np.swapaxes(F, 1, 2) * tt
    C1[:, 1, m + 1] = t0
    C1[:, m:, m:] = F * tt
    E1 = _expm_small(C1)
    # block 2: expm(t0 [[F, I, 0], [0, 0, I], [0, 0, 0]]) = [[Phi, J0, Y], ...]
    C2 = np.zeros((n, 3 * m, 3 * m))
    C2[:, :m, :m] = F * tt
    C2[:, :m, m:2 * m] = eye * tt
    C2[:, m:2 * m, 2 * m:] = eye * tt
    E2 = _expm_small(C2)
    J0 = E2[:, :m, m:2 * m].copy()
    J1 = tt * J0 - E2[:, :m, 2 * m:]         # int u Phi = t0 J0 - int (t0-u) Phi
    W = np.swapaxes(E1[:, m:, m:], 1, 2) @ E1[:, :m, m:]
    W = 0.5 * (W + np.swapaxes(W, 1, 2))
    t = t0.copy()
    for j in range(int(k.max())):
        msk = k > j
        mm = msk[:, None, None]
        Phi = phi(t)
        J1n = J1 + Phi @ (J1 + t[:, None, None] * J0)
        J0n = J0 + Phi @ J0
        Wn = W + np.swapaxes(Phi, 1, 2) @ W @ Phi
        Wn = 0.5 * (Wn + np.swapaxes(Wn, 1, 2))
        J1 = np.where(mm, J1n, J1)
        J0 = np.where(mm, J0n, J0)
        W = np.where(mm, Wn, W)
        t = np.where(msk, 2.0 * t, t)
    return J0, J1, W
