"""The ``[[link]]`` tables of a scene: links with laws between two slabs.

Each table names two buildings (or one twice: two of its floors), the slab of each, an attachment
point on each slab and a law of the ``pounding.hysteresis`` family. Checked here, one message each
naming the key path: an unknown building, a storey the building does not have, a point outside its
slab, two equal points (the link would have no direction), an unknown law or parameters out of its
range (the law's own checks). The structure (keys, types) is checked with the rest of the scene
(:mod:`pounding.io.scene_structure`).
"""

from __future__ import annotations

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.law_tables import link_law
from pounding.framework.model.levels import LEVEL_TOL, distance_to_polygon
from pounding.framework.model.scene import Building, Link



def parse_links(tables: list, buildings: list[Building]) -> tuple[Link, ...]:
    """The scene's links from its ``[[link]]`` tables (InputError naming ``link[i].key``)."""
    names = [b.name for b in buildings]
    out, seen = [], {}
    for i, table in enumerate(tables):
        where = f"link[{i}]"
        name = str(table.get("name", f"link-{i + 1}"))
        if name in seen:
            raise InputError(f"the link name {name!r} is used twice (link[{seen[name]}])", field=f"{where}.name")
        seen[name] = i
        between, storeys = list(table["between"]), [int(s) for s in table["storeys"]]
        points = np.asarray(table["points"], dtype=float)
        # first: two equal points are one slip, whichever slab they lie on
        if float(np.hypot(*(points[1] - points[0]))) <= LEVEL_TOL:
            raise InputError("the two points are the same: the line from the first to the second is the link's direction, "
                             f"give two points more than {LEVEL_TOL:g} m apart", field=f"{where}.points")
        for j, nm in enumerate(between):
            if nm not in names:
                raise InputError(f"no building is named {nm!r}; the buildings: {', '.join(map(repr, names))}",
                                 field=f"{where}.between[{j}]")
            b = buildings[names.index(nm)]
            if not 1 <= storeys[j] <= b.n_storeys:
                raise InputError(f"building {nm!r} has storeys 1 to {b.n_storeys}, got {storeys[j]}", field=f"{where}.storeys[{j}]")
            slab = b.slabs[storeys[j] - 1]
            if distance_to_polygon(slab.vertices, points[j]) > LEVEL_TOL:
                raise InputError(f"the point ({points[j][0]:g}, {points[j][1]:g}) lies outside the slab of storey {storeys[j]} "
                                 f"of {nm!r}", field=f"{where}.points[{j}]")
        if between[0] == between[1] and storeys[0] == storeys[1]:
            raise InputError(f"both ends are on the slab of storey {storeys[0]} of {between[0]!r}: a link joins two slabs",
                             field=f"{where}.storeys")
        law, params = link_law(table["law"], f"{where}.law")
        out.append(Link(name, (between[0], between[1]), (storeys[0], storeys[1]), points, law, params))
    return tuple(out)


def link_table(link: Link) -> dict:
    """The ``[[link]]`` table of ``link`` (the scene writer's): it loads back to the same link."""
    law = link.law.describe()
    if link.law.own_values() is None:
        law.update(stiffness=float(link.params[0]), yield_force=float(link.params[1]), hardening=float(link.params[2]))
    return {"name": link.name, "between": list(link.between), "storeys": list(link.storeys),
            "points": [[float(x), float(y)] for x, y in link.points], "law": law}
