"""Where a closing gap crosses zero inside a step: the ``crossing`` locator's screen.

With ``locate = "crossing"`` (the default) an impact is applied where the gap is zero
to rounding, never where it is merely within the contact tolerance. A step is handed
to the driver's impact search when a slab pair ends it overlapping (``g(h) < -eps``)
or when the pair may have dipped below zero and come back inside it (a *graze*).
The graze test is a bound, not a guess: with the gap g(t) of the nearest feature,
its rates g'(0), g'(h) at the step's ends and a bound A on |g''| over the step,

    g(t) >= f0(t) = g(0) + g'(0) t - A t^2 / 2,   g(t) >= f1(t) = g(h) - g'(h) (h - t) - A (h - t)^2 / 2,

and the smallest max(f0, f1) over [0, h] is at the single point where f0 = f1 (f0 - f1
is linear in t); a step whose bound there is below zero is searched (sampled, then the
root bracketed by Brent's method), every other step cannot have touched.

A bounds the relative acceleration of the slabs' points: for each slab, twice the
larger of its end values of |(u'', v'')| + R |phi''| + R phi'^2 (R the largest
distance of a vertex from the centre; the factor 2 covers the variation of the
acceleration inside a step, which for steps below half the shortest significant
period is far less), plus the turning of the normal, 2 |phi'| V. The same velocity
bound V gives a cheap first screen from the clearance bound alone, so the feature
geometry is formed only for pairs within (V + A h) h of contact.

Every function runs compiled by numba or, without numba, as plain Python.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.contact.geometry import EPS_REL, clearance_bound
from pounding.framework.engine.pairs import dofs_gap, pair_features, pair_gap


#: where a pair's two slab states start in its (18,) state array (:func:`pair_kinematics`); int64, not
#: literals, so that each helper is compiled once
SLAB_A = np.int64(0)
SLAB_B = np.int64(9)


@njit(borrowed=True)
def slab_state(rows, off, n_modes, building, storey, z, out, o):
    """out[o:o + 9] <- one slab's (u, v, phi), their rates and their accelerations from the modal
    state z (n, 3), in one pass over its modes: nine independent sums, each in mode order as
    :func:`~pounding.framework.engine.pairs.slab_dofs` forms it (the same numbers). Takes arrays, not the
    pair bundle: the compiled stretch calls it for every pair at every step, where passing the
    bundle cost more than the sums (~180 ns a call)."""
    s = off[building] + storey
    i0 = n_modes[building, 0]
    nb = n_modes[building, 1]
    d0 = d1 = d2 = v0 = v1 = v2 = a0 = a1 = a2 = 0.0
    for i in range(nb):
        r0 = rows[s, 0, i]
        r1 = rows[s, 1, i]
        r2 = rows[s, 2, i]
        q = z[i0 + i, 0]
        w = z[i0 + i, 1]
        a = z[i0 + i, 2]
        d0 += r0 * q
        d1 += r1 * q
        d2 += r2 * q
        v0 += r0 * w
        v1 += r1 * w
        v2 += r2 * w
        a0 += r0 * a
        a1 += r1 * a
        a2 += r2 * a
    out[o], out[o + 1], out[o + 2] = d0, d1, d2
    out[o + 3], out[o + 4], out[o + 5] = v0, v1, v2
    out[o + 6], out[o + 7], out[o + 8] = a0, a1, a2


@njit(borrowed=True)
def point_bounds(k, o, R):
    """(speed, acceleration) bounds of any point of a slab with state k[o:o + 9] (:func:`slab_state`):
    |(u', v')| + R |phi'| [m/s] and |(u'', v'')| + R |phi''| + R phi'^2 [m/s^2]; also |phi'| [rad/s]."""
    speed = np.hypot(k[o + 3], k[o + 4]) + R * abs(k[o + 5])
    acc = np.hypot(k[o + 6], k[o + 7]) + R * abs(k[o + 8]) + R * k[o + 5] * k[o + 5]
    return speed, acc, abs(k[o + 5])


@njit(borrowed=True)
def pair_kinematics(z, p, geo, out):
    """out (18,) <- :func:`slab_state` of pair p's slab a (out[:9]) and slab b (out[9:]) at z (n, 3)."""
    pa, pb, rows, off, n_modes = geo.pa, geo.pb, geo.rows, geo.off, geo.n_modes
    slab_state(rows, off, n_modes, pa[p, 0], pa[p, 1], z, out, SLAB_A)
    slab_state(rows, off, n_modes, pb[p, 0], pb[p, 1], z, out, SLAB_B)


