"""The compiled no-contact stretch: many steps at once, in modal coordinates.

:func:`advance` steps every mode of every building with its per-mode
transition, records the state at the output rate, accumulates the energy
terms, and after each step checks the slab pairs that could touch: first a
cheap lower bound on their clear distance, then the exact signed gap only
when that bound is below the tolerance. It stops at the first step that ends
with a pair within the tolerance (status 1: the state is the end of that
step) or overlapping (status 2: the state is rolled back to the start of that
step), so that the Python driver can locate the impact.

The same function runs compiled by numba (cache on, so a second process
starts warm) or as plain Python over numpy arrays when numba is missing; the
arithmetic is identical.
"""

from __future__ import annotations

import numpy as np

from pounding.contact.base import newton_lcp
from pounding.contact.geometry import MAX_FEATURES, axis_separation, clearance_bound, displaced, njit, signed_gap
from pounding.framework.pairs import closing, pair_features, pair_gap

DONE, CONTACT, OVERLAP, HELD = 0, 1, 2, 4


@njit
def _slab_dofs(rows, q, out):
    # rows (3, n) of Phi for one slab, restricted to its building's modes
    for r in range(3):
        s = 0.0
        for i in range(rows.shape[1]):
            s += rows[r, i] * q[i]
        out[r] = s


