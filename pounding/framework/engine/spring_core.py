"""The compiled core of yielding storey springs inside the driver (template of generated modules).

Every function here runs only from a copy of this module generated for the hysteresis laws of a
scene (:func:`pounding.framework.engine.yielding.core`), in which the placeholder :func:`update` below is
replaced by a dispatch on the law index of each spring to the laws' own compiled ``update``. numba
cannot cache a function that takes another compiled function as an argument (it keys the type on
the object), but it caches one that finds it among its globals: the generated copy is cached on
disk like every other kernel.

The same functions serve both paths of the driver, so that a step taken here and the same step
taken by the driver's Python path (``Driver.python_step``, which handles every contact event) do
the same arithmetic in the same order:

* :func:`solve_springs` and :func:`forces_at`: the yielding springs' end remainders of a step
  (Newton on ``u + S f(u) = G q_lin``, see :mod:`pounding.framework.engine.inelastic`), or at given end
  displacements (the fixed-point pass around held contact and penalty forces);
* :func:`spring_work`: the work of the remainders' modal loads in a step, by the integrator's
  energy rule;
* :func:`stretch`: grid steps between contact events (the driver's compiled stretch for scenes
  with yielding springs, :meth:`pounding.framework.engine.yielding.Yielding.advance`).

Springs are flat arrays over every building with yielding springs, in building order; the springs
of group (building) j are ``bounds[j]:bounds[j + 1]``, their rows G over that building's modes
``gmodes[j, 0] : gmodes[j, 0] + gmodes[j, 1]`` (G is padded with zeros to the most modes).
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.contact.geometry import axis_separation, clearance_bound
from pounding.framework.engine.inelastic import MAX_ITER, solve_in_place
from pounding.framework.engine.kernel import _accumulate_forces, _pair_gap, _slab_dofs, modal_load, update_peaks

#: :func:`stretch`'s answers (the values of :class:`pounding.framework.engine.bundles.Status` it uses)
DONE, OVERLAP = 0, 2
#: :func:`stretch` stopped because the springs' Newton iteration diverged in the step it returns
DIVERGED = 5


# <dispatch>
@njit
def update(law, u, state, params, new_state, s):
    """Placeholder: each generated copy of this module dispatches on ``law`` to the laws' updates
    (the contract of :mod:`pounding.hysteresis.base`)."""
    raise NotImplementedError("spring_core runs from a generated copy (pounding.framework.engine.yielding.core)")
# </dispatch>


@njit
def solve_group(lo, hi, law, dl, sf, S, f, state, params, k0, tol, trial, d, f1, kt, J, x, act):
    """Newton on ``u + S f(u) = dl`` for springs lo..hi-1 (one building).

    dl (ns,) the linear step's end deformations [m]; sf (ns,) = S f, the start remainders' share
    (the predictor keeps them through the step); S (ns, ns) the step's compliance (block diagonal
    by building); f (ns,) the remainders at the step's start [N]; state, params the committed law
    states and parameters; k0 (ns,) initial stiffnesses [N/m]; tol the residual tolerance [m].
    Writes the end deformations d, remainders f1, tangents kt and trial states (rows lo..hi-1);
    J (m, m), x (m,), act (m,) int are work buffers, m >= hi - lo.

    The Jacobian I + S diag(k_t - k0) differs from I only in the columns of the springs off their
    initial branch (the active set a): (I + S_aa D_a) x_a = res_a is solved, and every row follows
    as res - S[:, a] D_a x_a.

    Returns the Newton iterations taken, or -1 when it did not converge in MAX_ITER.
    """
    for a in range(lo, hi):  # predictor: the start remainders kept through the step
        d[a] = dl[a] - sf[a]
    for it in range(MAX_ITER + 1):
        same = True
        for a in range(lo, hi):
            r, k = update(law[a], d[a], state, params, trial, a)
            f1[a] = r - k0[a] * d[a]
            kt[a] = k
            if f1[a] != f[a]:
                same = False
        if it == 0 and same:
            return 0  # nothing changed: the predictor solves the step
        worst = 0.0
        for a in range(lo, hi):
            acc = d[a] - dl[a]
            for b in range(lo, hi):
                acc += S[a, b] * f1[b]
            x[a - lo] = acc
            worst = max(worst, abs(acc))
        if worst <= tol:
            return it
        na = 0
        for a in range(lo, hi):
            if kt[a] != k0[a]:
                act[na] = a
                na += 1
        if na == 0:
            for a in range(lo, hi):
                d[a] -= x[a - lo]
            continue
        for i in range(na):
            for j in range(na):
                J[i, j] = S[act[i], act[j]] * (kt[act[j]] - k0[act[j]])
            J[i, i] += 1.0
        y = x[hi - lo : hi - lo + na]  # the active rows' right-hand side, after the residuals
        for i in range(na):
            y[i] = x[act[i] - lo]
        solve_in_place(J, y, na)
        for i in range(na):
            y[i] *= kt[act[i]] - k0[act[i]]
        for a in range(lo, hi):
            acc = x[a - lo]
            for i in range(na):
                acc -= S[a, act[i]] * y[i]
            d[a] -= acc
    return -1


@njit
def compliance_load(f, S, bounds, sf):
    """sf (ns,) <- S f per group (S block diagonal by building)."""
    for j in range(bounds.shape[0] - 1):
        for a in range(bounds[j], bounds[j + 1]):
            acc = 0.0
            for b in range(bounds[j], bounds[j + 1]):
                acc += S[a, b] * f[b]
            sf[a] = acc


@njit
def deformations(q, G, bounds, gmodes, out):
    """out (ns,) <- G q per group: the springs' deformations [m] from the stacked modal vector q (n,)."""
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for s in range(bounds[j], bounds[j + 1]):
            acc = 0.0
            for i in range(nm):
                acc += G[s, i] * q[m0 + i]
            out[s] = acc


