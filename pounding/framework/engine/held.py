"""Rigid sustained contact, compiled: the held step, the plastic stop and a run of held steps.

A pair whose impacts accumulate (a Zeno sequence) or that is pressed together
is *held*: a rigid unilateral contact force, carried from step to step as a load
like any other, so each step and its energy audit are the integrator's own.

* :func:`held_step` takes one step of any size with the held pairs' contact
  forces on the points that touch at its start (used by the driver for every trial,
  including an impact search). With the ``crossing`` locator a point touches within
  :func:`touch_gap` (1e-3 of the tolerance); a point of a held pair that is apart moves
  freely through the step, and where it ends the step overlapping it *arrives*: the
  step reports the smallest such gap and its pair, and the driver locates the instant
  at which that gap is zero on the held trajectory (its one crossing search), steps
  there and strikes the pair with the contact law's impulses, every touching point of
  the pair taking part in the same impulse problem, like any impact. The paper's rules
  hold every point within the tolerance, so nothing arrives;
* :func:`stop_closing` removes what closing speed a held pair's touching
  points still have (a plastic impact: the limit of the Zeno sequence), at the start
  of every held step;
* :func:`held_stretch` runs grid steps while pairs are held and nothing else
  happens, and stops for the driver when a free pair touches or overlaps, or a
  point of a held pair arrives.

The driver's Python path calls the first two step by step; the stretch calls
the very same functions, so both paths give the same numbers. With yielding storey
springs (links with laws) a held step is :func:`held_fixed_point` (their end remainders
by a fixed point around :func:`held_step`), in the Python step and in the stretch alike. Like
:mod:`pounding.framework.engine.kernel`, everything runs compiled by numba or, without
numba, as plain Python with the same arithmetic.
"""

from __future__ import annotations

import numpy as np

from pounding.contact.base import keep_pushing, newton_lcp, solve_small
from pounding.compiler import njit
from pounding.framework.engine.bundles import Features, HeldContact, HeldFixedPoint, HeldSet, HeldStep, LinkPass, LinkTrial, Status, StretchEnd
from pounding.framework.engine.crossing import suspect
from pounding.framework.engine.ground_load import modal_load
from pounding.framework.engine.kernel import _accumulate_forces, _record, update_peaks
from pounding.framework.engine.inelastic import MAX_ITER
from pounding.framework.engine.pairs import closing, pair_features, pair_gap, slab_dofs, struck_features
from pounding.framework.engine.spring_core import RELAXATION, book_links, commit_trial, fixed_point_pass, record_links
from pounding.framework.engine.modal_step import stepped

#: struck_features's ``deep`` from compiled callers: a typed bool, not a literal True, so that they
#: and the driver share one specialization
_DEEP = np.bool_(True)


@njit
def chatter_duration(z, p_ext, p, restitution, tol, modes, geo):
    """How long [s] the impact sequence pair p starts, just struck, lasts at most (the Zeno bound).

    After a rebound at opening speed r = w . q' against a closing relative acceleration
    a = -w . q'' (q'' = p_ext - 2 zeta omega q' - omega^2 q, the modal state z (n, 3) and the
    modal loads other than the structure's own, p_ext (n,)), restitution k gives impacts that
    accumulate within 2 r / (a (1 - k)) [s] and end with the points moving together. The shortest
    over the pair's touching features (within ``tol`` [m]) that close (a > 0); inf where none
    closes, none touches, or k >= 1 (no sequence ends)."""
    if restitution >= 1.0:
        return np.inf
    n = z.shape[0]
    touching = pair_features(z[:, 0].copy(), p, tol, n, geo)
    W = touching.W
    c2, om2 = modes.c2, modes.om2
    best = np.inf
    for f in range(touching.count):
        r = 0.0
        a = 0.0
        for i in range(n):
            r += W[f, i] * z[i, 1]
            a -= W[f, i] * (p_ext[i] - c2[i] * z[i, 1] - om2[i] * z[i, 0])
        if a > 0.0:
            best = min(best, 2.0 * max(r, 0.0) / (a * (1.0 - restitution)))
    return best


