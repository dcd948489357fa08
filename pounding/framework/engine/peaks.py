"""True peaks: extremes over the continuous trajectory, not over step ends.

A step-by-step run knows the state at the step ends only; a peak taken there
misses the true one by up to ``y'' h^2 / 8`` (the extreme falls anywhere in
the step), i.e. ``(omega h)^2 / 8`` of the amplitude of a mode of circular
frequency omega: 2 % for omega h = 0.4. Every modal coordinate is therefore
interpolated inside each step, the same way for all of them, so that a
physical quantity y = c . q (a slab's u, v, phi, a corner's x, y, a storey
drift, a point's displacement along a direction) is a polynomial in each step
and its extreme is found in closed form.

Interpolants, by integrator
---------------------------
* **Cubic Hermite** through (q, q') at both step ends, for every integrator but
  ``exact``:

  - ``newmark`` with average acceleration (beta = 1/4, gamma = 1/2, the default):
    the step obeys q1 - q0 = h (q'0 + q'1) / 2, so the cubic coefficient
    vanishes and the Hermite cubic *is* the scheme's own constant-average-
    acceleration parabola (exact for the scheme's trajectory);
  - ``newmark`` with other beta, gamma, ``hht``, ``generalized_alpha`` and
    ``central_difference``: the natural C1 interpolant of their step-end
    states (their own intra-step assumptions are not C1 in q' across steps).

  Its interpolation error is ``h^4 / 384 max |y''''|`` (Hermite's
  remainder), so the peak it gives differs from the extreme of the smooth
  trajectory through the same step ends by O(h^4) — ``(omega h)^4 / 384`` of
  a mode's amplitude, 7e-5 at omega h = 0.4 — well below the O(h^2) error of
  the schemes themselves; the step-end peak's own error is O(h^2).
  The extreme is closed form: y' is a quadratic in the step, its roots in the
  step and the step ends are the candidates (:func:`cubic_abs_max`).
* **exact**: its own intra-step solution. The extreme of the Hermite cubic
  gives the starting instant; Newton on y'(t) = 0 with y' and y'' from the
  exact transition to that instant (:meth:`Exact.transition`, load linear in
  the step) converges quadratically to the true extreme, to rounding, in
  two or three iterations (:class:`ExactIntraStep`). This is done where the
  full history is kept (``output_every = 1``); with thinned output the
  compiled kernel tracks the Hermite extreme (O(h^4), above) for every
  integrator.

Impulses change velocities at event instants, so a step that holds impacts is
split there: ``Result.event_q`` / ``event_qd`` hold the state *before* the
impulses (the left end of the part before the event); the velocity after them
is ``event_qd + sum_j w_j I_j`` over the instant's impacts
(:func:`pounding.framework.engine.event_record.impact_velocity_changes`). An impact at a
step's end only replaces that step's end velocity by the one before the
impulses (the history records the velocity after them).

Magnitudes of plan vectors (a drift ratio's |(dx, dy)| / h) are not
polynomials; their extreme in a step is bounded by the componentwise extremes,
and only the steps whose bound reaches the best step-end value are refined
(roots of the derivative of the squared magnitude, a quintic).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine.ground_load import modal_loads

__all__ = ["cubic_abs_max", "hermite_extremes", "Segments", "segments", "abs_peaks", "norm_peaks",
           "ExactIntraStep", "refine_max"]


# --------------------------------------------------------------------------- closed forms in a step
@njit(borrowed=True)
def cubic_abs_max(y0, y1, m0, m1):
    """max |y(s)| over s in [0, 1] of the cubic Hermite y with y(0) = y0, y(1) = y1, dy/ds = m0, m1.

    With a step of h [s] and rates y'0, y'1, the slopes are m = h y'. The candidates are the
    step ends and the roots in (0, 1) of y'(s) = m0 + 2 c2 s + 3 c3 s^2 (stable quadratic formula).
    """
    c2 = 3.0 * (y1 - y0) - 2.0 * m0 - m1
    c3 = 2.0 * (y0 - y1) + m0 + m1
    best = max(abs(y0), abs(y1))
    a = 3.0 * c3
    b = 2.0 * c2
    disc = b * b - 4.0 * a * m0
    if disc < 0.0:
        return best
    r = np.sqrt(disc)
    qq = -0.5 * (b + r if b >= 0.0 else b - r)
    if qq != 0.0:
        s = m0 / qq
        if 0.0 < s < 1.0:
            best = max(best, abs(y0 + s * (m0 + s * (c2 + s * c3))))
        if a != 0.0:
            s = qq / a
            if 0.0 < s < 1.0:
                best = max(best, abs(y0 + s * (m0 + s * (c2 + s * c3))))
    return best


def hermite_extremes(y0, y1, m0, m1, signed: bool = False):
    """Vectorised :func:`cubic_abs_max`: (max |y| over each step, its fraction s in [0, 1]), arrays like
    y0; with ``signed``, the largest value of y itself. Compiled, element by element
    (:func:`_hermite_extremes_flat`)."""
    y0, y1, m0, m1 = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (y0, y1, m0, m1)))
    shape = y0.shape
    flat = [np.ascontiguousarray(a).reshape(-1) for a in (y0, y1, m0, m1)]
    best, where = np.empty(flat[0].size), np.empty(flat[0].size)
    if flat[0].size:
        _hermite_extremes_flat(*flat, bool(signed), best, where)
    return best.reshape(shape), where.reshape(shape)


@njit(borrowed=True)
def _hermite_extremes_flat(y0, y1, m0, m1, signed, best, where):
    """best, where (m,) <- the extreme of |y| (with ``signed``: of y) of the cubic Hermite of every
    element over s in [0, 1] and its fraction s: the step ends and the roots in (0, 1) of y'(s) = m0 +
    2 c2 s + 3 c3 s^2 (stable quadratic formula), with the operations of the former numpy version
    (same numbers), the first of equal candidates kept."""
    for i in range(y0.shape[0]):
        a0, a1, d0, d1 = y0[i], y1[i], m0[i], m1[i]
        c2 = 3.0 * (a1 - a0) - 2.0 * d0 - d1
        c3 = 2.0 * (a0 - a1) + d0 + d1
        b_ = a0 if signed else abs(a0)
        w = 0.0
        e1 = a1 if signed else abs(a1)
        if e1 > b_:
            b_ = e1
            w = 1.0
        a = 3.0 * c3
        b = 2.0 * c2
        disc = b * b - 4.0 * a * d0
        if disc >= 0.0:
            r = np.sqrt(disc)
            qq = -0.5 * (b + r if b >= 0.0 else b - r)
            if qq != 0.0:
                for root in range(2):
                    if root == 0:
                        s = d0 / qq
                    elif a != 0.0:
                        s = qq / a
                    else:
                        break
                    if s > 0.0 and s < 1.0:
                        val = a0 + s * (d0 + s * (c2 + s * c3))
                        if not signed:
                            val = abs(val)
                        if val > b_:
                            b_ = val
                            w = s
        best[i] = b_
        where[i] = w


def hermite_value(y0, y1, m0, m1, s):
    """The cubic Hermite at fraction s (arrays broadcast)."""
    c2 = 3.0 * (y1 - y0) - 2.0 * m0 - m1
    c3 = 2.0 * (y0 - y1) + m0 + m1
    return y0 + s * (m0 + s * (c2 + s * c3))


# --------------------------------------------------------------------------- the continuous trajectory
@dataclass
class Segments:
    """The run as smooth pieces: between grid points, split at impact instants.

    Attributes
    ----------
    t0, h : ndarray (m,)
        Start [s] and length [s] of every piece.
    q0, v0, q1, v1 : ndarray (m, n)
        Stacked modal displacements and velocities at its start (after any impulses) and its end
        (before any impulses).
    exact : ExactIntraStep or None
        The integrator's own intra-step solution when it is ``exact`` (else the Hermite cubic).
    """

    t0: np.ndarray
    h: np.ndarray
    q0: np.ndarray
    v0: np.ndarray
    q1: np.ndarray
    v1: np.ndarray
    exact: "ExactIntraStep | None" = None


def segments(result) -> Segments | None:
    """The smooth pieces of a run with every step in its output; None when the output is thinned
    (the peaks of the slabs are then tracked during the run, :func:`pounding.framework.engine.kernel.update_peaks`)."""
    t, q, v = np.asarray(result.t), np.asarray(result.q), np.asarray(result.qd)
    if len(t) < 2 or len(t) != int(result.steps) + 1:
        return None
    q0, v0, q1, v1 = q[:-1], v[:-1], q[1:].copy(), v[1:].copy()
    t0, h = t[:-1], np.diff(t)
    et = np.asarray(result.event_t, dtype=float)
    if et.size == 0:
        return Segments(t0, h, q0, v0, q1, v1, getattr(result, "intra_step", None))
    from pounding.framework.engine.event_record import impact_velocity_changes

    after = {}
    for te, state, _idx, dv in impact_velocity_changes(result):
        after[te] = state[1] + dv
    tol = 1e-9 * float(np.min(h))
    inner: dict[int, list[int]] = {}
    for j, te in enumerate(et):
        k = int(np.searchsorted(t, te))
        if k < len(t) and abs(t[k] - te) <= tol:
            if k > 0:  # at a grid point: the step ending there ends with the velocity before the impulses
                v1[k - 1] = result.event_qd[j]
            continue
        if k > 0 and abs(t[k - 1] - te) <= tol:
            continue
        inner.setdefault(k - 1, []).append(j)
    if not inner:
        return Segments(t0, h, q0, v0, q1, v1, getattr(result, "intra_step", None))
    keep = np.ones(len(t0), dtype=bool)
    extra = []
    for k, js in inner.items():
        keep[k] = False
        js = sorted(js, key=lambda j: et[j])
        ta, qa, va = t[k], q[k], v[k]
        for j in js:
            extra.append((ta, et[j] - ta, qa, va, result.event_q[j], result.event_qd[j]))
            ta, qa, va = et[j], result.event_q[j], after.get(float(et[j]), result.event_qd[j])
        extra.append((ta, t[k + 1] - ta, qa, va, q1[k], v1[k]))
    T0 = np.concatenate([t0[keep], [e[0] for e in extra]])
    order = np.argsort(T0, kind="stable")
    H = np.concatenate([h[keep], [e[1] for e in extra]])
    stack = lambda a, i: np.concatenate([a[keep], np.array([e[i] for e in extra])])  # noqa: E731
    return Segments(T0[order], H[order], stack(q0, 2)[order], stack(v0, 3)[order], stack(q1, 4)[order],
                    stack(v1, 5)[order], getattr(result, "intra_step", None))


class ExactIntraStep:
    """The exact integrator's state inside a step: the transition to tau (load linear from the
    step's start), for the modes ``omega``, ``zeta`` (n,), with the modal load p(t) = -L ag(t).

    Parameters
    ----------
    integrator : Exact
    omega, zeta : (n,)
    L : (n, c) modal load per unit ground acceleration
    ag : (nsteps + 1, c) ground acceleration on the grid [m/s^2], linear in between
    dt : float
        Grid step [s].
    """

    def __init__(self, integrator, omega, zeta, L, ag, dt):
        self.integrator, self.omega, self.zeta = integrator, np.asarray(omega, float), np.asarray(zeta, float)
        self.L, self.ag, self.dt = np.asarray(L, float), np.asarray(ag, float), float(dt)

    def load(self, t: float) -> np.ndarray:
        """p(t) (n,): -L ag(t), ag linear between grid samples."""
        x = t / self.dt
        k = min(max(int(np.floor(x)), 0), self.ag.shape[0] - 2)
        f = x - k
        ag = self.ag[k] + f * (self.ag[k + 1] - self.ag[k]) if abs(f) > 1e-12 else self.ag[k]
        p = np.empty(self.L.shape[0])
        modal_loads(self.L, np.ascontiguousarray(ag), p)
        return p

    def state(self, t0: float, q0: np.ndarray, v0: np.ndarray, tau: float) -> np.ndarray:
        """(q, q', q'') (3, n) at t0 + tau from (q0, v0) at t0."""
        p0, p1 = self.load(t0), self.load(t0 + tau)
        a0 = p0 - 2.0 * self.zeta * self.omega * v0 - self.omega**2 * q0
        # the compiled per-mode maps (equal to transition()'s to rounding, ~50x cheaper for one tau)
        tr = self.integrator.partial_transition(self.omega, self.zeta, float(tau))
        z0 = np.stack([q0, v0, a0], axis=1)
        z = np.einsum("nij,nj->ni", tr.A, z0) + tr.B[:, :, 0] * p0[:, None] + tr.B[:, :, 1] * p1[:, None]
        return z.T

    def consistent(self, t0, q0, v0, h, q1) -> bool:
        """Whether the free exact solution from the piece's start reproduces its end (no contact
        or spring force acted in it): then it is the piece's own trajectory. (Rounding leaves
        ~1e-14 of the scale; a force that acted leaves far more than the 1e-9 asked.)"""
        key = (float(t0), float(h))
        memo = self.__dict__.setdefault("_memo", {})
        if key not in memo:
            z = self.state(t0, q0, v0, h)
            scale = np.max(np.abs(q1)) + np.max(np.abs(q0)) + 1e-300
            memo[key] = bool(np.max(np.abs(z[0] - q1)) <= 1e-9 * scale)
        return memo[key]


def refine_max(seg: Segments, i: int, c: np.ndarray, s0: float, signed: bool = False) -> float:
    """|y| (with ``signed``: y) at the extreme of y = c . q in piece i, from the fraction s0 of the
    Hermite extreme: Newton on y' = 0 with the exact intra-step solution (``seg.exact``); the Hermite
    value when the piece is not a free exact step."""
    mag = (lambda x: x) if signed else abs
    h = float(seg.h[i])
    herm = mag(float(hermite_value(c @ seg.q0[i], c @ seg.q1[i], h * (c @ seg.v0[i]), h * (c @ seg.v1[i]), s0)))
    ex = seg.exact
    if ex is None or not ex.consistent(seg.t0[i], seg.q0[i], seg.v0[i], h, seg.q1[i]):
        return herm
    ends = max(mag(float(c @ seg.q0[i])), mag(float(c @ seg.q1[i])))
    if s0 <= 0.0 or s0 >= 1.0:
        return ends
    tau = s0 * h
    for _ in range(8):
        z = ex.state(seg.t0[i], seg.q0[i], seg.v0[i], tau)
        d1, d2 = float(c @ z[1]), float(c @ z[2])
        if d2 == 0.0:
            break
        new = min(max(tau - d1 / d2, 0.0), h)
        done = abs(new - tau) <= 1e-15 * h
        tau = new
        if done:
            break
    return max(ends, mag(float(c @ ex.state(seg.t0[i], seg.q0[i], seg.v0[i], tau)[0])))


# --------------------------------------------------------------------------- peaks of linear quantities
def abs_peaks(seg: Segments, C: np.ndarray, refine_margin: float = 1e-3, signed: bool = False) -> np.ndarray:
    """max over the run of |C q(t)| (k,) for quantities C (k, n) over the stacked modes (with
    ``signed``: of C q(t) itself).

    Hermite extremes in every piece; with ``seg.exact``, the pieces whose Hermite extreme is within
    ``refine_margin`` (relative) of the best are refined on the exact solution (the Hermite error,
    (omega h)^4 / 384 of a mode's amplitude, is below 1e-3 for omega h < 1.4).
    """
    C = np.atleast_2d(np.asarray(C, dtype=float))
    y0, y1 = seg.q0 @ C.T, seg.q1 @ C.T
    m0, m1 = seg.h[:, None] * (seg.v0 @ C.T), seg.h[:, None] * (seg.v1 @ C.T)
    best, where = hermite_extremes(y0, y1, m0, m1, signed)  # (m, k)
    out = best.max(axis=0) if len(best) else np.zeros(C.shape[0])
    if seg.exact is None or not len(best):
        return out
    for j in range(C.shape[0]):
        cand = np.flatnonzero(best[:, j] >= out[j] - abs(out[j]) * refine_margin)
        cand = cand[np.argsort(-best[cand, j], kind="stable")][:4]
        out[j] = max(refine_max(seg, int(i), C[j], float(where[i, j]), signed) for i in cand)
    return out


def norm_peaks(seg: Segments, C: np.ndarray) -> np.ndarray:
    """max over the run of |(Cx q, Cy q)| (k,) for plan vectors C (k, 2, n), on the Hermite cubics.

    Per piece, |y(s)| <= hypot(max |yx|, max |yy|); only the pieces whose bound reaches the best
    step-end magnitude are refined, at the real roots in (0, 1) of d|y|^2/ds (a quintic).
    """
    C = np.asarray(C, dtype=float)
    k = C.shape[0]
    Cf = C.reshape(2 * k, -1)
    y0, y1 = (seg.q0 @ Cf.T).reshape(-1, k, 2), (seg.q1 @ Cf.T).reshape(-1, k, 2)
    m0 = (seg.h[:, None] * (seg.v0 @ Cf.T)).reshape(-1, k, 2)
    m1 = (seg.h[:, None] * (seg.v1 @ Cf.T)).reshape(-1, k, 2)
    ends = np.maximum(np.hypot(y0[..., 0], y0[..., 1]), np.hypot(y1[..., 0], y1[..., 1]))
    comp, _ = hermite_extremes(y0, y1, m0, m1)
    bound = np.hypot(comp[..., 0], comp[..., 1])
    out = ends.max(axis=0) if len(ends) else np.zeros(k)
    for j in range(k):
        for i in np.flatnonzero(bound[:, j] > out[j]):
            out[j] = max(out[j], _norm_max_cubic(y0[i, j], y1[i, j], m0[i, j], m1[i, j]))
    return out


def _norm_max_cubic(y0, y1, m0, m1) -> float:
    """max over s in [0, 1] of |P(s)| for the vector cubic Hermite P (2 components)."""
    c2 = 3.0 * (y1 - y0) - 2.0 * m0 - m1
    c3 = 2.0 * (y0 - y1) + m0 + m1
    # P(s) = y0 + m0 s + c2 s^2 + c3 s^3 per component; |P|^2 as a polynomial (highest first)
    sq = np.zeros(7)
    for d in range(2):
        p = np.array([c3[d], c2[d], m0[d], y0[d]])
        sq += np.convolve(p, p)
    roots = np.roots(np.polyder(sq)) if np.any(sq[:-1]) else np.zeros(0)
    s = np.concatenate([[0.0, 1.0], roots[(np.abs(roots.imag) < 1e-9) & (roots.real > 0) & (roots.real < 1)].real])
    return float(np.sqrt(np.max(np.polyval(sq, s))))


# --------------------------------------------------------------------------- what a building reports
def slab_rows(system) -> np.ndarray:
    """(u, v, phi) of every slab as rows over the building's modes, shape (3 N, n)."""
    return np.asarray(system.modes, dtype=float)


def drift_rows(system, points: np.ndarray) -> np.ndarray:
    """Rows of the drift ratio vectors (x, y) at plan points of every storey, shape (N, k, 2, n):
    (U_f(r) - U_{f-1}(r)) / h_f with U_f(r) = (u - phi (r_y - c_y), v + phi (r_x - c_x)) of slab f."""
    Phi = np.asarray(system.modes, dtype=float)
    N, k = system.n_storeys, points.shape[1]
    out = np.zeros((N, k, 2, Phi.shape[1]))
    h = np.asarray(system.storey_heights, dtype=float)
    centres = np.array([s.centre for s in system.slabs])

    def at(f, r):  # (k, 2, n)
        d = r - centres[f]
        u, v, phi = Phi[3 * f], Phi[3 * f + 1], Phi[3 * f + 2]
        return np.stack([u[None, :] - d[:, 1:2] * phi[None, :], v[None, :] + d[:, 0:1] * phi[None, :]], axis=1)

    for f in range(N):
        rel = at(f, points[f]) - (at(f - 1, points[f]) if f > 0 else 0.0)
        out[f] = rel / h[f]
    return out


def building_segments(seg: Segments, result, name: str) -> Segments:
    """The pieces restricted to one building's modes (its exact intra-step solution too)."""
    i = result.names.index(name)
    i0, n = int(result.mode_start[i]), int(result.systems[i].n_dof)
    sl = slice(i0, i0 + n)
    ex = seg.exact
    if ex is not None:
        ex = ExactIntraStep(ex.integrator, ex.omega[sl], ex.zeta[sl], ex.L[sl], ex.ag, ex.dt)
    return Segments(seg.t0, seg.h, seg.q0[:, sl], seg.v0[:, sl], seg.q1[:, sl], seg.v1[:, sl], ex)


def slab_peaks(result) -> np.ndarray | None:
    """Peak |u|, |v|, |phi| of every slab over the continuous trajectory (slabs, 3), slabs numbered
    building by building; None when the output is thinned."""
    seg = segments(result)
    if seg is None:
        return None
    out = []
    for i, name in enumerate(result.names):
        s = result.systems[i]
        out.append(abs_peaks(building_segments(seg, result, name), slab_rows(s)).reshape(s.n_storeys, 3))
    return np.vstack(out) if out else np.zeros((0, 3))


def drift_peaks(result, name: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Peak drift ratio magnitudes (N,) at the centres of mass and at the worst corner over the
    continuous trajectory; None when the output is thinned."""
    seg = segments(result)
    if seg is None:
        return None
    s = result.systems[result.names.index(name)]
    bs = building_segments(seg, result, name)
    centres = np.array([sl.centre for sl in s.slabs])
    cm = norm_peaks(bs, drift_rows(s, centres[:, None, :])[:, 0])
    corner = np.zeros(s.n_storeys)
    for f, sl in enumerate(s.slabs):
        pts = np.full((s.n_storeys, len(sl.vertices), 2), 0.0)
        pts[f] = sl.vertices
        rows = drift_rows(s, pts)[f]  # (k, 2, n)
        corner[f] = norm_peaks(bs, rows).max()
    return cm, corner


def state_at(seg: Segments, i: int, s: float) -> np.ndarray:
    """Stacked modal displacements q (n,) at the fraction s in [0, 1] of piece i: the exact
    intra-step solution for ``exact`` (when the piece is a free exact step), else the Hermite cubic."""
    h = float(seg.h[i])
    ex = seg.exact
    if ex is not None and 0.0 < s < 1.0 and ex.consistent(seg.t0[i], seg.q0[i], seg.v0[i], h, seg.q1[i]):
        return ex.state(seg.t0[i], seg.q0[i], seg.v0[i], s * h)[0]
    return hermite_value(seg.q0[i], seg.q1[i], h * seg.v0[i], h * seg.v1[i], s)


def refine_over(seg: Segments, pieces, f) -> tuple[float, int, float]:
    """max of a scalar function f(q) of the modal state over the given pieces (continuous in each):
    bounded Brent search on the fraction s of each piece, the ends included. Returns
    (value, piece, s). For functions that are smooth near their maximum (a fixed vertex on a fixed
    edge), the value is exact to the square of the search's resolution (xatol 1e-10 of the piece)."""
    from scipy.optimize import minimize_scalar

    best = (-np.inf, -1, 0.0)
    for i in pieces:
        for s in (0.0, 1.0):
            v = f(state_at(seg, i, s))
            if v > best[0]:
                best = (v, i, s)
        r = minimize_scalar(lambda s: -f(state_at(seg, i, s)), bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-10})
        if -r.fun > best[0]:
            best = (float(-r.fun), i, float(r.x))
    return best
