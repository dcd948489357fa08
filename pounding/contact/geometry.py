"""Contact geometry of two rigid slab polygons in plan.

Conventions
-----------
* A slab is a simple polygon, vertices as a float64 array ``(k, 2)`` in global
  plan coordinates [m], counter-clockwise (normalise user input once with
  :func:`ccw`). Edge ``j`` runs from vertex ``j`` to vertex ``j + 1`` (mod k);
  its outward unit normal is ``(dy, -dx) / L``.
* A slab moves rigidly by ``(u, v, phi)``: its centre of mass ``c`` by ``(u, v)``
  and a turn phi about it, so a point P goes to ``c + (u, v) + R(phi) (P - c)``
  (:func:`displaced`). The turn is exact, not linearised: the contact rows, which
  take a point's lever arm about the displaced centre, are then the exact gradient
  of the gap, so a contact force that follows a potential of the gap does no net
  work, and an impulse pair at a common point keeps the slabs' angular momentum.
  (The structural model is linear in phi; only where slabs touch is the position
  exact, as the paper's contact conditions ask.)
* Normals of contact features point from polygon A towards polygon B.

Penetration depth
-----------------
:func:`signed_gap` returns the clear distance between the boundaries when the
polygons are apart and minus a penetration depth when their interiors overlap.
The depth is the largest distance from a *penetrating* vertex P of one
polygon S to the nearest *entering edge* of the other polygon T, an edge of T
part of which lies inside S::

    depth = max over penetrating P of S (S = A, B) of
            min over edges e of T with e ∩ int S != {} of dist(P, e)

This refines the plain "distance from a vertex inside the other polygon to
the other's boundary" (which it never undercuts) for a case that matters for
buildings: slabs of equal plan depth side by side have collinear facades, so
at impact a corner of one slab slides *along* an edge line of the other and
lies on (or within rounding of) its boundary. Its distance to the whole
boundary is then ~0 whatever the overlap; that edge does not enter the
striker, so it is skipped and the depth is the true overlap (0.02 for two
unit squares overlapping by 0.02 along x, even offset by 1e-9 along y). For
a vertex poking through an edge (how separated slabs first meet) both
definitions give the distance to that edge, so the gap is continuous, with
slope at most 1, through 0.

A vertex of S *penetrates* T if it lies strictly inside T, or on T's boundary
with one of its two edges entering the interior of T. If no vertex
penetrates yet the boundaries cross (a "plus sign" overlap, possible only in a
bad scene), the same formula is applied to the midpoints of the boundary
pieces of each polygon lying inside the other (reported as features with
vertex index -1); it is negative and tends to 0 as the crossing shrinks. If
one polygon lies wholly inside the other (no entering edge), the depth falls
back to the distance to the container's whole boundary.

Known limit: the set of entering edges changes when an edge of T starts to
enter S. If that happens within the penetration depth of a vertex (two
nearly collinear edges sliding over a corner while already overlapping), the
depth can jump down to the distance to the new edge (never below the plain
nearest-boundary depth). Random tests with slab-like shapes (rectangles, L, U)
show no such jump at penetrations small compared with the edges; random
polygons with acute corners do, at penetrations of a few per cent of their
size.

Tolerance
---------
All geometric decisions (on the boundary, collinear, same point) use
``eps = EPS_REL * max(1, max |coordinate|)`` [m], i.e. about 1e-11 m for
slabs tens of metres from the origin.

Compilation
-----------
The kernels are written with plain loops over float64 arrays and declared with
:func:`pounding.compiler.njit`: compiled by numba on first use, or plain Python
without it. No fastmath: both paths give bit-identical results. One-off calls
from Python (the rest gaps of a scene at load) run interpreted
(:func:`rest_gap`), so loading a scene compiles nothing.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pounding.compiler import interpreted, njit


EPS_REL = 1e-12
"""Relative geometric tolerance (see the module docstring)."""

MAX_FEATURES = 8
"""Rows of the fixed-size arrays returned by :func:`contact_points`."""

FACE_ANGLE = 1e-3
"""Two edges facing each other within this angle [rad] are face to face (:func:`contact_points`,
:func:`face_ends`)."""


# =============================================================================
# Python helpers (called once per scene, not in the hot loop)
# =============================================================================


def _as_vertices(vertices) -> np.ndarray:
    P = np.array(vertices, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 3:
        raise ValueError(f"a polygon needs vertices of shape (k >= 3, 2), got {P.shape}")
    return P


def _signed_area(P: np.ndarray) -> float:
    # shoelace about the mean vertex: avoids cancellation far from the origin
    X = P - P.mean(axis=0)
    x, y = X[:, 0], X[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def ccw(vertices) -> np.ndarray:
    """Return the polygon as a contiguous float64 ``(k, 2)`` array, counter-clockwise.

    A clockwise polygon is reversed keeping its first vertex first: new vertex
    ``i`` is old vertex ``(-i) mod k``.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        Vertices [m] in either orientation.

    Returns
    -------
    ndarray, shape (k, 2)
        A new array (the input is never modified).
    """
    P = _as_vertices(vertices)
    if _signed_area(P) < 0.0:
        P = P[(-np.arange(P.shape[0])) % P.shape[0]]
    return np.ascontiguousarray(P)


def polygon_properties(vertices):
    """Area, centroid and polar second moment of area of a simple polygon.

    Exact (shoelace-type formulas) for any simple polygon, either orientation.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        Vertices [m].

    Returns
    -------
    area : float
        [m^2], positive.
    centroid : ndarray, shape (2,)
        [m].
    polar_moment : float
        ``∫ r^2 dA`` about the centroid [m^4] (``Ixx + Iyy``).
    """
    P = ccw(vertices)
    x0 = P.mean(axis=0)  # work about the mean vertex to limit cancellation
    X = P - x0
    x, y = X[:, 0], X[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    area = 0.5 * float(cr.sum())
    if not area > 0.0:
        raise ValueError("polygon has zero area")
    cx = float(((x + xn) * cr).sum()) / (6.0 * area)
    cy = float(((y + yn) * cr).sum()) / (6.0 * area)
    ixx = float((cr * (y * y + y * yn + yn * yn)).sum()) / 12.0  # ∫ y^2 dA about x0
    iyy = float((cr * (x * x + x * xn + xn * xn)).sum()) / 12.0  # ∫ x^2 dA about x0
    polar = ixx + iyy - area * (cx * cx + cy * cy)  # parallel axes back to the centroid
    return area, x0 + np.array([cx, cy]), polar


def radius(vertices, c) -> float:
    """Largest distance [m] from the point ``c`` (2,) to a vertex: the R of :func:`clearance_bound`."""
    P = np.asarray(vertices, dtype=np.float64)
    return float(np.max(np.hypot(P[:, 0] - c[0], P[:, 1] - c[1])))


def is_simple(vertices):
    """Check that a polygon is simple, for the scene validator.

    Rejects: a wrong shape or non-finite values, a vertex repeating the next
    one, zero area, two edges that cross or touch (other than consecutive edges
    at their shared vertex), and consecutive edges folding back on each other.

    Parameters
    ----------
    vertices : array_like, shape (k, 2)
        Vertices [m], either orientation.

    Returns
    -------
    ok : bool
    reason : str
        Empty if ``ok``; otherwise what is wrong, naming vertices/edges by
        0-based index in the given order (edge i joins vertex i and i+1).
    """
    try:
        P = _as_vertices(vertices)
    except (ValueError, TypeError) as exc:
        return False, str(exc)
    if not np.all(np.isfinite(P)):
        return False, "vertices must be finite numbers"
    k = P.shape[0]
    eps = EPS_REL * max(1.0, float(np.max(np.abs(P))))
    for i in range(k):
        j = (i + 1) % k
        if math.hypot(P[j, 0] - P[i, 0], P[j, 1] - P[i, 1]) <= eps:
            return False, f"vertex {j} repeats vertex {i}"
    size = float(np.max(np.ptp(P, axis=0)))
    if abs(_signed_area(P)) <= eps * size:
        return False, "polygon has zero area"
    for i in range(k):
        a0, a1 = P[i], P[(i + 1) % k]
        for j in range(i + 1, k):
            b0, b1 = P[j], P[(j + 1) % k]
            if j == i + 1 or (i == 0 and j == k - 1):
                # consecutive edges share one vertex; they must not fold back along each other
                v, u, w = (a1, a0, b1) if j == i + 1 else (a0, a1, b0)
                du, dw = u - v, w - v
                cross = du[0] * dw[1] - du[1] * dw[0]
                dot = du[0] * dw[0] + du[1] * dw[1]
                if abs(cross) <= eps * (np.hypot(*du) + np.hypot(*dw)) and dot > 0.0:
                    return False, f"edges {i} and {j} fold back on each other"
            elif _segments_touch(a0, a1, b0, b1, eps):
                return False, f"edges {i} and {j} intersect"
    return True, ""


def _segments_touch(a0, a1, b0, b1, eps) -> bool:
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    o1, o2 = orient(a0, a1, b0), orient(a0, a1, b1)
    o3, o4 = orient(b0, b1, a0), orient(b0, b1, a1)
    if o1 * o2 < 0.0 and o3 * o4 < 0.0:
        return True  # proper crossing
    # otherwise they touch only if an end point lies on the other segment
    closest = getattr(_closest_on_segment, "py_func", _closest_on_segment)  # no compile for validation
    d = min(
        closest(a0[0], a0[1], b0[0], b0[1], b1[0], b1[1])[0],
        closest(a1[0], a1[1], b0[0], b0[1], b1[0], b1[1])[0],
        closest(b0[0], b0[1], a0[0], a0[1], a1[0], a1[1])[0],
        closest(b1[0], b1[1], a0[0], a0[1], a1[0], a1[1])[0],
    )
    return d <= eps


# =============================================================================
# Kernels (numba-compiled)
# =============================================================================


@njit
def displaced(vertices, c, u, v, phi):
    """Vertices after a rigid displacement of the slab.

    Parameters
    ----------
    vertices : ndarray, shape (k, 2)
        Rest positions [m].
    c : ndarray, shape (2,)
        Centre of mass [m] (the point whose displacement is ``(u, v)``).
    u, v : float
        Displacement of ``c`` [m].
    phi : float
        Rotation about ``c`` [rad], counter-clockwise positive.

    Returns
    -------
    ndarray, shape (k, 2)
        ``P + (u, v) + (R(phi) - I) (P - c)`` for each vertex P (:func:`turn`).
    """
    k = vertices.shape[0]
    out = np.empty((k, 2))
    cm1, sn = turn(phi)
    for i in range(k):
        dx = vertices[i, 0] - c[0]
        dy = vertices[i, 1] - c[1]
        out[i, 0] = vertices[i, 0] + u + (cm1 * dx - sn * dy)
        out[i, 1] = vertices[i, 1] + v + (sn * dx + cm1 * dy)
    return out


def turned(r, phi):
    """(R(phi) - I) r [m], shape (..., k, 2): how far a turn phi [rad] (shape (..., 1)) about a centre
    moves the points at offsets r (k, 2) [m] from it (numpy, for results over many steps; the same
    arithmetic as :func:`displaced`)."""
    h = np.sin(0.5 * phi)
    cm1, sn = -2.0 * h * h, np.sin(phi)
    return np.stack([cm1 * r[:, 0] - sn * r[:, 1], sn * r[:, 0] + cm1 * r[:, 1]], axis=-1)


@njit(borrowed=True)
def turn(phi):
    """(cos(phi) - 1, sin(phi)) of a turn phi [rad], the first as -2 sin^2(phi / 2): a point's move
    (R(phi) - I) r without the cancellation of cos(phi) - 1 at the small turns of a building
    (a vertex at rest keeps its coordinates to the bit when phi = 0)."""
    h = math.sin(0.5 * phi)
    return -2.0 * h * h, math.sin(phi)


@njit(borrowed=True)
def axis_separation(A, cA, uA, vA, phiA, B, cB, uB, vB, phiB, nx, ny):
    """Separation [m] of two displaced slabs along the unit axis (nx, ny), from A towards B.

    ``min over B - max over A`` of the projections of the displaced vertices
    (:func:`displaced`, computed on the fly). A polygon's projection is that of
    its vertices, so when the result is positive every point of B lies at least
    that far beyond every point of A along the axis: the slabs are disjoint and
    their distance is at least the result (a separating-axis lower bound, for
    convex and non-convex slabs alike). Tight for slabs side by side when the
    axis is the direction of their closest points at rest.
    """
    top = -np.inf
    cm1, sn = turn(phiA)
    for i in range(A.shape[0]):
        dx = A[i, 0] - cA[0]
        dy = A[i, 1] - cA[1]
        x = A[i, 0] + uA + (cm1 * dx - sn * dy)
        y = A[i, 1] + vA + (sn * dx + cm1 * dy)
        top = max(top, nx * x + ny * y)
    bottom = np.inf
    cm1, sn = turn(phiB)
    for i in range(B.shape[0]):
        dx = B[i, 0] - cB[0]
        dy = B[i, 1] - cB[1]
        x = B[i, 0] + uB + (cm1 * dx - sn * dy)
        y = B[i, 1] + vB + (sn * dx + cm1 * dy)
        bottom = min(bottom, nx * x + ny * y)
    return bottom - top


@njit(borrowed=True)
def clearance_bound(d_rest, u1, v1, phi1, R1, u2, v2, phi2, R2):
    """Cheap lower bound on the signed gap, to skip geometry work.

    Parameters
    ----------
    d_rest : float
        ``signed_gap`` of the two slabs at zero displacement [m].
    u1, v1, phi1 : float
        Displacement [m, m] and rotation [rad] of slab 1's centre ``c1``.
    R1 : float
        Largest distance from ``c1`` to a vertex of slab 1 [m] (:func:`radius`).
    u2, v2, phi2, R2 : float
        The same for slab 2.

    Returns
    -------
    float
        ``d_rest - hypot(u1 - u2, v1 - v2) - |phi1| R1 - |phi2| R2`` [m].

    Notes
    -----
    Why it is a lower bound. The rigid map ``T_i(P) = P + t_i + (R(phi_i) - I)
    (P - c_i)`` (t_i = (u_i, v_i)) is affine, so it maps the polygon onto the
    polygon of the displaced vertices, and it moves a point at distance r from
    c_i by t_i plus at most 2 |sin(phi_i / 2)| r <= |phi_i| r. Every point P of
    slab i lies in the convex hull of its vertices, hence in the disc of radius
    ``R_i`` about ``c_i``. For P in slab 1 and Q in slab 2,
    ``T_1(P) - T_2(Q) = (P - Q) + (t_1 - t_2) + (R_1 - I) (P - c_1) - (R_2 - I) (Q - c_2)``,
    and ``|P - Q| >= d_rest``, so ``|T_1(P) - T_2(Q)| >= d_rest - |t_1 - t_2| -
    |phi_1| R_1 - |phi_2| R_2``: only the *relative* translation counts, so two
    slabs moving in phase keep a large bound. If the bound is positive the
    displaced slabs are disjoint and their signed gap (the distance between
    them) is at least the bound. This is the only case the caller should rely
    on: skip the geometry while the bound exceeds the contact tolerance.
    """
    return d_rest - math.hypot(u1 - u2, v1 - v2) - abs(phi1) * R1 - abs(phi2) * R2


@njit(borrowed=True)
def _tolerance(A, B):
    s = 1.0
    for i in range(A.shape[0]):
        s = max(s, abs(A[i, 0]), abs(A[i, 1]))
    for i in range(B.shape[0]):
        s = max(s, abs(B[i, 0]), abs(B[i, 1]))
    return EPS_REL * s


@njit(borrowed=True)
def _closest_on_segment(px, py, ax, ay, bx, by):
    """Distance from P to segment ab, the parameter t in [0, 1] and the closest point."""
    dx = bx - ax
    dy = by - ay
    L2 = dx * dx + dy * dy
    t = 0.0
    if L2 > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / L2
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
    qx = ax + t * dx
    qy = ay + t * dy
    return math.hypot(px - qx, py - qy), t, qx, qy


@njit(borrowed=True)
def _edge_normal(P, j):
    """Outward unit normal of edge j of the counter-clockwise polygon P."""
    j1 = j + 1 if j + 1 < P.shape[0] else 0
    dx = P[j1, 0] - P[j, 0]
    dy = P[j1, 1] - P[j, 1]
    L = math.hypot(dx, dy)
    if L == 0.0:
        return 0.0, 0.0
    return dy / L, -dx / L


@njit(borrowed=True)
def _edge_length(P, j):
    j1 = j + 1 if j + 1 < P.shape[0] else 0
    return math.hypot(P[j1, 0] - P[j, 0], P[j1, 1] - P[j, 1])


@njit(borrowed=True)
def _classify(px, py, P, eps):
    """Where P lies relative to polygon P, and the nearest boundary point.

    Returns (status, dist, edge, t, qx, qy); status 1 strictly inside,
    0 on the boundary (within eps), -1 outside.
    """
    k = P.shape[0]
    best = np.inf
    bj = 0
    bt = 0.0
    bqx = 0.0
    bqy = 0.0
    inside = False
    for j in range(k):
        j1 = j + 1 if j + 1 < k else 0
        ax = P[j, 0]
        ay = P[j, 1]
        bx = P[j1, 0]
        by = P[j1, 1]
        d, t, qx, qy = _closest_on_segment(px, py, ax, ay, bx, by)
        if d < best:
            best = d
            bj = j
            bt = t
            bqx = qx
            bqy = qy
        # crossing number with a half-open rule (exact for non-convex polygons;
        # points on the boundary are caught by the distance test instead)
        if (ay > py) != (by > py):
            xc = ax + (py - ay) * (bx - ax) / (by - ay)
            if px < xc:
                inside = not inside
    if best <= eps:
        status = 0
    elif inside:
        status = 1
    else:
        status = -1
    return status, best, bj, bt, bqx, bqy


@njit
def _bboxes_overlap(A, B, eps):
    return (
        A[:, 0].min() <= B[:, 0].max() + eps
        and B[:, 0].min() <= A[:, 0].max() + eps
        and A[:, 1].min() <= B[:, 1].max() + eps
        and B[:, 1].min() <= A[:, 1].max() + eps
    )


@njit(borrowed=True)
def _edge(P, i):
    """Edge i of polygon P: its start (ax, ay), its vector (dx, dy) and its length L [m]."""
    i1 = i + 1 if i + 1 < P.shape[0] else 0
    ax = P[i, 0]
    ay = P[i, 1]
    dx = P[i1, 0] - ax
    dy = P[i1, 1] - ay
    return ax, ay, dx, dy, math.hypot(dx, dy)


@njit(borrowed=True)
def _ends_across(ax, ay, dx, dy, L, T, j):
    """Edge j of polygon T seen from the edge starting at (ax, ay) along (dx, dy) of length L: its
    ends' offsets from (ax, ay), (wx0, wy0) and (wx1, wy1), and their signed distances h0, h1 [m]
    from that edge's line (positive on its left)."""
    j1 = j + 1 if j + 1 < T.shape[0] else 0
    wx0 = T[j, 0] - ax
    wy0 = T[j, 1] - ay
    wx1 = T[j1, 0] - ax
    wy1 = T[j1, 1] - ay
    return wx0, wy0, wx1, wy1, (dx * wy0 - dy * wx0) / L, (dx * wy1 - dy * wx1) / L


