"""Rigid sustained contact, compiled: the held step, the plastic stop and a run of held steps.

A pair whose impacts accumulate (a Zeno sequence) or that is pressed together
is *held*: a rigid unilateral contact force, carried from step to step as a load
like any other, so each step and its energy audit are the integrator's own.

* :func:`held_step` takes one step of any size with the held pairs' contact
  forces (used by the driver for every trial, including an impact search);
* :func:`stop_closing` removes what closing speed a held pair's touching
  points still have (a plastic impact: the limit of the Zeno sequence). With the
  ``crossing`` locator it is given the points that touch (within :func:`touch_gap`,
  1e-3 of the tolerance) and no others: a point of a held pair that is apart (its
  features reach a tolerance beyond the pair's smallest gap) closes freely until the
  step in which it would reach contact, whose start (:func:`held_step`) stops it by
  plastic impulses that push and never pull, so it is stopped at most one step's
  travel before contact (and that step's start force may hold it off). The paper's
  rules stop every point within the tolerance;
* :func:`held_stretch` runs grid steps while pairs are held and nothing else
  happens, and stops for the driver when a free pair touches or overlaps.

The driver's Python path calls the first two step by step; the stretch calls
the very same functions, so both paths give the same numbers. Like
:mod:`pounding.framework.engine.kernel`, everything runs compiled by numba or, without
numba, as plain Python with the same arithmetic.
"""

from __future__ import annotations

import numpy as np

from pounding.contact.base import newton_lcp, solve_small
from pounding.compiler import njit
from pounding.framework.engine.bundles import HeldContact, Status
from pounding.framework.engine.crossing import suspect
from pounding.framework.engine.kernel import _accumulate_forces, _record, modal_load, update_peaks
from pounding.framework.engine.pairs import closing, features_of, pair_gap

#: features_of's ``deep`` from compiled callers: a typed bool, not a literal True, so that they
#: and the driver share one specialization
_DEEP = np.bool_(True)


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
        sol = solve_small(sub, rhs)
        lam[:] = 0.0
        ok = True
        for r in range(na):
            lam[idx[r]] = sol[r]
            if sol[r] < 0:
                active[idx[r]] = False
                ok = False
        if ok:
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
            z1[i, r] = A[i, r, 0] * z[i, 0] + A[i, r, 1] * z[i, 1] + A[i, r, 2] * z[i, 2] + B[i, r, 0] * p0[i] + B[i, r, 1] * p1[i]
    return z1