@njit
def advance(
    A, B, L, c2, dt, ag, z, k0, k1, every, Q, V, E, GA, GB, gc, gw, WA1, WA2, WM,
    bidx, pair_a, pair_b, rows, off, n_modes,
    verts, nvert, centres, radii, rest_gap, axis, tol, overlap, v_min, slab_building, peak,
    restitution, after_eq, om2, imp, imp_n, ev_t, ev_q, ev_v, ev_n, zeno,
):
    """Advance z from step k0 towards k1 (exclusive of events).

    Parameters
    ----------
    A : (n, 3, 3), B : (n, 3, 2)
        Per-mode transition for the grid step dt.
    L : (n, c)
        Modal load per unit ground acceleration of each of the c components:
        p_i = -sum_j L[i, j] ag[k, j].
    c2 : (n,)
        Modal damping 2 zeta omega [1/s].
    dt : float
        Grid step [s].
    ag : (nsteps + 1, c)
        Ground acceleration of each component on the grid [m/s^2].
    z : (n, 3)
        Modal state (q, q', q''), updated in place.
    k0, k1 : int
        First and last grid index.
    every : int
        Output rate: the state at grid index k is stored in Q[k // every] when k % every == 0.
    Q, V : (n_out, n)
        Recorded modal displacements and velocities.
    E : (n_buildings, 3)
        Accumulated ground-motion work and damping work [J] (column 2, contact-force
        work, is the driver's).
    GA, GB : (nq, n, 3, 3), (nq, n, 3, 2)
        Transitions from the step start to the quadrature points c_j dt (nq = 0:
        trapezoidal rule on step-end values).
    gc, gw : (nq,)
        Quadrature points and weights on [0, 1].
    WA1, WA2 : (n, 4), WM : (n, 4, 4)
        Closed-form work integrals of the step when the integrator has them (``work_maps``;
        shape (0, ...) otherwise): with x = (q0, q'0, p0, p1), int q' = WA1 x,
        int s q' = WA2 x, int q'^2 = x WM x.
    bidx : (n,) int
        Building of every mode. The remaining arrays describe the slab pairs
        that share a level: ``pair_a``/``pair_b`` (P, 2) = (building, storey),
        ``rows`` (S, 3, nmax) the Phi rows of slab s (slab index =
        ``off[building] + storey``), ``n_modes`` (n_buildings,) with
        the first mode index of each building in ``n_modes[:, 0]`` and the
        count in ``n_modes[:, 1]``, ``verts`` (S, kmax, 2) rest polygons,
        ``nvert`` (S,), ``centres`` (S, 2), ``radii`` (S,), ``rest_gap`` (P,), and
        ``axis`` (P, 2) the unit direction of the closest points at rest (see
        :mod:`pounding.framework.pairs`).
    tol : float
        Contact tolerance [m]: a step ending with a gap <= tol is reported.
    overlap : float
        Gap [m] below which a step is rejected: -tol for impulse laws (touching within
        the tolerance is contact), 0 for force laws (any penetration needs the force).
    v_min : float
        Closing speed [m/s] below which a touching point is not approaching (rounding).
    slab_building : (S,) int, peak : (S, 3)
        Building of every slab, and the running peak |u|, |v|, |phi| of every slab,
        updated at every step when the output is thinned (every > 1).

    A step ending with a pair within the tolerance stops the kernel only if a touching
    point approaches (the velocity condition, eq. 7 of the paper): the same decision
    the driver's contact step takes, so a pair separating after an impact runs on.

    restitution : float
        With a law whose impulses are Newton's (:func:`~pounding.contact.base.newton_impulses`
        with this restitution), the kernel applies the impulses of such a step itself, as the
        driver would (:func:`impulses_at`), and runs on; -1 leaves them to the driver.
    after_eq : bool
        After impulses, reset the accelerations to equilibrium (``after_impact = "equilibrium"``).
    om2 : (n,)
        omega^2 [1/s^2].
    imp : (cap, 11), imp_n : (1,) int
        Impact records the kernel appends (see :func:`impulses_at`) and their count.
    ev_t : (cape,), ev_q, ev_v : (cape, n), ev_n : (1,) int
        The states just before the impulses of each impact instant, and their count.
    zeno : (P,) bool
        Set for a pair whose rebound is too slow to open the tolerance in a step: the
        kernel stops (status HELD) so that the driver holds it in sustained contact.

    Returns
    -------
    (k, status, pair) : the grid index reached, DONE/CONTACT/OVERLAP/HELD, the pair index (or -1).
    """
    n = z.shape[0]
    z0 = np.empty((n, 3))
    da = np.empty(3)
    db = np.empty(3)
    no_force = np.zeros(n)  # no contact force acts in a free stretch
    for k in range(k0, k1):
        for i in range(n):
            z0[i, 0] = z[i, 0]
            z0[i, 1] = z[i, 1]
            z0[i, 2] = z[i, 2]
        a0 = ag[k]
        a1 = ag[k + 1]
        for i in range(n):
            p0 = modal_load(L, i, a0)
            p1 = modal_load(L, i, a1)
            for r in range(3):
                z[i, r] = A[i, r, 0] * z0[i, 0] + A[i, r, 1] * z0[i, 1] + A[i, r, 2] * z0[i, 2] + B[i, r, 0] * p0 + B[i, r, 1] * p1
        # contact check on the pairs that could touch; a rejected step books no energy.
        # The cascade of pairs.pair_gap written out: a call per pair and step, with its many
        # array arguments, costs more than the check itself (0.8 -> 1.4 us/step measured).
        status = DONE
        hit = -1
        for p in range(pair_a.shape[0]):
            sa = off[pair_a[p, 0]] + pair_a[p, 1]
            sb = off[pair_b[p, 0]] + pair_b[p, 1]
            ba = pair_a[p, 0]
            bb = pair_b[p, 0]
            _slab_dofs(rows[sa, :, : n_modes[ba, 1]], z[n_modes[ba, 0] : n_modes[ba, 0] + n_modes[ba, 1], 0], da)
            _slab_dofs(rows[sb, :, : n_modes[bb, 1]], z[n_modes[bb, 0] : n_modes[bb, 0] + n_modes[bb, 1], 0], db)
            bound = clearance_bound(rest_gap[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb])
            if bound > tol:
                continue
            if axis_separation(verts[sa, : nvert[sa]], centres[sa], da[0], da[1], da[2],
                               verts[sb, : nvert[sb]], centres[sb], db[0], db[1], db[2], axis[p, 0], axis[p, 1]) > tol:
                continue
            g = _pair_gap(verts[sa, : nvert[sa]], centres[sa], da, verts[sb, : nvert[sb]], centres[sb], db)
            if g < overlap:
                for i in range(n):
                    z[i, 0] = z0[i, 0]
                    z[i, 1] = z0[i, 1]
                    z[i, 2] = z0[i, 2]
                return k, OVERLAP, p
            if g <= tol and status == DONE and closing(
                z[:, 0], z[:, 1], p, tol, v_min, n, pair_a, pair_b, rows, off, n_modes, verts, nvert, centres, radii, rest_gap, axis
            ):
                # keep checking the other pairs: one of them may overlap in this same step
                status = CONTACT
                hit = p
        _accumulate_forces(A, B, L, c2, dt, ag[k], ag[k + 1], z0, z, no_force, no_force, E, GA, GB, gc, gw, WA1, WA2, WM, bidx)
        held = False
        if status == CONTACT:
            P = pair_a.shape[0]
            if restitution < 0 or imp_n[0] + P * MAX_FEATURES > imp.shape[0] or ev_n[0] >= ev_t.shape[0]:
                _record(z, k + 1, every, Q, V)  # the driver applies the impulses and records again
                return k + 1, CONTACT, hit
            held = impulses_at((k + 1) * dt, ag[k + 1], z, L, c2, om2, restitution, after_eq, tol, v_min, dt,
                               imp, imp_n, ev_t, ev_q, ev_v, ev_n, zeno,
                               pair_a, pair_b, rows, off, n_modes, verts, nvert, centres, radii, rest_gap, axis)
        if every > 1:
            update_peaks(rows, z[:, 0], n_modes, slab_building, peak)
        _record(z, k + 1, every, Q, V)
        if held:
            return k + 1, HELD, -1
    return k1, DONE, -1