@njit
def _pieces_inside(S, T, eps):
    """Pieces of the boundary of S lying strictly inside T.

    Each edge of S is cut at its crossings with the boundary of T (and where a
    vertex of T lies on it, including collinear overlaps); a piece is kept if
    its midpoint is strictly inside T. Returns (n, edge, t0, t1): piece p is
    the part ``t0[p] <= t <= t1[p]`` of edge ``edge[p]`` of S.
    """
    k = S.shape[0]
    l = T.shape[0]
    cap = k * (2 * l + 1)
    edge = np.empty(cap, np.int64)
    t0 = np.empty(cap)
    t1 = np.empty(cap)
    ts = np.empty(2 * l + 2)
    n = 0
    for i in range(k):
        ax, ay, dx, dy, L = _edge(S, i)
        if L <= eps:
            continue
        L2 = L * L
        tl = -eps / L
        th = 1.0 + eps / L
        m = 2
        ts[0] = 0.0
        ts[1] = 1.0
        for j in range(l):
            wx0, wy0, wx1, wy1, h0, h1 = _ends_across(ax, ay, dx, dy, L, T, j)  # h: from S's edge line
            on0 = abs(h0) <= eps
            on1 = abs(h1) <= eps
            if on0 or on1:
                # an end of T's edge on the line (covers touching and collinear overlap)
                if on0:
                    t = (wx0 * dx + wy0 * dy) / L2
                    if t >= tl and t <= th:
                        ts[m] = min(max(t, 0.0), 1.0)
                        m += 1
                if on1:
                    t = (wx1 * dx + wy1 * dy) / L2
                    if t >= tl and t <= th:
                        ts[m] = min(max(t, 0.0), 1.0)
                        m += 1
            elif (h0 > 0.0) != (h1 > 0.0):
                s = h0 / (h0 - h1)
                t = ((wx0 + s * (wx1 - wx0)) * dx + (wy0 + s * (wy1 - wy0)) * dy) / L2
                if t >= tl and t <= th:
                    ts[m] = min(max(t, 0.0), 1.0)
                    m += 1
        # sorted in place (insertion: a handful of values; np.sort allocated a copy per edge)
        for a in range(1, m):
            x = ts[a]
            b = a - 1
            while b >= 0 and ts[b] > x:
                ts[b + 1] = ts[b]
                b -= 1
            ts[b + 1] = x
        for q in range(m - 1):
            ta = ts[q]
            tb = ts[q + 1]
            if (tb - ta) * L <= eps:
                continue
            tm = 0.5 * (ta + tb)
            st = _classify(ax + tm * dx, ay + tm * dy, T, eps)[0]
            if st == 1:
                edge[n] = i
                t0[n] = ta
                t1[n] = tb
                n += 1
    return n, edge, t0, t1


