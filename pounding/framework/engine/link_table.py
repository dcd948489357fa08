"""Links between slabs (the scene's ``[[link]]`` tables) as kinematic rows over the stacked modes.

A link joins point p_a of slab a to point p_b of slab b (two buildings, or two floors of one) and
acts along the unit vector n from p_a to p_b at rest. Its deformation is

    u = n . (r_b(p_b) - r_a(p_a)),     r(p) = (u_c - phi (p_y - c_y), v_c + phi (p_x - c_x)),

the displacement of each point from its slab's 3 DOF (:func:`pounding.framework.model.kinematics.placement`),
so u = G q with G the row over the stacked modal coordinates q of both buildings: the row of p_b
on b's modes minus that of p_a on a's. The force is the law's (as OpenSees' zeroLength element with
a uniaxial material between two nodes), equal and opposite on the two slabs: a link is an internal
force of the buildings it joins and moves no momentum out of them.

Its initial stiffness cannot go into the modes (the modal model is per building), so all its force is
the stepping's remainder (its split k0 is 0): the buildings it joins are solved together, one Newton
group (:func:`link_groups`).
"""

from __future__ import annotations

import numpy as np

from pounding.framework.model.kinematics import placement


def building_rows(scene, systems, link) -> dict:
    """{building name: (n_b,) the deformation's row over that building's own modes} of ``link``
    (``systems``: the buildings' assembled systems, scene order); a building named twice gets the
    sum of its two ends' rows."""
    names = [b.name for b in scene.buildings]
    out: dict = {}
    for sign, name, storey, point in zip((-1.0, 1.0), link.between, link.storeys, link.points):
        i = names.index(name)
        b = scene.buildings[i]
        centres = np.array([s.centre for s in b.slabs])
        T = placement(centres, [storey], np.asarray(point, float), link.direction, b.n_storeys)[0]
        out[name] = out.get(name, 0.0) + sign * (T @ systems[i].modes)
    return out


def link_row(scene, model, link) -> np.ndarray:
    """Row (n,) over the stacked modes of ``model`` of the deformation of ``link`` (module docstring)."""
    names = [b.name for b in scene.buildings]
    out = np.zeros(model.n)
    for name, row in building_rows(scene, model.systems, link).items():
        m0 = int(model.mode_start[names.index(name)])
        out[m0 : m0 + row.shape[0]] = row
    return out


def link_groups(n_buildings: int, joined: list[tuple[int, int]], active: list[int]) -> list[tuple[int, int]]:
    """The Newton groups: ranges [first, last] of building indices, in order, each the buildings
    joined by links (``joined``: pairs of building indices; union-find), widened to the consecutive
    buildings between its first and last (its modes one contiguous range of the stacked model), and
    ranges that overlap merged. Only groups holding a building of ``active`` (those with links)
    are returned."""
    parent = list(range(n_buildings))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in joined:
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    spans: dict[int, list[int]] = {}
    for i in range(n_buildings):
        r = root(i)
        spans.setdefault(r, [i, i])[1] = i
    ranges = sorted(tuple(v) for v in spans.values())
    merged: list[list[int]] = []
    for first, last in ranges:
        if merged and first <= merged[-1][1]:  # an interleaved component: one group (contiguous modes)
            merged[-1][1] = max(merged[-1][1], last)
        else:
            merged.append([first, last])
    keep = set(active)
    return [(f, l) for f, l in merged if any(f <= i <= l for i in keep)]
