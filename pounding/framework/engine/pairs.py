"""Slab pairs in modal coordinates, compiled: gaps, touching features and their modal rows.

The driver asks these questions many times per contact event (every trial step
of an impact search, every held step), so each is one compiled call over flat
arrays rather than a chain of small numpy operations. The arrays are the
stacked modal model's (:class:`~pounding.framework.engine.stacked_model.Model`), packed
once into :class:`~pounding.framework.engine.bundles.PairArrays` (``geo``), which every function
takes as one argument:

``pa``, ``pb`` (P, 2) int
    (building, storey) of the two slabs of every pair.
``rows`` (S + V, 3, nmax)
    The Phi rows (u, v, phi) of every slab over its building's modes; slab
    index = ``off[building] + storey``. After the S real slabs come the V facade
    slabs (:mod:`pounding.framework.model.facade`: a neighbour's storey at the level of a
    slab that strikes it between floors), addressed the same way by a pair whose
    "storey" is their index minus ``off[building]``.
``n_modes`` (n_buildings, 2) int
    First stacked mode index and number of modes of every building.
``verts`` (S + V, kmax, 2), ``nvert``, ``centres`` (S + V, 2), ``radii``
    Rest polygons [m], their vertex counts, centres of mass [m] and the
    largest distance of a vertex from the centre [m].
``rest`` (P,)
    Signed gap of every pair at rest [m].
``axis`` (P, 2)
    Unit direction from slab a to slab b of their closest points at rest (zero when
    none is defined): the axis of the separating-axis bound.

Like :mod:`pounding.framework.engine.kernel`, every function runs compiled by numba or,
without numba, as plain Python with the same arithmetic.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine.bundles import Features, PairFeatures, TouchingFeatures
from pounding.contact.geometry import MAX_FEATURES, axis_separation, clearance_bound, contact_points, displaced, signed_gap
from pounding.framework.engine.modal_step import stepped


@njit(borrowed=True)
def slab_dofs(rows, off, n_modes, building, storey, x, out):
    """out (3,) <- (u, v, phi) of one slab [m, m, rad] (or their rates) from stacked modal x (n,)."""
    s = off[building] + storey
    i0 = n_modes[building, 0]
    nb = n_modes[building, 1]
    for r in range(3):
        acc = 0.0
        for i in range(nb):
            acc += rows[s, r, i] * x[i0 + i]
        out[r] = acc


@njit
def slab_polygon(s, d, geo):
    """The polygon (k, 2) [m] of slab s (index into ``geo.verts``) displaced by its (u, v, phi) = d (3,)
    [m, m, rad], turned about its centre of mass."""
    return displaced(geo.verts[s, : geo.nvert[s]], geo.centres[s], d[0], d[1], d[2])


@njit
def pair_polygons(q, p, da, db, geo):
    """The displaced polygons of pair p's two slabs for modal displacements q (n,).

    Fills da, db (3,) with the slabs' (u, v, phi) [m, m, rad]; returns (A, B, sa, sb): the
    polygons (k, 2) [m] of the first and the second slab and their slab indices.
    """
    pa, pb, off = geo.pa, geo.pb, geo.off
    slab_dofs(geo.rows, off, geo.n_modes, pa[p, 0], pa[p, 1], q, da)
    slab_dofs(geo.rows, off, geo.n_modes, pb[p, 0], pb[p, 1], q, db)
    sa = off[pa[p, 0]] + pa[p, 1]
    sb = off[pb[p, 0]] + pb[p, 1]
    return slab_polygon(sa, da, geo), slab_polygon(sb, db, geo), sa, sb


@njit
def pair_gap(q, p, cutoff, geo):
    """Signed gap [m] of pair p for modal displacements q (n,).

    With a finite ``cutoff``, a cheap lower bound is returned whenever it already
    exceeds the cutoff: the rest gap minus the relative motion of the slabs
    (:func:`~pounding.contact.geometry.clearance_bound`), else their separation
    along the rest axis (:func:`~pounding.contact.geometry.axis_separation`); callers
    that compare the gap with thresholds <= cutoff get the same answers without the
    polygon test. Pass ``np.inf`` for the exact gap.
    """
    return pair_gap_into(q, p, cutoff, np.empty(3), np.empty(3), geo)


@njit
def pair_gap_into(q, p, cutoff, da, db, geo):
    """:func:`pair_gap` with scratch arrays da, db (3,) for the slabs' (u, v, phi), for hot loops."""
    pa, pb, rows, off, n_modes = geo.pa, geo.pb, geo.rows, geo.off, geo.n_modes
    slab_dofs(rows, off, n_modes, pa[p, 0], pa[p, 1], q, da)
    slab_dofs(rows, off, n_modes, pb[p, 0], pb[p, 1], q, db)
    return dofs_gap(da, db, p, cutoff, geo)[0]