@njit
def end_load(f1, G, bounds, gmodes, g):
    """g (n,) <- the modal load G^T f1 of the remainders f1 (ns,), zero on modes without springs."""
    for i in range(g.shape[0]):
        g[i] = 0.0
    for j in range(bounds.shape[0] - 1):
        m0, nm = gmodes[j, 0], gmodes[j, 1]
        for i in range(nm):
            acc = 0.0
            for s in range(bounds[j], bounds[j + 1]):
                acc += G[s, i] * f1[s]
            g[m0 + i] = acc


@njit
def solve_springs(q_lin, S, law, G, bounds, gmodes, f, state, params, k0, tol, trial, f1, g1):
    """Every group's Newton (:func:`solve_group`) for the linear step's end displacements q_lin (n,).

    Writes the end remainders f1 (ns,), trial states and their modal load g1 (n,). Returns the
    index of a group whose Newton diverged, or -1.
    """
    ns = f.shape[0]
    mmax = 0
    for j in range(bounds.shape[0] - 1):
        mmax = max(mmax, bounds[j + 1] - bounds[j])
    sf = np.empty(ns)
    compliance_load(f, S, bounds, sf)
    j = _solve_springs(q_lin, sf, S, law, G, bounds, gmodes, f, state, params, k0, tol, trial, f1, np.empty(ns), np.empty(ns),
                       np.empty(ns), np.empty((mmax, mmax)), np.empty(2 * mmax), np.empty(mmax, dtype=np.int64))
    if j < 0:
        end_load(f1, G, bounds, gmodes, g1)
    return j


@njit
def _solve_springs(q_lin, sf, S, law, G, bounds, gmodes, f, state, params, k0, tol, trial, f1, dl, d, kt, J, x, act):
    """The groups' Newton (:func:`solve_group`) with S f and the work buffers given: dl, d, kt (ns,),
    J (m, m), x (2 m,), act (m,) for the largest group of m springs (the stretch allocates them
    once, and keeps S f until f changes). Returns the index of a group that diverged, or -1."""
    deformations(q_lin, G, bounds, gmodes, dl)
    for j in range(bounds.shape[0] - 1):
        if solve_group(bounds[j], bounds[j + 1], law, dl, sf, S, f, state, params, k0, tol[j], trial, d, f1, kt, J, x, act) < 0:
            return j
    return -1


@njit
def forces_at(q1, law, G, bounds, gmodes, state, params, k0, trial, f1, g1):
    """Remainders f1 (ns,), trial states and their modal load g1 (n,) at end displacements q1 (n,)."""
    ns = k0.shape[0]
    d = np.empty(ns)
    deformations(q1, G, bounds, gmodes, d)
    for s in range(ns):
        r, _ = update(law[s], d[s], state, params, trial, s)
        f1[s] = r - k0[s] * d[s]
    end_load(f1, G, bounds, gmodes, g1)


