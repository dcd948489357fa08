"""The compiled stretch of grid steps between contact events: :func:`advance`.

It steps every mode of every building with its per-mode transition, records the state at the
output rate, accumulates the energy terms, and after each step checks the slab pairs that could
touch (:mod:`pounding.framework.engine.kernel`'s docstring: the screen, the paper's rules and the
statuses). With the crossing locator a step the screen suspects is searched for an impact as the
driver's Python step searches it (:func:`~pounding.framework.engine.event_search.step_touches`,
the same compiled search): the stretch stops only where a pair touches, and runs on through a
graze the bounds could not exclude, which the driver would have stepped whole. The stretch and the
driver's steps give one run, to the bit.

With the compiler off the same function runs as Python.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.contact.geometry import MAX_FEATURES, axis_separation, clearance_bound
from pounding.framework.engine.bundles import Status, StretchEnd
from pounding.framework.engine.crossing import SLAB_A, SLAB_B, motion_from, point_bounds, slab_state, suspect_given
from pounding.framework.engine.event_search import step_touches
from pounding.framework.engine.kernel import _accumulate, _free_step, _record, impulses_at, update_peaks
from pounding.framework.engine.pairs import closing, dofs_gap, slab_dofs


@njit(fingerprinted=True)  # (its search bundle, a bundle of bundles, is built once a run)
def advance(tr, modes, ground, z, k0, k1, rec, geo, settings, log, rules, graze):
    """Advance z from grid index k0 towards k1 (exclusive of events).

    Parameters
    ----------
    tr : Transition
        The integrator's per-mode step of the grid step and its energy rule.
    modes : Modes
        Modal load L (n, c), damping 2 zeta omega, omega^2, building of every mode and slab.
    ground : Ground
        Grid step dt [s] and ground acceleration ag (nsteps + 1, c) [m/s^2].
    z : (n, 3)
        Modal state (q, q', q''), updated in place.
    k0, k1 : int
        First and last grid index.
    rec : Recorder
        Recorded modal displacements and velocities, the energy account (ground-motion and
        damping work; column 2, contact-force work, is the driver's), and the running slab
        peaks, updated at every step when the output is thinned (every > 1).
    geo : PairArrays
        The slab pairs that could touch (none: no contact check).
    settings : Settings
        Tolerance, overlap threshold, rounding speed v_min; with ``restitution`` >= 0 the
        kernel applies Newton impulses itself (:func:`impulses_at`) and runs on, with -1
        it stops for the driver.
    log : EventLog
        Impacts and event states the kernel appends; ``zeno`` is set for a pair whose
        rebound is too slow to open the tolerance in a step (the kernel stops: HELD).
    rules : None or bool
        None with the ``crossing`` locator (``settings.instant``: the driver strikes every
        impact where the gap is zero; the kernel only screens); True with the paper's rules
        (struck within the tolerance). numba prunes the branch of the other rules before
        compiling (an argument typed None), so a run compiles and loads only its own: the
        crossing run does not compile :func:`impulses_at` (~10 s of a cold start), the
        paper's does not compile the graze screen (:func:`~pounding.framework.engine.crossing.suspect_given`).
    graze : GrazeSearch or None
        With the crossing locator, what the driver's search of a step needs
        (:class:`~pounding.framework.engine.bundles.GrazeSearch`): a step the screen suspects is
        searched here as the driver's Python step searches it
        (:func:`~pounding.framework.engine.event_search.step_touches`), and one in which no pair
        touches runs on, committed as that step commits it (a graze the bounds could not exclude);
        None: every suspected step stops the stretch (the driver's search is not compiled whole
        for this run, or the paper's rules). numba prunes the branch of a None argument.

    A step ending with a pair within the tolerance stops the kernel only if a touching
    point approaches (the velocity condition, eq. 7 of the paper): the same decision
    the driver's contact step takes, so a pair separating after an impact runs on.
    A step ending with a pair below ``overlap`` is rolled back to its start.

    Returns
    -------
    :class:`~pounding.framework.engine.bundles.StretchEnd` (k, status, pair) : the grid index reached, a :class:`~pounding.framework.engine.bundles.Status`
    (DONE, CONTACT, OVERLAP or HELD), the pair index (or -1).
    """
    A, B = tr.A, tr.B
    L = modes.L
    dt, ag = ground.dt, ground.ag
    pair_a, pair_b, rows, off, n_modes = geo.pa, geo.pb, geo.rows, geo.off, geo.n_modes
    verts, nvert, centres, radii, rest_gap, axis = geo.verts, geo.nvert, geo.centres, geo.radii, geo.rest, geo.axis
    tol, overlap, v_min, restitution = settings.tol, settings.overlap, settings.v_min, settings.restitution
    E, every, peak, slab_building = rec.E, rec.every, rec.peak, modes.slab_building
    n = z.shape[0]
    z0 = np.empty((n, 3))
    da = np.empty(3)
    db = np.empty(3)
    no_force = np.zeros(n)  # no contact force acts in a free stretch
    free = np.ones(pair_a.shape[0], dtype=np.bool_)  # no pair is held in a free stretch
    rates = np.full((pair_a.shape[0], 3), -1.0)  # the graze screen's memories (crossing.suspect_step)
    gaps = np.full((pair_a.shape[0], 7), np.nan)
    kin = np.empty((pair_a.shape[0], 2, 18))  # the pairs' slab_state at the last two step ends, by k % 2
    kin_at = np.full((pair_a.shape[0], 2), -1, dtype=np.int64)  # the grid index each slot describes
    xw = np.empty(4)
    q1 = np.empty(n)  # the step's end displacements, contiguous (the paper's rules: slab_dofs of them)
    for k in range(k0, k1):
        _free_step(A, B, L, ag[k], ag[k + 1], z0, z)
        if rules is not None:
            for i in range(n):
                q1[i] = z[i, 0]
        # contact check on the pairs that could touch; a rejected step books no energy.
        # The cascade of pairs.pair_gap written out: a call per pair and step, with its many
        # array arguments, costs more than the check itself (0.8 -> 1.4 us/step measured).
        status = Status.DONE
        hit = -1
        searched = 0  # the step's search (graze): 0 not run, 1 a pair touches, -1 none does
        for p in range(pair_a.shape[0]):
            sa = off[pair_a[p, 0]] + pair_a[p, 1]
            sb = off[pair_b[p, 0]] + pair_b[p, 1]
            ba = pair_a[p, 0]
            bb = pair_b[p, 0]
            if rules is None:
                # the crossing locator: impacts only where the gap is zero, found by the driver. A cheap
                # screen first (end positions, speeds and accelerations of the two slabs, no allocation):
                # the gap cannot reach zero within the step when the clearance bound exceeds twice what
                # the end speeds and accelerations carry the points in a step; suspect() bounds both ends.
                # (the slabs' states at the step's end are kept for the next step's start: slot (k + 1) % 2)
                k1v = kin[p, (k + 1) % 2]
                slab_state(rows, off, n_modes, ba, pair_a[p, 1], z, k1v, SLAB_A)
                slab_state(rows, off, n_modes, bb, pair_b[p, 1], z, k1v, SLAB_B)
                kin_at[p, (k + 1) % 2] = k + 1
                for i in range(3):  # the slabs' (u, v, phi) at the step's end
                    da[i] = k1v[SLAB_A + i]
                    db[i] = k1v[SLAB_B + i]
                bound = clearance_bound(rest_gap[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb])
                speed_a, acc_a, _ = point_bounds(k1v, SLAB_A, radii[sa])
                speed_b, acc_b, _ = point_bounds(k1v, SLAB_B, radii[sb])
                reach = 2.0 * (speed_a + speed_b + 2.0 * (acc_a + acc_b) * dt) * dt
                if bound > reach:
                    continue
                if axis_separation(verts[sa, : nvert[sa]], centres[sa], da[0], da[1], da[2],
                                   verts[sb, : nvert[sb]], centres[sb], db[0], db[1], db[2], axis[p, 0], axis[p, 1]) > reach:
                    continue
                k0v = kin[p, k % 2]
                if kin_at[p, k % 2] != k:  # not formed at the last step's end (this stretch's first step)
                    slab_state(rows, off, n_modes, ba, pair_a[p, 1], z0, k0v, SLAB_A)
                    slab_state(rows, off, n_modes, bb, pair_b[p, 1], z0, k0v, SLAB_B)
                    kin_at[p, k % 2] = k
                V, Amax = motion_from(k0v, k1v, radii[sa], radii[sb])
                if suspect_given(z0, z, p, dt, -overlap, tol, geo, k, rates, gaps, da, db, V, Amax):
                    if graze is not None and searched == 0:  # (nested: numba prunes a branch on the None test alone)
                        # the driver's search of the step, once for every pair: -1 when no pair touches
                        searched = 1 if step_touches(graze, k * dt, ag[k], z0, z) else -1
                    if graze is None or searched == 1:
                        for i in range(n):
                            z[i, 0] = z0[i, 0]
                            z[i, 1] = z0[i, 1]
                            z[i, 2] = z0[i, 2]
                        return StretchEnd(k, Status.OVERLAP, p)
            else:
                slab_dofs(rows, off, n_modes, ba, pair_a[p, 1], q1, da)
                slab_dofs(rows, off, n_modes, bb, pair_b[p, 1], q1, db)
                # the rest-gap bound inline first (most pairs end there at most steps: a call per pair and
                # step that reads the pair bundle cost more than the check, 15 -> 8 ms of the penalty run),
                # then pairs.dofs_gap's cascade (a bound where it exceeds the tolerance)
                if clearance_bound(rest_gap[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb]) > tol:
                    continue
                g = dofs_gap(da, db, p, tol, geo)[0]
                if g > tol:
                    continue
                if g < overlap:
                    for i in range(n):
                        z[i, 0] = z0[i, 0]
                        z[i, 1] = z0[i, 1]
                        z[i, 2] = z0[i, 2]
                    return StretchEnd(k, Status.OVERLAP, p)
                if g <= tol and status == Status.DONE and closing(z[:, 0].copy(), z[:, 1].copy(), p, tol, v_min, n, geo):
                    # keep checking the other pairs: one of them may overlap in this same step
                    status = Status.CONTACT
                    hit = p
        _accumulate(tr, modes, dt, ag[k], ag[k + 1], z0, z, no_force, no_force, E, xw)
        if every > 1:  # before any impulse at the step's end: the step's own end velocities
            update_peaks(rows, off, z0, z, dt, n_modes, slab_building, peak)
        held = False
        if rules is not None:  # (nested: numba prunes a branch on the None test alone)
            if status == Status.CONTACT:
                P = pair_a.shape[0]
                if restitution < 0 or log.n_impacts[0] + P * MAX_FEATURES > log.impacts.shape[0] or log.n_events[0] >= log.t.shape[0]:
                    _record(z, k + 1, rec)  # the driver applies the impulses and records again
                    return StretchEnd(k + 1, Status.CONTACT, hit)
                _, held = impulses_at(None, (k + 1) * dt, ag[k + 1], z, no_force, modes, settings, dt, log, geo, free)
        _record(z, k + 1, rec)
        if held:
            return StretchEnd(k + 1, Status.HELD, -1)
    return StretchEnd(k1, Status.DONE, -1)