@njit
def _entering_edges(T, nT, eT):
    """Flags (len(T),): edges of T with a piece inside the other polygon."""
    flags = np.zeros(T.shape[0], np.bool_)
    for p in range(nT):
        flags[eT[p]] = True
    return flags


@njit(borrowed=True)
def _nearest_on_edges(px, py, T, flags):
    """Nearest point to P on the flagged (whole) edges of T: (dist, edge, t, qx, qy)."""
    k = T.shape[0]
    best = np.inf
    bj = 0
    bt = 0.0
    bqx = 0.0
    bqy = 0.0
    for j in range(k):
        if not flags[j]:
            continue
        j1 = j + 1 if j + 1 < k else 0
        d, t, qx, qy = _closest_on_segment(px, py, T[j, 0], T[j, 1], T[j1, 0], T[j1, 1])
        if d < best:
            best = d
            bj = j
            bt = t
            bqx = qx
            bqy = qy
    return best, bj, bt, bqx, bqy


@njit(borrowed=True)
def _target_normal(T, j, t, px, py, qx, qy, pen, eps):
    """Unit normal at the contact, pointing from target T towards the striker.

    Q in the interior of T's edge j: that edge's outward normal. Q at a vertex
    of T: the direction between the two points (the gradient of the distance,
    so it turns continuously round a corner); at zero distance (vertex on
    vertex) the bisector of the outward normals of the two edges at T's vertex.
    """
    k = T.shape[0]
    L = _edge_length(T, j)
    if t * L > eps and (1.0 - t) * L > eps:
        return _edge_normal(T, j)
    vx = px - qx
    vy = py - qy
    d = math.hypot(vx, vy)
    if d > eps:
        if pen:  # striker inside T: it leaves T from P towards Q
            return -vx / d, -vy / d
        return vx / d, vy / d
    v = j if t * L <= eps else (j + 1 if j + 1 < k else 0)
    vp = v - 1 if v > 0 else k - 1
    n1x, n1y = _edge_normal(T, vp)
    n2x, n2y = _edge_normal(T, v)
    sx = n1x + n2x
    sy = n1y + n2y
    s = math.hypot(sx, sy)
    if s > 0.0:
        return sx / s, sy / s
    return n2x, n2y