@njit
def spring_work(tr, h, pg0, pg1, z0, z1, ftot0, ftot1, w0, w1, out):
    """out (n,) <- work [J] in a step of h [s] of a modal load w linear in it (w0 at its start, w1
    at its end), on the integrator's trajectory driven by the modal ground loads (pg0, pg1 (n,) at
    the ends) and the total extra loads ftot0, ftot1 (n,): the three rules of
    :func:`pounding.framework.engine.kernel._accumulate_forces` (closed-form maps, Gauss points on the
    trajectory, or the trapezoidal rule)."""
    A, B, GA, GB, gc, gw, WA1, WA2, WM = tr
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


@njit
def _reach(rows, n_modes, radii, sa, ba, sb, bb, z0, z1, dt):
    """A bound [m] on how far pair (sa, sb)'s points move towards each other within a step of dt [s]
    from the modal states z0 to z1 (n, 3): twice what the larger end speeds and accelerations of
    the two slabs (centre motion plus rotation at their radii) carry them, as kernel.advance's
    crossing screen bounds it."""
    w = np.empty(3)
    speed = 0.0
    acc = 0.0
    for zz in (z0, z1):
        sp = 0.0
        ac = 0.0
        for s, b in ((sa, ba), (sb, bb)):
            i0, nm = n_modes[b, 0], n_modes[b, 1]
            _slab_dofs(rows[s, :, :nm], zz[i0 : i0 + nm, 1], w)
            om = w[2]
            sp += np.hypot(w[0], w[1]) + radii[s] * abs(om)
            _slab_dofs(rows[s, :, :nm], zz[i0 : i0 + nm, 2], w)
            ac += np.hypot(w[0], w[1]) + radii[s] * (abs(w[2]) + om * om)
        speed = max(speed, sp)
        acc = max(acc, ac)
    return 2.0 * (speed + 2.0 * acc * dt) * dt