@njit(borrowed=True)
def motion_from(k0, k1, Ra, Rb):
    """Bounds (V [m/s], A [m/s^2]) on the relative speed and acceleration of a pair's points over a
    step, from its slab states k0, k1 (18,) at the step's ends (:func:`pair_kinematics`; the module
    docstring); Ra, Rb [m] the slabs' radii."""
    V = 0.0
    A = 0.0
    om = 0.0
    for k in (k0, k1):
        sa, aa, wa = point_bounds(k, SLAB_A, Ra)
        sb, ab, wb = point_bounds(k, SLAB_B, Rb)
        V = max(V, sa + sb)
        A = max(A, aa + ab)
        om = max(om, wa + wb)
    return V, 2.0 * A + 2.0 * om * V


@njit
def nearest_rate(q, v, p, tol, n, geo):
    """(gap [m], gap rate [m/s]) of the nearest feature of pair p for modal q, v (n,)."""
    return rate_at_gap(q, v, p, pair_gap(q, p, np.inf, geo), tol, n, geo)


@njit
def rate_at_gap(q, v, p, g, tol, n, geo):
    """:func:`nearest_rate` given the pair's exact signed gap g [m] at q (``pair_gap`` with no cutoff,
    or with a cutoff it does not exceed)."""
    # contact_points reports nothing beyond its tolerance: widen it to reach the nearest feature
    f = pair_features(q, p, max(g, 0.0) + tol, n, geo)
    gap, W = f.gap, f.W
    if f.count == 0:
        return g, 0.0
    j = 0
    for k in range(1, f.count):
        if gap[k] < gap[j]:
            j = k
    r = 0.0
    for i in range(n):
        r += W[j, i] * v[i]
    return gap[j], r


@njit(borrowed=True)
def graze_bound(g0, r0, g1, r1, A, h):
    """Lower bound [m] on the gap over a step of h [s] from its end values g0, g1 [m], rates
    r0, r1 [m/s] and |g''| <= A [m/s^2]: the smallest max(f0, f1) of the module docstring."""
    c0 = g0 - g1 + r1 * h + 0.5 * A * h * h  # f0 - f1 = c0 + c1 t
    c1 = r0 - r1 - A * h
    low = min(g0, g1)
    if c1 != 0.0:
        tc = -c0 / c1
        if 0.0 < tc < h:
            low = min(low, g0 + r0 * tc - 0.5 * A * tc * tc)
    return low


@njit
def suspect(z0, z1, p, h, eps, tol, geo):
    """Whether pair p may touch inside a step of h [s] from z0 to z1 (n, 3): it ends overlapping
    (gap < -eps [m]) or its gap may have dipped below -eps inside the step (a graze), by the
    bound of the module docstring. A pair that starts the step overlapping is not a new contact
    (it is pressed or held: the caller's other checks see it)."""
    return suspect_step(z0, z1, p, h, eps, tol, geo, np.int64(-1), np.empty((0, 3)), np.empty((0, 7)))  # (an int64, not a literal: one specialization)


@njit(borrowed=True)
def moved_bound(ref, da, db, Ra, Rb):
    """Lower bound [m] on the signed gap of a pair whose gap was ref[0] >= 0 [m] with its slabs at
    (u, v, phi) = ref[1:4], ref[4:7], now at da, db (3,): :func:`~pounding.contact.geometry.clearance_bound`
    with that state for the rest state (the same proof: every point of a slab moves from one state
    to the other by its centre's translation plus at most R |phi change|)."""
    return clearance_bound(ref[0], da[0] - ref[1], da[1] - ref[2], da[2] - ref[3], Ra,
                           db[0] - ref[4], db[1] - ref[5], db[2] - ref[6], Rb)