# columns of the candidate tables built by _candidates
_F_PX, _F_PY, _F_QX, _F_QY, _F_NX, _F_NY, _F_GAP, _F_T = 0, 1, 2, 3, 4, 5, 6, 7
_I_WHO, _I_IDX, _I_OWN, _I_EDGE, _I_OVTX, _I_PEN = 0, 1, 2, 3, 4, 5


@njit(borrowed=True)
def _strike(S, T, who, eps, F, I, c):
    """Rows for the vertices of striker S against target T, non-penetrating values.

    Returns the next free row and whether a vertex of S is strictly inside T.
    """
    any_inside = False
    for i in range(S.shape[0]):
        st, d, j, t, qx, qy = _classify(S[i, 0], S[i, 1], T, eps)
        F[c, _F_PX] = S[i, 0]
        F[c, _F_PY] = S[i, 1]
        F[c, _F_QX] = qx
        F[c, _F_QY] = qy
        F[c, _F_GAP] = d
        F[c, _F_T] = t
        I[c, _I_WHO] = who
        I[c, _I_IDX] = i
        I[c, _I_OWN] = -1
        I[c, _I_EDGE] = j
        I[c, _I_PEN] = 1 if st == 1 else (0 if st == 0 else -1)  # status, resolved later
        if st == 1:
            any_inside = True
        c += 1
    return c, any_inside


