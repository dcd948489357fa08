"""Where buildings stand: their slabs' sites, the clear distance between two buildings along a
direction, and the translation that sets it (the scene's ``with_gap``).

Slab pairs at a common level, and a slab facing another building's facade between its floors,
are the *sites* where two buildings can meet. Along a unit direction d the translation that
brings one polygon against the other is found edge by edge (a ray from every vertex of each
polygon to the other's edges); the clear distance of two buildings along d is the smallest over
their sites. Used by the scene (``Scene.with_gap``) and by the gap study above it.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError
from pounding.framework.model.levels import LEVEL_TOL, common_levels, distance_to_polygon, same_level

if TYPE_CHECKING:
    from pounding.framework.model.scene import Scene

S_TOL = 1e-9  # relative tolerance on the edge parameter of a ray hit


# =============================================================================
# Geometry: translation along a direction until two polygons touch
# =============================================================================


@njit(borrowed=True)
def _cast_into(P, Q, d0, d1, f, base, delta, s):
    """Rays from the vertices of polygon P (m, 2) along (d0, d1) onto the edges of polygon Q (n, 2)
    (edge j from vertex j to j + 1): ``delta[base + i n + j]`` <- the ray length [m] at which vertex
    i lands on edge j (NaN where the line misses the edge or runs parallel to it) and ``s[...]`` the
    edge parameter, for frame f of delta and s (F, 2 m n)."""
    m, n = P.shape[0], Q.shape[0]
    for j in range(n):
        e0 = Q[(j + 1) % n, 0] - Q[j, 0]
        e1 = Q[(j + 1) % n, 1] - Q[j, 1]
        den = e0 * d1 - e1 * d0  # cross(e, d)
        ok = abs(den) > 1e-12 * math.hypot(e0, e1)
        if not ok:
            den = 1.0
        for i in range(m):
            w0 = P[i, 0] - Q[j, 0]
            w1 = P[i, 1] - Q[j, 1]
            sij = (w0 * d1 - w1 * d0) / den
            k = base + i * n + j
            s[f, k] = sij
            delta[f, k] = (w0 * e1 - w1 * e0) / den if ok and -S_TOL <= sij <= 1.0 + S_TOL else np.nan


@njit(borrowed=True)
def _last_touch(A, B, d, delta, who, vertex, edge, s, scratch, sscratch):
    """Per frame f of A (F, k, 2) and B (F, l, 2): the largest translation ``delta[f]`` [m] of B
    along d at which the two touch (-inf where none), and which vertex of which polygon then lies
    on which edge of the other at parameter ``s[f]`` (see :func:`translation_to_contact`).

    The candidates of a frame are B's vertices cast along d onto A's edges (l k of them, first),
    then A's vertices cast along -d onto B's edges (k l); the first largest wins (ties: the lowest
    index), and a frame with none reports the first candidate's indices. ``scratch``,
    ``sscratch`` (F, 2 k l) hold the candidates."""
    k, l = A.shape[1], B.shape[1]
    for f in range(A.shape[0]):
        _cast_into(B[f], A[f], d[0], d[1], f, 0, scratch, sscratch)
        _cast_into(A[f], B[f], -d[0], -d[1], f, l * k, scratch, sscratch)
        best, at = -np.inf, 0
        for c in range(2 * k * l):
            v = scratch[f, c]
            if v == v and v > best:  # (v == v: not NaN)
                best, at = v, c
        delta[f] = best
        if at < l * k:
            who[f], vertex[f], edge[f] = 1, at // k, at % k
        else:
            who[f], vertex[f], edge[f] = 0, (at - l * k) // l, (at - l * k) % l
        s[f] = min(max(sscratch[f, at], 0.0), 1.0)


def translation_to_contact(A, B, d):
    """Signed translation of polygon B along d at which A and B last touch.

    Parameters
    ----------
    A, B : array_like, shape (..., k, 2) and (..., l, 2)
        Simple polygons (any orientation, convex or not) in plan [m]; leading
        axes (e.g. time) broadcast.
    d : array_like, shape (2,)
        Unit direction.

    Returns
    -------
    delta : ndarray (...)
        ``max {delta : A and B + delta d touch}`` [m]; ``-inf`` if B moving
        along the line never touches A. For B beyond A along d, ``-delta`` is
        their clear distance along d (negative when they overlap).
    info : dict of ndarray (...)
        The last contact: ``who`` (1: a vertex of B on an edge of A, 0: a
        vertex of A on an edge of B), ``vertex`` (index in the striking
        polygon), ``edge`` (index in the other; edge j runs from vertex j to
        j + 1) and ``s`` (parameter along that edge, 0..1).

    Every frame is one call of the compiled :func:`_last_touch` (the gap study asks one frame at a
    time inside its maximisation, some thousand times a run: array operations on a few vertices
    cost about 0.3 ms a frame in overhead alone).
    """
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    d = np.ascontiguousarray(d, dtype=float)
    lead = np.broadcast_shapes(A.shape[:-2], B.shape[:-2])
    k, l = A.shape[-2], B.shape[-2]
    A = np.ascontiguousarray(np.broadcast_to(A, lead + A.shape[-2:]).reshape(-1, k, 2))
    B = np.ascontiguousarray(np.broadcast_to(B, lead + B.shape[-2:]).reshape(-1, l, 2))
    F = A.shape[0]
    delta, s = np.empty(F), np.empty(F)
    who, vertex, edge = np.empty(F, dtype=np.int64), np.empty(F, dtype=np.int64), np.empty(F, dtype=np.int64)
    _last_touch(A, B, d, delta, who, vertex, edge, s, np.empty((F, 2 * k * l)), np.empty((F, 2 * k * l)))
    info = {"who": who.reshape(lead), "vertex": vertex.reshape(lead), "edge": edge.reshape(lead), "s": s.reshape(lead)}
    return delta.reshape(lead), info


def _closest_points(A: np.ndarray, B: np.ndarray):
    """Closest points (pa, pb) of two disjoint polygons' boundaries and their distance."""
    best = (np.inf, None, None)
    for P, Q, flip in ((A, B, False), (B, A, True)):
        E = np.roll(Q, -1, axis=0) - Q
        for p in P:
            w = p - Q
            t = np.clip(np.einsum("ij,ij->i", w, E) / np.einsum("ij,ij->i", E, E), 0.0, 1.0)
            foot = Q + t[:, None] * E
            dist = np.hypot(*(p - foot).T)
            i = int(np.argmin(dist))
            if dist[i] < best[0]:
                best = (float(dist[i]), foot[i], p) if flip else (float(dist[i]), p, foot[i])
    return best[1], best[2], best[0]


