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
from pounding.framework.pairs import pair_features, pair_gap, slab_dofs


@njit
def _point_bounds(rows, off, n_modes, building, storey, z, R, d, w):
    """(speed, acceleration) bounds of any point of one slab from the modal state z (n, 3):
    |(u', v')| + R |phi'| [m/s] and |(u'', v'')| + R |phi''| + R phi'^2 [m/s^2]; also
    returns |phi'| [rad/s]. d, w (3,) are work arrays."""
    slab_dofs(rows, off, n_modes, building, storey, z[:, 1].copy(), d)
    slab_dofs(rows, off, n_modes, building, storey, z[:, 2].copy(), w)
    speed = np.hypot(d[0], d[1]) + R * abs(d[2])
    acc = np.hypot(w[0], w[1]) + R * abs(w[2]) + R * d[2] * d[2]
    return speed, acc, abs(d[2])


@njit
def motion_bounds(z0, z1, p, geo):
    """Bounds (V [m/s], A [m/s^2]) on the relative speed and acceleration of pair p's points
    over a step from z0 to z1 (n, 3) (see the module docstring)."""
    pa, pb, rows, off, n_modes, verts, nvert, centres, radii, rest, axis, _, _ = geo
    d = np.empty(3)
    w = np.empty(3)
    a, fa, b, fb = pa[p, 0], pa[p, 1], pb[p, 0], pb[p, 1]
    Ra, Rb = radii[off[a] + fa], radii[off[b] + fb]
    V = 0.0
    A = 0.0
    om = 0.0
    for z in (z0, z1):
        sa, aa, wa = _point_bounds(rows, off, n_modes, a, fa, z, Ra, d, w)
        sb, ab, wb = _point_bounds(rows, off, n_modes, b, fb, z, Rb, d, w)
        V = max(V, sa + sb)
        A = max(A, aa + ab)
        om = max(om, wa + wb)
    return V, 2.0 * A + 2.0 * om * V


@njit
def nearest_rate(q, v, p, tol, n, geo):
    """(gap [m], gap rate [m/s]) of the nearest feature of pair p for modal q, v (n,)."""
    g = pair_gap(q, p, np.inf, geo)
    # contact_points reports nothing beyond its tolerance: widen it to reach the nearest feature
    count, Q, N, gap, who, idx, face, W = pair_features(q, p, max(g, 0.0) + tol, n, geo)
    if count == 0:
        return g, 0.0
    j = 0
    for k in range(1, count):
        if gap[k] < gap[j]:
            j = k
    r = 0.0
    for i in range(n):
        r += W[j, i] * v[i]
    return gap[j], r


@njit
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
    q1 = z1[:, 0].copy()
    V, A = motion_bounds(z0, z1, p, geo)
    reach = (V + A * h) * h + eps  # the most the gap can fall over the step, from its end backwards
    # the end gap (a cheap lower bound where it exceeds the reach: pair_gap's cutoff)
    g_end = pair_gap(q1, p, reach, geo)
    if g_end > reach:
        return False
    if g_end < -eps:
        return True
    n = z0.shape[0]
    g1, r1 = nearest_rate(q1, z1[:, 1].copy(), p, tol, n, geo)
    g0, r0 = nearest_rate(z0[:, 0].copy(), z0[:, 1].copy(), p, tol, n, geo)
    if g0 < -eps:
        return False
    return graze_bound(g0, r0, g1, r1, A, h) < -eps
