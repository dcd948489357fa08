"""The crossing locator's impact search, written once: :func:`crossing_search`.

An impact instant is the first zero of the smallest gap of the suspect pairs over a step, found on
the integrator's own intra-step solution ``gap(hh, sol)`` (the state a step of hh [s] from the
step's start reaches), with the step's cubic Hermite interpolant as a cheap guide
(:mod:`pounding.framework.engine.crossing`): a bracket, Newton steps with the interpolant's
slope, then regula falsi with the Illinois rule.

The search is one compiled function; where the gap comes from is its first argument. When the
integrator has compiled maps to any step length (:meth:`pounding.solvers.base.Integrator.search_maps`:
``exact``, Newmark, HHT, generalized-alpha) and the law acts by impulses, it runs compiled whole
with :func:`stepped_gap` (:func:`locate`, one call per located event): the integrator's maps to
any instant and the record interpolated there, and what else acts in the step stepped by the
functions the driver's own trial steps call: the held pairs' rigid contact
(:func:`~pounding.framework.engine.held.held_step`), and yielding storey springs (links with
laws) by their own step (:func:`~pounding.framework.engine.spring_core.spring_step`: their Newton
with the step's compliance :func:`~pounding.framework.engine.spring_core.compliance`), or with
held pairs by the fixed point around the held step
(:func:`~pounding.framework.engine.held.held_fixed_point`).
Otherwise (an integrator without compiled maps, the driver without its compiled core) the driver
runs the very same function with the compiler off for its own body
(``crossing_search.py_func``), its gap a Python callable that takes the integrator's trial step;
the arithmetic it calls (the interpolant's search, the Newton and Illinois updates) is compiled
either way.

The modal load at t + hh is :meth:`~pounding.framework.engine.driver.Driver.load`'s: the grid row
of the record at a grid instant, else the record interpolated by :func:`record_at` (numpy's
``interp`` arithmetic, :func:`interp`), which the driver calls too, so the compiled search and
the driver's give the same instants to the bit (tests/test_event_search.py).
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine.crossing import (ILLINOIS_ITERATIONS, LEAVE_HALVINGS, hermite_search, hermite_slope, hermite_zero, illinois_bracket,
                                         illinois_point, newton_bracket, suspects)
from pounding.framework.engine.bundles import LinkPass, LinkTrial, Status, StepSolution
from pounding.framework.engine.ground_load import modal_loads
from pounding.framework.engine.held import held_fixed_point, held_step
from pounding.framework.engine.spring_core import compliance, spring_step
from pounding.framework.engine.pairs import pair_gap, stepped_min_gap
from pounding.solvers.exact_partial import exact_maps
from pounding.solvers.newmark import alpha_maps

#: hermite_zero's ``checked`` as typed bools, not literals: the driver calls it from Python with a
#: bool, and one specialization serves both
_UNCHECKED = np.bool_(False)
_CHECKED = np.bool_(True)
#: how many of its last gap evaluations the search keeps (:func:`crossing_search`)
_MEMO = 8


@njit(borrowed=True)
def interp(x, xp, fp):
    """numpy's ``interp(x, xp, fp, left=0, right=0)`` for one point x and increasing xp (m,), with its
    arithmetic: the sample itself at a sample, else slope (x - xp[j]) + fp[j] with slope =
    (fp[j+1] - fp[j]) / (xp[j+1] - xp[j]) and xp[j] <= x < xp[j+1]."""
    m = xp.shape[0]
    if x != x:
        return x
    if x > xp[m - 1] or x < xp[0]:
        return 0.0
    j = np.searchsorted(xp, x, side="right") - 1
    if j == m - 1 or xp[j] == x:
        return fp[j]
    slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j])
    out = slope * (x - xp[j]) + fp[j]
    if out != out:
        out = slope * (x - xp[j + 1]) + fp[j + 1]
        if out != out and fp[j] == fp[j + 1]:
            out = fp[j]
    return out


@njit
def record_at(t, rec_t, rec_acc):
    """Ground acceleration (c,) [m/s^2] of a record (times rec_t (m,), accelerations rec_acc (m, c))
    at time t [s], each component by :func:`interp`. The driver's :meth:`~pounding.framework.engine.driver.Driver.ag_at`
    calls it too, so its search and this one interpolate with the same machine code on any processor
    (numpy's interp, compiled by another compiler, may fuse its multiply-add where this does not)."""
    c = rec_acc.shape[1]
    a = np.empty(c)
    for j in range(c):
        a[j] = interp(t, rec_t, rec_acc[:, j])
    return a


@njit
def modal_load_at(t, dt, ag, rec_t, rec_acc, L):
    """Modal ground-motion load p = -L ag(t) (n,) at time t [s], as the driver forms it: ag(t) is the
    grid row ag[k] (nsteps + 1, c) when t is within 1e-9 steps of grid instant k, else the record
    (rec_t (m,), rec_acc (m, c)) interpolated linearly, zero outside it."""
    k = t / dt
    kr = int(k + 0.5)
    c = L.shape[1]
    if abs(k - kr) < 1e-9 and 0 <= kr <= ag.shape[0] - 1:
        a = np.empty(c)
        for j in range(c):
            a[j] = ag[kr, j]
    else:
        a = record_at(t, rec_t, rec_acc)
    p = np.empty(L.shape[0])
    modal_loads(L, a, p)
    return p


@njit
def stepped_gap(hh, sol):
    """The gap [m] the search seeks the zero of, after the integrator's step of hh [s] (at hh <= 0,
    at the step's start). ``sol``: the :class:`~pounding.framework.engine.bundles.StepSolution`,
    the step's start time [s], state (n, 3) and load (n,) (with the links' start load -g0 in it
    where only the ground acts), the pairs (k,), the
    :class:`~pounding.framework.engine.bundles.StepSearch` bundle, the integrator's maps (a compiled
    ``maps(omega, zeta, hh, params) -> (A, B)``, or None and the number of built-in maps:
    :func:`step_maps`) and their parameters, ``held``: the held pairs'
    :class:`~pounding.framework.engine.bundles.HeldSearch` (the step with them, and its gap), or
    one with no held pair (only the ground acts in the step: the pairs' smallest gap after it), and
    ``laws``, ``springs``: the run's links' law updates (:mod:`pounding.framework.engine.links`) and
    the links (:class:`~pounding.framework.engine.bundles.LinkSearch`), or None (every building elastic)."""
    t, z, p0, plist, ex, held, laws, springs = sol.t, sol.z, sol.p0, sol.plist, sol.search, sol.held, sol.laws, sol.springs
    maps, builtin, params = sol.maps, sol.builtin, sol.params
    if held.held.pairs.shape[0] == 0:  # no held pair (a run's every search has the one type: one specialization)
        if hh <= 0.0:
            return _smallest_gap(z[:, 0].copy(), plist, ex.geo)
        p1 = modal_load_at(t + hh, ex.dt, ex.ag, ex.rec_t, ex.rec_acc, ex.L)
        if hh == ex.dt:
            return free_gap(laws, springs, ex.A, ex.B, z, p0, p1, hh, plist, ex.geo)
        A, B = step_maps(maps, builtin, ex.omega, ex.zeta, hh, params)
        return free_gap(laws, springs, A, B, z, p0, p1, hh, plist, ex.geo)
    if hh <= 0.0:
        return held.g0
    p1 = modal_load_at(t + hh, ex.dt, ex.ag, ex.rec_t, ex.rec_acc, ex.L)
    if hh == ex.dt:
        A, B = ex.A, ex.B
    else:
        A, B = step_maps(maps, builtin, ex.omega, ex.zeta, hh, params)
    z1, arrival = held_end(laws, springs, z, p0, p1, A, B, hh, held, ex.geo)
    if held.arrival:
        return arrival if arrival < np.inf else held.far
    return _smallest_gap(z1[:, 0].copy(), plist, ex.geo)


@njit
def free_gap(laws, springs, A, B, z, p0, p1, hh, plist, geo):
    """The smallest gap [m] of the pairs ``plist`` after a step of hh [s] from z (n, 3) in which only
    the ground acts, by the maps A (n, 3, 3), B (n, 3, 2), with the modal loads p0, p1 (n,) at its
    ends: the integrator's linear step (``springs`` None; numba drops the other branch), or the
    links' own step (:func:`~pounding.framework.engine.spring_core.spring_step`, the driver's
    ``Yielding.step``: their Newton with the step's compliance, p0 holding their start load -g0)."""
    if springs is None:
        return stepped_min_gap(A, B, z, p0, p1, plist, geo)
    links, now = springs.links, springs.now
    out = LinkTrial(np.empty(now.f.shape[0]), now.state.copy(), np.empty(z.shape[0]))  # (Yielding._trial)
    j, z1 = spring_step(laws, A, B, z, p0, p1, hh, links, compliance(links, B[:, 0, 1].copy()), now, out)
    if j >= 0:  # (the driver raises what its trial step raises)
        springs.failed[0] = j
    return _smallest_gap(z1[:, 0].copy(), plist, geo)


@njit
def held_end(laws, springs, z, p0, p1, A, B, hh, held, geo):
    """(z1 (n, 3), arrival [m]) of the held step of hh [s] from z (the held pairs'
    :class:`~pounding.framework.engine.bundles.HeldSearch`), with the ground's modal loads p0, p1
    (n,) at its ends: :func:`~pounding.framework.engine.held.held_step` (``springs`` None), or with
    the links :func:`~pounding.framework.engine.held.held_fixed_point`, as the driver's held trial
    takes them."""
    if springs is None:
        st = held_step(z, p0, p1, A, B, hh, held.modes, held.held, geo)
        return st.z1, st.arrival
    now = springs.now
    spr = LinkPass(springs.links, now, LinkTrial(np.empty(now.f.shape[0]), now.state.copy(), np.empty(z.shape[0])))
    fixed = held_fixed_point(laws, z, p0, p1, A, B, hh, held.modes, held.held, geo, spr)
    if fixed.status != Status.DONE:
        springs.failed[0] = 0
    return fixed.step.z1, fixed.step.arrival


@njit
def _smallest_gap(q, plist, geo):
    """The smallest gap [m] of the pairs ``plist`` at modal displacements q, NaN as numpy's min of
    the driver's gaps gives it."""
    g = np.inf
    for j in range(plist.shape[0]):
        gj = pair_gap(q, plist[j], np.inf, geo)
        if gj != gj:
            return gj
        g = min(g, gj)
    return g


@njit
def step_maps(maps, builtin, omega, zeta, hh, params):
    """The integrator's maps (A (n, 3, 3), B (n, 3, 2)) for a step of hh [s]: ``maps(omega, zeta,
    hh, params)``, or with ``maps`` None the built-in maps number ``builtin`` called directly
    (:data:`BUILTIN_MAPS`: 0 ``exact``'s, 1 the alpha family's). numba drops the branch not taken
    for a None argument, so :func:`locate_builtin` holds no function value: the extension module
    built at install holds it and numba caches it."""
    if maps is None:
        if builtin == 0:
            return exact_maps(omega, zeta, hh, params)
        return alpha_maps(omega, zeta, hh, params)
    return maps(omega, zeta, hh, params)


@njit
def locate_with(t, z, herm, p0, plist, eps, xtol, search, maps, params, held, laws, springs):
    """:func:`crossing_search` on the integrator's step from state z (n, 3) at t [s] with start load
    p0 (n,), for the pairs plist (k,): (found, hs) (see there). ``herm`` = (q0, v0, q1, v1 (n,), h)
    the step's cubic Hermite interpolant (h [s] its length); ``search``:
    :class:`~pounding.framework.engine.bundles.StepSearch`; ``maps``, ``params``: the integrator's
    compiled maps to any step length and their parameters
    (:meth:`pounding.solvers.base.Integrator.search_maps`); ``held``: the held pairs'
    :class:`~pounding.framework.engine.bundles.HeldSearch`, with none held where only the ground
    acts (:func:`stepped_gap`); ``laws``, ``springs``: the links' law updates
    (:func:`pounding.framework.engine.links.law_tuple`) and their
    :class:`~pounding.framework.engine.bundles.LinkSearch`, or None both (every building elastic)."""
    return crossing_search(None, StepSolution(t, z, p0, plist, search, maps, -1, params, held, laws, springs), herm, eps, xtol,
                           plist, search.geo)


@njit
def locate_builtin(t, z, herm, p0, plist, eps, xtol, search, builtin, params, held, laws, springs):
    """:func:`locate_with` on built-in maps number ``builtin`` (:data:`BUILTIN_MAPS`), called
    directly: an entry without a function argument (the extension module takes arrays, numbers
    and bundles only, and numba does not cache a function that holds a function value)."""
    return crossing_search(None, StepSolution(t, z, p0, plist, search, None, builtin, params, held, laws, springs), herm, eps,
                           xtol, plist, search.geo)


#: the maps :func:`locate_builtin` calls directly, by number: the built-in integrators' (a third
#: party's maps run through :func:`locate_with`, compiled by numba for them)
BUILTIN_MAPS = (exact_maps, alpha_maps)


def locate(t, z, herm, p0, plist, eps, xtol, search, maps, params, held, laws=None, springs=None):
    """The compiled search on the integrator's maps and parameters
    (:meth:`pounding.solvers.base.Integrator.search_maps`): (found, hs) of :func:`crossing_search`
    (arguments: :func:`locate_with`)."""
    j = builtin_maps(maps)
    if j >= 0:
        return locate_builtin(t, z, herm, p0, plist, eps, xtol, search, j, params, held, laws, springs)
    return locate_with(t, z, herm, p0, plist, eps, xtol, search, maps, params, held, laws, springs)


def builtin_maps(maps) -> int:
    """The number of the integrator's compiled ``maps`` among :data:`BUILTIN_MAPS` (the one
    :func:`locate_builtin` and the compiled stretch's search call directly), or -1 (a third party's)."""
    return next((j for j, known in enumerate(BUILTIN_MAPS) if maps is known), -1)


@njit
def step_touches(graze, t, ag0, z0, z1):
    """Whether a pair touches in the grid step from z0 (n, 3) at t [s] to z1, where only the ground
    acts (ag0 (c,) its acceleration at t): the driver's Python step of it
    (``Driver.python_step``) would strike or locate something, rather than commit the step whole.

    As that step decides: the pairs :func:`~pounding.framework.engine.crossing.suspects` flags (the
    driver's ``crossing_pairs``), then :func:`crossing_search` on the integrator's built-in maps for
    them (``Driver.locate``: a zero of their smallest gap inside the step), then a pair whose gap is
    within ``graze.eps`` at the step's end (``Driver.touching_pairs``, struck there by the driver).
    ``graze``: :class:`~pounding.framework.engine.bundles.GrazeSearch`; where the search finds a zero,
    ``graze.found`` receives (t, the step length to it) and ``graze.culprits`` the pairs searched,
    which the driver's step takes."""
    ex = graze.search
    h = ex.dt
    plist = graze.plist
    mask = suspects(z0, z1, plist, h, graze.eps, graze.tol, ex.geo)
    culprits = plist[mask]
    if culprits.shape[0] > 0:
        p0 = np.empty(z0.shape[0])
        modal_loads(ex.L, ag0, p0)
        herm = (z0[:, 0].copy(), z0[:, 1].copy(), z1[:, 0].copy(), z1[:, 1].copy(), h)
        sol = StepSolution(t, z0, p0, culprits, ex, None, graze.builtin, graze.params, graze.held, None, None)
        found, hs = crossing_search(None, sol, herm, graze.eps, graze.xtol, culprits, ex.geo)
        if found:
            graze.found[0] = t
            graze.found[1] = hs
            graze.culprits[:] = mask
            return True
    q1 = z1[:, 0].copy()
    for j in range(plist.shape[0]):
        if pair_gap(q1, plist[j], graze.tol, ex.geo) <= graze.eps:
            return True
    return False


@njit
def crossing_search(py_gap, sol, herm, eps, xtol, plist, geo):
    """The first zero of the pairs' smallest gap over a step: (found, hs), hs [s] the step length to
    it (where |gap| <= eps [m], the geometry's zero), found False when the gap stays above -eps (a
    graze that did not touch).

    The gap at hh [s] is the smallest gap [m] of the pairs ``plist`` (k,) after the integrator's own
    step of hh (at hh = 0, of the start state): ``py_gap(hh)``, a Python callable (this function
    then runs interpreted: ``crossing_search.py_func``), or with ``py_gap`` None, compiled,
    ``stepped_gap(hh, sol)`` (numba drops the other branch, so the compiled search holds
    no Python object and is cached); ``herm`` = (q0, v0, q1, v1 (n,), h) the step's
    cubic Hermite interpolant, whose gap (``geo``) guides the search; ``xtol`` [s] ends the
    bracketing where the gap is not smooth.

    1. A step that starts open (> eps) and ends overlapping (< -eps) brackets a zero at once.
    2. Otherwise samples then Brent's bounded minimisation of the interpolant's gap tell whether it
       dips below zero (:func:`~pounding.framework.engine.crossing.hermite_search`); the
       integrator's own solution decides.
    3. A pair touching at the bracket's start that overlaps at its end was struck there and opens,
       while another corner (or the same one coming back) closes: the zero sought is the first
       after it has left contact, found by halving back from the end; if it never leaves contact
       (pressed together) the start is the event.
    4. The zero is polished from the interpolant's (Newton with the interpolant's slope, kept in
       the bracket each evaluation narrows: two evaluations when the guess is good), then regula
       falsi with the Illinois rule, bisection down to xtol where the gap is not smooth.
    """
    # the search asks some step lengths twice (a Newton point that becomes the bracket's end, the
    # bracket's ends again for regula falsi): the integrator's solution is deterministic, so the
    # last few are kept (a step of a one-off length costs its maps)
    memo_h = np.empty(_MEMO)
    memo_g = np.empty(_MEMO)
    memo_n = np.zeros(1, dtype=np.int64)

    def gap(hh, sol):
        for i in range(min(memo_n[0], _MEMO)):
            if memo_h[i] == hh:
                return float(memo_g[i])
        if py_gap is None:
            g = stepped_gap(hh, sol)
        else:
            g = py_gap(hh)
        j = memo_n[0] % _MEMO
        memo_h[j] = hh
        memo_g[j] = g
        memo_n[0] += 1
        return g

    h = herm[4]
    g0 = gap(0.0, sol)
    gh = gap(h, sol)
    lo = 0.0
    hi = h
    if g0 > eps and gh < -eps:
        x = hermite_zero(*herm, 0.0, h, eps, xtol, _UNCHECKED, plist, geo)
    else:
        found, lo, hi = hermite_search(*herm, g0, gh, eps, plist, geo)
        ghi = gap(hi, sol)
        if not found and ghi >= -eps:
            return False, 0.0
        if ghi >= -eps and gh < -eps:
            hi = h
            ghi = gh
        if gap(lo, sol) <= eps:  # touching at the bracket's start
            if ghi >= -eps:
                return True, lo
            left = False
            prev = hi
            fprev = ghi
            x = hi
            for _ in range(LEAVE_HALVINGS):
                x = lo + 0.5 * (x - lo)
                if x - lo <= xtol:
                    break
                fx = gap(x, sol)
                if fx > eps:
                    left = True
                    break
                prev = x
                fprev = fx
            if not left:  # it stays in contact (pressed): the start is the event
                return True, lo
            if fprev >= -eps:
                return True, prev
            lo, hi, ghi = x, prev, fprev
        if ghi >= -eps:
            return False, 0.0
        x = hermite_zero(*herm, lo, hi, eps, xtol, _CHECKED, plist, geo)
    for _ in range(4):  # Newton with the interpolant's slope
        if not lo < x < hi:
            break
        fx = gap(x, sol)
        if abs(fx) <= eps:
            return True, x
        lo, hi, x, more = newton_bracket(lo, hi, x, fx, hermite_slope(*herm, x, plist, geo))
        if not more:
            break
    flo = gap(lo, sol)  # regula falsi, Illinois rule
    if flo <= eps:
        return True, lo
    fhi = gap(hi, sol)
    side = 0.0
    for _ in range(ILLINOIS_ITERATIONS):
        if hi - lo <= xtol:
            break
        x = illinois_point(lo, hi, flo, fhi)
        fx = gap(x, sol)
        if abs(fx) <= eps:
            return True, x
        lo, hi, flo, fhi, side = illinois_bracket(lo, hi, flo, fhi, side, x, fx)
    return True, lo
