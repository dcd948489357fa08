"""The compiled stepping of links with laws (the yielding storey springs): one implementation.

Every link's force is its initial elastic part k0 u (kept in the modes of the initial model) plus a
remainder f = r(u) - k0 u, a modal load g = G^T f over its building's modes (u = G q). A step of h
from the modal state z is the integrator's linear step with the start remainders' load -g0, the
links' Newton on their end deformations,

    u1 + S(h) f(u1) = G q_lin,        S(h) = G diag(B1(h)) G^T  (block diagonal by Newton group),

and the end load: z1 = z_lin - B1 G^T f(u1) (the method: :mod:`pounding.framework.engine.inelastic`).

The laws are plugins: every entry point takes the run's laws as a tuple of their compiled updates
and each link's index in it (:mod:`pounding.framework.engine.links`); nothing here knows a law. The same
functions serve every path that steps links, so that a step taken here and the same step taken in
Python do the same arithmetic in the same order:

* :func:`stretch`: grid steps between contact events, for the pounding driver and for the
  contact-free run (:func:`pounding.framework.post.inelastic_run.run_inelastic` is the driver without
  contact): :meth:`pounding.framework.engine.yielding.Yielding.advance`;
* :func:`spring_step`: one step of any length (the linear step, the links' Newton, their end load),
  the very step the stretch takes (:func:`_step_with_links`), for the driver's Python step;
* :func:`forces_at` and :func:`fixed_point_pass`: the links' end remainders at given end
  displacements, and a pass of the fixed point on them around a contact solve: held contact
  (:func:`pounding.framework.engine.held.held_fixed_point`), or a force law's
  (:func:`contact_fixed_point`, which takes the law's solve as a plugin beside the links' laws);
* :func:`spring_work`: the work of the remainders' modal loads in a step, by the integrator's
  energy rule.

Entry points take named bundles (:mod:`pounding.framework.engine.bundles`: ``Links``, ``LinkTrial``,
``LinkRecord`` and the driver's) and answer with a :class:`~pounding.framework.engine.bundles.Status`;
the small leaf kernels below them take arrays.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine.bundles import ContactFixedPoint, LinkPass, LinkTrial, NewtonWork, Status, StepEnds, StretchEnd
from pounding.framework.engine.inelastic import MAX_ITER, solve_in_place
from pounding.contact.geometry import clearance_bound
from pounding.framework.engine.ground_load import modal_load
from pounding.framework.engine.kernel import _accumulate, _record, update_peaks
from pounding.framework.engine.pairs import dofs_gap, slab_dofs
from pounding.framework.engine.links import law_update
from pounding.framework.engine.modal_step import stepped


@njit(borrowed=True)
def _rows(lo, hi, links, S, now, out, ws, tol):
    """The residual R = d - dl + S f (m,) [m] of the group's links (lo..hi-1, m = hi - lo) into
    ``ws.x[:m]``, at the trial end deformations ``ws.d`` with the laws evaluated there. Returns the
    largest |R| [m] beyond the precision the deformations allow where a row's |R| exceeds ``tol``
    (the rows within it are converged whatever their floor: the iteration only compares the result
    with tol).

    That precision: a row's residual is rounded to eps of its terms (|d|, |dl|, |S f|), and a change
    of one ulp in the deformations (or the committed ones the rates are taken from) moves it by the
    Jacobian's row times those ulps, sum_b |S_ab (k_t - k0)_b| eps max(|d_b|, |u0_b|): negligible
    for springs and linear dampers (below 1e-16 of the deformations), but not for a dashpot
    near rest, whose tangent alpha c |v|^(alpha - 1) / h grows without bound (its solution lies
    between two floats whose forces differ by much). The floor is 4 eps of the terms plus 32 ulps
    through the Jacobian's row: the nearest float is not reachable (the iterates' steps are rounded
    too), and with 8 ulps the step from rest of a building with alpha = 0.2 dampers cycled among
    neighbouring floats (measured); a tolerance of a few ulps of the deformations, not of the step."""
    k0, f1, d, x, dl, kt, u0 = links.k0, out.f, ws.d, ws.x, ws.dl, ws.kt, now.state[:, 0]
    worst = 0.0
    for a in range(lo, hi):
        acc = d[a] - dl[a]
        for b in range(lo, hi):
            acc += S[a, b] * f1[b]
        x[a - lo] = acc
        if abs(acc) <= tol:
            worst = max(worst, abs(acc))
            continue
        floor = abs(d[a]) + abs(dl[a])
        for b in range(lo, hi):
            floor += abs(S[a, b] * f1[b]) + 8.0 * abs(S[a, b] * (kt[b] - k0[b])) * max(abs(d[b]), abs(u0[b]))
        worst = max(worst, abs(acc) - 4.0 * EPS * floor)
    return worst


@njit(borrowed=True)
def _newton_step(lo, hi, links, S, out, ws):
    """The Newton step at the iterate ``ws.d``, solved in the forces: q [N] (``ws.x[2m:3m]``) with
    (I + D S) q = f - y, D = diag(k_t - k0), y (``ws.x[3m:4m]``) the forces the iterate implies
    (d = dl - S y), and its deformations dd = S q [m] (``ws.dd``; the step is -dd). This is the
    step -(I + S D)^-1 R of the residual R = S (f - y), taken in the variable that stays well scaled
    where a link's tangent is huge (a dashpot near rest): there the step in the deformations is
    R / (S k_t), which formed as R - S D J^-1 R would lose all its digits when S k_t nears 1 / eps.

    Only the links off their initial branch (the active set a, D_a != 0) couple: q is f - y on the
    others, and on them (D_a^-1 + S_aa) q_a = D_a^-1 (f - y)_a - S_a,rest (f - y)_rest."""
    m = hi - lo
    k0, kt, J, x, act, dd, f1 = links.k0, ws.kt, ws.J, ws.x, ws.act, ws.dd, out.f
    for a in range(lo, hi):
        x[2 * m + a - lo] = f1[a] - x[3 * m + a - lo]
    na = 0
    for a in range(lo, hi):
        if kt[a] != k0[a]:
            act[na] = a
            na += 1
    rhs = x[m : m + na]  # the active rows' right-hand side, after the residuals
    for i in range(na):
        a = act[i]
        flex = 1.0 / (kt[a] - k0[a])
        acc = x[2 * m + a - lo] * flex
        for b in range(lo, hi):
            if kt[b] == k0[b]:
                acc -= S[a, b] * x[2 * m + b - lo]
        rhs[i] = acc
        for c in range(na):
            J[i, c] = S[a, act[c]]
        J[i, i] += flex
    solve_in_place(J, rhs, na)
    for i in range(na):
        x[2 * m + act[i] - lo] = rhs[i]
    for a in range(lo, hi):
        acc = 0.0
        for b in range(lo, hi):
            acc += S[a, b] * x[2 * m + b - lo]
        dd[a] = acc


@njit(borrowed=True)
def _slope(m, x):
    """phi'(t) = -q . R [N m]: the slope of the group's potential along the Newton step (see
    :func:`solve_group`), from q (``x[2m:3m]``) and the residual at the share t of the step (``x[:m]``)."""
    acc = 0.0
    for i in range(m):
        acc -= x[2 * m + i] * x[i]
    return acc


@njit(borrowed=True)
def _go_to(lo, hi, t, ws):
    """ws.d <- d0 - t dd: the share t of the Newton step from the accepted iterate d0. Returns whether
    that moved any link."""
    d, d0, dd = ws.d, ws.d0, ws.dd
    moved = False
    for a in range(lo, hi):
        u = d0[a] - t * dd[a]
        if u != d[a]:
            moved = True
        d[a] = u
    return moved


@njit(borrowed=True)
def _between(lo, hi, a, t, b, ws):
    """Whether the share t of the Newton step gives some link a deformation other than those of the
    shares a and b: when it does not, no float lies between the two iterates."""
    d0, dd = ws.d0, ws.dd
    for k in range(lo, hi):
        u = d0[k] - t * dd[k]
        if u != d0[k] - a * dd[k] and u != d0[k] - b * dd[k]:
            return True
    return False


@njit(borrowed=True)
def _residual(laws, lo, hi, links, h, S, now, out, ws, tol):
    """The laws at ``ws.d`` (:func:`_evaluate`) and the residual's rows (:func:`_rows`): the largest
    |R| beyond its precision [m]."""
    _evaluate(laws, lo, hi, links, h, now, out, ws)
    return _rows(lo, hi, links, S, now, out, ws, tol)


@njit(borrowed=True)
def _line_minimum(laws, lo, hi, links, h, S, now, out, ws, s0, s1, tol, it):
    """The minimum of the potential along the Newton step when the full step went past it
    (phi'(0) = s0 < 0 < phi'(1) = s1): the Illinois variant of regula falsi on the nondecreasing
    phi', to |phi'(t)| <= ETA |phi'(0)| or a residual within tol. Leaves the laws evaluated at the
    iterate it takes. Returns (t, largest |R|, evaluations so far). When no float lies between the
    bracket's ends, t is its lower end; t = 0 then means the accepted iterate is the solution to
    the deformations' precision (a dashpot near rest: its force jumps by c (ulp(u) / h)^alpha
    between neighbouring floats)."""
    m = hi - lo
    x = ws.x
    a, sa, b, sb = 0.0, s0, 1.0, s1
    side = 0
    worst = np.inf
    while it <= NEWTON_CAP:
        t = a - sa * (b - a) / (sb - sa)
        if not a < t < b:
            t = 0.5 * (a + b)
        if not _between(lo, hi, a, t, b, ws):
            t = a  # no float between the ends: the end before the minimum
            _go_to(lo, hi, t, ws)
            worst = _residual(laws, lo, hi, links, h, S, now, out, ws, tol)
            return t, worst, it + 1
        _go_to(lo, hi, t, ws)
        worst = _residual(laws, lo, hi, links, h, S, now, out, ws, tol)
        it += 1
        if worst <= tol:
            return t, worst, it
        st = _slope(m, x)
        if abs(st) <= ETA * -s0:
            return t, worst, it
        if st < 0.0:
            a, sa = t, st
            if side < 0:
                sb *= 0.5  # Illinois: the end kept twice has its slope halved
            side = -1
        else:
            b, sb = t, st
            if side > 0:
                sa *= 0.5
            side = 1
    return 1.0, worst, it


@njit(borrowed=True)
def solve_group(laws, j, links, h, S, now, out, ws):
    """Newton on ``u + S f(u) = dl`` for the links of group j (one building, or the buildings links join), for a step of h [s].

    links : :class:`Links` (the group's bounds, law indices, parameters, initial stiffnesses and
    residual tolerance [m] are read); S (ns, ns) the step's compliance (block diagonal by group);
    now : :class:`LinkTrial`, the committed remainders f [N] and states; ws : :class:`NewtonWork`,
    whose ``dl`` holds the linear step's end deformations [m] and ``sf`` = S f (the predictor keeps
    the start remainders through the step). Writes the end deformations ``ws.d``, tangents
    ``ws.kt`` (the step's, dr/du + dr/dv / h) and the group's rows of ``out.f`` (end remainders)
    and ``out.state`` (trial states).

    Globalisation. S is symmetric positive semi-definite (G diag(B1) G^T), and on the iterates
    d = dl - S y (y the forces they imply) the residual is S (f(d) - y), S times the gradient of

        Phi(d) = 1/2 (d - dl)^T S^+ (d - dl) + sum_a F_a(d_a),    F_a' = f_a,

    convex where every law's force is nondecreasing in its deformation over the step (then its
    remainder's slope k_t - k0 >= -k0, and S diag(k0) < 1: the module docstring of
    :mod:`pounding.framework.engine.inelastic`). The Newton step -dd, dd = (I + S D)^-1 R, is -S q
    with q = (I + D S)^-1 (f - y), Newton's step on Phi, a descent direction of Phi for any tangents
    D >= 0, exact or not (a dashpot's, taken at its smallest rate near rest), where descent of the
    squared residual fails (its halving stalled and the iteration cycled for a dashpot with alpha
    below about 0.45). Along the step the slope of Phi is phi'(t) = -q . R(d - t dd), nondecreasing
    in t, so Phi needs no evaluation and the laws no potential: the full step is taken when
    phi'(1) <= ETA |phi'(0)| (then Phi fell by at least ETA |phi'(0)|, by convexity), else the
    minimum along it is bracketed in (0, 1) (:func:`_line_minimum`). No law's kind is asked: a law
    whose force falls with its deformation (phi'(0) >= 0) gets the full Newton step. The step is
    solved in the forces (:func:`_newton_step`), and the residual is met to tol beyond the precision
    the deformations' floats allow (:func:`_residual`); a step that moves no deformation, or a
    bracket with no float inside, ends the iteration there.

    The predictor, where almost every step ends, is this function; the iteration past it is
    :func:`_iterate`, and both evaluate the laws with :func:`_evaluate`.

    Returns the laws' evaluations after the predictor's (one per Newton step and per step of the
    line search), or -1 when that exceeds NEWTON_CAP without converging.
    """
    lo, hi = links.bounds[j], links.bounds[j + 1]
    d, dl, sf = ws.d, ws.dl, ws.sf
    for a in range(lo, hi):  # predictor: the start remainders kept through the step
        d[a] = dl[a] - sf[a]
    if _evaluate(laws, lo, hi, links, h, now, out, ws):
        return 0  # nothing changed: the predictor solves the step
    return _iterate(laws, j, links, h, S, now, out, ws)


@njit(borrowed=True)
def _evaluate(laws, lo, hi, links, h, now, out, ws):
    """The laws of the group's links (lo..hi-1) at the trial end deformations ``ws.d``: remainders
    into ``out.f``, trial states into ``out.state``, tangents into ``ws.kt``. Returns whether every
    remainder is the committed one (at the predictor: the step is solved, no residual to form)."""
    law, params, k0, f, f1, d = links.law, links.params, links.k0, now.f, out.f, ws.d
    state, trial, kt = now.state, out.state, ws.kt
    same = True
    for a in range(lo, hi):
        r, k = law_update(laws, law[a], d[a], h, state, params, trial, a)
        f1[a] = r - k0[a] * d[a]
        kt[a] = k
        if f1[a] != f[a]:
            same = False
    return same


@njit(borrowed=True)
def _iterate(laws, j, links, h, S, now, out, ws):
    """:func:`solve_group` past a predictor that moved some law (the laws evaluated there): the
    globalised Newton iteration. Returns the evaluations it took, or -1."""
    lo, hi, tol = links.bounds[j], links.bounds[j + 1], links.tol[j]
    m = hi - lo
    f, d, d0, x = now.f, ws.d, ws.d0, ws.x
    for a in range(lo, hi):
        x[3 * m + a - lo] = f[a]  # the forces that imply the predictor: d = dl - S y
    worst = _rows(lo, hi, links, S, now, out, ws, tol)
    it = 0
    while worst > tol:
        if it >= NEWTON_CAP:
            return -1
        _newton_step(lo, hi, links, S, out, ws)
        s0 = _slope(m, x)
        for a in range(lo, hi):
            d0[a] = d[a]
        if not _go_to(lo, hi, 1.0, ws):
            return it  # a step below the deformations' precision: the iterate is the solution to it
        worst = _residual(laws, lo, hi, links, h, S, now, out, ws, tol)
        it += 1
        t = 1.0
        if worst > tol and s0 < 0.0:
            s1 = _slope(m, x)
            if s1 > ETA * -s0:  # past the minimum along the step
                t, worst, it = _line_minimum(laws, lo, hi, links, h, S, now, out, ws, s0, s1, tol, it)
                if t == 0.0:
                    return it
        for a in range(lo, hi):
            x[3 * m + a - lo] += t * x[2 * m + a - lo]  # the implied forces follow the step
    return it


#: the share of the Newton step's initial slope of the potential left at the iterate the links' line
#: search takes (a strong Wolfe curvature condition)
ETA = 0.5


@njit(borrowed=True)
def compliance_load(f, S, bounds, sf):
    """sf (ns,) <- S f per group (S block diagonal by group)."""
    for j in range(bounds.shape[0] - 1):
        for a in range(bounds[j], bounds[j + 1]):
            acc = 0.0
            for b in range(bounds[j], bounds[j + 1]):
                acc += S[a, b] * f[b]
            sf[a] = acc


@njit(borrowed=True)
def step_compliance(links, B1, S):
    """S (ns, ns) <- the compliance [m/N] of a step of the links ``links`` (:class:`Links`): G diag(B1) G^T
    per Newton group, zero between groups (uncoupled), B1 (n,) = B[:, 0, 1] the step's end-load map
    [s^2] of every stacked mode. The one compliance every path steps with (the driver's trials and
    stretches through ``Yielding.S``, the compiled impact search at any step length)."""
    G, bounds, gmodes = links.G, links.bounds, links.gmodes
    for a in range(S.shape[0]):
        for b in range(S.shape[1]):
            S[a, b] = 0.0
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for a in range(bounds[j], bounds[j + 1]):
            for b in range(bounds[j], bounds[j + 1]):
                acc = 0.0
                for i in range(nm):
                    acc += G[a, i] * B1[m0 + i] * G[b, i]
                S[a, b] = acc


@njit
def compliance(links, B1):
    """A new (ns, ns) compliance of a step with end-load map B1 (n,) (:func:`step_compliance`)."""
    ns = links.k0.shape[0]
    S = np.empty((ns, ns))
    step_compliance(links, B1, S)
    return S


@njit(borrowed=True)
def deformations(q, G, bounds, gmodes, out):
    """out (ns,) <- G q per group: the links' deformations [m] from the stacked modal vector q (n,)."""
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for s in range(bounds[j], bounds[j + 1]):
            acc = 0.0
            for i in range(nm):
                acc += G[s, i] * q[m0 + i]
            out[s] = acc


@njit(borrowed=True)
def end_load(f1, G, bounds, gmodes, g):
    """g (n,) <- the modal load G^T f1 of the remainders f1 (ns,), zero on modes without links."""
    for i in range(g.shape[0]):
        g[i] = 0.0
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for i in range(nm):
            acc = 0.0
            for s in range(bounds[j], bounds[j + 1]):
                acc += G[s, i] * f1[s]
            g[m0 + i] = acc


@njit(borrowed=True)
def joined_load(f, links, g):
    """g (n,) <- the modal load of the remainders f (ns,) of the links between slabs only
    (``links.joins``): the part of :func:`end_load` whose work is booked to the buildings' ``links`` term."""
    G, bounds, gmodes, joins = links.G, links.bounds, links.gmodes, links.joins
    for i in range(g.shape[0]):
        g[i] = 0.0
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for i in range(nm):
            acc = 0.0
            for s in range(bounds[j], bounds[j + 1]):
                acc += G[s, i] * (f[s] * joins[s])
            g[m0 + i] = acc


@njit(borrowed=True)
def _has_joins(links):
    joins = links.joins
    for s in range(joins.shape[0]):
        if joins[s] != 0.0:
            return True
    return False


@njit(borrowed=True)
def _largest_group(bounds):
    m = 0
    for j in range(bounds.shape[0] - 1):
        m = max(m, bounds[j + 1] - bounds[j])
    return m


@njit
def newton_work(bounds, n):
    """Fresh :class:`NewtonWork` for the links of groups ``bounds`` (:attr:`Links.bounds`) of a model
    of n stacked modes."""
    ns = bounds[-1]
    m = _largest_group(bounds)
    return NewtonWork(np.empty(n), np.empty(ns), np.empty(ns), np.empty(ns), np.empty(ns), np.empty((m, m)), np.empty(4 * m),
                      np.empty(m, dtype=np.int64), np.empty(ns), np.empty(ns))


@njit(borrowed=True)
def _solve_springs(laws, links, S, h, q_lin, now, out, ws, counts):
    """Every group's Newton (:func:`solve_group`) with ``ws.sf`` = S f given (the stretch keeps it
    until f changes) and the work buffers ``ws`` (:class:`NewtonWork`). Adds every group's
    iterations, and a step that iterated, to counts (n_groups, 3) columns 0 and 1. Returns the
    index of a group that diverged, or -1."""
    bounds = links.bounds
    deformations(q_lin, links.G, bounds, links.gmodes, ws.dl)
    for j in range(bounds.shape[0] - 1):
        it = solve_group(laws, j, links, h, S, now, out, ws)
        if it < 0:
            return j
        counts[j, 0] += it
        if it > 0:
            counts[j, 1] += 1
    return -1


@njit
def forces_at(laws, links, h, q1, now, out):
    """The trial ``out`` (:class:`LinkTrial`: remainders, trial states, their modal load) of a step
    of h [s] from the committed links ``now`` that ends at the modal displacements q1 (n,)."""
    law, G, bounds, gmodes, k0, params = links.law, links.G, links.bounds, links.gmodes, links.k0, links.params
    state, trial, f1 = now.state, out.state, out.f
    ns = k0.shape[0]
    d = np.empty(ns)
    deformations(q1, G, bounds, gmodes, d)
    for s in range(ns):
        r, _ = law_update(laws, law[s], d[s], h, state, params, trial, s)
        f1[s] = r - k0[s] * d[s]
    end_load(f1, G, bounds, gmodes, out.g)


#: the fixed point's relaxation weights, tried in turn (:func:`fixed_point_pass`): plain substitution,
#: then under-relaxed by 1/2 and 1/4 where the plain map does not settle
RELAXATION = (1.0, 0.5, 0.25)


@njit
def fixed_point_pass(laws, links, h, q1, now, out, g, prev, w):
    """One pass of the links' fixed point around a contact solve whose step of h [s] ended at the modal
    displacements q1 (n,) with the remainders' end load g (n,): the trial ``out`` (:class:`LinkTrial`)
    at q1 (:func:`forces_at`), then the convergence test and the next load.

    Converged when every group's end deformations differ from the last pass's ``prev`` (ns,) [m] by
    at most w times its Newton tolerance (deformations, not forces: a damper has no stiffness to scale
    a force by; w scales the tolerance so that a relaxed iteration stops at the same residual as a
    plain one). Otherwise prev takes the new deformations and g (n,) the next end load, in place:
    out.g (w = 1), or g + w (out.g - g) (under-relaxed, w < 1). Returns True when converged."""
    forces_at(laws, links, h, q1, now, out)
    d, bounds, tol, g1 = out.state, links.bounds, links.tol, out.g
    done = True
    for j in range(bounds.shape[0] - 1):
        worst = 0.0
        for s in range(bounds[j], bounds[j + 1]):
            worst = max(worst, abs(d[s, 0] - prev[s]))
        if worst > w * tol[j]:
            done = False
    if done:
        return True
    for s in range(prev.shape[0]):
        prev[s] = d[s, 0]
    for i in range(g.shape[0]):
        g[i] = g1[i] if w == 1.0 else g[i] + w * (g1[i] - g[i])
    return False


@njit
def contact_fixed_point(laws, spr, h, B1, Bv, pressed, q, prev0, g, solve, args):
    """The links' end remainders and the contact forces of a step of h [s], solved together: a fixed
    point on the remainders' end load g around the contact law's solve with the step.

    The step is linear in its end load: from the links' own step (their Newton with no contact force
    at the end, end load g on entry, end displacements q (n,), the links' end deformations prev0
    (ns,) [m]), a change dg of the end load moves the end displacements by -B1 dg and a contact
    force lambda (m,) [N] along the rows W (m, n) by B1 W^T lambda; the points' end gaps gap (m,) [m]
    and rates rate (m,) [m/s] without contact forces (``pressed``, the
    :class:`~pounding.framework.engine.bundles.PressedPoints`) move by -W (B1 dg), -W (Bv dg) (B1, Bv (n,) the
    step's end-load maps of displacement and velocity, B[:, 0, 1] and B[:, 1, 1]). Each pass asks the
    law's solve for the forces at the gaps and rates of the current load, ``solve(args, gap, rate) ->
    lambda`` (the contact law's :meth:`~pounding.contact.base.ContactLaw.forces_solver`), then the
    links' trial at the end displacements with those forces (:func:`fixed_point_pass`: plain
    substitution, then under-relaxed, ``RELAXATION``) until the links' end deformations agree to
    their groups' Newton tolerances. The contact points are those the links' own step presses; the
    law's compliances S_q, S_v are in ``args``.

    ``laws`` the run's link-law updates, ``spr`` the :class:`~pounding.framework.engine.bundles.LinkPass`
    (its trial ``spr.out`` is written). Compiled, ``solve`` is a compiled function; with a law whose
    solve only Python knows (a third party's, or several laws on pairs that share a building) the
    driver runs this same function as Python (``py_func``).

    Returns a :class:`~pounding.framework.engine.bundles.ContactFixedPoint`: Status.DONE or
    Status.DIVERGED (the last pass's then), the forces, and the points' end gaps and rates without
    them at the converged load, which is left in g (n,).
    """
    links, now, out = spr.links, spr.now, spr.out
    W, gap, rate = pressed.W, pressed.gap, pressed.rate
    n, m, ns = g.shape[0], gap.shape[0], prev0.shape[0]
    g_in = g.copy()
    prev = np.empty(ns)
    gp, rp, q1, dq = np.empty(m), np.empty(m), np.empty(n), np.empty(n)
    lam = np.zeros(m)
    for w in RELAXATION:
        for i in range(n):
            g[i] = g_in[i]
        for s in range(ns):
            prev[s] = prev0[s]
        for _ in range(4 * MAX_ITER):
            for i in range(n):
                dq[i] = g_in[i] - g[i]  # the end load is -g: its change moves the step's end by B (-dg)
            for a in range(m):
                accq, accv = gap[a], rate[a]
                for i in range(n):
                    accq += W[a, i] * B1[i] * dq[i]
                    accv += W[a, i] * Bv[i] * dq[i]
                gp[a], rp[a] = accq, accv
            lam = solve(args, gp, rp)
            for i in range(n):
                acc = dq[i]
                for a in range(m):
                    acc += W[a, i] * lam[a]
                q1[i] = q[i] + B1[i] * acc
            if fixed_point_pass(laws, links, h, q1, now, out, g, prev, w):
                return ContactFixedPoint(Status.DONE, lam, gp, rp)
    return ContactFixedPoint(Status.DIVERGED, lam, gp, rp)


@njit(borrowed=True)
def spring_work(tr, h, pg0, pg1, z0, z1, ftot0, ftot1, w0, w1, out):
    """out (n,) <- work [J] in a step of h [s] of a modal load w linear in it (w0 at its start, w1
    at its end), on the integrator's trajectory (``tr``, the :class:`Transition`) driven by the
    modal ground loads (pg0, pg1 (n,) at the ends) and the total extra loads ftot0, ftot1 (n,): the
    three rules of :func:`pounding.framework.engine.kernel._accumulate_forces` (closed-form maps,
    Gauss points on the trajectory, or the trapezoidal rule)."""
    GA, GB, gc, gw, WA1, WA2 = tr.GA, tr.GB, tr.gc, tr.gw, tr.WA1, tr.WA2
    n = z0.shape[0]
    for i in range(n):
        p0 = pg0[i]
        p1 = pg1[i]
        if WA1.shape[0] > 0:
            x0 = z0[i, 0]
            x1 = z0[i, 1]
            x2 = p0 + ftot0[i]
            x3 = p1 + ftot1[i]
            iv0 = WA1[i, 0] * x0 + WA1[i, 1] * x1 + WA1[i, 2] * x2 + WA1[i, 3] * x3
            iv1 = WA2[i, 0] * x0 + WA2[i, 1] * x1 + WA2[i, 2] * x2 + WA2[i, 3] * x3
            out[i] = w0[i] * iv0 + (w1[i] - w0[i]) / h * iv1
        elif gc.shape[0] == 0:
            vm = 0.5 * (z0[i, 1] + z1[i, 1])
            out[i] = h * vm * 0.5 * (w0[i] + w1[i])
        else:
            acc = 0.0
            for j in range(gc.shape[0]):
                pj = p0 + gc[j] * (p1 - p0)
                fj = ftot0[i] + gc[j] * (ftot1[i] - ftot0[i])
                vj = (GA[j, i, 1, 0] * z0[i, 0] + GA[j, i, 1, 1] * z0[i, 1] + GA[j, i, 1, 2] * z0[i, 2]
                      + GB[j, i, 1, 0] * (p0 + ftot0[i]) + GB[j, i, 1, 1] * (pj + fj))
                acc += h * gw[j] * vj * (w0[i] + gc[j] * (w1[i] - w0[i]))
            out[i] = acc


@njit(borrowed=True)
def _step_with_links(laws, A, B, z0, p0, p1, h, spr, S, ws, counts, z):
    """z (n, 3) <- a step of h [s] from z0 (n, 3) with links: the integrator's linear step (A (n, 3, 3),
    B (n, 3, 2)) with the modal loads p0 (the start's, the links' -g0 in it) and p1 (n,) at its ends,
    the links' Newton on its end displacements (written to ``ws.qlin``), and their end load
    -B1 out.g. ``spr`` the :class:`LinkPass`: the links, the committed ``now`` and the trial ``out``
    it writes (:class:`LinkTrial`); S (ns, ns) the step's compliance [m/N]; ``ws``, ``counts`` as
    :func:`_solve_springs`, with ``ws.sf`` = S now.f. Returns the index of a group whose Newton
    diverged (z is then the linear step's), or -1."""
    links, now, out, qlin = spr.links, spr.now, spr.out, ws.qlin
    n = z0.shape[0]
    for i in range(n):
        for r in range(3):
            z[i, r] = stepped(A, B, i, r, z0, p0[i], p1[i])
        qlin[i] = z[i, 0]
    j = _solve_springs(laws, links, S, h, qlin, now, out, ws, counts)
    if j >= 0:
        return j
    f1, f, g1 = out.f, now.f, out.g
    changed = False
    for s in range(f.shape[0]):
        if f1[s] != f[s]:
            changed = True
            break
    if changed:
        end_load(f1, links.G, links.bounds, links.gmodes, g1)
    else:  # the same remainders: the same end load, bit for bit
        g0 = now.g
        for i in range(n):
            g1[i] = g0[i]
    for i in range(n):
        for r in range(3):
            z[i, r] = z[i, r] - B[i, r, 1] * g1[i]
    return -1


@njit
def spring_step(laws, A, B, z, p0, p1, h, links, S, now, out):
    """A step of h [s] from z (n, 3) of a model with links and no force depending on the step's end
    (the driver's Python step, ``Driver.spring_trial``): :func:`_step_with_links`, as the compiled
    :func:`stretch` takes each of its steps. p0, p1 (n,) the modal loads at the ends (p0 with the links'
    -g0); S (ns, ns) the step's compliance; writes the trial ``out``. Returns (j, z1): the index of a
    group whose Newton diverged, or -1, and the end state (n, 3)."""
    n = z.shape[0]
    ws = newton_work(links.bounds, n)
    compliance_load(now.f, S, links.bounds, ws.sf)
    z1 = np.empty((n, 3))
    j = _step_with_links(laws, A, B, z, p0, p1, h, LinkPass(links, now, out), S, ws,
                         np.zeros((links.tol.shape[0], 3), dtype=np.int64), z1)
    return j, z1


@njit
def stretch(laws, tr, modes, ground, z, k0, k1, rec, geo, tol, run):
    """Grid steps k0 -> k1 of a model with links, until a slab pair comes within the contact tolerance.

    Each step is the driver's Python step without contact (``Driver.spring_trial`` and
    ``Driver.commit``): :func:`_step_with_links` (the modal step with the remainders' start load -g,
    the links' Newton, the end load), the energy audit (the remainders' work booked to
    ``run.record.work`` per building and to the contact column as the Python path books it), the records.
    After the step every slab pair is checked (:func:`~pounding.framework.engine.pairs.pair_gap`'s cascade): when a pair ends within
    ``tol`` of contact (or overlapping), the step is rolled back (state, links and energy
    untouched) and the stretch returns (k, OVERLAP, pair): the driver takes that step in Python,
    where contact is handled. A model without pairs (contact off) steps to k1.

    Parameters
    ----------
    laws : tuple of compiled functions
        The run's link laws' updates (:func:`pounding.framework.engine.links.law_tuple`).
    tr, modes, ground, rec, geo : the driver's bundles (:mod:`pounding.framework.engine.bundles`)
    z : (n, 3) modal state, updated in place
    k0, k1 : int, the grid steps to take
    tol : contact tolerance [m]
    run : :class:`~pounding.framework.engine.bundles.LinkStepping`, the links, the grid step's
        compliance, the committed links and their record (the last two updated in place)

    Returns
    -------
    :class:`~pounding.framework.engine.bundles.StretchEnd` (k, status, pair): grid index reached; Status.DONE, OVERLAP (the state is the start of step k)
    or DIVERGED (Newton failed in step k, state at its start); the pair that stopped it, or -1.
    """
    # the bundles unpacked once, by name: the leaves called at every step take arrays
    A, B = tr.A, tr.B
    L = modes.L
    dt, ag = ground.dt, ground.ag
    every, E, slab_peak = rec.every, rec.E, rec.peak
    rows, n_modes, slab_building = geo.rows, geo.n_modes, modes.slab_building
    pa, pb, off, radii, rest = geo.pa, geo.pb, geo.off, geo.radii, geo.rest
    links, S, now, lrec = run.links, run.S, run.now, run.record
    bounds = links.bounds
    f, g, state = now.f, now.g, now.state
    work, counts, hist = lrec.work, lrec.counts, lrec.hist
    n = z.shape[0]
    ns = f.shape[0]
    nb = work.shape[0]
    z0 = np.empty((n, 3))
    f1 = np.empty(ns)
    g1 = np.empty(n)
    trial = state.copy()  # slots a law does not write (a narrower law than the widest) keep their values
    ftot0 = np.empty(n)
    ftot1 = np.empty(n)
    w = np.empty(n)
    pg0 = np.empty(n)
    pg1 = np.empty(n)
    pp0 = np.empty(n)
    per = np.empty(nb)
    da = np.empty(3)
    db = np.empty(3)
    q1 = np.empty(n)  # the end displacements, for the pair check
    xw = np.empty(4)
    out = LinkTrial(f1, trial, g1)
    ws = newton_work(bounds, n)
    spr = LinkPass(links, now, out)
    compliance_load(f, S, bounds, ws.sf)  # S f, kept until f changes (the same numbers spring_step computes)
    none = np.zeros(n)  # no contact force in a free step
    ends = StepEnds(z0, z, none, none)
    buf = (per, w, ftot0, ftot1, np.zeros(n), np.zeros(n), xw)
    for k in range(k0, k1):
        ag0 = ag[k]
        ag1 = ag[k + 1]
        for i in range(n):
            z0[i, 0] = z[i, 0]
            z0[i, 1] = z[i, 1]
            z0[i, 2] = z[i, 2]
        for i in range(n):
            # the Python step's loads: load(t) + fc - g0 with fc = 0, and load(t + h)
            pg0[i] = modal_load(L, i, ag0)
            pg1[i] = modal_load(L, i, ag1)
            pp0[i] = (pg0[i] + 0.0) - g[i]
        if _step_with_links(laws, A, B, z0, pp0, pg1, dt, spr, S, ws, counts, z) >= 0:
            for i in range(n):
                z[i, 0] = z0[i, 0]
                z[i, 1] = z0[i, 1]
                z[i, 2] = z0[i, 2]
            return StretchEnd(k, Status.DIVERGED, -1)
        changed = False  # (S f is renewed on commit when the remainders changed)
        for s in range(ns):
            if f1[s] != f[s]:
                changed = True
                break
        # contact check: within the tolerance, the Python step decides
        for i in range(n):
            q1[i] = z[i, 0]
        for p in range(pa.shape[0]):
            # the rest-gap bound inline first (most steps of most pairs end there: a call per pair and
            # step with the pair arrays cost more than the bound), then pair_gap's cascade; within the
            # tolerance (or overlapping) the Python step decides
            ba, bb = pa[p, 0], pb[p, 0]
            sa, sb = off[ba] + pa[p, 1], off[bb] + pb[p, 1]
            slab_dofs(rows, off, n_modes, ba, pa[p, 1], q1, da)
            slab_dofs(rows, off, n_modes, bb, pb[p, 1], q1, db)
            if clearance_bound(rest[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb]) > tol:
                continue
            if dofs_gap(da, db, p, tol, geo)[0] <= tol:
                for i in range(n):
                    z[i, 0] = z0[i, 0]
                    z[i, 1] = z0[i, 1]
                    z[i, 2] = z0[i, 2]
                return StretchEnd(k, Status.OVERLAP, p)
        # the energy audit, as Driver.commit books a step with links (accumulate_with_springs)
        book_links(tr, modes, dt, ag0, ag1, pg0, pg1, ends, E, run, out, buf)
        # commit the links
        if changed:
            compliance_load(f1, S, bounds, ws.sf)
        _commit_links(links, out, ws.kt, now, lrec)
        if every > 1:
            update_peaks(rows, off, z0, z, dt, n_modes, slab_building, slab_peak)
        _record(z, k + 1, rec)
        record_links(state, k + 1, every, hist)
    return StretchEnd(k1, Status.DONE, -1)


@njit(borrowed=True)
def _commit_links(links, out, kt, now, lrec):
    """Commit a step's trial links ``out`` and their tangents kt (ns,) into ``now`` (:func:`commit_trial`),
    counting the tangent changes (a link yields or unloads: its tangent moves by more than 1e-9 of the
    larger of k0 and its last tangent) per group in ``lrec.counts[:, 2]`` and remembering the tangents
    (:class:`LinkRecord`)."""
    bounds, k0 = links.bounds, links.k0
    tangent, counts = lrec.tangent, lrec.counts
    for j in range(bounds.shape[0] - 1):
        for s in range(bounds[j], bounds[j + 1]):
            if abs(kt[s] - tangent[s]) > 1e-9 * max(k0[s], abs(tangent[s])):  # (a damper: k0 = 0)
                counts[j, 2] += 1
            tangent[s] = kt[s]
    commit_trial(now, out, lrec.peak)


@njit(borrowed=True)
def book_links(tr, modes, h, ag0, ag1, p0, p1, st, E, run, out, buf):
    """Book a step of h [s] with links: ``st`` its start and end states z0, z1 and modal contact forces
    f0, f1 (:class:`~pounding.framework.engine.bundles.StepEnds`, or a held step), ``run`` the links
    (:class:`~pounding.framework.engine.bundles.LinkStepping`: the committed remainders' load -g at
    the start, ``run.now.g``; ``out`` the trial's, at the end). The contact forces and the remainders'
    loads go to the energy audit E (:func:`~pounding.framework.engine.kernel._accumulate`), the
    remainders' work (by the integrator's rule, :func:`spring_work`, on the ground loads p0, p1) to
    the contact column and ``run.record.work`` per building, and the links between slabs' part of it
    to ``run.record.joined_work``: what the driver's Python step books
    (``Driver.accumulate_with_springs``), for the compiled stretch and the held steps alike. ``buf``:
    work arrays (per (nb,), then five (n,), then (4,))."""
    per, w, ftot0, ftot1, gx0, gx1, xw = buf
    z0, z1, f0, f1 = st.z0, st.z1, st.f0, st.f1
    bidx = modes.bidx
    g, g1 = run.now.g, out.g
    lrec = run.record
    n = z0.shape[0]
    for i in range(n):
        ftot0[i] = f0[i] - g[i]
        ftot1[i] = f1[i] - g1[i]
    _accumulate(tr, modes, h, ag0, ag1, z0, z1, ftot0, ftot1, E, xw)
    spring_work(tr, h, p0, p1, z0, z1, ftot0, ftot1, g, g1, w)
    _add_per_building(w, bidx, per)
    work, joined_work = lrec.work, lrec.joined_work
    for b in range(per.shape[0]):
        E[b, 2] += per[b]
        work[b] += per[b]
    if _has_joins(run.links):  # the links between slabs' part of it, by the same rule
        joined_load(run.now.f, run.links, gx0)
        joined_load(out.f, run.links, gx1)
        spring_work(tr, h, p0, p1, z0, z1, ftot0, ftot1, gx0, gx1, w)
        _add_per_building(w, bidx, per)
        for b in range(per.shape[0]):
            joined_work[b] += per[b]


@njit(borrowed=True)
def _add_per_building(w, bidx, per):
    """per (nb,) <- the sum of w (n,) over each building's modes (bidx), in mode order (numpy's bincount)."""
    for b in range(per.shape[0]):
        per[b] = 0.0
    for i in range(w.shape[0]):
        per[bidx[i]] += w[i]


@njit(borrowed=True)
def record_links(state, k, every, hist):
    """hist (3, n_out, ns) <- at grid instant k, every ``every``-th, the committed deformation [m],
    force [N] and dissipated energy [J] of every link (the common state slots, ``state`` (ns, n_state)):
    the links' record, for every path that steps them."""
    if k % every != 0:
        return
    row = k // every
    for s in range(state.shape[0]):
        for c in range(3):
            hist[c, row, s] = state[s, c]


@njit(borrowed=True)
def commit_trial(now, out, peak):
    """Commit the trial links ``out`` into ``now`` (:class:`LinkTrial`: remainders, law states and their
    modal load) and raise the running peaks |deformation| ``peak`` (ns,): the links' commit, for every
    path that steps them (the compiled stretches, the held steps and the driver's Python step)."""
    f, state, g, f1, trial, g1 = now.f, now.state, now.g, out.f, out.state, out.g
    for s in range(f.shape[0]):
        f[s] = f1[s]
        for c in range(state.shape[1]):
            state[s, c] = trial[s, c]
        if abs(trial[s, 0]) > peak[s]:
            peak[s] = abs(trial[s, 0])
    for i in range(g.shape[0]):
        g[i] = g1[i]

#: the unit roundoff [-]
EPS = float(np.finfo(np.float64).eps)

#: the laws' evaluations a group's Newton may take in a step before it is declared diverged
NEWTON_CAP = 40 * MAX_ITER
