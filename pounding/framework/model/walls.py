"""Retaining walls fixed to the ground: the bodies a slab strikes that never move.

A wall (:class:`~pounding.framework.model.scene.Wall`) is a plan polyline, its *face*, standing from
the ground up to its ``top``; a slab at or below the top can strike it. The engine holds contact
between slabs as pairs of polygons with modal rows (:mod:`pounding.framework.engine.pairs`); a body
fixed to the ground is the limit of infinite mass, whose rows are zero. So every wall becomes, for
the slabs on each side of each face segment, a *wall slab*: a rectangle behind the segment, on the
side away from those slabs, ``THICKNESS`` deep, that never moves. Every contact path (gaps, the
impact search, impulses, held contact, force laws, the energy account) then handles a wall
unchanged: the contact row of a slab against a wall slab is the slab's own row, an impulse changes
only the striking building's velocities (its momentum by exactly the impulse), and the kinetic
energy the impact removes is booked in that building's account alone (the wall stores none).

Sides
-----
A slab stands on one side of a face segment at rest: the sign of the cross product of the
segment's direction with the vector from its start to the slab's centre of mass. Its wall slab is
the rectangle on the other side. A wall between two buildings gives each its own rectangle.

What a wall may not do
----------------------
A wall occupies the plan line of its face from the ground up to its top: it may not cut the
space of a storey that stands below its top (storey k spans the floor below it, or the ground, up
to slab k): :func:`cut_storeys` finds them, the scene loader refuses them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.levels import LEVEL_TOL, distance_to_polygon, reaches

#: [m] depth of a wall slab behind its face: far more than a slab can press into a wall in one
#: step (so no contact reaches its back face), far less than any plan dimension that matters
THICKNESS = 1.0


@dataclass(frozen=True)
class WallSlab:
    """One face segment of a wall as the slabs on one side see it: a fixed rectangle behind it.

    wall : int
        The wall (scene order).
    segment : int
        The face segment (0-based: between face points ``segment`` and ``segment + 1``).
    vertices : ndarray (4, 2)
        The rectangle, counter-clockwise [m]: the segment and its offset ``THICKNESS`` away from the slabs.
    centre : ndarray (2,)
        Its centroid [m] (a reference point only: the wall slab has no mass and never moves).
    """

    wall: int
    segment: int
    vertices: np.ndarray
    centre: np.ndarray

    @property
    def radius(self) -> float:
        """Largest distance from the centre to a vertex [m]."""
        return float(np.max(np.hypot(*(self.vertices - self.centre).T)))


def segments(face: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The face's segments (start (2,), end (2,)) [m]."""
    face = np.asarray(face, dtype=float)
    return [(face[i], face[i + 1]) for i in range(len(face) - 1)]


def side(p0: np.ndarray, p1: np.ndarray, point: np.ndarray) -> float:
    """+1 when ``point`` lies left of the segment p0 -> p1 (counter-clockwise of its direction), -1 right, 0 on its line."""
    d, r = p1 - p0, np.asarray(point, float) - p0
    return float(np.sign(d[0] * r[1] - d[1] * r[0]))


