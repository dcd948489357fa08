"""Bumpers: a rubber layer of thickness t on one building's face at chosen storeys, as geometry.

A bumper (:class:`~pounding.framework.model.scene.Bumper`, the ``bumper`` of a ``[[contact]]``
table) changes two things of the slab pairs it stands in, and nothing of the engine:

* the *surface* the other building strikes: the bumper's slab with its faces that face the other
  building moved outward by t (:func:`offset_facing`), so the pair's gap is the bare gap minus t
  and the penetration the contact law sees is delta = t - bare gap, the layer's compression;
* the pair's *law*: the layer's own law, and the slabs' law on what is left once the layer is
  compressed to the fraction ``compressible`` of t (:class:`pounding.contact.bumper.BumperLaw`).

The engine (:class:`pounding.framework.engine.stacked_model.Model`) appends the offset polygon as a
*bumper slab*: the real slab's modal rows, floor and weight with the offset outline, as it appends
facade and wall slabs, and pairs the other building's slab with it instead of the bare slab. The
contact rows are the real slab's rigid motion at the contact point on the layer's surface (the
layer has no mass): gaps, screening, features, episodes, energy and contacts.csv follow unchanged.

Which faces
-----------
Only the edges whose outward normal lies within 60 degrees of the direction from the slab to the
other building's slab at rest (their closest features) are moved: the faces that face the
neighbour, as a rubber strip fixed to a facade. A slab that faces its neighbour across a corner
(the rest axis diagonal) gets both faces at that corner covered. The other faces keep their
place, so a bumper changes nothing of what the slab does elsewhere. Each moved vertex is the
intersection of its two edges' lines after the move (a rectangle's facing face slides out whole).

Which pairs
-----------
The pairs at a common level (:func:`pounding.framework.model.levels.common_levels`) between the
rule's two buildings, at the bumper's storeys of ``on``. A slab that strikes the neighbour between
its floors (a facade pair) has no bumper: the layer is on the slab's edge, at the neighbour's floor.
"""

from __future__ import annotations

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.levels import common_levels

#: cosine of the largest angle between an edge's outward normal and the direction to the neighbour
#: for the edge to carry the layer (60 degrees: see the module docstring)
FACING_COS = 0.5


def outward_normals(vertices: np.ndarray) -> np.ndarray:
    """Unit outward normals (k, 2) of the edges i -> i + 1 of a simple polygon (k, 2) [m] of either
    orientation."""
    v = np.asarray(vertices, dtype=float)
    d = np.roll(v, -1, axis=0) - v
    area2 = float(np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]))
    sign = 1.0 if area2 > 0 else -1.0  # counter-clockwise: the outward normal is (dy, -dx)
    n = sign * np.stack([d[:, 1], -d[:, 0]], axis=1)
    return n / np.hypot(n[:, 0], n[:, 1])[:, None]


def offset_facing(vertices: np.ndarray, toward: np.ndarray, thickness: float) -> np.ndarray:
    """The polygon (k, 2) [m] with its edges that face ``toward`` (unit (2,), within 60 degrees of
    their outward normal) moved outward by ``thickness`` [m], each vertex at the intersection of its
    two edges' moved lines (see the module docstring)."""
    v = np.asarray(vertices, dtype=float)
    n = outward_normals(v)
    moved = np.where(n @ np.asarray(toward, dtype=float) > FACING_COS, float(thickness), 0.0)
    out = v.copy()
    k = len(v)
    for i in range(k):
        e0, e1 = (i - 1) % k, i  # the edges ending and starting at vertex i
        if moved[e0] == 0.0 and moved[e1] == 0.0:
            continue
        N = np.array([n[e0], n[e1]])
        det = N[0, 0] * N[1, 1] - N[0, 1] * N[1, 0]
        if abs(det) < 1e-9:  # collinear edges (same normal: both moved or neither)
            out[i] = v[i] + max(moved[e0], moved[e1]) * n[e1]
        else:
            out[i] = v[i] + np.linalg.solve(N, np.array([moved[e0], moved[e1]]))
    return out