@njit
def rigid_forces(gap, S):
    """Unilateral constraint forces lambda >= 0 (m,) closing the penetrations gap < 0 (m,) [m]:
    S lambda = -gap on the active set, S (m, m) the compliance [m/N]."""
    m = gap.shape[0]
    active = gap < 0
    lam = np.zeros(m)
    for _ in range(m + 1):
        idx = np.nonzero(active)[0]
        na = idx.shape[0]
        if na == 0:
            return lam
        sub = np.empty((na, na))
        rhs = np.empty(na)
        for r in range(na):
            rhs[r] = -gap[idx[r]]
            for s in range(na):
                sub[r, s] = S[idx[r], idx[s]]
        if keep_pushing(idx, solve_small(sub, rhs), lam, active):
            return lam
    return np.maximum(lam, 0.0)


@njit
def _weighted_compliance(W, D):
    """W diag(D) W^T for rows W (m, n) and weights D (n,)."""
    return (W * D) @ W.T


@njit
def step(A, B, z, p0, p1):
    """z1 (n, 3) = A z + B[:, :, 0] p0 + B[:, :, 1] p1, mode by mode (the kernel's arithmetic)."""
    n = z.shape[0]
    z1 = np.empty((n, 3))
    for i in range(n):
        for r in range(3):
            z1[i, r] = stepped(A, B, i, r, z, p0[i], p1[i])
    return z1