@njit(borrowed=True)
def _penetrate(S, T, r0, nS, eS, s0, s1, nT, flagsT, eps, F, I):
    """Resolve which vertex rows r0.. of S penetrate T and give them their depth.

    (nS, eS, s0, s1): pieces of S's boundary inside T; nT, flagsT: number of
    pieces of T's boundary inside S and the edges of T carrying them.
    Returns the number of penetrating vertices.
    """
    k = S.shape[0]
    npen = 0
    for i in range(k):
        r = r0 + i
        st = I[r, _I_PEN]
        pen = st == 1
        if st == 0:
            # on T's boundary: penetrating if one of its edges enters T's interior here
            ip = i - 1 if i > 0 else k - 1
            Li = _edge_length(S, i)
            Lp = _edge_length(S, ip)
            for p in range(nS):
                if (eS[p] == i and s0[p] * Li <= eps) or (eS[p] == ip and (1.0 - s1[p]) * Lp <= eps):
                    pen = True
                    break
        if pen:
            npen += 1
            if nT > 0:
                d, j, t, qx, qy = _nearest_on_edges(S[i, 0], S[i, 1], T, flagsT)
                F[r, _F_QX] = qx
                F[r, _F_QY] = qy
                F[r, _F_GAP] = -d
                F[r, _F_T] = t
                I[r, _I_EDGE] = j
            else:  # S's vertex inside T with no part of T's boundary inside S: containment
                F[r, _F_GAP] = -F[r, _F_GAP]
        I[r, _I_PEN] = 1 if pen else 0
    return npen


@njit(borrowed=True)
def _midpoints(S, T, who, nS, eS, s0, s1, nT, flagsT, eps, F, I, c):
    """Rows for the midpoints of crossing-bounded pieces of S's boundary inside T."""
    k = S.shape[0]
    for p in range(nS):
        i = eS[p]
        L = _edge_length(S, i)
        if s0[p] * L <= eps or (1.0 - s1[p]) * L <= eps:
            continue  # ends at a vertex of S: that vertex is the feature
        i1 = i + 1 if i + 1 < k else 0
        tm = 0.5 * (s0[p] + s1[p])
        px = S[i, 0] + tm * (S[i1, 0] - S[i, 0])
        py = S[i, 1] + tm * (S[i1, 1] - S[i, 1])
        if nT > 0:
            d, j, t, qx, qy = _nearest_on_edges(px, py, T, flagsT)
        else:
            st, d, j, t, qx, qy = _classify(px, py, T, eps)
        F[c, _F_PX] = px
        F[c, _F_PY] = py
        F[c, _F_QX] = qx
        F[c, _F_QY] = qy
        F[c, _F_GAP] = -d
        F[c, _F_T] = t
        I[c, _I_WHO] = who
        I[c, _I_IDX] = -1
        I[c, _I_OWN] = i
        I[c, _I_EDGE] = j
        I[c, _I_PEN] = 1
        c += 1
    return c


