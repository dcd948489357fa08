"""The compiled no-contact stretch: many steps at once, in modal coordinates.

:func:`~pounding.framework.engine.free_stretch.advance` steps every mode of every building with its per-mode
transition, records the state at the output rate, accumulates the energy
terms, and after each step checks the slab pairs that could touch: first a
cheap lower bound on their clear distance, then the exact signed gap only
when that bound is below the tolerance. A step that ends with a pair within
the tolerance and closing gets Newton impulses right there (:func:`impulses_at`,
when the law declares them compiled) or stops the kernel (``Status.CONTACT``:
the state is the end of that step); a step that ends overlapping stops it with
the state rolled back to the step's start (``Status.OVERLAP``), so that the
driver can locate the impact. :func:`advance_free` is the same stepping with no
pair to watch (contact off): it compiles and loads no contact code.

The entry points take the bundles of :mod:`pounding.framework.engine.bundles`. The same
functions run compiled by numba (:mod:`pounding.compiler`, cache on, so a second
process starts warm) or as plain Python over numpy arrays when numba is missing;
the arithmetic is identical.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.contact.base import newton_group
from pounding.framework.engine.bundles import Status, StretchEnd
from pounding.framework.engine.crossing import slab_state
from pounding.framework.engine.ground_load import modal_load
from pounding.framework.engine.modal_step import stepped
from pounding.framework.engine.pairs import building_groups, touching_features
from pounding.framework.engine.peaks import cubic_abs_max


@njit
def advance_free(tr, modes, ground, z, k0, k1, rec, geo):
    """:func:`~pounding.framework.engine.free_stretch.advance` without slab pairs (contact off): grid steps k0 -> k1 with the same
    arithmetic and records, and no contact code compiled or loaded (``geo`` gives only the slabs'
    Phi rows, for their peaks). Returns (k1, DONE, -1)."""
    A, B, L = tr.A, tr.B, modes.L
    dt, ag = ground.dt, ground.ag
    E, every, peak, slab_building, rows, off, n_modes = rec.E, rec.every, rec.peak, modes.slab_building, geo.rows, geo.off, geo.n_modes
    n = z.shape[0]
    z0 = np.empty((n, 3))
    no_force = np.zeros(n)
    xw = np.empty(4)
    for k in range(k0, k1):
        _free_step(A, B, L, ag[k], ag[k + 1], z0, z)
        _accumulate(tr, modes, dt, ag[k], ag[k + 1], z0, z, no_force, no_force, E, xw)
        if every > 1:
            update_peaks(rows, off, z0, z, dt, n_modes, slab_building, peak)
        _record(z, k + 1, rec)
    return StretchEnd(k1, Status.DONE, -1)


@njit(borrowed=True)
def _free_step(A, B, L, ag0, ag1, z0, z):
    """One step of every mode: z0 <- z, then z = A z0 + B[:, :, 0] p0 + B[:, :, 1] p1 with the
    modal ground loads p0, p1 at the step's ends (ag0, ag1 (c,))."""
    n = z.shape[0]
    for i in range(n):
        z0[i, 0] = z[i, 0]
        z0[i, 1] = z[i, 1]
        z0[i, 2] = z[i, 2]
    for i in range(n):
        p0 = modal_load(L, i, ag0)
        p1 = modal_load(L, i, ag1)
        for r in range(3):
            z[i, r] = stepped(A, B, i, r, z0, p0, p1)