@njit
def held_step(z, g0, g1, A, B, h, modes, held, geo):
    """One step of size h [s] from state z (n, 3) with the pairs of ``held`` in rigid sustained contact.

    held : :class:`~pounding.framework.engine.bundles.HeldSet`, the held pairs, the contact
    settings (the tolerance and the gap ``touch`` [m] up to which a point touches, :func:`touch_gap`;
    inf: every point within the tolerance, the paper's rules) and the held pairs' touching features
    at the start. Only the points that touch at the step's start are held. A
    touching point that would close within the step has its normal velocity projected out at the
    start: rounding for points at rest, and for a point that opens but falls back within the step
    (a rebound too short for the step) the limit of its chatter, as when a pair is held. A point
    that opens and stays open through the step gets no force. A point that is apart at the start (gap above
    ``touch``) gets no force: it moves with its slabs through the step, and the smallest end gap
    of such points is returned (``arrival``), for the caller to locate and strike where it is zero.
    ``held.start``: the touching features at the start, a
    :class:`~pounding.framework.engine.bundles.Features`
    (:func:`~pounding.framework.engine.pairs.struck_features` with ``deep``; its pairs, gaps (m,),
    modal rows (m, n) and contact points (m, 2) are read).
    g0, g1 (n,) are the modal loads at the step's ends; A (n, 3, 3),
    B (n, 3, 2) the integrator's transition for h; ``modes`` the
    :class:`~pounding.framework.engine.bundles.Modes` (c2 = 2 zeta omega and
    om2 = omega^2 (n,) are read). Unilateral and rigid: no touching point of a held pair
    closes further during the step than it was at its start (never deeper than
    half the tolerance) and no force pulls (the projection at the start is bilateral, and
    takes kinetic energy out: it is orthogonal in the modes' mass-normalised metric).

    * Implicit schemes (the end displacement depends on the end load): at the
      start, the force that stops the normal acceleration of the touching points
      that would close (consistent with zero closing speed after
      :func:`stop_closing`); at the end, the force that holds the points where
      they started, solved with the step's compliance W diag(B[:, 0, 1]) W^T.
    * Explicit schemes (the end displacement depends on the start load only,
      central differences): the start force that holds the points at the end of
      the step (the forward-increment Lagrange multiplier), kept through the step.

    Features are re-found on the corrected state (they slide as the slabs turn;
    two faces may be pressed at once) for up to four passes. An end feature is a point that
    touched at the start when it lies where one did, within how far the pair's slabs move in the
    step (:func:`same_contact`): a contact point moves with the slabs, while another point of
    the pair is elsewhere on them. (Its gap at the start linearised back from the end is no
    test: at a corner against a corner the normal turns as the slabs slide past each other.)

    Returns a :class:`~pounding.framework.engine.bundles.HeldStep`: the start state with its
    acceleration consistent with f0, the end state, the modal contact forces at the ends, the held
    pairs' features at the end state (the next step's ``start``), and the smallest end gap of a
    point that was apart at the start with its pair.
    """
    c2, om2 = modes.c2, modes.om2
    plist, contact, start = held.pairs, held.contact, held.start
    tol, touch = contact.tol, contact.touch
    pair0, gap0, W, Q0 = start.pair, start.gap, start.W, start.Q
    n = z.shape[0]
    z0 = z.copy()
    for i in range(n):
        z0[i, 2] = g0[i] - c2[i] * z[i, 1] - om2[i] * z[i, 0]  # without contact force
    f0 = np.zeros(n)
    explicit = True
    for i in range(n):
        if abs(B[i, 0, 1]) > 1e-12 * h * h:
            explicit = False
    q0 = z[:, 0].copy()
    zf = step(A, B, z0, g0 + f0, g1 + f0)
    m = gap0.shape[0]
    touching = gap0 <= touch
    if m > 0:
        free_end = gap0 + W @ (zf[:, 0] - q0)
        target = np.minimum(np.maximum(gap0, -0.5 * tol), 0.0)
        # Points pressed together move together: what normal velocity they still have (rounding,
        # after stop_closing) is projected out. A position constraint alone leaves it free, and
        # some schemes amplify it from step to step (linear acceleration: by -2 per step). A
        # touching point that opens but would close again within the step is chatter too short
        # for the step: projected (its limit), not pushed by the start force while it opens
        # (work the contact would do on the buildings). A rebound that stays open is left alone.
        # Only what touches is held. A point that is apart gets no force, even if it would reach
        # contact within the step: that is an impact, which the caller locates and strikes with
        # the law (a force here would stop it before it touches, or push it back over the step).
        pressed = (free_end < target) & touching
        if np.any(pressed):
            Wa = rows_where(pressed, W)
            mu = solve_small(Wa @ Wa.T, Wa @ z0[:, 1].copy())
            dv = Wa.T @ mu
            for i in range(n):
                z0[i, 1] -= dv[i]
                z0[i, 2] = g0[i] - c2[i] * z0[i, 1] - om2[i] * z0[i, 0]
            zf = step(A, B, z0, g0 + f0, g1 + f0)
            free_end = gap0 + W @ (zf[:, 0] - q0)
        arg = np.ones(m)
        if explicit:
            D0 = A[:, 0, 2] + B[:, 0, 0]
            for k in range(m):
                if touching[k] and free_end[k] < target[k]:
                    arg[k] = free_end[k] - target[k]
            lam = rigid_forces(arg, _weighted_compliance(W, D0))
        else:
            acc = W @ z0[:, 2].copy()
            for k in range(m):
                if touching[k] and free_end[k] < target[k]:
                    arg[k] = acc[k]
            lam = rigid_forces(arg, W @ W.T)
        if np.any(lam > 0):
            f0 = W.T @ lam
            for i in range(n):
                z0[i, 2] += f0[i]
            zf = step(A, B, z0, g0 + f0, g1 + (f0 if explicit else 0.0 * f0))
    f1 = f0.copy() if explicit else np.zeros(n)
    z1 = zf
    grow = np.empty((n, 3))
    for i in range(n):
        for r in range(3):
            grow[i, r] = A[i, r, 2] + B[i, r, 0] + B[i, r, 1] if explicit else B[i, r, 1]
    D = grow[:, 0].copy()
    found = False
    for attempt in range(4):
        end = struck_features(z1[:, 0].copy(), plist, tol, _DEEP, n, geo)
        fpair, g1f, Wr, Q1 = end.pair, end.gap, end.W, end.Q
        found = True
        m = g1f.shape[0]
        if m == 0:
            break
        # the points that touched are held where each started (linearised), but never deeper than
        # half the tolerance (features slide as the slabs turn, and the linearised start drifts
        # with them); a point that was apart is not held (an arrival, for the caller)
        kept = _kept(fpair, Q1, pair0, Q0, touching, z1[:, 0] - q0, plist, touch, tol, geo)
        target = np.minimum(np.maximum(g1f - Wr @ (z1[:, 0] - q0), -0.5 * tol), 0.0)
        short = g1f - target
        arg = np.ones(m)
        worst = 0.0
        for k in range(m):
            if kept[k] and short[k] < 0:
                arg[k] = short[k]
                worst = min(worst, short[k])
        # the first pass closes every shortfall; later ones only what linearisation left
        if worst >= (0.0 if attempt == 0 else -1e-3 * tol):
            break
        lam = rigid_forces(arg, _weighted_compliance(Wr, D))
        if not np.any(lam > 0):
            break
        found = False
        df = Wr.T @ lam
        z1 = z1.copy()
        for i in range(n):
            for r in range(3):
                z1[i, r] += grow[i, r] * df[i]
            if explicit:
                f0[i] += df[i]
                z0[i, 2] += df[i]
            f1[i] += df[i]
    if not found:  # the last pass moved the slabs: the features of the end state itself
        end = struck_features(z1[:, 0].copy(), plist, tol, _DEEP, n, geo)
        fpair, g1f, Q1 = end.pair, end.gap, end.Q
    kept = _kept(fpair, Q1, pair0, Q0, touching, z1[:, 0] - q0, plist, touch, tol, geo)
    arrival = np.inf
    apair = -1
    for k in range(g1f.shape[0]):
        if not kept[k] and g1f[k] < arrival:
            arrival = g1f[k]
            apair = fpair[k]
    return HeldStep(z0, z1, f0, f1, end, arrival, apair)