# =============================================================================
# Scene-level helpers
# =============================================================================


def direction_vector(value) -> np.ndarray | None:
    """A plan unit vector from ``None``, ``"x"``, ``"y"``, ``"-x"``, ``"-y"``, an angle in degrees (number or text) or a 2-vector.

    Multiples of 90 degrees give exact 0/±1 components.
    """
    if value is None:
        return None
    if isinstance(value, str):
        text = value.strip().lower()
        named = {"x": 0.0, "+x": 0.0, "-x": 180.0, "y": 90.0, "+y": 90.0, "-y": 270.0}
        if text in named:
            value = named[text]
        else:
            try:
                value = float(text)
            except ValueError:
                raise InputError(f"expected x, y or an angle in degrees, got {value!r}", field="direction") from None
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        angle = float(value)
        if not math.isfinite(angle):
            raise InputError(f"expected a finite angle in degrees, got {value!r}", field="direction")
        quarter, rest = divmod(angle, 90.0)
        if rest == 0.0:
            return np.array(((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4])
        a = math.radians(angle)
        return np.array((math.cos(a), math.sin(a)))
    v = np.asarray(value, dtype=float)
    if v.shape != (2,) or not np.all(np.isfinite(v)) or np.hypot(*v) == 0.0:
        raise InputError(f"expected a non-zero plan vector (dx, dy), got {value!r}", field="direction")
    return v / np.hypot(*v)


class _AtRest:
    """A scene building seen by :func:`pounding.framework.model.facade.facade` before assembly: its slabs,
    no modes (the facade's outline, storey and eta at rest; its rows come from the run's system)."""

    def __init__(self, building):
        self.slabs = building.slabs
        self.modes = np.zeros((3 * len(building.slabs), 0))


def _facade_at(building, height: float):
    """The :class:`~pounding.framework.model.facade.Facade` of a scene building at ``height`` [m] at rest
    (no modal rows), or None (at a floor, at or below the ground, above the roof)."""
    from pounding.framework.model.facade import facade

    return facade(_AtRest(building), -1, height)


def pair_sites(a, b) -> list[tuple]:
    """Every place where two buildings can meet, 0-based: slabs at a common level ``(fa, fb)`` first
    (scene order), then a slab of one against the facade of the other between two of its floors:
    ``(fa, j, "b")`` slab fa of a against b's storey j (0-based, between floor j - 1 or the ground
    and floor j), and ``(j, fb, "a")`` slab fb of b against a's storey j."""
    sites = common_levels(a, b)
    for fa, sa in enumerate(a.slabs):
        F = _facade_at(b, sa.elevation)
        if F is not None:
            sites.append((fa, F.storey, "b"))
    for fb, sb in enumerate(b.slabs):
        F = _facade_at(a, sb.elevation)
        if F is not None:
            sites.append((F.storey, fb, "a"))
    return sites


def _site_outlines(a, b, site) -> tuple[np.ndarray, np.ndarray]:
    """Rest outlines (A, B) of a site: a slab, or the facade's (the outline of the floor above)."""
    return a.slabs[site[0]].vertices, b.slabs[site[1]].vertices


def _site_level(a, b, site) -> float:
    """Elevation [m] of a site: the common level, or the striking slab's."""
    if len(site) == 3 and site[2] == "a":
        return float(b.slabs[site[1]].elevation)
    return float(a.slabs[site[0]].elevation)


def _site_facade(a, b, site) -> dict | None:
    """What a slab-facade site is, for the report (None at a common level); storeys 1-based."""
    if len(site) == 2:
        return None
    fa, fb, side = site
    z = _site_level(a, b, site)
    struck, striking, slab = (b, a, fa) if side == "b" else (a, b, fb)
    F = _facade_at(struck, z)
    return {"striking": striking.name, "slab_storey": slab + 1, "height": z, "struck": struck.name,
            "struck_storey": F.storey + 1, "eta": F.eta}


def _pair_of(scene: Scene, storeys=None):
    """The two buildings and their sites (:func:`pair_sites`; only those in ``storeys`` if given: a
    pair of a row where it faces, see :func:`facing_storeys`)."""
    if len(scene.buildings) != 2:
        raise InputError(f"setting or designing one gap needs a scene of exactly two buildings, this one has {len(scene.buildings)} "
                         "(`pounding gap` reports every adjacent pair of a row)", field="building")
    a, b = scene.buildings
    common = pair_sites(a, b)
    if storeys is not None:
        common = [c for c in common if c in set(storeys)]
    if not common:
        raise InputError(f"buildings {a.name!r} and {b.name!r} have no storey at a common level and no slab between the other's "
                         "floors: their slabs can never meet", field="building")
    return a, b, common


def _crosses(p: np.ndarray, q: np.ndarray, V: np.ndarray) -> bool:
    """True if the segment p-q meets the closed polygon V away from its ends.

    The segment is shortened by LEVEL_TOL at each end (its ends lie on the pair's own slabs);
    it meets V if its midpoint is inside V or it meets an edge of V, touching and collinear
    overlap included (a segment running along a third building's facade is screened by it).
    """
    L = float(np.hypot(*(q - p)))
    if L <= 2 * LEVEL_TOL:
        return False
    u = (q - p) / L
    p, q = p + LEVEL_TOL * u, q - LEVEL_TOL * u
    if distance_to_polygon(V, 0.5 * (p + q)) == 0.0:
        return True
    scale = LEVEL_TOL * max(1.0, L)

    def turn(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    def on(o, a, x):  # x, collinear with o-a, lies within the segment's box
        return min(o[0], a[0]) - LEVEL_TOL <= x[0] <= max(o[0], a[0]) + LEVEL_TOL and min(o[1], a[1]) - LEVEL_TOL <= x[1] <= max(o[1], a[1]) + LEVEL_TOL

    for k in range(len(V)):
        a, b = V[k], V[(k + 1) % len(V)]
        d1, d2, d3, d4 = turn(p, q, a), turn(p, q, b), turn(a, b, p), turn(a, b, q)
        if ((d1 > scale and d2 < -scale) or (d1 < -scale and d2 > scale)) and ((d3 > scale and d4 < -scale) or (d3 < -scale and d4 > scale)):
            return True
        if (abs(d1) <= scale and on(p, q, a)) or (abs(d2) <= scale and on(p, q, b)) or (abs(d3) <= scale and on(a, b, p)) or (abs(d4) <= scale and on(a, b, q)):
            return True
    return False


def _screens(scene: Scene, i: int, j: int, z: float) -> list[np.ndarray]:
    """Rest outlines at the level z [m] of the buildings other than i and j (j = -1: other than i
    only): a slab at that level, else the facade there (the outline of the floor above, when z is
    between two floors)."""
    out = []
    for k, c in enumerate(scene.buildings):
        if k in (i, j):
            continue
        at = [s.vertices for s in c.slabs if same_level(s.elevation, z)]
        F = None if at else _facade_at(c, z)
        out += at if F is None else [F.vertices]
    return out


def screened(scene: Scene, i: int, j: int, p: np.ndarray, q: np.ndarray, z: float) -> bool:
    """Whether the straight path p -> q (2,) [m] at the level z [m], between a slab of building i and
    what it faces (a slab of building j, or a retaining wall's face: j = -1), passes through another
    building at that level, a slab of it or its facade (:func:`_crosses`): then i cannot reach it
    there without striking that building first."""
    return any(_crosses(p, q, V) for V in _screens(scene, i, j, z))


def facing_storeys(scene: Scene, i: int, j: int) -> list[tuple]:
    """Sites (:func:`pair_sites`) at which buildings i and j face each other: the shortest segment
    between their outlines at rest (slab, or facade: the outline of the floor above) passes
    through no other building at that level, neither a slab of it at that level nor its facade
    there (the segment's midpoint inside, or an edge crossed)."""
    bs = scene.buildings
    return [site for site in pair_sites(bs[i], bs[j]) if outlines_face(scene, i, j, *_site_outlines(bs[i], bs[j], site),
                                                                        _site_level(bs[i], bs[j], site))]


def outlines_face(scene: Scene, i: int, j: int, A: np.ndarray, B: np.ndarray, z: float) -> bool:
    """Whether the outlines A of building i and B of building j (k, 2) [m] at rest at the level z [m]
    face each other: the shortest segment between them passes through no other building at that
    level (:func:`screened`); where it does, i cannot reach j there without striking that building
    first (the ends of a row)."""
    pa, pb, _ = _closest_points(np.asarray(A, float), np.asarray(B, float))
    return not screened(scene, i, j, pa, pb, z)


def adjacent_pairs(scene: Scene) -> tuple[list[tuple[int, int]], list[tuple[int, int]]]:
    """(adjacent, screened): pairs (i, j), i < j, of buildings that can meet (:func:`pair_sites`:
    slabs at a common level, or a slab of one between two floors of the other, below its roof).

    A pair is adjacent when it faces at one site at least (:func:`facing_storeys`). A pair with
    sites but a third building between them at every one (the ends of a row of equal heights) is
    screened. Pairs with no site are in neither list (no slab of theirs can meet the other).
    """
    bs = scene.buildings
    adjacent, screened = [], []
    for i, a in enumerate(bs):
        for j in range(i + 1, len(bs)):
            if not pair_sites(a, bs[j]):
                continue
            (adjacent if facing_storeys(scene, i, j) else screened).append((i, j))
    return adjacent, screened


def pair_scene(scene: Scene, i: int, j: int) -> Scene:
    """The scene with buildings i and j only (in that order): one adjacent pair, the others absent."""
    from dataclasses import replace

    return replace(scene, buildings=(scene.buildings[i], scene.buildings[j]))


def _oriented(scene: Scene, direction, storeys=None) -> tuple[np.ndarray, float]:
    """(d, g0): the unit direction from the first building towards the second, and the rest clear distance along it."""
    a, b, common = _pair_of(scene, storeys)
    d = direction_vector(direction)
    if d is None:
        # the normal of the facing edges: the shortest segment between the slabs at rest
        best = None
        for site in common:
            pa, pb, dist = _closest_points(*_site_outlines(a, b, site))
            if best is None or dist < best[0]:
                best = (dist, pa, pb)
        dist, pa, pb = best
        v = pb - pa if dist > 1e-9 else (np.mean([s.centre for s in b.slabs], axis=0) - np.mean([s.centre for s in a.slabs], axis=0))
        v = np.where(np.abs(v) < 1e-12 * max(1.0, float(np.abs(v).max())), 0.0, v)
        d = v / np.hypot(*v)
    lo, hi = np.inf, -np.inf
    for site in common:
        dl, _ = translation_to_contact(*_site_outlines(a, b, site), d)
        if np.isfinite(dl):
            hi = max(hi, float(dl))
        dr, _ = translation_to_contact(*_site_outlines(a, b, site), -d)
        if np.isfinite(dr):
            lo = min(lo, -float(dr))
    if not np.isfinite(hi):
        raise InputError(
            f"moving {b.name!r} along ({d[0]:.6g}, {d[1]:.6g}) never brings its slabs against {a.name!r}'s: "
            "the buildings do not face each other in that direction", field="direction")
    tol = 1e-9 * max(1.0, float(np.max(np.abs(np.concatenate([s.vertices for s in a.slabs + b.slabs])))))
    if hi <= tol:
        return d, max(0.0, -hi)
    # {delta : touching} = {-delta' : touching along -d}: B lies behind A along d -> flip
    flipped = -d
    hi_f = -lo
    if hi_f <= tol:
        return flipped + 0.0, max(0.0, -hi_f)
    raise InputError(f"the slabs of {a.name!r} and {b.name!r} interlock along ({d[0]:.6g}, {d[1]:.6g}): no translation along it separates them",
                     field="direction")


def rest_gap(scene: Scene, direction=None) -> tuple[float, np.ndarray]:
    """Clear distance at rest along the direction [m] (smallest over the sites, :func:`pair_sites`) and the oriented unit direction."""
    d, g0 = _oriented(scene, direction)
    return g0, d


def with_gap(scene: Scene, gap: float, direction=None) -> Scene:
    """The scene with the second building moved along the direction so that the clear distance at rest is ``gap`` [m]."""
    if not (isinstance(gap, (int, float, np.integer, np.floating)) and math.isfinite(gap) and gap >= 0):
        raise InputError(f"expected a gap >= 0 m, got {gap!r}", field="gap")
    d, g0 = _oriented(scene, direction)
    return scene.with_building_shifted(scene.buildings[1].name, (float(gap) - g0) * d)


