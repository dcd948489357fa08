"""Which slabs can meet: the same-level rule, and plan-distance helpers, in one place.

Two slabs are at a common level when their elevations differ by less than :data:`LEVEL_TOL`
(1e-6 m, far below any storey height and far above the rounding of summed storey heights).
The driver watches such pairs for pounding, the gap study measures them, the scene checks and
drawings use the same rule: :func:`same_level` is the only place it is written, and
:func:`reaches` the only place a slab is compared with a wall's top.
"""

from __future__ import annotations

import numpy as np

#: [m] slabs at a common level (and a point on a polygon's boundary) within this length
LEVEL_TOL = 1e-6


def same_level(za, zb):
    """Whether elevations ``za`` and ``zb`` [m] (scalars or broadcastable arrays) are at a common level."""
    return np.abs(np.asarray(za, dtype=float) - np.asarray(zb, dtype=float)) < LEVEL_TOL


def reaches(elevation: float, top: float) -> bool:
    """Whether a slab at ``elevation`` [m] can strike a wall whose top is at ``top`` [m]: it is not
    above the top (a slab level with the top, within :data:`LEVEL_TOL`, strikes it)."""
    return not elevation > top + LEVEL_TOL


def common_levels(a, b) -> list[tuple[int, int]]:
    """(storey of a, storey of b), 0-based, of every slab pair of buildings ``a`` and ``b`` (anything
    with ``slabs`` that have an ``elevation``) at a common level."""
    return [(fa, fb) for fa, sa in enumerate(a.slabs) for fb, sb in enumerate(b.slabs) if same_level(sa.elevation, sb.elevation)]


def unchecked_pairs(buildings) -> list[tuple[str, str]]:
    """Pairs of buildings (names) with no slabs at a common level.

    Pounding is checked between slabs at a common level only, so nothing is
    checked between such a pair, however close they stand.
    """
    return [(a.name, b.name) for i, a in enumerate(buildings) for b in buildings[i + 1:] if not common_levels(a, b)]


def distance_to_polygon(vertices: np.ndarray, p: np.ndarray) -> float:
    """Distance [m] from point p (2,) to a simple polygon with vertices (k, 2) [m] (0 when p is inside or on it)."""
    a, b = vertices, np.roll(vertices, -1, axis=0)
    ab, ap = b - a, p - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    d = float(np.min(np.hypot(*(ap - t[:, None] * ab).T)))
    # crossing number: a ray from p towards +x crosses the boundary an odd number of times when inside
    crosses = ((a[:, 1] > p[1]) != (b[:, 1] > p[1])) & (p[0] < a[:, 0] + (p[1] - a[:, 1]) * ab[:, 0] / np.where(ab[:, 1] == 0, 1, ab[:, 1]))
    return 0.0 if np.count_nonzero(crosses) % 2 == 1 else d