@njit
def suspect_step(z0, z1, p, h, eps, tol, geo, k, rates, gaps):
    """:func:`suspect` for the step k -> k + 1 of a stretch of consecutive steps (each step's start
    state the last one's end state, unchanged), with two memories (k < 0: none; the same answers):

    * ``gaps`` (pairs, 7): the last exact gap the screen computed, with its slabs' (u, v, phi)
      (gap NaN: none). Near contact the rest-state bounds of :func:`~pounding.framework.engine.pairs.dofs_gap`
      rarely decide (an L-shaped slab's axis separation is far below its gap) and each step would
      form the polygons; the gap bounded from that state (:func:`moved_bound`, less a rounding margin
      far above the geometry's, 1e3 ``EPS_REL`` of the coordinates) decides instead while the slabs
      have moved less than the clearance left.
    * ``rates`` (pairs, 3): the nearest feature's (gap, rate) at a step's end as (k + 1, gap, rate),
      the next step's start values: one feature search fewer per searched step.
    """
    pa, pb, off, radii = geo.pa, geo.pb, geo.off, geo.radii
    k0 = np.empty(18)
    k1 = np.empty(18)
    pair_kinematics(z0, p, geo, k0)
    pair_kinematics(z1, p, geo, k1)
    V, A = motion_from(k0, k1, radii[off[pa[p, 0]] + pa[p, 1]], radii[off[pb[p, 0]] + pb[p, 1]])
    return suspect_given(z0, z1, p, h, eps, tol, geo, k, rates, gaps, k1[0:3].copy(), k1[9:12].copy(), V, A)


@njit
def suspect_given(z0, z1, p, h, eps, tol, geo, k, rates, gaps, da, db, V, A):
    """:func:`suspect_step` given the slabs' end (u, v, phi) da, db (3,) and the motion bounds V, A
    (:func:`motion_from`): for the compiled stretch, which has formed them already."""
    pa, pb, off, centres, radii = geo.pa, geo.pb, geo.off, geo.centres, geo.radii
    reach = (V + A * h) * h + eps  # the most the gap can fall over the step, from its end backwards
    # the end gap: the bound from the remembered state, then pair_gap's cascade (lower bounds all: a
    # bound above the reach decides, whichever it is)
    if k >= 0 and gaps[p, 0] >= 0.0:  # (False for NaN: no memory)
        sa = off[pa[p, 0]] + pa[p, 1]
        sb = off[pb[p, 0]] + pb[p, 1]
        scale = max(1.0, abs(centres[sa, 0]) + abs(centres[sa, 1]) + radii[sa] + abs(centres[sb, 0]) + abs(centres[sb, 1]) + radii[sb])
        if moved_bound(gaps[p], da, db, radii[sa], radii[sb]) - 1e3 * EPS_REL * scale > reach:
            return False
    g_end, exact = dofs_gap(da, db, p, reach, geo)
    if not exact:  # a cheap bound above the reach
        return False
    if k >= 0:
        gaps[p, 0] = g_end
        for i in range(3):
            gaps[p, 1 + i] = da[i]
            gaps[p, 4 + i] = db[i]
    if g_end > reach:
        return False
    if g_end < -eps:
        return True
    n = z0.shape[0]
    g1, r1 = rate_at_gap(z1[:, 0].copy(), z1[:, 1].copy(), p, g_end, tol, n, geo)
    if k >= 0 and rates[p, 0] == k:
        g0, r0 = rates[p, 1], rates[p, 2]
    else:
        g0, r0 = nearest_rate(z0[:, 0].copy(), z0[:, 1].copy(), p, tol, n, geo)
    if k >= 0:
        rates[p, 0], rates[p, 1], rates[p, 2] = k + 1, g1, r1
    if g0 < -eps:
        return False
    return graze_bound(g0, r0, g1, r1, A, h) < -eps


# --------------------------------------------------------------------------- the search on the interpolant
# The impact search (:func:`pounding.framework.engine.event_search.crossing_search`) runs on the
# cubic Hermite interpolant of a step's end displacements and velocities (a fourth-order guess of the
# integrator's own intra-step solution, with no transition to build) and then confirms and polishes the
# zero on the integrator's solution. These functions do the interpolant's part in one compiled call each,
# with the arithmetic of the Python code they replace (the same samples, the same Illinois iteration, and
# Brent's bounded minimiser as scipy's ``minimize_scalar(method="bounded")`` runs it).

#: samples of a step searched for a graze (on the interpolant) before the minimum is refined
GRAZE_SAMPLES = 16