@njit
def _candidates(A, B, eps):
    """Every candidate contact feature with its gap.

    Rows 0..l-1: vertices of B against A (who = 1); rows l..l+k-1: vertices of
    A against B (who = 0); then, only if the interiors overlap but no vertex
    penetrates, midpoints of boundary pieces (vertex index -1).

    Returns (count, F, I): F float columns _F_*, I int columns _I_* (see the
    constants above); the normal points from A towards B.
    """
    k = A.shape[0]
    l = B.shape[0]
    if _bboxes_overlap(A, B, eps):
        nA, eA, a0, a1 = _pieces_inside(A, B, eps)  # boundary of A inside B
        nB, eB, b0, b1 = _pieces_inside(B, A, eps)  # boundary of B inside A
    else:  # far apart: no overlap possible, skip the edge cutting
        nA = 0
        nB = 0
        eA = np.empty(0, np.int64)
        eB = np.empty(0, np.int64)
        a0 = np.empty(0)
        a1 = np.empty(0)
        b0 = np.empty(0)
        b1 = np.empty(0)
    cap = k + l + nA + nB
    F = np.zeros((cap, 8))
    I = np.zeros((cap, 6), np.int64)
    # typed int64, not literals: each helper is compiled once, not once per constant
    zero, one = np.int64(0), np.int64(1)
    c, inB = _strike(B, A, one, eps, F, I, zero)
    c, inA = _strike(A, B, zero, eps, F, I, c)
    npen = 0
    if nA > 0 or nB > 0 or inA or inB:  # interiors overlap
        fA = _entering_edges(A, nA, eA)
        fB = _entering_edges(B, nB, eB)
        npen += _penetrate(B, A, zero, nB, eB, b0, b1, nA, fA, eps, F, I)
        npen += _penetrate(A, B, l, nA, eA, a0, a1, nB, fB, eps, F, I)
        if npen == 0:  # "plus sign": boundaries cross, no vertex inside
            c = _midpoints(B, A, one, nB, eB, b0, b1, nA, fA, eps, F, I, c)
            c = _midpoints(A, B, zero, nA, eA, a0, a1, nB, fB, eps, F, I, c)
    else:
        for r in range(k + l):
            I[r, _I_PEN] = 0
    for r in range(c):
        T = A if I[r, _I_WHO] == 1 else B
        j = I[r, _I_EDGE]
        t = F[r, _F_T]
        nx, ny = _target_normal(
            T, j, t, F[r, _F_PX], F[r, _F_PY], F[r, _F_QX], F[r, _F_QY], I[r, _I_PEN] == 1, eps
        )
        if I[r, _I_WHO] == 0:  # target is B: its outward normal points from B to A
            nx = -nx
            ny = -ny
        F[r, _F_NX] = nx
        F[r, _F_NY] = ny
        # is Q a vertex of the target? (vertex-to-vertex bookkeeping)
        L = _edge_length(T, j)
        if t * L <= eps:
            I[r, _I_OVTX] = j
        elif (1.0 - t) * L <= eps:
            I[r, _I_OVTX] = j + 1 if j + 1 < T.shape[0] else 0
        else:
            I[r, _I_OVTX] = -1
    return c, F, I


@njit
def signed_gap(A, B):
    """Signed gap between two polygons in their current positions.

    Parameters
    ----------
    A, B : ndarray, shape (k, 2) and (l, 2)
        Counter-clockwise vertices [m] (:func:`ccw`, then :func:`displaced`).

    Returns
    -------
    float
        [m]. Apart: the minimum distance between the boundaries (>= 0).
        Interiors overlapping: minus the penetration depth defined in the
        module docstring (< 0; continuous through 0 for vertex-to-edge,
        vertex-to-vertex and edge-to-edge approach). Equals the smallest
        ``gap`` of the features of :func:`contact_points`.
    """
    eps = _tolerance(A, B)
    g = _apart_gap(A, B, eps)
    if g > -np.inf:
        return g
    c, F, I = _candidates(A, B, eps)
    g = np.inf
    for r in range(c):
        if F[r, _F_GAP] < g:
            g = F[r, _F_GAP]
    return g


@njit(borrowed=True)
def _apart_gap(A, B, eps):
    """:func:`signed_gap` of two polygons that are apart, or -inf when they may touch or overlap.

    Apart (every vertex outside the other polygon by more than ``eps`` and no two edges crossing),
    :func:`_candidates` finds no boundary piece inside the other polygon, so its gap is the smallest
    distance of a vertex to the other boundary: the same :func:`_classify` distances, hence the
    same number, without cutting the edges or building the feature table. That is the case of
    almost every gap a run asks for (screens, searches near contact).
    """
    g = _vertices_outside(A, B, eps, _vertices_outside(B, A, eps, np.inf))  # B's vertices first, as _candidates
    if g == -np.inf or _edges_may_cross(A, B, eps):
        return -np.inf
    return g


@njit(borrowed=True)
def _vertices_outside(S, T, eps, g):
    """min(g, the distance of every vertex of S to T's boundary) when each lies outside T by more
    than eps (:func:`_classify`), else -inf (also when g is -inf already)."""
    if g == -np.inf:
        return g
    for i in range(S.shape[0]):
        st, d, _, _, _, _ = _classify(S[i, 0], S[i, 1], T, eps)
        if st != -1:
            return -np.inf
        if d < g:
            g = d
    return g


@njit(borrowed=True)
def _edges_may_cross(A, B, eps):
    """False only if no edge of A meets an edge of B. Two segments that meet straddle each other's
    lines and overlap in their projections on either; each test allows ``eps`` (well above the
    rounding of the signed distances), so a pair that meets is never cleared."""
    for i in range(A.shape[0]):
        ax, ay, dx, dy, L = _edge(A, i)
        if L <= eps:
            return True
        for j in range(B.shape[0]):
            wx0, wy0, wx1, wy1, h0, h1 = _ends_across(ax, ay, dx, dy, L, B, j)  # B's edge from A's edge line
            if (h0 > eps and h1 > eps) or (h0 < -eps and h1 < -eps):
                continue
            t0 = (wx0 * dx + wy0 * dy) / (L * L)  # B's edge ends along A's edge (0..1 on it)
            t1 = (wx1 * dx + wy1 * dy) / (L * L)
            if min(t0, t1) > 1.0 + eps / L or max(t0, t1) < -eps / L:
                continue
            bx, by, ex, ey, M = _edge(B, j)
            if M <= eps:
                return True
            _, _, _, _, g0, g1 = _ends_across(bx, by, ex, ey, M, A, i)  # A's edge from B's edge line
            if (g0 > eps and g1 > eps) or (g0 < -eps and g1 < -eps):
                continue
            return True
    return False


def rest_gap(A, B) -> float:
    """:func:`signed_gap` [m] of two polygons (k, 2), (l, 2) run interpreted: for one-off calls
    from Python (a scene's slabs at rest), which would otherwise compile the gap (seconds)."""
    with interpreted():
        return float(signed_gap(np.ascontiguousarray(A, dtype=float), np.ascontiguousarray(B, dtype=float)))