@njit
def _kept(pair1, Q1, pair0, Q0, touching0, dq, held, touch, tol, geo):
    """Which end features (pairs pair1 (k,), points Q1 (k, 2)) a held step holds: with the crossing
    locator the points that touched at the start (:func:`same_contact`, within how far the slabs
    moved over dq (n,), :func:`slide_bound`, plus the tolerance), with the paper's rules
    (``touch`` inf) every one. A bool mask (k,)."""
    if touch == np.inf:
        return np.ones(pair1.shape[0], dtype=np.bool_)
    return same_contact(pair1, Q1, pair0, Q0, touching0, slide_bound(dq, held, geo) + tol)


@njit
def slide_bound(dq, plist, geo):
    """How far [m] a contact point of a pair in plist (k,) int can move over a modal displacement
    dq (n,), the largest over the pairs: a point of a slab moves at most |(du, dv)| + R |dphi| (R
    the slab's radius); summed over the pair's two slabs, this also bounds where a contact between
    them can slide to (a face-to-face end passing from a vertex of one slab to one of the other)."""
    d = np.empty(3)
    pa, pb, rows, off, n_modes, radii = geo.pa, geo.pb, geo.rows, geo.off, geo.n_modes, geo.radii
    out = 0.0
    for j in range(plist.shape[0]):
        p = plist[j]
        bound = 0.0
        for side in range(2):
            building, storey = (pa[p, 0], pa[p, 1]) if side == 0 else (pb[p, 0], pb[p, 1])
            slab_dofs(rows, off, n_modes, building, storey, dq, d)
            bound += np.hypot(d[0], d[1]) + radii[off[building] + storey] * abs(d[2])
        out = max(out, bound)
    return out


@njit
def same_contact(pair1, Q1, pair0, Q0, touching0, reach):
    """Which end features (pairs pair1 (k,), contact points Q1 (k, 2) [m]) are points that touched at
    the start: a start feature of the same pair (pair0 (m,), Q0 (m, 2)) with ``touching0`` (m,) set
    lies within ``reach`` [m] of it. A bool mask (k,)."""
    out = np.zeros(pair1.shape[0], dtype=np.bool_)
    for k in range(pair1.shape[0]):
        for j in range(pair0.shape[0]):
            if touching0[j] and pair0[j] == pair1[k] and np.hypot(Q1[k, 0] - Q0[j, 0], Q1[k, 1] - Q0[j, 1]) <= reach:
                out[k] = True
                break
    return out


@njit(borrowed=True)
def book_velocity_change(E, bidx, v_old, v_new):
    """Book the kinetic-energy change of a velocity jump v_old -> v_new (n,) as contact work,
    E[:, 2] of each mode's building [J] (mass-normalised modes: 1/2 v^2 per mode)."""
    for i in range(v_old.shape[0]):
        if v_new[i] != v_old[i]:
            E[bidx[i], 2] += 0.5 * v_new[i] ** 2 - 0.5 * v_old[i] ** 2