@njit
def stretch(tr, modes, ground, z, k0, k1, rec, geo, tol, law, G, bounds, gmodes, S, kel, ntol, params, state, trial, f, g,
            peak, work, hist):
    """Grid steps k0 -> k1 of a scene with yielding springs, until a slab pair comes within the
    contact tolerance.

    Each step is the driver's Python step without contact (``Driver.spring_trial`` and
    ``Driver.commit``): the modal step with the remainders' start load -g, the springs' Newton
    (:func:`solve_springs`), the end load, the energy audit (the remainders' work booked to
    ``work`` per building, the contact column left as the Python path leaves it), the records.
    After the step every slab pair is checked with the cascade of
    :func:`pounding.framework.engine.kernel.advance` (cheap clearance bound, separating axis, exact gap):
    when a pair ends within ``tol`` of contact (or overlapping), the step is rolled back (state,
    springs and energy untouched) and the stretch returns (k, OVERLAP, pair): the driver takes
    that step in Python, where contact is handled.

    Parameters
    ----------
    tr, modes, ground, rec, geo : the compiled core's bundles (:mod:`pounding.framework.engine.bundles`)
    z : (n, 3) modal state, updated in place
    tol : contact tolerance [m]
    law, G, bounds, gmodes, S, kel, ntol, params : the springs (:class:`pounding.framework.engine.yielding.Yielding`):
        law index (ns,), rows (ns, nmax), group bounds, group modes, the grid step's compliance
        (ns, ns), initial stiffnesses (ns,) [N/m], Newton tolerance per group [m], parameters
    state, trial : (ns, n_state) committed states (updated) and a trial buffer
    f : (ns,) remainders at the current instant [N]; g : (n,) their modal load; both updated
    peak : (ns,) running peak |deformation| [m]; work : (n_buildings,) the remainders' work [J]
    hist : (3, n_out, ns) deformation, force and dissipated energy at the output rows

    Returns
    -------
    (k, status, pair) : grid index reached; DONE, OVERLAP (the state is the start of step k) or
    DIVERGED (Newton failed in step k, state at its start); the pair that stopped it, or -1.
    """
    A, B = tr.A, tr.B
    L, bidx = modes.L, modes.bidx
    dt, ag = ground.dt, ground.ag
    pair_a, pair_b, rows, off, n_modes, verts, nvert, centres, radii, rest_gap, axis, _, _ = geo
    n = z.shape[0]
    ns = f.shape[0]
    nb = work.shape[0]
    z0 = np.empty((n, 3))
    qlin = np.empty(n)
    f1 = np.empty(ns)
    g1 = np.empty(n)
    ftot0 = np.empty(n)
    ftot1 = np.empty(n)
    w = np.empty(n)
    pg0 = np.empty(n)
    pg1 = np.empty(n)
    per = np.empty(nb)
    da = np.empty(3)
    db = np.empty(3)
    mmax = 0
    for j in range(bounds.shape[0] - 1):
        mmax = max(mmax, bounds[j + 1] - bounds[j])
    dl, d, kt, J, x = np.empty(ns), np.empty(ns), np.empty(ns), np.empty((mmax, mmax)), np.empty(2 * mmax)
    act = np.empty(mmax, dtype=np.int64)
    sf = np.empty(ns)
    compliance_load(f, S, bounds, sf)  # S f, kept until f changes (the same numbers solve_springs computes)
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
            p0 = (pg0[i] + 0.0) - g[i]
            p1 = pg1[i]
            for r in range(3):
                z[i, r] = A[i, r, 0] * z0[i, 0] + A[i, r, 1] * z0[i, 1] + A[i, r, 2] * z0[i, 2] + B[i, r, 0] * p0 + B[i, r, 1] * p1
            qlin[i] = z[i, 0]
        if _solve_springs(qlin, sf, S, law, G, bounds, gmodes, f, state, params, kel, ntol, trial, f1, dl, d, kt, J, x, act) >= 0:
            for i in range(n):
                z[i, 0] = z0[i, 0]
                z[i, 1] = z0[i, 1]
                z[i, 2] = z0[i, 2]
            return k, DIVERGED, -1
        changed = False
        for s in range(ns):
            if f1[s] != f[s]:
                changed = True
                break
        if changed:
            end_load(f1, G, bounds, gmodes, g1)
        else:  # the same remainders: the same end load, bit for bit
            for i in range(n):
                g1[i] = g[i]
        for i in range(n):
            for r in range(3):
                z[i, r] = z[i, r] - B[i, r, 1] * g1[i]
        # contact check: the cascade of kernel.advance; within the tolerance, the Python step decides
        for p in range(pair_a.shape[0]):
            sa = off[pair_a[p, 0]] + pair_a[p, 1]
            sb = off[pair_b[p, 0]] + pair_b[p, 1]
            ba = pair_a[p, 0]
            bb = pair_b[p, 0]
            _slab_dofs(rows[sa, :, : n_modes[ba, 1]], z[n_modes[ba, 0] : n_modes[ba, 0] + n_modes[ba, 1], 0], da)
            _slab_dofs(rows[sb, :, : n_modes[bb, 1]], z[n_modes[bb, 0] : n_modes[bb, 0] + n_modes[bb, 1], 0], db)
            if clearance_bound(rest_gap[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb]) > tol:
                continue
            if axis_separation(verts[sa, : nvert[sa]], centres[sa], da[0], da[1], da[2],
                               verts[sb, : nvert[sb]], centres[sb], db[0], db[1], db[2], axis[p, 0], axis[p, 1]) > tol:
                continue
            if _pair_gap(verts[sa, : nvert[sa]], centres[sa], da, verts[sb, : nvert[sb]], centres[sb], db) <= tol:
                for i in range(n):
                    z[i, 0] = z0[i, 0]
                    z[i, 1] = z0[i, 1]
                    z[i, 2] = z0[i, 2]
                return k, OVERLAP, p
        # the energy audit, as Driver.commit books a step with springs (accumulate_with_springs)
        for i in range(n):
            ftot0[i] = 0.0 - g[i]
            ftot1[i] = 0.0 - g1[i]
        _accumulate_forces(tr, modes, dt, ag0, ag1, z0, z, ftot0, ftot1, rec.E)
        spring_work(tr, dt, pg0, pg1, z0, z, ftot0, ftot1, g, g1, w)
        for b in range(nb):
            per[b] = 0.0
        for i in range(n):
            per[bidx[i]] += w[i]
        for b in range(nb):
            rec.E[b, 2] += per[b]
            work[b] += per[b]
        # commit the springs
        for i in range(n):
            g[i] = g1[i]
        if changed:
            compliance_load(f1, S, bounds, sf)
        for s in range(ns):
            f[s] = f1[s]
            for c in range(state.shape[1]):
                state[s, c] = trial[s, c]
            if abs(trial[s, 0]) > peak[s]:
                peak[s] = abs(trial[s, 0])
        if rec.every > 1:
            update_peaks(rows, z0, z, dt, n_modes, modes.slab_building, rec.peak)
        if (k + 1) % rec.every == 0:
            j = (k + 1) // rec.every
            for i in range(n):
                rec.Q[j, i] = z[i, 0]
                rec.V[j, i] = z[i, 1]
            for s in range(ns):
                hist[0, j, s] = state[s, 0]
                hist[1, j, s] = state[s, 1]
                hist[2, j, s] = state[s, 2]
    return k1, DONE, -1