@njit
def dofs_gap(da, db, p, cutoff, geo):
    """(gap [m], exact) of pair p with its slabs at (u, v, phi) = da, db (3,): :func:`pair_gap`'s cascade
    (the rest-gap bound, the rest-axis separation, then the polygons' signed gap), ``exact`` False when
    a bound above ``cutoff`` decided."""
    pa, pb, off, verts, nvert, centres, radii, rest, axis = geo.pa, geo.pb, geo.off, geo.verts, geo.nvert, geo.centres, geo.radii, geo.rest, geo.axis
    sa = off[pa[p, 0]] + pa[p, 1]
    sb = off[pb[p, 0]] + pb[p, 1]
    bound = clearance_bound(rest[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb])
    if bound > cutoff:
        return bound, False
    sep = axis_separation(verts[sa, : nvert[sa]], centres[sa], da[0], da[1], da[2],
                          verts[sb, : nvert[sb]], centres[sb], db[0], db[1], db[2], axis[p, 0], axis[p, 1])
    if sep > cutoff:
        return sep, False
    return signed_gap(slab_polygon(sa, da, geo), slab_polygon(sb, db, geo)), True


@njit
def pair_gaps(q, plist, cutoff, geo):
    """Gaps [m] (m,) of the pairs ``plist`` (m,) int; lower bounds where they exceed ``cutoff``."""
    out = np.empty(plist.shape[0])
    for j in range(plist.shape[0]):
        out[j] = pair_gap(q, plist[j], cutoff, geo)
    return out


@njit
def pair_features(q, p, tol, n, geo):
    """Touching features of pair p within ``tol`` [m] of its smallest gap, with their modal rows, for
    modal displacements q (n,): a :class:`~pounding.framework.engine.bundles.PairFeatures` (the
    points, normals, gaps and strikers as :func:`pounding.contact.geometry.contact_points` gives them)."""
    A, B, sa, sb = pair_polygons(q, p, np.empty(3), np.empty(3), geo)
    cp = contact_points(A, B, tol)
    Q, N = cp.Q, cp.N
    W = np.zeros((MAX_FEATURES, n))
    a, b = geo.pa[p, 0], geo.pb[p, 0]
    for k in range(cp.count):
        contact_row(geo, q, a, sa, b, sb, Q[k, 0], Q[k, 1], N[k, 0], N[k, 1], W[k])
    return PairFeatures(cp.count, Q, N, cp.gap, cp.who, cp.idx, cp.pair, W)


@njit
def contact_row(geo, q, a, sa, b, sb, qx, qy, nx, ny, w):
    """Add the modal row of a contact at (qx, qy) [m] with unit normal (nx, ny) from slab a to
    slab b into w (n,): d gap = w . dq, and an impulse pair I pushing the slabs apart changes q'
    by w I. Slabs a, b (building, slab index), modal displacements q (n,).

    A slab's row is the sum over the real slabs that make it up (``geo.floors``, weights
    ``geo.weights``) of their rigid-slab rows about their own displaced centres: a real slab is
    itself with weight 1; a facade slab (:mod:`pounding.framework.model.facade`) is the floors below
    and above with the storey shape's N1, N2, so that the impulse reaches each floor as the
    force at Q with its moment about that floor's centre, exactly (momentum laws to rounding).

    The one implementation of the row: the compiled pair queries and the driver's
    :meth:`~pounding.framework.engine.stacked_model.Model.row` both call it.
    """
    rows, off, n_modes, centres, floors, weights = geo.rows, geo.off, geo.n_modes, geo.centres, geo.floors, geo.weights
    d = np.empty(3)
    for side in range(2):
        if side == 0:
            sign, bld, s = -1.0, a, sa
        else:
            sign, bld, s = 1.0, b, sb
        for k in range(2):
            f = floors[s, k]
            if f < 0:
                continue
            slab_dofs(rows, off, n_modes, bld, f - off[bld], q, d)
            rx = qx - (centres[f, 0] + d[0])
            ry = qy - (centres[f, 1] + d[1])
            g0 = nx
            g1 = ny
            g2 = rx * ny - ry * nx
            sw = sign * weights[s, k]
            i0 = n_modes[bld, 0]
            for i in range(n_modes[bld, 1]):
                w[i0 + i] += sw * (rows[f, 0, i] * g0 + rows[f, 1, i] * g1 + rows[f, 2, i] * g2)


