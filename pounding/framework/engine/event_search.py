"""The crossing locator's impact search for ``exact``, compiled whole: one call per located event.

The driver's search (:meth:`pounding.framework.engine.driver.Driver.locate_crossing`) asks the
integrator's own solution for the pairs' smallest gap at a handful of step lengths (the
``gmin`` of its docstring), each a Python call that builds the step's transition, forms the
ground-motion load at its end and calls the compiled gap: about 0.15 ms of an event's 0.5 ms.
When the integrator is ``exact`` and nothing acts in the step but the ground (no held pair, an
impulse law, no yielding springs), the same search runs here in one compiled call, with the same
arithmetic in the same order, so the instants it returns are the driver's to the bit
(tests/test_event_search.py; ``benchmarks/check_identity.py``):

* the step of length hh is the grid transition when hh is the grid step, else
  :func:`~pounding.solvers.exact_partial.exact_transition` (the driver's
  :class:`~pounding.solvers.base.TransitionCache` for ``exact`` with the crossing locator);
* the modal load at t + hh is :meth:`~pounding.framework.engine.driver.Driver.load`'s: the grid row of
  the record at a grid instant, else the record interpolated by :func:`record_at` (numpy's
  ``interp`` arithmetic, :func:`interp`), which the driver calls too;
* the search is :meth:`~pounding.framework.engine.driver.Driver.locate_crossing` with
  :func:`~pounding.framework.engine.driver._polish` and :func:`~pounding.framework.engine.driver._first_zero`
  on that solution, the Hermite interpolant's search and slope as there.

The regula falsi's arithmetic is :func:`~pounding.framework.engine.crossing.illinois_point` and
:func:`~pounding.framework.engine.crossing.illinois_bracket`, shared with the interpolant's zero finder and
the driver's. Each keeps its own loop around them: numba could take the gap function as an argument
of one shared loop, but every function passed would make another specialization of it, and the
compiled core keeps one per function (tests/test_compiled_core.py).
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine.crossing import (ILLINOIS_ITERATIONS, LEAVE_HALVINGS, hermite_search, hermite_slope, hermite_zero, illinois_bracket,
                                         illinois_point, newton_bracket)
from pounding.framework.engine.pairs import pair_gap, stepped_min_gap
from pounding.solvers.exact_partial import exact_transition

#: hermite_zero's ``checked`` as typed bools, not literals: the driver calls it from Python with a
#: bool, and one specialization serves both
_UNCHECKED = np.bool_(False)
_CHECKED = np.bool_(True)


@njit
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
    n = L.shape[0]
    p = np.empty(n)
    for i in range(n):
        p[i] = L[i, 0] * -a[0]
    for j in range(1, c):
        for i in range(n):
            p[i] += L[i, j] * -a[j]
    return p


@njit
def stepped_gap(hh, sol):
    """The smallest gap [m] of the pairs after ``exact``'s step of hh [s] (the driver's ``gmin``); at
    hh <= 0, at the start state itself. ``sol`` = (t, z, p0, plist, grid_dt, A_dt, B_dt, omega, zeta,
    dt, ag, rec_t, rec_acc, L, geo): the step's start time [s], state (n, 3) and load (n,), the pairs,
    the grid step [s] and its transition, the modes and what :func:`modal_load_at` takes."""
    t, z, p0, plist, grid_dt, A_dt, B_dt, omega, zeta, dt, ag, rec_t, rec_acc, L, geo = sol
    if hh <= 0.0:
        g = np.inf
        q = z[:, 0].copy()
        for j in range(plist.shape[0]):
            gj = pair_gap(q, plist[j], np.inf, geo)
            if gj != gj:  # NaN, as numpy's min of the driver's gaps gives it
                return gj
            g = min(g, gj)
        return g
    p1 = modal_load_at(t + hh, dt, ag, rec_t, rec_acc, L)
    if hh == grid_dt:
        return stepped_min_gap(A_dt, B_dt, z, p0, p1, plist, geo)
    A, B = exact_transition(omega, zeta, hh)
    return stepped_min_gap(A, B, z, p0, p1, plist, geo)


@njit
def locate_exact(t, h, z, q1, v1, p0, plist, eps, xtol, grid_dt, A_dt, B_dt, omega, zeta, dt, ag, rec_t, rec_acc, L, geo):
    """:meth:`~pounding.framework.engine.driver.Driver.locate_crossing` for ``exact``'s step of h [s] from
    state z (n, 3) at t [s], start load p0 (n,), ending at displacements q1 and velocities v1 (n,):
    returns (found, hs), hs [s] the step length to the first zero of the pairs' smallest gap (to eps
    [m]), found False when the gap stays above -eps (a graze that did not touch)."""
    sol = (t, z, p0, plist, grid_dt, A_dt, B_dt, omega, zeta, dt, ag, rec_t, rec_acc, L, geo)
    herm = (z[:, 0].copy(), z[:, 1].copy(), q1, v1, h)  # the step's cubic Hermite interpolant
    g0 = stepped_gap(0.0, sol)
    gh = stepped_gap(h, sol)
    if g0 > eps and gh < -eps:
        x = hermite_zero(*herm, 0.0, h, eps, xtol, _UNCHECKED, plist, geo)
        return True, _polish(0.0, h, x, eps, xtol, sol, herm)
    found, lo, hi = hermite_search(*herm, g0, gh, eps, plist, geo)
    ghi = stepped_gap(hi, sol)
    if not found and ghi >= -eps:
        return False, 0.0
    if ghi >= -eps:
        if gh < -eps:
            hi = h
            ghi = gh
    if stepped_gap(lo, sol) <= eps:
        # touching at the start: struck there and opening, the zero sought is after it has left contact
        if ghi >= -eps:
            return True, lo
        left, x, prev, fprev = _leave_contact(lo, hi, eps, xtol, sol)
        if not left:
            return True, lo
        if fprev >= -eps:
            return True, prev
        lo, hi, ghi = x, prev, fprev
    if ghi >= -eps:
        return False, 0.0
    x = hermite_zero(*herm, lo, hi, eps, xtol, _CHECKED, plist, geo)
    return True, _polish(lo, hi, x, eps, xtol, sol, herm)


@njit
def _polish(lo, hi, x, eps, xtol, sol, herm):
    """:func:`pounding.framework.engine.driver._polish` on ``exact``'s solution (:func:`stepped_gap`), with
    the slope of the Hermite interpolant ``herm`` = (q0, v0, q1, v1, h), then :func:`_first_zero`."""
    plist, geo = sol[3], sol[14]
    for _ in range(4):
        if not lo < x < hi:
            break
        fx = stepped_gap(x, sol)
        if abs(fx) <= eps:
            return x
        lo, hi, x, more = newton_bracket(lo, hi, x, fx, hermite_slope(*herm, x, plist, geo))
        if not more:
            break
    return _first_zero(lo, hi, eps, xtol, sol)


@njit
def _leave_contact(lo, hi, eps, xtol, sol):
    """:func:`pounding.framework.engine.driver._leave_contact` on ``exact``'s solution: (left, x, prev, f(prev)),
    left False when the pair stays in contact down to xtol past lo."""
    prev = hi
    fprev = stepped_gap(hi, sol)
    x = hi
    for _ in range(LEAVE_HALVINGS):
        x = lo + 0.5 * (x - lo)
        if x - lo <= xtol:
            break
        fx = stepped_gap(x, sol)
        if fx > eps:
            return True, x, prev, fprev
        prev = x
        fprev = fx
    return False, x, prev, fprev


@njit
def _first_zero(lo, hi, eps, xtol, sol):
    """:func:`pounding.framework.engine.driver._first_zero` on ``exact``'s solution: regula falsi with the
    Illinois rule, bisection down to xtol."""
    flo = stepped_gap(lo, sol)
    if flo <= eps:
        return lo
    fhi = stepped_gap(hi, sol)
    side = 0.0
    for _ in range(ILLINOIS_ITERATIONS):
        if hi - lo <= xtol:
            break
        x = illinois_point(lo, hi, flo, fhi)
        fx = stepped_gap(x, sol)
        if abs(fx) <= eps:
            return x
        lo, hi, flo, fhi, side = illinois_bracket(lo, hi, flo, fhi, side, x, fx)
    return lo