@njit
def impulses_at(law, t, ag, z, fc, modes, settings, dt, log, geo, candidates):
    """Impulses at time t [s] on every touching, approaching pair among ``candidates`` (P,) bool
    that is not held, solved together by the contact law: the one impulse step of every path.

    ``law`` None: the Newton rule with ``settings.restitution``
    (:func:`~pounding.contact.base.newton_group`), for a law that declares ``compiled_impulses``;
    the kernel's stretches and the driver's Python step call this function compiled so (numba
    drops the other branch, and no function is an argument of a cached function). Else ``law(D, b,
    settings, pairs) -> I``, the impulses I >= 0 [N s] (m,) of one group of features from its
    Delassus matrix D (m, m) [1/kg], closing speeds b (m,) [m/s] and the features' pairs (m,) int:
    a law only Python knows (its ``impulses(W, b)``) or walls with restitutions of their own (the
    driver's rule), for which the driver runs this same function with the compiler off
    (``impulses_at.py_func``). ag (c,) is the ground acceleration at t and fc (n,) the modal force
    acting besides the ground's (held contact, the yielding springs' remainders -g), for the
    equilibrium accelerations of ``settings.after_eq``.

    The features of every touching pair (:func:`~pounding.framework.engine.pairs.touching_features`)
    are stacked. Touching pairs linked through a shared building (a building struck from both
    sides, two storeys of one pair) form one Newton problem over all their features, with the
    Delassus matrix W = Wr Wr^T of their stacked rows
    (:func:`~pounding.framework.engine.pairs.building_groups`), when one of them approaches (a point
    closing faster than ``v_min``; slower is rounding); the others take part with their
    points that only touch (Newton's cradle). Groups share no mode, so they are independent.
    A group of one pair is the problem of that pair alone, with the same arithmetic as when
    pairs were solved one by one.

    Each impulse appends a record (:data:`~pounding.framework.engine.bundles.IMPACT_DTYPE`) to
    ``log.impacts``, in pair order; the state before the impulses at t goes to the log's event
    states unless the last one recorded (``log.last_t``) is already at t. Returns (acted,
    zeno): whether an impulse acted, and whether a pair's rebound is too slow to open the
    tolerance within one step (``log.zeno`` is set for it).
    """
    tol, v_min = settings.tol, settings.v_min
    n = z.shape[0]
    q = z[:, 0].copy()
    v = z[:, 1].copy()
    touching = touching_features(q, candidates, tol, n, geo)
    m, pair, who, vertex, Q, N, Wst = touching.count, touching.pair, touching.who, touching.vertex, touching.Q, touching.N, touching.W
    b, kept, approaching = closing_speeds(Wst, pair, m, v, v_min)
    if not np.any(approaching):
        return False, False
    label = building_groups(kept, geo)
    # a group is a Newton problem when one of its pairs approaches; its touching pairs that do
    # not approach take part (a building pushed into its other neighbour: Newton's cradle)
    live = np.zeros(kept.shape[0], dtype=np.bool_)
    for j in range(kept.shape[0]):
        if approaching[j]:
            live[label[j]] = True
    I_all = np.zeros(m)
    after_all = np.zeros(m)
    in_pair = np.full(candidates.shape[0], -1, dtype=np.int64)
    for j in range(kept.shape[0]):
        in_pair[kept[j]] = label[j]
    for g in range(kept.shape[0]):
        if label[g] != g or not live[g]:
            continue
        idx = group_features(pair, m, in_pair, g)
        Wg = Wst[idx]
        bg = b[idx]
        D = Wg @ Wg.T
        if law is None:  # the Newton rule, compiled here (numba drops the other branch)
            I = newton_group(D, bg, settings.restitution)
        else:
            I = law(D, bg, settings, pair[idx])
        after = bg - D @ I
        for r in range(idx.shape[0]):
            I_all[idx[r]] = I[r]
            after_all[idx[r]] = after[r]
    if not np.any(I_all > 0):
        return False, False
    if log.last_t[0] != t:
        ne = log.n_events[0]
        log.t[ne] = t
        lq, lv = log.q, log.v
        for i in range(n):
            lq[ne, i] = z[i, 0]
            lv[ne, i] = z[i, 1]
        log.n_events[0] += 1
        log.last_t[0] = t
    for g in range(kept.shape[0]):
        if label[g] != g or not live[g]:
            continue
        idx = group_features(pair, m, in_pair, g)
        Wg = Wst[idx]
        dv = Wg.T @ I_all[idx]
        for i in range(n):
            z[i, 1] += dv[i]
    if settings.after_eq:
        L, c2, om2 = modes.L, modes.c2, modes.om2
        for i in range(n):
            z[i, 2] = modal_load(L, i, ag) + fc[i] - c2[i] * z[i, 1] - om2[i] * z[i, 0]
    held = False
    for j in range(m):
        if I_all[j] > 0:
            r = log.n_impacts[0]
            rec = log.impacts[r]
            rec["time"] = t
            rec["pair"] = pair[j]
            rec["striker"] = who[j]
            rec["vertex"] = vertex[j]
            rec["impulse"] = I_all[j]
            rec["nx"] = N[j, 0]
            rec["ny"] = N[j, 1]
            rec["approach_velocity"] = b[j]
            rec["energy_loss"] = 0.5 * I_all[j] * (b[j] + after_all[j])
            rec["px"] = Q[j, 0]
            rec["py"] = Q[j, 1]
            log.n_impacts[0] += 1
    # Zeno: a rebound too slow to open the tolerance within one step starts a sequence
    # of ever smaller impacts that accumulates in finite time and ends with the points
    # moving together, all their closing kinetic energy lost. The pair is held: its next
    # approach is stopped plastically (the sequence's limit), see held.stop_closing.
    # A touching pair that did not approach is not in such a sequence.
    s = 0
    c = 0
    while s < m:
        e = s
        top = -np.inf
        hit = False
        while e < m and pair[e] == pair[s]:
            top = max(top, b[e])
            hit = hit or I_all[e] > 0
            e += 1
        if hit and approaching[c] and top * dt < tol:
            log.zeno[pair[s]] = True
            held = True
        s = e
        c += 1
    return True, held