def segment_frame(p0: np.ndarray, p1: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """(length [m], unit direction (2,), unit left normal (2,)) of the segment p0 -> p1: a point x lies
    ``(x - p0) @ direction`` along it and ``(x - p0) @ normal`` to its left (negative: to its right)."""
    length = float(np.hypot(*(p1 - p0)))
    along = (p1 - p0) / length
    return length, along, np.array([-along[1], along[0]])  # the left normal is (-dy, dx)


def wall_slab(wall: int, segment: int, p0: np.ndarray, p1: np.ndarray, slab_side: float) -> WallSlab:
    """The rectangle behind segment p0 -> p1 on the side away from slabs on ``slab_side`` (+1 left, -1 right)."""
    back = -slab_side * segment_frame(p0, p1)[2]
    rect = np.array([p0, p1, p1 + THICKNESS * back, p0 + THICKNESS * back])
    if slab_side > 0:  # behind on the right: p0, p1, ... turns clockwise
        rect = rect[::-1].copy()
    return WallSlab(wall, segment, rect, rect.mean(axis=0))


def open_vertices(scene, i: int, f: int, p0: np.ndarray, p1: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(facing, open, dist) (m,) over the rest vertices of slab f of building i of ``scene``: ``facing``
    (bool) those whose foot on the line of the face segment p0 -> p1 falls within it, ``open`` (bool)
    among them those whose straight path to that foot crosses no other building at the slab's level (a
    slab of it or its facade: :func:`pounding.framework.model.placement.screened`), and ``dist`` [m]
    each vertex's signed distance from the segment's line, positive on its left
    (:func:`segment_frame`). A facing vertex that is not open strikes that building before it could
    reach the wall."""
    from pounding.framework.model.placement import screened

    slab = scene.buildings[i].slabs[f]
    rest = np.asarray(slab.vertices, float)
    length, along, n = segment_frame(p0, p1)
    foot = (rest - p0) @ along
    dist = (rest - p0) @ n
    facing = (foot >= -LEVEL_TOL) & (foot <= length + LEVEL_TOL)
    open_ = facing.copy()
    for v in np.flatnonzero(facing):
        open_[v] = not screened(scene, i, -1, rest[v], rest[v] - dist[v] * n, float(slab.elevation))
    return facing, open_, dist


def screened_from(scene, i: int, f: int, p0: np.ndarray, p1: np.ndarray) -> bool:
    """Whether slab f of building i of ``scene`` faces the wall segment p0 -> p1 only through other
    buildings (:func:`open_vertices`: some vertex faces it, none is open). A slab with no vertex facing
    the segment is not screened: it may still reach the segment's end by turning."""
    facing, open_, _ = open_vertices(scene, i, f, p0, p1)
    return bool(facing.any() and not open_.any())


def wall_sites(systems, walls, scene=None) -> list[tuple[int, int, WallSlab]]:
    """(building, storey (0-based), wall slab) for every slab at or below a wall's top and every
    segment of that wall's face, the wall slab on the side away from the slab (one rectangle per
    segment and side, shared by the slabs that see it). ``systems``: anything with ``slabs`` whose
    items have ``vertices``, ``centre`` and ``elevation``; ``walls``: the scene's walls. Given the
    ``scene`` (the buildings of ``systems`` in its order), a slab that faces a segment only through
    other buildings (:func:`screened_from`) has no site there: it strikes them first."""
    out, made = [], {}
    for w, wall in enumerate(walls):
        for k, (p0, p1) in enumerate(segments(wall.face)):
            for b, system in enumerate(systems):
                for f, slab in enumerate(system.slabs):
                    if not reaches(slab.elevation, wall.top):
                        continue
                    if scene is not None and screened_from(scene, b, f, p0, p1):
                        continue
                    s = side(p0, p1, slab.centre) or side(p0, p1, np.mean(slab.vertices, axis=0))
                    if s == 0.0:
                        continue  # centred on the face's line (beyond its ends): no side to strike from
                    key = (w, k, s)
                    if key not in made:
                        made[key] = wall_slab(w, k, p0, p1, s)
                    out.append((b, f, made[key]))
    return out


def segment_cuts_polygon(p0: np.ndarray, p1: np.ndarray, vertices: np.ndarray, tol: float = LEVEL_TOL) -> bool:
    """Whether the segment p0 -> p1 [m] passes through the inside of the polygon (k, 2) [m] (touching
    its boundary, within ``tol``, does not count): some piece of the segment between its crossings
    with the polygon's edges has its midpoint inside, farther than ``tol`` from the boundary."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    a, b = vertices, np.roll(vertices, -1, axis=0)
    d, e = p1 - p0, b - a
    den = d[0] * e[:, 1] - d[1] * e[:, 0]
    ok = np.abs(den) > 1e-300
    r = a - p0
    s = np.where(ok, (r[:, 0] * e[:, 1] - r[:, 1] * e[:, 0]) / np.where(ok, den, 1.0), -1.0)
    u = np.where(ok, (r[:, 0] * d[1] - r[:, 1] * d[0]) / np.where(ok, den, 1.0), -1.0)
    cuts = s[ok & (s > 0.0) & (s < 1.0) & (u >= 0.0) & (u <= 1.0)]
    params = np.unique(np.concatenate([[0.0, 1.0], cuts]))
    for lo, hi in zip(params[:-1], params[1:]):
        mid = p0 + 0.5 * (lo + hi) * d
        if distance_to_polygon(vertices, mid) == 0.0 and _boundary_distance(vertices, mid) > tol:
            return True
    return False


def _boundary_distance(vertices: np.ndarray, p: np.ndarray) -> float:
    a, b = vertices, np.roll(vertices, -1, axis=0)
    ab, ap = b - a, p - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return float(np.min(np.hypot(*(ap - t[:, None] * ab).T)))


def cut_storeys(building, wall) -> list[int]:
    """The storeys (0-based) of ``building`` (a scene Building) whose space the ``wall``'s face cuts:
    the storey stands below the wall's top (its floor below, or the ground, is lower than the top)
    and a face segment passes through its slab's plan."""
    out = []
    for f, slab in enumerate(building.slabs):
        bottom = building.slabs[f - 1].elevation if f else 0.0
        if bottom >= wall.top - LEVEL_TOL:
            continue
        if any(segment_cuts_polygon(p0, p1, np.asarray(slab.vertices, float)) for p0, p1 in segments(wall.face)):
            out.append(f)
    return out


def check_wall(wall, buildings) -> None:
    """Raise :class:`~pounding.errors.InputError` (its field relative to the wall's table: ``name``,
    ``face``, ``top``) for a wall that cannot stand in a scene of ``buildings``: a name a building has,
    a top <= 0, a face of fewer than two points or with a segment of no length, a face that cuts
    the space of a storey standing below its top (:func:`cut_storeys`)."""
    if wall.name in [b.name for b in buildings]:
        raise InputError(f"wall name {wall.name!r} is a building's name; impacts.csv names the struck body", field="name")
    if not wall.top > 0.0:
        raise InputError(f"expected a number > 0, got {wall.top!r}", field="top")
    face = np.asarray(wall.face, dtype=float)
    if face.ndim != 2 or face.shape[1] != 2 or len(face) < 2:
        raise InputError(f"expected at least 2 points [x, y], got {face.tolist()!r}", field="face")
    lengths = np.hypot(*np.diff(face, axis=0).T)
    if np.any(lengths <= LEVEL_TOL):
        k = int(np.argmax(lengths <= LEVEL_TOL))
        raise InputError(f"expected segments of nonzero length, got points {k} and {k + 1} at the same place "
                         f"({face[k, 0]:g}, {face[k, 1]:g})", field="face")
    for b in buildings:
        cut = cut_storeys(b, wall)
        if cut:
            raise InputError(f"the wall's face cuts the space of storey {cut[0] + 1} of {b.name!r}, which stands below its top "
                             f"({wall.top:g} m): a wall may stand beside a storey or under a slab above its top, not through it",
                             field="face")