def face_ends(A, B, rest: float, ang_tol: float = FACE_ANGLE) -> tuple[np.ndarray, np.ndarray]:
    """How many faces of two slabs at rest each vertex ends: (k,) and (l,) int64 for A (k, 2) and
    B (l, 2), counter-clockwise [m], whose signed gap at rest is ``rest`` [m].

    A *face* is a pair of edges, one of each polygon, facing each other (outward normals opposite
    within ``ang_tol`` [rad]), overlapping along their length, whose two overlap ends both lie at
    the pair's rest gap (to ``ang_tol`` times the overlap plus the geometric tolerance): the
    facades that meet face to face when the gap closes. The four vertices of its two edges are
    the points that can press on it as its ends (the overlap's ends, whichever slab's vertex
    ends it as the slabs slide along each other), so each counts one for that face. Plain Python,
    called once per pair when a run's force laws first need it.
    """
    A = np.ascontiguousarray(A, dtype=float)
    B = np.ascontiguousarray(B, dtype=float)
    k, l = A.shape[0], B.shape[0]
    ends_a, ends_b = np.zeros(k, np.int64), np.zeros(l, np.int64)
    eps = EPS_REL * max(1.0, float(np.abs(A).max(initial=0.0)), float(np.abs(B).max(initial=0.0)))
    cosmax = -math.cos(ang_tol)
    for i in range(k):
        i1 = (i + 1) % k
        ta = A[i1] - A[i]
        La = float(np.hypot(*ta))
        if La <= eps:
            continue
        ta = ta / La
        na = np.array([ta[1], -ta[0]])
        for j in range(l):
            j1 = (j + 1) % l
            tb = B[j1] - B[j]
            Lb = float(np.hypot(*tb))
            if Lb <= eps:
                continue
            nb = np.array([tb[1], -tb[0]]) / Lb
            if float(na @ nb) > cosmax:
                continue  # not facing each other
            sb = sorted((float(ta @ (B[j] - A[i])), float(ta @ (B[j1] - A[i]))))
            lo, hi = max(sb[0], 0.0), min(sb[1], La)
            if hi - lo <= eps:
                continue  # no overlap along the edges
            # the overlap's ends, and their gaps across (from A's edge line to B's edge line)
            ends = [A[i] + lo * ta, A[i] + hi * ta]
            gaps = [float(nb @ (P - B[j])) for P in ends]  # > 0: P (on A's edge) lies outside B's edge line
            slack = ang_tol * (hi - lo) + eps
            if all(abs(g - rest) <= slack for g in gaps):
                ends_a[i] += 1
                ends_a[i1] += 1
                ends_b[j] += 1
                ends_b[j1] += 1
    return ends_a, ends_b


@njit(borrowed=True)
def _on_partner(I, r, partner, nT):
    """True if candidate r's point Q lies on the target's edge ``partner`` (closed)."""
    if I[r, _I_EDGE] == partner:
        return True
    v = I[r, _I_OVTX]
    p1 = partner + 1 if partner + 1 < nT else 0
    return v == partner or v == p1


class ContactPoints(NamedTuple):
    """The contact features of two polygons (:func:`contact_points`), MAX_FEATURES rows of which the
    first ``count`` hold features."""

    count: int  #: number of valid rows (0..MAX_FEATURES)
    Q: np.ndarray  #: (MAX_FEATURES, 2) contact points [m]
    N: np.ndarray  #: (MAX_FEATURES, 2) unit normals from A towards B
    gap: np.ndarray  #: (MAX_FEATURES,) signed gaps [m], negative when penetrating
    who: np.ndarray  #: (MAX_FEATURES,) int64, 0: a point of A strikes B; 1: a point of B strikes A
    idx: np.ndarray  #: (MAX_FEATURES,) int64, that vertex's index in its polygon (-1: not a vertex)
    pair: np.ndarray  #: (MAX_FEATURES,) int64, the face-to-face pair id of an overlap's ends (-1: a point feature)