@njit
def closing_speeds(Wst, pair, m, v, v_min):
    """Closing speeds b (m,) = -Wr v [m/s] of stacked features, computed pair by pair (rows
    Wst (cap, n) grouped by ``pair``), the touching pairs (k,) in stacked order and whether
    each approaches (k,) bool: has a point closing faster than ``v_min``. Closing below v_min
    is rounding, not approach: such speeds are set to 0."""
    b = np.zeros(m)
    touching = np.empty(m, dtype=np.int64)
    approaching = np.zeros(m, dtype=np.bool_)
    nk = 0
    s = 0
    while s < m:
        e = s
        while e < m and pair[e] == pair[s]:
            e += 1
        bp = -(Wst[s:e].copy() @ v)
        for j in range(e - s):
            b[s + j] = 0.0 if (bp[j] > 0.0 and bp[j] <= v_min) else bp[j]
        touching[nk] = pair[s]
        approaching[nk] = np.max(bp) > v_min
        nk += 1
        s = e
    return b, touching[:nk].copy(), approaching[:nk].copy()


@njit
def group_features(pair, m, in_pair, g):
    """Indices (k,) of the stacked features whose pair belongs to group g (``in_pair`` (P,):
    group of every pair, -1 for a pair left out), in stacked order."""
    c = 0
    for j in range(m):
        if in_pair[pair[j]] == g:
            c += 1
    idx = np.empty(c, dtype=np.int64)
    c = 0
    for j in range(m):
        if in_pair[pair[j]] == g:
            idx[c] = j
            c += 1
    return idx


@njit
def update_peaks(rows, off, z0, z1, h, n_modes, slab_building, peak):
    """peak (S, 3) <- max(peak, max over the step of |(u, v, phi)|) of every slab, from the modal
    states z0, z1 (n, 3) at the ends of a step of h [s] (z1 before any impulse at its end): the
    extreme of the cubic Hermite through (q, q') at both ends (:func:`pounding.framework.engine.peaks.cubic_abs_max`)."""
    ends = np.empty(18)  # each end's (u, v, phi), rates and accelerations (crossing.slab_state)
    for s in range(peak.shape[0]):  # the real slabs (rows may hold facade slabs after them)
        b = slab_building[s]
        storey = s - off[b]
        slab_state(rows, off, n_modes, b, storey, z0, ends, 0)
        slab_state(rows, off, n_modes, b, storey, z1, ends, 9)
        for j in range(3):
            y = cubic_abs_max(ends[j], ends[9 + j], h * ends[3 + j], h * ends[12 + j])
            if y > peak[s, j]:
                peak[s, j] = y


@njit(borrowed=True)
def _record(z, k, rec):
    every, Q, V = rec.every, rec.Q, rec.V
    if k % every == 0:
        j = k // every
        for i in range(z.shape[0]):
            Q[j, i] = z[i, 0]
            V[j, i] = z[i, 1]