@njit
def held_step(z, g0, g1, A, B, h, modes, held, contact, gap0, W, geo):
    """One step of size h [s] from state z (n, 3) with the pairs ``held`` (int64) in rigid sustained contact.

    contact : :class:`~pounding.framework.engine.bundles.HeldContact`, the tolerance, the largest
    opening speed v_cut [m/s] of a pressed point that is rounding, and the gap ``touch`` [m] up to
    which a point touches (:func:`touch_gap`; inf: every point within the tolerance, the paper's
    rules). A point that is apart and would reach contact within the step
    has its closing speed removed at the step's start by unilateral plastic impulses
    (:func:`stop_closing`, with the touching points as constraints); the touching points' leftover
    normal velocity (rounding) is projected out as before.
    gap0 (m,), W (m, n) are the held pairs' touching features at the start
    (:func:`~pounding.framework.engine.pairs.features_of` with ``deep``: gaps and modal rows).
    g0, g1 (n,) are the modal loads at the step's ends; A (n, 3, 3),
    B (n, 3, 2) the integrator's transition for h; ``modes`` the
    :class:`~pounding.framework.engine.bundles.Modes` (c2 = 2 zeta omega and
    om2 = omega^2 (n,) are read). Unilateral and rigid: no touching point of a held pair
    closes further during the step than it was at its start (never deeper than
    half the tolerance) and no force pulls (the projection of the touching points'
    leftover normal velocity, at most v_cut, is bilateral: rounding).

    * Implicit schemes (the end displacement depends on the end load): at the
      start, the force that stops the normal acceleration of the touching points
      that would close (consistent with zero closing speed after
      :func:`stop_closing`); at the end, the force that holds the points where
      they started, solved with the step's compliance W diag(B[:, 0, 1]) W^T.
    * Explicit schemes (the end displacement depends on the start load only,
      central differences): the start force that holds the points at the end of
      the step (the forward-increment Lagrange multiplier), kept through the step.

    Features are re-found on the corrected state (they slide as the slabs turn;
    two faces may be pressed at once) for up to four passes.

    Returns
    -------
    z0 (n, 3) : the start state with its acceleration consistent with f0;
    z1 (n, 3) : the end state; f0, f1 (n,) : modal contact forces at the ends [N/kg^0.5];
    found : bool, gap1 (k,), W1 (k, n) : when ``found``, the held pairs' features at the end
    state (the next step's start features).
    """
    c2, om2 = modes.c2, modes.om2
    tol, v_cut, touch = contact.tol, contact.v_cut, contact.touch
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
    if m > 0:
        free_end = gap0 + W @ (zf[:, 0] - q0)
        target = np.minimum(np.maximum(gap0, -0.5 * tol), 0.0)
        # Points pressed together move together: what normal velocity they still have (rounding,
        # after stop_closing) is projected out. A position constraint alone leaves it free, and
        # some schemes amplify it from step to step (linear acceleration: by -2 per step). A
        # real rebound (opening faster than 1e3 v_min) is left alone: the points separate.
        rate = W @ z0[:, 1].copy()
        # A point that is apart (beyond touch) and would reach contact within the step is stopped
        # plastically now, with the touching points as unilateral constraints: impulses that push,
        # never pull (a projection would pull on the touching points to stop it).
        arriving = (gap0 > touch) & (free_end < target) & (rate < 0.0)
        if np.any(arriving):
            stop_closing(z0, rows_where(arriving | (gap0 <= touch), W), v_cut * 1e-3)
            for i in range(n):
                z0[i, 2] = g0[i] - c2[i] * z0[i, 1] - om2[i] * z0[i, 0]
            zf = step(A, B, z0, g0 + f0, g1 + f0)
            free_end = gap0 + W @ (zf[:, 0] - q0)
            rate = W @ z0[:, 1].copy()
        pressed = (free_end < target) & (rate <= v_cut) & (gap0 <= touch)
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
                if free_end[k] < target[k]:
                    arg[k] = free_end[k] - target[k]
            lam = rigid_forces(arg, _weighted_compliance(W, D0))
        else:
            acc = W @ z0[:, 2].copy()
            for k in range(m):
                if free_end[k] < target[k]:
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
        _, g1f, Wr, _, _ = features_of(z1[:, 0].copy(), held, tol, _DEEP, n, geo)
        found = True
        m = g1f.shape[0]
        if m == 0:
            break
        # where each point started (linearised), but never deeper than half the tolerance:
        # features slide as the slabs turn, and the linearised start drifts with them
        target = np.minimum(np.maximum(g1f - Wr @ (z1[:, 0] - q0), -0.5 * tol), 0.0)
        short = g1f - target
        # the first pass closes every shortfall; later ones only what linearisation left
        if np.min(short) >= (0.0 if attempt == 0 else -1e-3 * tol):
            break
        arg = np.ones(m)
        for k in range(m):
            if short[k] < 0:
                arg[k] = short[k]
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
    return z0, z1, f0, f1, found, g1f, Wr


@njit
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


@njit
def touch_gap(tol):
    """The gap [m] up to which a point of a held pair touches, with the crossing locator: the held
    contact's own resolution, 1e-3 of the tolerance tol [m] (held_step's end passes stop when every
    point is within it of where it is held). A point farther away is apart: it is neither stopped
    nor pushed until it reaches contact."""
    return 1e-3 * tol