def rule_pairs(buildings, pairs, rule) -> list[int]:
    """Indices into ``pairs`` ((building a, storey a, building b, storey b, rest gap), 0-based storeys,
    buildings in ``buildings`` order) of the common-level pairs a rule's bumper stands in."""
    bumper = rule.bumper
    if bumper is None:
        return []
    names = [b.name for b in buildings]
    on = names.index(bumper.on)
    other = names.index(rule.between[1] if rule.between[0] == bumper.on else rule.between[0])
    storeys = {s - 1 for s in bumper.storeys}
    out = []
    for p, (a, fa, b, fb, _) in enumerate(pairs):
        if {a, b} != {on, other}:
            continue
        f_on, f_other = (fa, fb) if a == on else (fb, fa)
        if f_on in storeys and (f_on, f_other) in common_levels(buildings[on], buildings[other]):
            out.append(p)
    return out


def bumper_pairs(buildings, pairs, rules) -> dict:
    """{pair index: the :class:`~pounding.framework.model.scene.ContactRule` whose bumper stands in it}
    over the ``rules`` (the scene's ``contacts``): :func:`rule_pairs` of each."""
    return {p: rule for rule in rules for p in rule_pairs(buildings, pairs, rule)}


def check_bumper(rule, buildings, rest_gap) -> None:
    """Raise :class:`~pounding.errors.InputError` (its field relative to the bumper's table: ``on``,
    ``storeys[j]``, ``thickness``, ``compressible``) for a bumper that cannot stand between the
    rule's buildings (``buildings``: the scene's, with ``name`` and ``slabs`` carrying ``vertices``
    and ``elevation``): ``on`` not one of the two, a storey that does not exist or has no slab of the
    other building at its level, t <= 0 or >= the rest gap of a pair it stands in, ``compressible``
    outside (0, 1]. ``rest_gap(A, B)``: the signed gap [m] of two polygons (k, 2) at rest
    (:func:`pounding.contact.geometry.rest_gap`, passed in: the model layer does not import plugins)."""
    bumper = rule.bumper
    if bumper.on not in rule.between:
        raise InputError(f"expected one of the pair's buildings {rule.between[0]!r} or {rule.between[1]!r}, got {bumper.on!r}",
                         field="on")
    by_name = {b.name: b for b in buildings}
    on = by_name[bumper.on]
    other = by_name[rule.between[1] if rule.between[0] == bumper.on else rule.between[0]]
    t = bumper.thickness
    if not (isinstance(t, (int, float)) and not isinstance(t, bool) and np.isfinite(t) and t > 0):
        raise InputError(f"expected a layer thickness > 0 [m], got {t!r}", field="thickness")
    c = bumper.compressible
    if not (isinstance(c, (int, float)) and not isinstance(c, bool) and 0.0 < c <= 1.0):
        raise InputError(f"expected the fraction of the thickness the layer compresses, in (0, 1], got {c!r}", field="compressible")
    if not bumper.storeys:
        raise InputError("expected at least one storey", field="storeys")
    levels = common_levels(on, other)
    for j, s in enumerate(bumper.storeys):
        if not (isinstance(s, int) and not isinstance(s, bool) and 1 <= s <= len(on.slabs)):
            raise InputError(f"{bumper.on!r} has storeys 1 to {len(on.slabs)}, got {s!r}", field=f"storeys[{j}]")
        partners = [fo for fa, fo in levels if fa == s - 1]
        if not partners:
            raise InputError(f"storey {s} of {bumper.on!r} has no slab of {other.name!r} at its level: "
                             "a bumper stands between two slabs at a common level", field=f"storeys[{j}]")
        for fo in partners:
            gap = rest_gap(on.slabs[s - 1].vertices, other.slabs[fo].vertices)
            if not t < gap:
                raise InputError(f"a layer of {t:g} m does not fit in the rest gap of {gap:.6g} m between storey {s} of "
                                 f"{bumper.on!r} and {other.name!r}: expected a thickness less than the gap",
                                 field="thickness")