@njit
def hermite_gap(q0, v0, q1, v1, h, x, plist, geo):
    """Smallest gap [m] of the pairs ``plist`` at x [s] in a step of h [s], on the cubic Hermite of the
    step's end displacements q0, q1 and velocities v0, v1 (n,)."""
    s = x / h
    # (1 - s)^2 by the C library's pow, as the Python search computed it (``(1 - s) ** 2``): pow is not
    # always the correctly rounded x * x, and a last bit here moves an accepted zero within the geometry's
    # rounding. The exponent is not a literal so that the compiler keeps the call.
    two = 2.0 + 0.0 * s
    u2 = (1 - s) ** two
    h00 = (1 + 2 * s) * u2
    h10 = s * u2
    h01 = s * s * (3 - 2 * s)
    h11 = s * s * (s - 1)
    c10 = h10 * h
    c11 = h11 * h
    n = q0.shape[0]
    q = np.empty(n)
    for i in range(n):
        q[i] = h00 * q0[i] + c10 * v0[i] + h01 * q1[i] + c11 * v1[i]
    g = np.inf
    for j in range(plist.shape[0]):
        g = min(g, pair_gap(q, plist[j], np.inf, geo))
    return g


@njit
def hermite_slope(q0, v0, q1, v1, h, x, plist, geo):
    """Slope [m/s] of :func:`hermite_gap` at x, by a central difference of 1e-7 h (one-sided at the
    step's ends): the Newton slope of the driver's polish."""
    dh = 1e-7 * h
    a = max(x - dh, 0.0)
    b = min(x + dh, h)
    return (hermite_gap(q0, v0, q1, v1, h, b, plist, geo) - hermite_gap(q0, v0, q1, v1, h, a, plist, geo)) / (b - a)


@njit
def hermite_zero(q0, v0, q1, v1, h, lo, hi, eps, xtol, checked, plist, geo):
    """A zero [s] of :func:`hermite_gap` on [lo, hi] where the interpolant's gap is positive at lo and
    negative at hi: the first point found where it is within eps [m] of zero, by regula falsi with the
    Illinois rule (superlinear, bracketing), bisection down to xtol [s] where the gap is not smooth;
    lo when the gap at lo is within eps already. With ``checked``, the midpoint when the interpolant
    does not bracket a zero (without, the caller knows it does)."""
    flo = hermite_gap(q0, v0, q1, v1, h, lo, plist, geo)
    fhi = hermite_gap(q0, v0, q1, v1, h, hi, plist, geo)
    if checked and not (fhi < 0.0 < flo):
        return 0.5 * (lo + hi)
    if flo <= eps:
        return lo
    side = 0.0
    for _ in range(ILLINOIS_ITERATIONS):
        if hi - lo <= xtol:
            break
        x = illinois_point(lo, hi, flo, fhi)
        fx = hermite_gap(q0, v0, q1, v1, h, x, plist, geo)
        if abs(fx) <= eps:
            return x
        lo, hi, flo, fhi, side = illinois_bracket(lo, hi, flo, fhi, side, x, fx)
    return lo


#: the regula falsi's most iterations (the bracket reaches xtol long before: bisection halves it)
ILLINOIS_ITERATIONS = 200

#: the most halvings back from a step's end towards a pair touching at its start, looking for where it
#: has left contact (:func:`pounding.framework.engine.event_search.crossing_search`): 2^-60 of a step is below xtol
LEAVE_HALVINGS = 60


@njit(borrowed=True)
def illinois_point(lo, hi, flo, fhi):
    """The next trial point [s] of regula falsi on the bracket [lo, hi] with f(lo) = flo > 0 > fhi = f(hi)
    (the secant's zero; the midpoint where the secant is flat or leaves the bracket).

    The zero finders share it and :func:`illinois_bracket`: :func:`hermite_zero` on the interpolant and
    :func:`pounding.framework.engine.event_search.crossing_search` on the integrator's own solution:
    each loop is theirs, the arithmetic is these two functions'."""
    x = hi - fhi * (hi - lo) / (fhi - flo) if fhi != flo else 0.5 * (lo + hi)
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    return x


@njit(borrowed=True)
def illinois_bracket(lo, hi, flo, fhi, side, x, fx):
    """The bracket (lo, hi, flo, fhi, side) after f(x) = fx at the trial point x, with the Illinois rule:
    the end kept twice in a row has its value halved (side: 1.0 when lo moved last, -1.0 when hi did,
    0.0 at the start; a float, which numba never types as a literal, so every caller shares one
    specialization), which makes regula falsi superlinear."""
    if fx > 0:
        lo, flo = x, fx
        if side == 1.0:
            fhi *= 0.5
        side = 1.0
    else:
        hi, fhi = x, fx
        if side == -1.0:
            flo *= 0.5
        side = -1.0
    return lo, hi, flo, fhi, side