@njit
def stop_closing(z, W, v_min):
    """Plastic impulses (restitution 0) on the touching points (modal rows W (m, n)) of held
    pairs that close faster than v_min [m/s]; updates the velocities z[:, 1] in place.
    Returns the velocity change (n,) (all zero when nothing closed).

    Points that cannot push on one another (W W^T block-diagonal up to rounding: pairs at
    different storeys, with every mode kept) are solved group by group, so the enumerating
    LCP sees at most one pair's features (MAX_FEATURES) in the usual two-building scene.
    """
    n = z.shape[0]
    dv = np.zeros(n)
    m = W.shape[0]
    if m == 0:
        return dv
    b = -(W @ z[:, 1].copy())
    closing = False
    for k in range(m):
        if b[k] > v_min:
            closing = True
        else:
            b[k] = min(b[k], 0.0)
    if not closing:
        return dv
    D = W @ W.T
    group = np.arange(m)  # coupled points share a group (label = smallest index)
    for a in range(m):
        for c in range(a + 1, m):
            if abs(D[a, c]) > 1e-12 * np.sqrt(D[a, a] * D[c, c]):
                ga, gc = group[a], group[c]
                lo, hi = min(ga, gc), max(ga, gc)
                for k in range(m):
                    if group[k] == hi:
                        group[k] = lo
    for g in range(m):
        idx = np.nonzero(group == g)[0]
        if idx.shape[0] == 0:
            continue
        bg = b[idx]
        if not np.any(bg > v_min):
            continue
        Dg = np.empty((idx.shape[0], idx.shape[0]))
        for r in range(idx.shape[0]):
            for c in range(idx.shape[0]):
                Dg[r, c] = D[idx[r], idx[c]]
        I = newton_lcp(Dg, bg, 0.0)
        for r in range(idx.shape[0]):
            if I[r] != 0.0:
                for i in range(n):
                    dv[i] += W[idx[r], i] * I[r]
    for i in range(n):
        z[i, 1] += dv[i]
    return dv


@njit(borrowed=True)
def touch_gap(tol):
    """The gap [m] up to which a point of a held pair touches, with the crossing locator: the held
    contact's own resolution, 1e-3 of the tolerance tol [m] (held_step's end passes stop when every
    point is within it of where it is held). A point farther away is apart: no force acts on it,
    and where it reaches contact the driver strikes it with the contact law (:func:`held_step`)."""
    return 1e-3 * tol


@njit
def rows_where(mask, W):
    """The rows of W (m, n) where mask (m,) bool is set, in order (a new C array): the points of a
    held pair that touch or are pressed."""
    out = np.empty((int(np.sum(mask)), W.shape[1]))
    c = 0
    for k in range(mask.shape[0]):
        if mask[k]:
            out[c] = W[k]
            c += 1
    return out


@njit
def held_fixed_point(laws, z, p0, p1, A, B, h, modes, held, geo, spr):
    """A held step of h [s] (:func:`held_step`) of a model with links with laws (yielding storey
    springs): the links' end remainders by a fixed point around it.

    The links' remainders are loads like the ground's: -g0 at the start (the committed ``spr.now.g``)
    and -g1 at the end, g1 iterated (:func:`~pounding.framework.engine.spring_core.fixed_point_pass`:
    plain substitution, then under-relaxed, ``RELAXATION``) until the links' end deformations agree to
    their groups' Newton tolerances. p0, p1 (n,) the ground motion's modal loads at the step's ends;
    tr the :class:`~pounding.framework.engine.bundles.Transition` of h (A and B are read); ``laws``
    the run's law updates (:mod:`pounding.framework.engine.links`); ``spr`` the
    :class:`~pounding.framework.engine.bundles.LinkPass` (the links' trial ``spr.out`` is written);
    the rest as :func:`held_step`. The driver's Python step and :func:`held_stretch` both take held
    steps of models with links through this function.

    Returns a :class:`~pounding.framework.engine.bundles.HeldFixedPoint`: Status.DONE, or
    Status.DIVERGED when the fixed point did not converge (its step is then the last pass's), and the
    :func:`held_step`, with the links' loads not in its f0, f1 (the contact forces only).
    """
    links, now, out = spr.links, spr.now, spr.out
    g_now, state = now.g, now.state  # (a bundle's array read in a loop costs a reference count each time)
    n = z.shape[0]
    ns = now.f.shape[0]
    e0 = np.empty(n)
    e1 = np.empty(n)
    g = np.empty(n)
    prev = np.empty(ns)
    for i in range(n):
        e0[i] = p0[i] - g_now[i]
    q1 = np.empty(n)
    for w in RELAXATION:
        for i in range(n):
            g[i] = g_now[i]
        for s in range(ns):
            prev[s] = state[s, 0]
        for _ in range(4 * MAX_ITER):
            for i in range(n):
                e1[i] = p1[i] - g[i]
            st = held_step(z, e0, e1, A, B, h, modes, held, geo)
            z1 = st.z1
            for i in range(n):
                q1[i] = z1[i, 0]
            if fixed_point_pass(laws, links, h, q1, now, out, g, prev, w):
                return HeldFixedPoint(Status.DONE, st)
    return HeldFixedPoint(Status.DIVERGED, st)


