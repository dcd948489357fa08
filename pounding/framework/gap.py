"""Separation-gap design: the smallest clear distance at which no slabs ever touch.

Method
------
One run of the scene without contact (``contact = "none"``; both buildings
are then independent, so this is one no-contact run of each building) gives
the displaced slab polygons of every common storey (and facade, below) at every step (rotations
included, any simple polygon). For a plan unit vector d pointing from the
first building towards the second, define for two polygons A, B

    D(A, B, d) = max { delta : A and B + delta d touch }        (-inf if none)

the signed translation of B along d at which the two polygons last touch:
``-D`` is the clear distance between them measured along d (negative when
they overlap). It is computed exactly by casting every vertex of B along d
onto every edge of A and every vertex of A along -d onto every edge of B
(:func:`translation_to_contact`): the last contact of two polygons sliding
along a line is always a vertex of one on an edge of the other. Moving the
second building by ``(s - g0) d``, where ``g0`` is the clear distance along d
at rest in the scene as given (smallest over the sites), keeps every
pair apart at every instant if and only if

    s > min_gap = g0 + max over storeys and time of D(A_f(t), B_f(t), d).

On the output grid of the no-contact run this is exact (``min_gap_grid``: the
full runs check contact on the same grid); ``min_gap`` is the maximum over the
continuous trajectory, refined inside the steps next to the largest step-end
values on the integrator's own interpolant (:mod:`pounding.framework.peaks`).
:func:`verify_gap` checks it with two full runs at 0.99 and 1.01 times the answer.

Slabs between a neighbour's floors
----------------------------------
A slab whose level lies strictly between two floors of the other building (or between the
ground and its first floor), below its roof, strikes that building's facade (its columns and
walls) there. The facade is the one the run with contact uses
(:func:`pounding.framework.facade.facade`): the outline of the floor above, moving rigidly in
plan with the Hermite blend N1 u_below + N2 u_above of the two floors' motions. Such a
slab-facade pair is one more site, treated exactly like a pair of slabs at a common level
(translation to contact along d at every step, refined inside the steps); a pair of buildings
with no common level but such a site is adjacent.

Building-code estimates
-----------------------
From the same run, at the governing storey, with u_a and u_b the peak
displacements along d of the facing slab points (the material points of each
slab at the governing contact, rotation included):

* ABS  = u_a + u_b (absolute sum);
* SRSS = sqrt(u_a^2 + u_b^2);
* DDC  = sqrt(u_a^2 + u_b^2 - 2 rho u_a u_b), the double difference combination
  (Jeng, Kasai and Maison 1992; Penzien 1997; Lopez-Garcia and Soong 2009),
  with the CQC correlation of two oscillators (Der Kiureghian 1981)

      rho = 8 sqrt(z_a z_b) (z_a + r z_b) r^1.5
            / ((1 - r^2)^2 + 4 z_a z_b r (1 + r^2) + 4 (z_a^2 + z_b^2) r^2),

  r = T_a / T_b, using each building's fundamental period along d (the mode
  with the largest effective mass along d) and that mode's damping ratio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pounding.errors import InputError
from pounding.framework.model import Scene

LEVEL_TOL = 1e-6  # [m] slabs at the same elevation (as the analysis driver)
S_TOL = 1e-9  # relative tolerance on the edge parameter of a ray hit
CHUNK = 2048  # time steps per vectorised block (bounds memory for large polygons)
BOUND_BLOCK = 64  # steps per block when only the steps that can govern are evaluated (full=False)

__all__ = [
    "GapCheck",
    "GapReport",
    "correlation",
    "direction_vector",
    "gap_from_result",
    "minimum_gap",
    "rest_gap",
    "translation_to_contact",
    "verify_gap",
    "with_gap",
]


# =============================================================================
# Geometry: translation along a direction until two polygons touch
# =============================================================================


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _cast(P: np.ndarray, Q: np.ndarray, d: np.ndarray):
    """Rays from the vertices of P along d onto the edges of Q.

    P (..., m, 2), Q (..., n, 2), d (2,). Returns delta (..., m, n) with
    ``P_i + delta d`` on edge j of Q (from vertex j to j + 1), NaN where the
    line misses the edge or runs parallel to it, and the edge parameter s.
    """
    E = np.roll(Q, -1, axis=-2) - Q  # (..., n, 2)
    W = P[..., :, None, :] - Q[..., None, :, :]  # (..., m, n, 2)
    den = _cross(E, d)  # (..., n): cross(e, d)
    elen = np.hypot(E[..., 0], E[..., 1])
    ok_den = np.abs(den) > 1e-12 * elen
    den_safe = np.where(ok_den, den, 1.0)[..., None, :]
    s = _cross(W, d) / den_safe
    delta = _cross(W, E[..., None, :, :]) / den_safe
    hit = ok_den[..., None, :] & (s >= -S_TOL) & (s <= 1.0 + S_TOL)
    return np.where(hit, delta, np.nan), s


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
    """
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    d = np.asarray(d, dtype=float)
    lead = np.broadcast_shapes(A.shape[:-2], B.shape[:-2])
    A = np.broadcast_to(A, lead + A.shape[-2:])
    B = np.broadcast_to(B, lead + B.shape[-2:])
    k, l = A.shape[-2], B.shape[-2]
    d1, s1 = _cast(B, A, d)  # B_i + delta d on edge j of A: (..., l, k)
    d0, s0 = _cast(A, B, -d)  # A_i - delta d on edge j of B: (..., k, l)
    flat = np.concatenate([d1.reshape(lead + (l * k,)), d0.reshape(lead + (k * l,))], axis=-1)
    sflat = np.concatenate([s1.reshape(lead + (l * k,)), s0.reshape(lead + (k * l,))], axis=-1)
    none = np.all(np.isnan(flat), axis=-1)
    j = np.argmax(np.where(np.isnan(flat), -np.inf, flat), axis=-1)
    delta = np.where(none, -np.inf, np.take_along_axis(np.where(np.isnan(flat), -np.inf, flat), j[..., None], axis=-1)[..., 0])
    who = np.where(j < l * k, 1, 0)
    jj = np.where(who == 1, j, j - l * k)
    vertex = np.where(who == 1, jj // k, jj // l)
    edge = np.where(who == 1, jj % k, jj % l)
    s = np.take_along_axis(sflat, j[..., None], axis=-1)[..., 0]
    info = {"who": who, "vertex": vertex, "edge": edge, "s": np.clip(s, 0.0, 1.0)}
    return delta, info


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
                raise InputError(f"expected x, y or an angle in degrees, got {value!r}", field="--direction") from None
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        angle = float(value)
        if not math.isfinite(angle):
            raise InputError(f"expected a finite angle in degrees, got {value!r}", field="--direction")
        quarter, rest = divmod(angle, 90.0)
        if rest == 0.0:
            return np.array(((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4])
        a = math.radians(angle)
        return np.array((math.cos(a), math.sin(a)))
    v = np.asarray(value, dtype=float)
    if v.shape != (2,) or not np.all(np.isfinite(v)) or np.hypot(*v) == 0.0:
        raise InputError(f"expected a non-zero plan vector (dx, dy), got {value!r}", field="--direction")
    return v / np.hypot(*v)


class _AtRest:
    """A scene building seen by :func:`pounding.framework.facade.facade` before assembly: its slabs,
    no modes (the facade's outline, storey and eta at rest; its rows come from the run's system)."""

    def __init__(self, building):
        self.slabs = building.slabs
        self.modes = np.zeros((3 * len(building.slabs), 0))


def _facade_at(building, height: float):
    """The :class:`~pounding.framework.facade.Facade` of a scene building at ``height`` [m] at rest
    (no modal rows), or None (at a floor, at or below the ground, above the roof)."""
    from pounding.framework.facade import facade

    return facade(_AtRest(building), -1, height)


def pair_sites(a, b) -> list[tuple]:
    """Every place where two buildings can meet, 0-based: slabs at a common level ``(fa, fb)`` first
    (scene order), then a slab of one against the facade of the other between two of its floors:
    ``(fa, j, "b")`` slab fa of a against b's storey j (0-based, between floor j - 1 or the ground
    and floor j), and ``(j, fb, "a")`` slab fb of b against a's storey j."""
    sites = [(fa, fb) for fa, sa in enumerate(a.slabs) for fb, sb in enumerate(b.slabs) if abs(sa.elevation - sb.elevation) < LEVEL_TOL]
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
    from pounding.io.scene import distance_to_polygon

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
    """Rest outlines at the level z [m] of the buildings other than i and j: a slab at that level,
    else the facade there (the outline of the floor above, when z is between two floors)."""
    out = []
    for k, c in enumerate(scene.buildings):
        if k in (i, j):
            continue
        at = [s.vertices for s in c.slabs if abs(s.elevation - z) < LEVEL_TOL]
        F = None if at else _facade_at(c, z)
        out += at if F is None else [F.vertices]
    return out


def facing_storeys(scene: Scene, i: int, j: int) -> list[tuple]:
    """Sites (:func:`pair_sites`) at which buildings i and j face each other: the shortest segment
    between their outlines at rest (slab, or facade: the outline of the floor above) passes
    through no other building at that level, neither a slab of it at that level nor its facade
    there (the segment's midpoint inside, or an edge crossed)."""
    bs = scene.buildings
    a, b = bs[i], bs[j]
    out = []
    for site in pair_sites(a, b):
        pa, pb, _ = _closest_points(*_site_outlines(a, b, site))
        if not any(_crosses(pa, pb, V) for V in _screens(scene, i, j, _site_level(a, b, site))):
            out.append(site)
    return out


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
            "the buildings do not face each other in that direction", field="--direction")
    tol = 1e-9 * max(1.0, float(np.max(np.abs(np.concatenate([s.vertices for s in a.slabs + b.slabs])))))
    if hi <= tol:
        return d, max(0.0, -hi)
    # {delta : touching} = {-delta' : touching along -d}: B lies behind A along d -> flip
    flipped = -d
    hi_f = -lo
    if hi_f <= tol:
        return flipped + 0.0, max(0.0, -hi_f)
    raise InputError(f"the slabs of {a.name!r} and {b.name!r} interlock along ({d[0]:.6g}, {d[1]:.6g}): no translation along it separates them",
                     field="--direction")


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


# =============================================================================
# The report
# =============================================================================


def correlation(T_a: float, T_b: float, z_a: float, z_b: float) -> float:
    """CQC correlation of two damped oscillators (Der Kiureghian 1981), r = T_a / T_b; symmetric in (a, b)."""
    r = T_a / T_b
    num = 8.0 * math.sqrt(z_a * z_b) * (z_a + r * z_b) * r**1.5
    den = (1.0 - r * r) ** 2 + 4.0 * z_a * z_b * r * (1.0 + r * r) + 4.0 * (z_a * z_a + z_b * z_b) * r * r
    return num / den


@dataclass
class GapCheck:
    """Two full runs with pounding at ``factors`` times the minimum gap."""

    factors: tuple[float, float]
    gaps: tuple[float, float]
    n_impacts: tuple[int, int]
    tolerance: float  # the contact law's length tolerance [m]

    @property
    def ok(self) -> bool:
        """Impacts below the answer and none above it."""
        return self.n_impacts[0] > 0 and self.n_impacts[1] == 0

    def to_dict(self) -> dict:
        return {
            "below": {"factor": self.factors[0], "gap": self.gaps[0], "n_impacts": self.n_impacts[0]},
            "above": {"factor": self.factors[1], "gap": self.gaps[1], "n_impacts": self.n_impacts[1]},
            "contact_tolerance": self.tolerance,
            "ok": self.ok,
        }


@dataclass
class GapReport:
    """The minimum separation gap of a pair and the code estimates (lengths in m, times in s).

    ``buildings`` = (fixed, moved): the second building is the one moved along
    ``direction`` (a unit vector from the first towards the second). Storeys are
    1-based, of the first building (``storey_b`` of the second); vertices and
    edges 0-based in the slab polygons' order (edge j from vertex j to j + 1).
    """

    min_gap: float
    current_gap: float
    direction: np.ndarray
    buildings: tuple[str, str]
    storey: int
    storey_b: int
    time: float
    striking: str  # building whose corner touches
    vertex: int
    struck: str
    edge: int
    point: np.ndarray  # contact point in plan at the governing instant, second building at min_gap
    required: list  # per site (:func:`pair_sites`): (storey a, storey b, required gap, time); see ``facades``
    periods: tuple[float, float]
    damping: tuple[float, float]
    peaks: tuple[float, float]  # peak displacement along d of the facing points at the governing storey
    rho: float
    abs: float
    srss: float
    ddc: float
    t: np.ndarray = field(repr=False)
    clearance: np.ndarray = field(repr=False)  # (nt, sites) clear distance along d in the scene as given, at the step ends
    check: GapCheck | None = None
    #: the minimum gap over the step ends only (what a run with contact, which checks after each step, sees);
    #: ``min_gap`` is over the continuous trajectory (:mod:`pounding.framework.peaks`)
    min_gap_grid: float | None = None
    #: the governing site when a slab strikes the other building's facade between two of its floors:
    #: {"striking", "slab_storey", "height" [m], "struck", "struck_storey", "eta"} (storeys 1-based), else None
    facade: dict | None = None
    #: per row of ``required``: the same for slab-facade rows, None at a common level
    facades: list = field(default_factory=list)

    def to_dict(self) -> dict:
        out = {
            "min_gap": self.min_gap,
            "min_gap_step_ends": self.min_gap_grid,
            "current_gap": self.current_gap,
            "direction": [float(self.direction[0]), float(self.direction[1])],
            "storey": self.storey,
            "time": self.time,
            "abs": self.abs,
            "srss": self.srss,
            "ddc": self.ddc,
            "buildings": {"fixed": self.buildings[0], "moved": self.buildings[1]},
            "storey_b": self.storey_b,
            "corner": {"building": self.striking, "vertex": self.vertex},
            "edge": {"building": self.struck, "edge": self.edge},
            "point": [float(self.point[0]), float(self.point[1])],
            "required_per_storey": [self._row(k, fa, fb, g, t) for k, (fa, fb, g, t) in enumerate(self.required)],
            "periods": {self.buildings[0]: self.periods[0], self.buildings[1]: self.periods[1]},
            "damping_ratios": {self.buildings[0]: self.damping[0], self.buildings[1]: self.damping[1]},
            "peak_displacements": {self.buildings[0]: self.peaks[0], self.buildings[1]: self.peaks[1]},
            "rho": self.rho,
        }
        if self.facade is not None:
            out["facade"] = dict(self.facade)
        if self.check is not None:
            out["check"] = self.check.to_dict()
        return out

    def _row(self, k: int, fa: int, fb: int, g, t) -> dict:
        row = {"storey": fa, "storey_b": fb, "gap": g, "time": t}
        if k < len(self.facades) and self.facades[k] is not None:
            row["facade"] = dict(self.facades[k])
        return row


def _fundamental(system, d: np.ndarray) -> tuple[float, float]:
    """(period, damping ratio) of the mode with the largest effective mass along d."""
    gamma = system.participation(system.influence(d))
    i = int(np.argmax(gamma**2))
    return float(system.periods[i]), float(system.zeta[i])


def _point_history(cm: np.ndarray, centre: np.ndarray, point: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Displacement along d of a slab's material point (rest position ``point``), shape (nt,)."""
    r = point - centre
    ux = cm[:, 0] - cm[:, 2] * r[1]
    uy = cm[:, 1] + cm[:, 2] * r[0]
    return ux * d[0] + uy * d[1]


@dataclass
class _Side:
    """One side of a site in a run: a slab or a facade, as modal rows (3, n) of its (u, v, phi) about
    ``centre``, its rest outline, and its displaced-vertex offsets (nt, k, 2) at the output steps."""

    name: str
    vertices: np.ndarray
    centre: np.ndarray
    rows: np.ndarray
    offsets: np.ndarray
    facade: bool

    def at(self, q: np.ndarray) -> np.ndarray:
        """The displaced outline (k, 2) for the building's modal coordinates q (n,)."""
        u, v, phi = self.rows @ q
        r = self.vertices - self.centre
        return self.vertices + np.stack([u - phi * r[:, 1], v + phi * r[:, 0]], axis=-1)


def _sides(result, a, b, site, vertices: dict) -> tuple[_Side, _Side]:
    """The two sides of ``site`` (:func:`pair_sites`) in ``result``: the slabs' motion, or the facade
    the driver uses (:func:`pounding.framework.facade.facade`, from the run's assembled system);
    ``vertices``: {building name: ``result.vertices(name)``}."""
    from pounding.framework.facade import facade

    z = _site_level(a, b, site)
    out = []
    for building, f, struck in ((a, site[0], len(site) == 3 and site[2] == "a"), (b, site[1], len(site) == 3 and site[2] == "b")):
        i = result.names.index(building.name)
        system = result.systems[i]
        if not struck:
            k = len(building.slabs[f].vertices)
            out.append(_Side(building.name, building.slabs[f].vertices, system.slabs[f].centre,
                             np.asarray(system.modes, dtype=float)[3 * f: 3 * f + 3], vertices[building.name][:, f, :k], False))
            continue
        F = facade(system, i, z)
        uvp = result.modal(building.name) @ F.rows.T  # (nt, 3) about the facade's centre
        r = F.vertices - F.centre
        off = np.stack([uvp[:, :1] - uvp[:, 2:] * r[:, 1], uvp[:, 1:2] + uvp[:, 2:] * r[:, 0]], axis=-1)
        out.append(_Side(building.name, F.vertices, F.centre, F.rows, off, True))
    return out[0], out[1]


def gap_from_result(scene: Scene, result, direction=None, *, full: bool = True, storeys=None) -> GapReport:
    """The :class:`GapReport` from a run of ``scene`` (normally without contact; output every step).

    ``full=False`` evaluates the exact translation to contact only at the steps that can govern:
    per site, steps are taken in decreasing order of the bound
    ``max_i A_i . d - min_j B_j . d`` (two polygons that touch overlap in their projections on d),
    block by block, until the bound (raised by 1e-12 of the coordinates against rounding) falls
    below the best exact value found. The answer is the same (same values, same governing step on
    ties); ``clearance`` then holds ``inf`` at the steps not evaluated. ``storeys``: only these
    sites (:func:`pair_sites`; a pair of a row, where it faces). Sites are slabs at a common level
    and slabs against the other building's facade between two of its floors.
    """
    a, b, common = _pair_of(scene, storeys)
    d, g0 = _oriented(scene, direction, storeys)
    cm_a, cm_b = result.cm(a.name), result.cm(b.name)
    va, vb = result.vertices(a.name), result.vertices(b.name)
    nt = len(result.t)
    D = np.full((nt, len(common)), -np.inf)
    infos = []
    sides = [_sides(result, a, b, site, {a.name: va, b.name: vb}) for site in common]
    for c, site in enumerate(common):
        side_a, side_b = sides[c]
        A = side_a.vertices + side_a.offsets
        B = side_b.vertices + side_b.offsets
        info = {k: np.zeros(nt, dtype=float if k == "s" else int) for k in ("who", "vertex", "edge", "s")}
        if full:
            blocks = [slice(i0, min(nt, i0 + CHUNK)) for i0 in range(0, nt, CHUNK)]
            bound = None
        else:
            # >= the translation to contact at each step; raised by far more than the rounding of either
            # computation (~1e-16 of the coordinates) so that rounding never skips a governing step
            bound = (A @ d).max(axis=-1) - (B @ d).min(axis=-1) + 1e-12 * (1.0 + float(np.max(np.abs(A))) + float(np.max(np.abs(B))))
            order = np.argsort(-bound, kind="stable")
            blocks = (np.sort(order[i0:i0 + BOUND_BLOCK]) for i0 in range(0, nt, BOUND_BLOCK))
        best = -np.inf
        for sl in blocks:
            if bound is not None and np.max(bound[sl]) < best:
                break  # no step left can reach the best value (ties are still evaluated)
            D[sl, c], inf = translation_to_contact(A[sl], B[sl], d)
            best = max(best, float(np.max(D[sl, c])))
            for key in info:
                info[key][sl] = inf[key]
        infos.append(info)
    if not np.any(np.isfinite(D)):
        raise InputError("the slabs never face each other along the direction", field="--direction")
    # true peaks: the translation to contact over the continuous trajectory, refined inside the steps
    # around each storey's governing step (pounding.framework.peaks)
    # (D itself, and the clearance history, stay at the step ends: what a run with contact checks)
    t_best = np.asarray(result.t, dtype=float)[np.argmax(D, axis=0)]
    cont = np.max(D, axis=0)
    refined = _refine_inside_steps(result, a, b, sides, d, D)
    if refined is not None:
        for cc, (val, tc) in enumerate(refined):
            if val > cont[cc]:
                cont[cc], t_best[cc] = val, tc
    c = int(np.argmax(cont))
    k_t = int(np.argmax(D[:, c]))  # the governing step: the contact features are read there
    min_gap = g0 + float(cont[c])
    fa, fb = common[c][:2]
    side_a, side_b = sides[c]
    info = {key: val[k_t] for key, val in infos[c].items()}
    who, vertex, edge, s = int(info["who"]), int(info["vertex"]), int(info["edge"]), float(info["s"])
    # the facing material points (rest positions) and the contact point at min_gap
    Va, Vb, oa = side_a.vertices, side_b.vertices, side_a.offsets
    if who == 1:  # a corner of b on an edge of a
        striking, struck = b.name, a.name
        rest_b = Vb[vertex]
        ea0, ea1 = Va[edge], Va[(edge + 1) % len(Va)]
        rest_a = ea0 + s * (ea1 - ea0)
        point = rest_a + oa[k_t, edge] + s * (oa[k_t, (edge + 1) % len(Va)] - oa[k_t, edge])
    else:  # a corner of a on an edge of b
        striking, struck = a.name, b.name
        rest_a = Va[vertex]
        eb0, eb1 = Vb[edge], Vb[(edge + 1) % len(Vb)]
        rest_b = eb0 + s * (eb1 - eb0)
        point = rest_a + oa[k_t, vertex]
    u_a, u_b = _point_peaks(result, (side_a, fa, rest_a), (side_b, fb, rest_b), d, cm_a, cm_b)
    sys_a, sys_b = (result.systems[result.names.index(n)] for n in (a.name, b.name))
    (T_a, z_a), (T_b, z_b) = _fundamental(sys_a, d), _fundamental(sys_b, d)
    rho = correlation(T_a, T_b, z_a, z_b)
    required = []
    for cc, site in enumerate(common):
        ga, gb = site[:2]
        required.append((ga + 1, gb + 1, float(g0 + cont[cc]) if np.isfinite(cont[cc]) else None, float(t_best[cc])))
    return GapReport(
        min_gap=float(min_gap),
        min_gap_grid=float(g0 + np.max(D)),
        current_gap=float(g0),
        direction=d,
        buildings=(a.name, b.name),
        storey=fa + 1,
        storey_b=fb + 1,
        time=float(t_best[c]),
        striking=striking,
        vertex=vertex,
        struck=struck,
        edge=edge,
        point=np.asarray(point, dtype=float),
        required=required,
        periods=(T_a, T_b),
        damping=(z_a, z_b),
        peaks=(u_a, u_b),
        rho=float(rho),
        abs=u_a + u_b,
        srss=math.hypot(u_a, u_b),
        ddc=math.sqrt(max(0.0, u_a * u_a + u_b * u_b - 2.0 * rho * u_a * u_b)),
        t=np.asarray(result.t),
        clearance=-D,
        facade=_site_facade(a, b, common[c]),
        facades=[_site_facade(a, b, site) for site in common],
    )


def _point_row(side: _Side, rest: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Row over a building's modes of the displacement along d of a slab's or facade's material point ``rest``."""
    r = np.asarray(rest, dtype=float) - side.centre
    u, v, phi = side.rows
    return d[0] * (u - r[1] * phi) + d[1] * (v + r[0] * phi)


def _point_peaks(result, pa, pb, d, cm_a, cm_b) -> tuple[float, float]:
    """Peak |displacement along d| of the facing points over the continuous trajectory
    (:func:`pounding.framework.peaks.abs_peaks`); over the output steps when the output is thinned."""
    from pounding.framework import peaks

    seg = peaks.segments(result)
    out = []
    for (side, f, rest), cm in ((pa, cm_a), (pb, cm_b)):
        if seg is None:
            hist = result.modal(side.name) @ side.rows.T if side.facade else cm[:, f]
            out.append(float(np.max(np.abs(_point_history(hist, side.centre, rest, d)))))
            continue
        out.append(float(peaks.abs_peaks(peaks.building_segments(seg, result, side.name), _point_row(side, rest, d)[None, :])[0]))
    return out[0], out[1]


def _refine_inside_steps(result, a, b, sides, d, D, top: int = 3):
    """Per site (its two :class:`_Side`): (max of the translation to contact inside the steps next to its ``top``
    largest step-end values, the instant [s]) on the continuous trajectory; None when the output is
    thinned. The translation is piecewise smooth in the displacements (a fixed vertex on a fixed
    edge near its maximum), so a bounded search on each piece finds it."""
    from pounding.framework import peaks

    seg = peaks.segments(result)
    if seg is None:
        return None
    ia, ib = result.names.index(a.name), result.names.index(b.name)
    sys_a, sys_b = result.systems[ia], result.systems[ib]
    sla = slice(int(result.mode_start[ia]), int(result.mode_start[ia]) + sys_a.n_dof)
    slb = slice(int(result.mode_start[ib]), int(result.mode_start[ib]) + sys_b.n_dof)
    t0 = np.asarray(seg.t0)
    out = []
    for c, (side_a, side_b) in enumerate(sides):
        if not np.any(np.isfinite(D[:, c])):
            out.append((-np.inf, 0.0))
            continue

        def D_of(q, side_a=side_a, side_b=side_b):
            val, _ = translation_to_contact(side_a.at(q[sla]), side_b.at(q[slb]), d)
            return float(val) if np.isfinite(val) else -np.inf

        ks = np.argsort(-np.where(np.isfinite(D[:, c]), D[:, c], -np.inf), kind="stable")[:top]
        pieces = set()
        for k in ks:
            tk = float(result.t[k])
            j = int(np.searchsorted(t0, tk))
            pieces.update(i for i in (j - 1, j) if 0 <= i < len(t0))
        val, i, s = peaks.refine_over(seg, sorted(pieces), D_of)
        out.append((val, float(t0[i] + s * seg.h[i]) if i >= 0 else 0.0))
    return out


def no_contact(scene: Scene) -> Scene:
    """The scene without contact, recording every step."""
    return scene.with_analysis(contact="none", contact_params={}, output_every=1)


def minimum_gap(scene: Scene, direction=None, *, progress=None) -> GapReport:
    """Smallest clear distance at rest along ``direction`` at which no slabs touch under the scene's ground motion.

    Parameters
    ----------
    scene : Scene
        Exactly two buildings that can meet: a storey at a common level, or a slab between
        two floors of the other (:func:`pair_sites`).
    direction : None, "x", "y", angle [degrees] or (dx, dy)
        The direction the gap is measured and the second building moved along
        (oriented from the first building towards the second). Default: the
        shortest segment between the slabs at rest (the normal of the facing edges).

    Returns
    -------
    GapReport
        Without a check; see :func:`verify_gap`.
    """
    from pounding.framework.analysis import run

    _oriented(scene, direction)  # bad directions fail before the run
    result = run(no_contact(scene), progress=progress)
    return gap_from_result(scene, result, direction)


@dataclass
class RowGaps:
    """The required gap of every adjacent pair of a scene of three or more buildings.

    ``reports`` holds one :class:`GapReport` per adjacent pair (scene order), each found from
    one run of the whole scene without contact, over the storeys where the pair faces
    (:func:`facing_storeys`), and measured as if the pair stood alone (the second building of
    the pair is the one moved); ``screened`` names the pairs with slabs at a
    common level (or slab-facade sites) that never face each other (a building between them
    at every such level).
    """

    reports: list
    screened: list[tuple[str, str]]

    def to_dict(self) -> dict:
        return {"pairs": [r.to_dict() for r in self.reports], "screened": [list(p) for p in self.screened]}


def minimum_gaps(scene: Scene, direction=None, *, progress=None) -> RowGaps:
    """:func:`minimum_gap` of every adjacent pair (:func:`adjacent_pairs`) from one run without contact.

    ``direction`` applies to every pair (None: each pair's own facing normal).
    """
    from pounding.framework.analysis import run

    adjacent, screened = adjacent_pairs(scene)
    if not adjacent:
        raise InputError("no two buildings have slabs facing each other at a common level or a facade between floors: there is no gap to design", field="building")
    subs = [(pair_scene(scene, i, j), facing_storeys(scene, i, j)) for i, j in adjacent]
    for sub, storeys in subs:
        _oriented(sub, direction, storeys)  # bad directions fail before the run
    result = run(no_contact(scene), progress=progress)
    names = [b.name for b in scene.buildings]
    return RowGaps([gap_from_result(sub, result, direction, storeys=storeys) for sub, storeys in subs],
                   [(names[i], names[j]) for i, j in screened])


def verify_gap(scene: Scene, report: GapReport, factors=(0.99, 1.01)) -> GapCheck:
    """Two full runs with the second building at ``factors`` times the minimum gap: impacts expected at the first, none at the second.

    The scene's own contact law is used (the impulse law if the scene has none).
    Contact is detected within the law's length tolerance (1e-4 m by default), so
    the check is only meaningful when ``(factors[1] - 1) * min_gap`` exceeds it.
    """
    from pounding.framework.analysis import run
    from pounding.framework.registry import CONTACT_LAWS

    if scene.analysis.contact == "none":
        scene = scene.with_analysis(contact="impulse", contact_params={})
    law = CONTACT_LAWS.get(scene.analysis.contact)(**scene.analysis.contact_params)
    gaps, counts = [], []
    for f in factors:
        g = float(f) * report.min_gap
        counts.append(run(scene.with_gap(g, report.direction)).n_impacts)
        gaps.append(g)
    check = GapCheck(tuple(float(f) for f in factors), tuple(gaps), tuple(counts), float(getattr(law, "tolerance", 0.0)))
    report.check = check
    return check