@njit
def pair_row(q, p, qx, qy, nx, ny, geo):
    """The modal row (n,) of a contact of pair p at (qx, qy) with normal (nx, ny), for modal
    displacements q (n,) (see :func:`contact_row`)."""
    pa, pb, off = geo.pa, geo.pb, geo.off
    a, fa, b, fb = pa[p, 0], pa[p, 1], pb[p, 0], pb[p, 1]
    w = np.zeros(q.shape[0])
    contact_row(geo, q, a, off[a] + fa, b, off[b] + fb, qx, qy, nx, ny, w)
    return w


@njit
def struck_features(q, plist, tol, deep, n, geo):
    """Touching features of the pairs ``plist`` (k,) int64, stacked, with what strikes at each, for
    modal displacements q (n,): a :class:`~pounding.framework.engine.bundles.Features` (the strikers
    as :func:`pounding.contact.geometry.contact_points` gives them).

    A pair is searched when its gap is within ``tol`` [m]; with ``deep`` the search
    tolerance grows with the penetration (max(tol, tol - gap)) so that every
    penetrating feature of a deeply overlapping pair is found.
    """
    cap = plist.shape[0] * MAX_FEATURES
    pair = np.empty(cap, dtype=np.int64)
    gaps = np.empty(cap)
    W = np.empty((cap, n))
    Q = np.empty((cap, 2))
    N = np.empty((cap, 2))
    who = np.empty(cap, dtype=np.int64)
    idx = np.empty(cap, dtype=np.int64)
    face = np.empty(cap, dtype=np.int64)
    m = 0
    for j in range(plist.shape[0]):
        p = plist[j]
        g = pair_gap(q, p, tol, geo)
        if g >= tol:
            continue
        t = max(tol, tol - g) if deep else tol
        f = pair_features(q, p, t, n, geo)
        # the fields read once (a bundle's array read in a loop costs a reference count each time)
        gp, Wp, Qp, Np, wp, ip, fp = f.gap, f.W, f.Q, f.N, f.who, f.idx, f.face
        for k in range(f.count):
            pair[m] = p
            gaps[m] = gp[k]
            W[m] = Wp[k]
            Q[m] = Qp[k]
            N[m] = Np[k]
            who[m] = wp[k]
            idx[m] = ip[k]
            face[m] = fp[k]
            m += 1
    return Features(pair[:m], gaps[:m], W[:m], Q[:m], N[:m], who[:m], idx[:m], face[:m])


@njit
def stepped_min_gap(A, B, z, p0, p1, plist, geo):
    """Smallest gap [m] of the pairs ``plist`` after one step z1 = A z + B[:, :, 0] p0 + B[:, :, 1] p1.

    A (n, 3, 3), B (n, 3, 2): the step's per-mode transition; z (n, 3) the start state;
    p0, p1 (n,) the modal loads at the step's ends. Only the displacements are formed.
    """
    n = z.shape[0]
    q1 = np.empty(n)
    for i in range(n):
        q1[i] = stepped(A, B, i, 0, z, p0[i], p1[i])
    g = np.inf
    for j in range(plist.shape[0]):
        g = min(g, pair_gap(q1, plist[j], np.inf, geo))
    return g


def rest_axis(A: np.ndarray, B: np.ndarray, rest_gap: float) -> np.ndarray:
    """Unit direction (2,) from polygon A to polygon B of their closest features at rest
    (zeros when the polygons overlap so much that none is found).

    Run interpreted, like the rest gaps: a one-off call per pair while the model is built, which
    would otherwise load (or compile) the contact points from Python in every run."""
    from pounding.compiler import interpreted

    with interpreted():
        cp = contact_points(A, B, max(rest_gap, 0.0) + 1e-9 * (1.0 + abs(rest_gap)))
    if cp.count == 0:
        return np.zeros(2)
    return cp.N[int(np.argmin(cp.gap[: cp.count]))].copy()