@njit
def impulses_at(t, ag, z, L, c2, om2, restitution, after_eq, tol, v_min, dt, imp, imp_n, ev_t, ev_q, ev_v, ev_n, zeno,
                pa, pb, rows, off, n_modes, verts, nvert, centres, radii, rest, axis):
    """Newton impulses at time t [s] on every touching, approaching pair: the driver's contact step
    (``Driver.contact_at``) for a law whose impulses are :func:`~pounding.contact.base.newton_impulses`.

    Pairs are taken in order, each with the velocities the previous ones left. Each impact
    appends a row (t, pair, striker, vertex, impulse, nx, ny, b, energy loss, Qx, Qy) to imp;
    the state before the first impulse at t goes to ev_*. Returns True if a pair's rebound is
    too slow to open the tolerance within one step (zeno is set for it). ag (c,) is the ground
    acceleration of every component at t.
    """
    n = z.shape[0]
    q = z[:, 0].copy()
    held = False
    recorded = False
    for p in range(pa.shape[0]):
        if pair_gap(q, p, tol, pa, pb, rows, off, n_modes, verts, nvert, centres, radii, rest, axis) > tol:
            continue
        count, Qp, Np, _, who, idx, face, Wp = pair_features(q, p, tol, n, pa, pb, rows, off, n_modes, verts, nvert, centres, radii, rest, axis)
        if count == 0:
            continue
        W = Wp[:count].copy()
        b = -(W @ z[:, 1].copy())
        if np.max(b) <= v_min:  # rounding-level closing is not approach
            continue
        for j in range(count):
            if b[j] > 0.0 and b[j] <= v_min:
                b[j] = 0.0
        D = W @ W.T
        I = newton_lcp(D, b, restitution)
        if not np.any(I > 0):
            continue
        after = b - D @ I
        if not recorded:
            j = ev_n[0]
            ev_t[j] = t
            for i in range(n):
                ev_q[j, i] = z[i, 0]
                ev_v[j, i] = z[i, 1]
            ev_n[0] += 1
            recorded = True
        dv = W.T @ I
        for i in range(n):
            z[i, 1] += dv[i]
        if after_eq:
            for i in range(n):
                z[i, 2] = modal_load(L, i, ag) - c2[i] * z[i, 1] - om2[i] * z[i, 0]
        for j in range(count):
            if I[j] > 0:
                r = imp_n[0]
                imp[r, 0] = t
                imp[r, 1] = p
                imp[r, 2] = who[j]
                imp[r, 3] = -1 if face[j] >= 0 else idx[j]
                imp[r, 4] = I[j]
                imp[r, 5] = Np[j, 0]
                imp[r, 6] = Np[j, 1]
                imp[r, 7] = b[j]
                imp[r, 8] = 0.5 * I[j] * (b[j] + after[j])
                imp[r, 9] = Qp[j, 0]
                imp[r, 10] = Qp[j, 1]
                imp_n[0] += 1
        # Zeno: a rebound too slow to open the tolerance within one step (see Driver.contact_at)
        if np.max(b) * dt < tol:
            zeno[p] = True
            held = True
    return held