@njit
def _accumulate_forces(tr, modes, dt, ag0, ag1, z0, z, f0, f1, E):
    """Add a step of dt [s] to E (n_buildings, 3): ground-motion work (column 0), damping (1) and
    the work of the modal contact forces f0 -> f1 (n,) at its ends, linear in between (2). The
    forces drive the velocity too. ag0, ag1 (c,) are the ground accelerations at the ends.

    Three rules, by what the integrator offers (``tr``): closed-form integrals on its
    trajectory (WA1, WA2, WM: with x = (q0, q'0, p0, p1), int q' = WA1 x, int s q' = WA2 x,
    int q'^2 = x WM x), Gauss points on it (GA, GB, gc, gw), or the trapezoidal rule on the
    step-end velocities (no points: average acceleration's exact identity).
    """
    _accumulate(tr, modes, dt, ag0, ag1, z0, z, f0, f1, E, np.empty(4))


@njit(borrowed=True)
def _accumulate(tr, modes, dt, ag0, ag1, z0, z, f0, f1, E, x):
    """:func:`_accumulate_forces` with a work array x (4,) given (the stretches allocate it once)."""
    GA, GB, gc, gw, WA1, WA2, WM = tr.GA, tr.GB, tr.gc, tr.gw, tr.WA1, tr.WA2, tr.WM
    L, c2, bidx = modes.L, modes.c2, modes.bidx
    n = z.shape[0]
    nq = gc.shape[0]
    maps = WA1.shape[0] > 0
    for i in range(n):
        g0 = modal_load(L, i, ag0)
        g1 = modal_load(L, i, ag1)
        if maps:
            x[0] = z0[i, 0]
            x[1] = z0[i, 1]
            x[2] = g0 + f0[i]
            x[3] = g1 + f1[i]
            iv0 = 0.0
            iv1 = 0.0
            ivv = 0.0
            for a in range(4):
                iv0 += WA1[i, a] * x[a]
                iv1 += WA2[i, a] * x[a]
                for b in range(4):
                    ivv += x[a] * WM[i, a, b] * x[b]
            E[bidx[i], 0] += g0 * iv0 + (g1 - g0) / dt * iv1
            E[bidx[i], 1] += c2[i] * max(ivv, 0.0)
            E[bidx[i], 2] += f0[i] * iv0 + (f1[i] - f0[i]) / dt * iv1
        elif nq == 0:
            vm = 0.5 * (z0[i, 1] + z[i, 1])
            E[bidx[i], 0] += _load_sum(dt * vm * 0.5, L, i, ag0, ag1)
            E[bidx[i], 1] += dt * c2[i] * vm * vm
            E[bidx[i], 2] += dt * vm * 0.5 * (f0[i] + f1[i])
        else:
            for j in range(nq):
                pj = _load_between(L, i, ag0, ag1, gc[j])
                fj = f0[i] + gc[j] * (f1[i] - f0[i])
                vj = (GA[j, i, 1, 0] * z0[i, 0] + GA[j, i, 1, 1] * z0[i, 1] + GA[j, i, 1, 2] * z0[i, 2]
                      + GB[j, i, 1, 0] * (g0 + f0[i]) + GB[j, i, 1, 1] * (pj + fj))
                E[bidx[i], 0] += dt * gw[j] * vj * pj
                E[bidx[i], 1] += dt * gw[j] * c2[i] * vj * vj
                E[bidx[i], 2] += dt * gw[j] * vj * fj


@njit(borrowed=True)
def _load_sum(x, L, i, ag0, ag1):
    """x (p_i(0) + p_i(1)) written as sum_j (x L[i, j]) (-ag0[j] + -ag1[j]) (with one component,
    to the bit the trapezoidal rule's x L (p0 + p1))."""
    s = x * L[i, 0] * (-ag0[0] + -ag1[0])
    for j in range(1, L.shape[1]):
        s += x * L[i, j] * (-ag0[j] + -ag1[j])
    return s


@njit(borrowed=True)
def _load_between(L, i, ag0, ag1, c):
    """p_i at the fraction c of a step, sum_j L[i, j] (p0_j + c (p1_j - p0_j)) with p = -ag."""
    s = L[i, 0] * (-ag0[0] + c * (-ag1[0] - -ag0[0]))
    for j in range(1, L.shape[1]):
        s += L[i, j] * (-ag0[j] + c * (-ag1[j] - -ag0[j]))
    return s