@njit
def held_stretch(tr, modes, ground, z, held_pairs, k0, k1, rec, geo, settings, rules, laws, run):
    """Run grid steps k0 -> k1 while pairs are held and nothing else happens.

    Bundles and ``rules`` (None: the crossing locator; True: the paper's rules, the other
    branch pruned before compiling) as in :func:`pounding.framework.engine.free_stretch.advance`, plus
    ``held_pairs``, the :class:`~pounding.framework.engine.bundles.HeldPairs` (the contact force at
    the current instant and the held pairs, both updated in place).
    Each step: :func:`stop_closing` on the held pairs' touching points (with ``rules`` None) or
    their points within the tolerance (the paper's rules), its kinetic-energy change booked as contact work,
    :func:`held_step`, then the same checks as the driver's Python step.

    A model with links with laws (yielding storey springs) passes the run's law updates ``laws`` and
    the :class:`~pounding.framework.engine.bundles.LinkStepping` ``run`` (its compliance is not read);
    without them both are None, and their branches are pruned before compiling. Every step is then
    :func:`held_fixed_point`, booked as the driver's Python step books it (``Driver.commit`` with the
    links: the contact forces' and the remainders' loads in the energy audit, the remainders' work
    to ``run.record.work``, the links committed and recorded).

    Returns a :class:`~pounding.framework.engine.bundles.StretchEnd` (k, status, pair): the grid index reached and a
    :class:`~pounding.framework.engine.bundles.Status`: DONE (k1 reached), RELEASED (every held
    pair let go at the end of step k - 1), OVERLAP (in step k a point of held pair ``pair``
    arrives, or free pair ``pair`` would overlap: the state and the energy account are as at its
    start, for the driver's Python step to locate the impact), CONTACT (a free pair touches and
    closes at the end of step k - 1) or, with links, DIVERGED (the fixed point did not converge in
    step k; the state is its start).
    """
    fc, held_mask = held_pairs.fc, held_pairs.mask
    A, B = tr.A, tr.B
    L, bidx = modes.L, modes.bidx
    dt, ag = ground.dt, ground.ag
    E, every, peak, slab_building = rec.E, rec.every, rec.peak, modes.slab_building
    rows, n_modes = geo.rows, geo.n_modes
    tol, overlap, v_min = settings.tol, settings.overlap, settings.v_min
    n = z.shape[0]
    P = geo.pa.shape[0]
    g0 = np.empty(n)
    g1 = np.empty(n)
    touch = touch_gap(tol) if rules is None else np.inf
    contact = HeldContact(tol, touch)
    have = False  # start features known (the last step's end features)
    none = np.empty(0, dtype=np.int64)
    startS = Features(none, np.empty(0), np.empty((0, n)), np.empty((0, 2)), np.empty((0, 2)), none, none, none)
    if run is not None:
        now, lrec = run.now, run.record
        spr = LinkPass(run.links, now, LinkTrial(np.empty(now.f.shape[0]), now.state.copy(), np.empty(n)))
        nb = lrec.work.shape[0]
        per, w, ftot0, ftot1 = np.empty(nb), np.empty(n), np.empty(n), np.empty(n)
        buf = (per, w, ftot0, ftot1, np.empty(n), np.empty(n), np.empty(4))
    for k in range(k0, k1):
        held = np.nonzero(held_mask)[0]
        if not have:
            startS = struck_features(z[:, 0].copy(), held, tol, _DEEP, n, geo)
        v_before = z[:, 1].copy()
        E_before = E.copy()
        # the points that touch (crossing), every point within the tolerance with the paper's rules (touch = inf)
        stop_closing(z, rows_where(startS.gap <= touch, startS.W), v_min)
        book_velocity_change(E, bidx, v_before, z[:, 1].copy())
        for i in range(n):
            g0[i] = modal_load(L, i, ag[k])
            g1[i] = modal_load(L, i, ag[k + 1])
        now_held = HeldSet(held, contact, startS)
        if run is None:
            st = held_step(z, g0, g1, A, B, dt, modes, now_held, geo)
        else:
            fixed = held_fixed_point(laws, z, g0, g1, A, B, dt, modes, now_held, geo, spr)
            if fixed.status != Status.DONE:
                for i in range(n):
                    z[i, 1] = v_before[i]
                E[:, :] = E_before
                return StretchEnd(k, Status.DIVERGED, -1)
            st = fixed.step
        z0, z1, f0, f1, startS, arrival, apair = st.z0, st.z1, st.f0, st.f1, st.end, st.arrival, st.apair
        have = True
        if arrival < overlap:  # a point of a held pair arrives: the driver locates and strikes it
            for i in range(n):
                z[i, 1] = v_before[i]
            E[:, :] = E_before
            return StretchEnd(k, Status.OVERLAP, apair)
        # a free pair that would overlap: the driver locates the impact
        for p in range(P):
            if held_mask[p]:
                continue
            # the crossing locator (rules None) also searches a step the pair may graze
            if rules is None:
                touches = suspect(z0, z1, p, dt, -overlap, tol, geo)
            else:
                touches = pair_gap(z1[:, 0].copy(), p, tol, geo) < overlap
            if touches:
                # back to the step's start as it was: the driver's Python step stops and books anew
                for i in range(n):
                    z[i, 1] = v_before[i]
                E[:, :] = E_before
                return StretchEnd(k, Status.OVERLAP, p)
        book_velocity_change(E, bidx, z[:, 1].copy(), z0[:, 1].copy())  # pressed points' start velocity projected (held_step)
        if run is None:
            _accumulate_forces(tr, modes, dt, ag[k], ag[k + 1], z0, z1, f0, f1, E)
        else:
            book_links(tr, modes, dt, ag[k], ag[k + 1], g0, g1, st, E, run, spr.out, buf)
            commit_trial(now, spr.out, lrec.peak)
        for i in range(n):
            z[i, 0] = z1[i, 0]
            z[i, 1] = z1[i, 1]
            z[i, 2] = z1[i, 2]
            fc[i] = f1[i]
        if every > 1:
            update_peaks(rows, geo.off, z0, z1, dt, n_modes, slab_building, peak)
        _record(z, k + 1, rec)
        if run is not None:
            record_links(now.state, k + 1, every, lrec.hist)
        # release the held pairs that opened beyond the tolerance
        q = z[:, 0].copy()
        any_held = False
        for p in range(P):
            if held_mask[p]:
                if pair_gap(q, p, tol, geo) > tol:
                    held_mask[p] = False
                    have = False  # the held set changed
                else:
                    any_held = True
        # a free pair touching and closing at the step's end: the driver applies the impulses
        # (crossing: a pair within the tolerance is struck where its gap is zero, in a later step)
        if rules is not None:
            for p in range(P):
                if held_mask[p]:
                    continue
                if pair_gap(q, p, tol, geo) <= tol and closing(q, z[:, 1].copy(), p, tol, v_min, n, geo):
                    return StretchEnd(k + 1, Status.CONTACT, p)
        if not any_held:
            return StretchEnd(k + 1, Status.RELEASED, -1)
    return StretchEnd(k1, Status.DONE, -1)