@njit
def update_peaks(rows, q, n_modes, slab_building, peak):
    """peak (S, 3) <- max(peak, |(u, v, phi)|) of every slab, from modal displacements q (n,)."""
    d = np.empty(3)
    for s in range(rows.shape[0]):
        b = slab_building[s]
        _slab_dofs(rows[s, :, : n_modes[b, 1]], q[n_modes[b, 0] : n_modes[b, 0] + n_modes[b, 1]], d)
        for r in range(3):
            if abs(d[r]) > peak[s, r]:
                peak[s, r] = abs(d[r])


@njit
def _pair_gap(va, ca, da, vb, cb, db):
    return signed_gap(displaced(va, ca, da[0], da[1], da[2]), displaced(vb, cb, db[0], db[1], db[2]))


@njit
def _record(z, k, every, Q, V):
    if k % every == 0:
        j = k // every
        for i in range(z.shape[0]):
            Q[j, i] = z[i, 0]
            V[j, i] = z[i, 1]


@njit
def modal_load(L, i, a):
    """Modal ground load of mode i, -sum_j L[i, j] a[j], for component accelerations a (c,).

    The sum starts from the first component's product, so one component gives exactly
    -(L[i, 0] a[0]) (= L[i, 0] (-a[0]) in IEEE arithmetic).
    """
    s = L[i, 0] * a[0]
    for j in range(1, a.shape[0]):
        s += L[i, j] * a[j]
    return -s


@njit
def _accumulate_forces(A, B, L, c2, dt, ag0, ag1, z0, z, f0, f1, E, GA, GB, gc, gw, WA1, WA2, WM, bidx):
    """Add a step's work to E: ground motion (column 0), damping (1) and the modal contact
    forces f0 -> f1 (n,) at its ends, linear in between (2). The forces drive the velocity too.

    ag0, ag1 (c,) are the component accelerations at the step's ends; L (n, c).
    Three rules, by what the integrator offers: closed-form integrals on its trajectory
    (WA1, WA2, WM, see advance), Gauss points on it (GA, GB, gc, gw), or the trapezoidal rule
    on the step-end velocities (nq = 0: average acceleration's exact identity).
    """
    n = z.shape[0]
    c = ag0.shape[0]
    nq = gc.shape[0]
    maps = WA1.shape[0] > 0
    x = np.empty(4)
    for i in range(n):
        if maps:
            g0 = modal_load(L, i, ag0)
            g1 = modal_load(L, i, ag1)
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
            for j in range(c):
                E[bidx[i], 0] += dt * vm * 0.5 * L[i, j] * (-ag0[j] + -ag1[j])
            E[bidx[i], 1] += dt * c2[i] * vm * vm
            E[bidx[i], 2] += dt * vm * 0.5 * (f0[i] + f1[i])
        else:
            g0 = modal_load(L, i, ag0)
            for j in range(nq):
                pj = L[i, 0] * (-ag0[0] + gc[j] * (-ag1[0] - -ag0[0]))
                for m in range(1, c):
                    pj += L[i, m] * (-ag0[m] + gc[j] * (-ag1[m] - -ag0[m]))
                fj = f0[i] + gc[j] * (f1[i] - f0[i])
                vj = (GA[j, i, 1, 0] * z0[i, 0] + GA[j, i, 1, 1] * z0[i, 1] + GA[j, i, 1, 2] * z0[i, 2]
                      + GB[j, i, 1, 0] * (g0 + f0[i]) + GB[j, i, 1, 1] * (pj + fj))
                E[bidx[i], 0] += dt * gw[j] * vj * pj
                E[bidx[i], 1] += dt * gw[j] * c2[i] * vj * vj
                E[bidx[i], 2] += dt * gw[j] * vj * fj