@njit
def contact_points(A, B, tol, ang_tol=FACE_ANGLE):
    """Contact features of two polygons that touch or overlap.

    Parameters
    ----------
    A, B : ndarray, shape (k, 2) and (l, 2)
        Counter-clockwise vertices [m] in their current positions.
    tol : float
        Contact tolerance [m]: nothing is reported if ``signed_gap(A, B) >
        tol``; otherwise every feature whose gap is within ``tol`` of the
        minimum gap ``g0`` is reported.
    ang_tol : float, optional
        Two edges facing each other count as face-to-face when their normals
        are opposite within this angle [rad] (default 1e-3) and both ends of
        their overlap have gaps within ``tol`` of ``g0``.

    Returns
    -------
    :class:`ContactPoints`, whose fields are:

    count : int
        Number of valid rows (0..MAX_FEATURES); the other rows hold zeros
        and -1.
    Q : ndarray, shape (MAX_FEATURES, 2)
        Contact point [m]: the striking vertex (or overlap end point, or piece
        midpoint) in its current position.
    N : ndarray, shape (MAX_FEATURES, 2)
        Unit normal pointing from A towards B.
    gap : ndarray, shape (MAX_FEATURES,)
        Signed gap of the feature [m], negative when penetrating.
    who : ndarray of int64, shape (MAX_FEATURES,)
        0: a point of A strikes an edge of B; 1: a point of B strikes A.
    idx : ndarray of int64, shape (MAX_FEATURES,)
        Index of that vertex in its polygon, or -1 for a point that is not a
        vertex (midpoint of an overlap in a "plus sign" crossing).
    pair : ndarray of int64, shape (MAX_FEATURES,)
        -1 for a point feature; for face-to-face contact the two end points of
        the overlap segment share the same pair id >= 0 (``face_to_face =
        pair >= 0``) and must get coupled impulses.

    Notes
    -----
    Rows are ordered: face-to-face pairs first (ends in increasing position
    along A's edge), then point features by increasing gap. Each end of a
    face-to-face overlap is a vertex of A or of B (``who``/``idx`` say which;
    on a tie, A's). Its gap is measured from that vertex to the other edge's
    line, and its normal is that edge's (-n_B for a vertex of A, n_A for a
    vertex of B): the gap's own gradient, so that a force along the normal at
    each end derives from a potential of the two gaps (with a normal shared
    by both ends, the faces' bisector, the rows missed half the faces'
    relative turn and a Hertz face contact created energy).

    Vertex-to-vertex contact is reported once, as B's vertex striking A, with
    the normal along the line joining the vertices (see ``_target_normal``).
    Features beyond MAX_FEATURES are dropped (largest gaps first).
    """
    M = MAX_FEATURES
    Q = np.zeros((M, 2))
    N = np.zeros((M, 2))
    gap = np.zeros(M)
    who = np.full(M, -1, np.int64)
    idx = np.full(M, -1, np.int64)
    pair = np.full(M, -1, np.int64)
    eps = _tolerance(A, B)
    c, F, I = _candidates(A, B, eps)
    g0 = np.inf
    for r in range(c):
        if F[r, _F_GAP] < g0:
            g0 = F[r, _F_GAP]
    if not g0 <= tol:
        return ContactPoints(0, Q, N, gap, who, idx, pair)
    k = A.shape[0]
    l = B.shape[0]

    # ---- face-to-face pairs --------------------------------------------------
    face_a = np.empty(M // 2, np.int64)
    face_b = np.empty(M // 2, np.int64)
    npair = 0
    nf = 0
    cosmax = -math.cos(ang_tol)
    for i in range(k):
        i1 = i + 1 if i + 1 < k else 0
        La = _edge_length(A, i)
        if La <= eps:
            continue
        nax, nay = _edge_normal(A, i)
        tx = (A[i1, 0] - A[i, 0]) / La
        ty = (A[i1, 1] - A[i, 1]) / La
        for j in range(l):
            if npair == M // 2:
                break
            j1 = j + 1 if j + 1 < l else 0
            nbx, nby = _edge_normal(B, j)
            if nax * nbx + nay * nby > cosmax:
                continue  # not facing each other
            # overlap of the two edges along A's edge direction
            sb0 = tx * (B[j, 0] - A[i, 0]) + ty * (B[j, 1] - A[i, 1])
            sb1 = tx * (B[j1, 0] - A[i, 0]) + ty * (B[j1, 1] - A[i, 1])
            if sb0 <= sb1:
                lo_b, lo_v, hi_b, hi_v = sb0, j, sb1, j1
            else:
                lo_b, lo_v, hi_b, hi_v = sb1, j1, sb0, j
            lo = max(lo_b, 0.0)
            hi = min(hi_b, La)
            if hi - lo <= eps:
                continue
            # each end: (who, vertex) and its gap to the other edge's line
            if lo_b <= eps:
                w_lo, v_lo = 0, i
                g_lo = nbx * (A[i, 0] - B[j, 0]) + nby * (A[i, 1] - B[j, 1])
            else:
                w_lo, v_lo = 1, lo_v
                g_lo = nax * (B[lo_v, 0] - A[i, 0]) + nay * (B[lo_v, 1] - A[i, 1])
            if hi_b >= La - eps:
                w_hi, v_hi = 0, i1
                g_hi = nbx * (A[i1, 0] - B[j, 0]) + nby * (A[i1, 1] - B[j, 1])
            else:
                w_hi, v_hi = 1, hi_v
                g_hi = nax * (B[hi_v, 0] - A[i, 0]) + nay * (B[hi_v, 1] - A[i, 1])
            if abs(g_lo - g0) > tol or abs(g_hi - g0) > tol:
                continue  # not the touching faces (or too tilted to touch along the whole overlap)
            for e in range(2):
                w = w_lo if e == 0 else w_hi
                v = v_lo if e == 0 else v_hi
                P = A if w == 0 else B
                Q[nf, 0] = P[v, 0]
                Q[nf, 1] = P[v, 1]
                # the normal of the edge the end's vertex strikes, from A towards B (the gap's gradient)
                N[nf, 0] = -nbx if w == 0 else nax
                N[nf, 1] = -nby if w == 0 else nay
                gap[nf] = g_lo if e == 0 else g_hi
                who[nf] = w
                idx[nf] = v
                pair[nf] = npair
                nf += 1
            face_a[npair] = i
            face_b[npair] = j
            npair += 1

    # ---- point features ---------------------------------------------------------
    keep = np.zeros(c, np.bool_)
    for r in range(c):
        if F[r, _F_GAP] > g0 + tol:
            continue
        w = I[r, _I_WHO]
        ns = k if w == 0 else l  # vertices of the striker
        nt = l if w == 0 else k  # vertices of the target
        iv = I[r, _I_IDX]
        covered = False
        for p in range(npair):
            own = face_a[p] if w == 0 else face_b[p]
            partner = face_b[p] if w == 0 else face_a[p]
            if iv >= 0:
                ivp = iv - 1 if iv > 0 else ns - 1
                mine = own == iv or own == ivp
            else:
                mine = own == I[r, _I_OWN]
            if mine and _on_partner(I, r, partner, nt):
                covered = True  # already an end of that face-to-face pair
                break
        if covered:
            continue
        if w == 0 and iv >= 0 and I[r, _I_OVTX] >= 0:
            # vertex of A on a vertex W of B: keep only W's row (rows 0..l-1 are B's vertices)
            rw = I[r, _I_OVTX]
            if (
                math.hypot(F[rw, _F_QX] - F[r, _F_PX], F[rw, _F_QY] - F[r, _F_PY]) <= eps
                and F[rw, _F_GAP] <= g0 + tol
            ):
                continue
        keep[r] = True
    # stable selection by increasing gap (no argsort: identical order with and without numba)
    while nf < M:
        best = -1
        for r in range(c):
            if keep[r] and (best < 0 or F[r, _F_GAP] < F[best, _F_GAP]):
                best = r
        if best < 0:
            break
        keep[best] = False
        Q[nf, 0] = F[best, _F_PX]
        Q[nf, 1] = F[best, _F_PY]
        N[nf, 0] = F[best, _F_NX]
        N[nf, 1] = F[best, _F_NY]
        gap[nf] = F[best, _F_GAP]
        who[nf] = I[best, _I_WHO]
        idx[nf] = I[best, _I_IDX]
        nf += 1
    return ContactPoints(nf, Q, N, gap, who, idx, pair)