@njit
def rows_where(mask, W):
    """The rows of W (m, n) where mask (m,) bool is set, in order (a new C array): the points of a
    held pair that touch, are pressed or arrive."""
    out = np.empty((int(np.sum(mask)), W.shape[1]))
    c = 0
    for k in range(mask.shape[0]):
        if mask[k]:
            out[c] = W[k]
            c += 1
    return out


@njit
def held_stretch(tr, modes, ground, z, fc, held_mask, k0, k1, rec, geo, settings, rules):
    """Run grid steps k0 -> k1 while pairs are held and nothing else happens.

    Bundles and ``rules`` (None: the crossing locator; True: the paper's rules, the other
    branch pruned before compiling) as in :func:`pounding.framework.engine.kernel.advance`, plus the contact force at the
    current instant fc (n,) and the held pairs held_mask (P,) bool, both updated in place.
    Each step: :func:`stop_closing` on the held pairs' touching points (with ``rules`` None) or
    their points within the tolerance (the paper's rules), its kinetic-energy change booked as contact work,
    :func:`held_step`, then the same checks as the driver's Python step.

    Returns (k, status, pair): the grid index reached and a
    :class:`~pounding.framework.engine.bundles.Status`: DONE (k1 reached), RELEASED (every held
    pair let go at the end of step k - 1), OVERLAP (a free pair would overlap in step k: the
    state and the energy account are as at its start) or CONTACT (a free pair touches and
    closes at the end of step k - 1).
    """
    A, B = tr.A, tr.B
    L, bidx = modes.L, modes.bidx
    dt, ag = ground.dt, ground.ag
    E = rec.E
    tol, overlap, v_min = settings.tol, settings.overlap, settings.v_min
    n = z.shape[0]
    P = geo.pa.shape[0]
    g0 = np.empty(n)
    g1 = np.empty(n)
    touch = touch_gap(tol) if rules is None else np.inf
    contact = HeldContact(tol, 1e3 * v_min, touch)
    have = False  # start features known (the last step's end features)
    gapS = np.empty(0)
    WS = np.empty((0, n))
    for k in range(k0, k1):
        held = np.nonzero(held_mask)[0]
        if not have:
            _, gapS, WS, _, _ = features_of(z[:, 0].copy(), held, tol, _DEEP, n, geo)
        v_before = z[:, 1].copy()
        E_before = E.copy()
        # the points that touch (crossing; an arriving one: held_step, in the step it reaches contact),
        # every point within the tolerance with the paper's rules (touch = inf)
        stop_closing(z, rows_where(gapS <= touch, WS), v_min)
        book_velocity_change(E, bidx, v_before, z[:, 1].copy())
        for i in range(n):
            g0[i] = modal_load(L, i, ag[k])
            g1[i] = modal_load(L, i, ag[k + 1])
        z0, z1, f0, f1, have, gapS, WS = held_step(z, g0, g1, A, B, dt, modes, held, contact, gapS, WS, geo)
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
                return k, Status.OVERLAP, p
        book_velocity_change(E, bidx, z[:, 1].copy(), z0[:, 1].copy())  # pressed points' start velocity projected (held_step)
        _accumulate_forces(tr, modes, dt, ag[k], ag[k + 1], z0, z1, f0, f1, E)
        for i in range(n):
            z[i, 0] = z1[i, 0]
            z[i, 1] = z1[i, 1]
            z[i, 2] = z1[i, 2]
            fc[i] = f1[i]
        if rec.every > 1:
            update_peaks(geo.rows, z0, z1, dt, geo.n_modes, modes.slab_building, rec.peak)
        _record(z, k + 1, rec)
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
                    return k + 1, Status.CONTACT, p
        if not any_held:
            return k + 1, Status.RELEASED, -1
    return k1, Status.DONE, -1