@njit(borrowed=True)
def newton_bracket(lo, hi, x, fx, slope):
    """One step of the zero finders' Newton polish: the bracket [lo, hi] narrowed by f(x) = fx, and
    the next point x - fx / slope with the interpolant's slope [m/s]; (lo, hi, next x, True), or
    (lo, hi, x, False) when the slope is not negative (no crossing from above to follow)."""
    if fx > 0:
        lo = x
    else:
        hi = x
    if not slope < 0.0:
        return lo, hi, x, False
    return lo, hi, x - fx / slope, True


@njit(borrowed=True)
def bounded_minimum(q0, v0, q1, v1, h, a, b, xatol, plist, geo):
    """(x [s], value [m]) of the smallest :func:`hermite_gap` on [a, b]: Brent's bounded minimiser
    (golden sections and parabolic steps; Forsythe, Malcolm & Moler 1977, ``fmin``), in the form of
    scipy's ``minimize_scalar(method="bounded")``, stopping when the bracket is within 2 (sqrt(eps) |x|
    + xatol / 3) of x, or after 500 evaluations."""
    sqrt_eps = np.sqrt(2.2e-16)
    golden_mean = 0.5 * (3.0 - np.sqrt(5.0))
    fulc = a + golden_mean * (b - a)
    nfc, xf = fulc, fulc
    rat = 0.0
    e = 0.0
    fx = hermite_gap(q0, v0, q1, v1, h, xf, plist, geo)
    num = 1
    ffulc = fx
    fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = sqrt_eps * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # a parabola through the three best points
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    d = xm - xf
                    rat = tol1 * ((1.0 if d > 0 else -1.0 if d < 0 else 0.0) + (1.0 if d == 0 else 0.0))
            else:
                golden = True
        if golden:
            e = (a - xf) if xf >= xm else (b - xf)
            rat = golden_mean * e
        si = (1.0 if rat > 0 else -1.0 if rat < 0 else 0.0) + (1.0 if rat == 0 else 0.0)
        x = xf + si * max(abs(rat), tol1)
        fu = hermite_gap(q0, v0, q1, v1, h, x, plist, geo)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = sqrt_eps * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= 500:
            break
    return xf, fx


@njit
def hermite_search(q0, v0, q1, v1, h, g0, gh, eps, plist, geo):
    """Where the interpolant's gap of a step of h [s] that does not end overlapping first goes below -eps
    [m]: samples at h j / (GRAZE_SAMPLES + 1); the first negative one and its left neighbour (or 0)
    bracket it. With none negative, the smallest of them and of the end gaps g0, gh (the integrator's own
    [m]) gives the interval around the minimum, refined by :func:`bounded_minimum` (xatol 1e-7 h).

    Returns (found, lo, hi): found = True with the bracket [lo, hi] [s] of a negative sample; else
    False with the minimiser's interval start ``lo`` and its minimum ``hi`` [s]."""
    m = GRAZE_SAMPLES
    prev = 0.0
    jmin = 0
    vmin = g0
    for j in range(1, m + 1):
        x = h * j / (m + 1)
        g = hermite_gap(q0, v0, q1, v1, h, x, plist, geo)
        if g < -eps:
            return True, prev, x
        if g < vmin:  # the first smallest, as numpy's argmin over [g0, samples..., gh]
            jmin, vmin = j, g
        prev = x
    if gh < vmin:
        jmin = m + 1
    a = 0.0 if jmin <= 1 else h * (jmin - 1) / (m + 1)
    b = h if jmin >= m else h * (jmin + 1) / (m + 1)
    x, _ = bounded_minimum(q0, v0, q1, v1, h, a, b, 1e-7 * h, plist, geo)
    return False, a, x


@njit
def suspects(z0, z1, plist, h, eps, tol, geo):
    """:func:`suspect` for every pair of ``plist`` (m,) int: a bool mask (m,), in one call."""
    out = np.zeros(plist.shape[0], dtype=np.bool_)
    for j in range(plist.shape[0]):
        out[j] = suspect(z0, z1, plist[j], h, eps, tol, geo)
    return out