@njit
def closing(q, v, p, tol, v_min, n, geo):
    """Whether a touching point of pair p (within ``tol``) closes faster than v_min [m/s],
    n . (v_Q(a) - v_Q(b)) > v_min with n from a to b, for modal displacements q and
    velocities v (n,): the velocity condition of an impact (eq. 7 of the paper)."""
    pa, pb, centres = geo.pa, geo.pb, geo.centres
    da = np.empty(3)
    db = np.empty(3)
    va = np.empty(3)
    vb = np.empty(3)
    A, B, sa, sb = pair_polygons(q, p, da, db, geo)
    slab_dofs(geo.rows, geo.off, geo.n_modes, pa[p, 0], pa[p, 1], v, va)
    slab_dofs(geo.rows, geo.off, geo.n_modes, pb[p, 0], pb[p, 1], v, vb)
    cp = contact_points(A, B, tol)
    count, Q, N = cp.count, cp.Q, cp.N
    cax, cay = centres[sa, 0] + da[0], centres[sa, 1] + da[1]
    cbx, cby = centres[sb, 0] + db[0], centres[sb, 1] + db[1]
    for j in range(count):
        vax, vay = va[0] - va[2] * (Q[j, 1] - cay), va[1] + va[2] * (Q[j, 0] - cax)
        vbx, vby = vb[0] - vb[2] * (Q[j, 1] - cby), vb[1] + vb[2] * (Q[j, 0] - cbx)
        if N[j, 0] * (vax - vbx) + N[j, 1] * (vay - vby) > v_min:
            return True
    return False


@njit
def touching_features(q, candidates, tol, n, geo):
    """Touching features (within ``tol``) of every candidate pair, stacked in pair order.

    The first half of the impulse problem at an instant, shared by the compiled
    (:func:`pounding.framework.engine.kernel.impulses_at`) and the Python path
    (``Driver._law_impulses_at``): which features touch and their modal rows, no arithmetic on
    velocities. candidates (P,) bool; q (n,) modal displacements. Returns a
    :class:`~pounding.framework.engine.bundles.TouchingFeatures` (only its first ``count`` rows valid).
    """
    cap = MAX_FEATURES
    for p in range(candidates.shape[0]):
        if candidates[p]:
            cap += MAX_FEATURES
    pair = np.empty(cap, dtype=np.int64)
    who = np.empty(cap, dtype=np.int64)
    vertex = np.empty(cap, dtype=np.int64)
    Q = np.empty((cap, 2))
    N = np.empty((cap, 2))
    W = np.empty((cap, n))
    m = 0
    for p in range(candidates.shape[0]):
        if not candidates[p]:
            continue
        if pair_gap(q, p, tol, geo) > tol:
            continue
        f = pair_features(q, p, tol, n, geo)
        wp, ip, fp, Qp, Np, Wp = f.who, f.idx, f.face, f.Q, f.N, f.W  # read once (see struck_features)
        for j in range(f.count):
            pair[m] = p
            who[m] = wp[j]
            vertex[m] = -1 if fp[j] >= 0 else ip[j]
            Q[m] = Qp[j]
            N[m] = Np[j]
            W[m] = Wp[j]
            m += 1
    return TouchingFeatures(m, pair, who, vertex, Q, N, W)


@njit
def building_groups(plist, geo):
    """Group label (k,) of every pair of ``plist`` (k,) int: pairs linked through shared buildings
    (directly or along a row) share a label, the smallest position in ``plist`` of their group.

    Impulses on pairs of different groups act on disjoint modes (their modal rows have no common
    entry, so their Delassus coupling is exactly zero): each group is one Newton problem.
    """
    nb = geo.n_modes.shape[0]
    parent = np.arange(nb)
    for j in range(plist.shape[0]):
        ra = _root(parent, geo.pa[plist[j], 0])
        rb = _root(parent, geo.pb[plist[j], 0])
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    first = np.full(nb, -1, dtype=np.int64)
    label = np.empty(plist.shape[0], dtype=np.int64)
    for j in range(plist.shape[0]):
        r = _root(parent, geo.pa[plist[j], 0])
        if first[r] < 0:
            first[r] = j
        label[j] = first[r]
    return label


@njit(borrowed=True)
def _root(parent, i):
    while parent[i] != i:
        i = parent[i]
    return i
