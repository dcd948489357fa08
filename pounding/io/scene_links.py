"""The ``[[link]]`` tables of a scene: links with laws between two slabs.

Each table names two buildings (or one twice: two of its floors), the slab of each, an attachment
point on each slab and a law of the ``pounding.hysteresis`` family. Checked here, one message each
naming the key path: an unknown building, a storey the building does not have, a point outside its
slab, two equal points (the link would have no direction), an unknown law or parameters out of its
range (the law's own checks). The structure (keys, types) is checked with the rest of the scene
(:mod:`pounding.io.scene_structure`).
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.levels import LEVEL_TOL, distance_to_polygon
from pounding.framework.model.scene import Building, Link

#: the keys of a yielding law's table that the link gives it (a storey_springs element's own keys)
SPRING_KEYS = ("stiffness", "yield_force", "hardening")


def link_law(spec: Mapping, where: str):
    """(law instance, parameter vector (n_params,)) of a link's ``law`` table; InputError naming ``where.key``.

    A law that sets its stiffness, yield force and hardening from its own parameters (``own_values``:
    elastic, viscous, maxwell, kelvin, friction_pendulum) takes only those; any other (bilinear,
    bouc_wen, a plugin's) takes ``stiffness`` [N/m] > 0, ``yield_force`` [N] > 0 and ``hardening`` in
    [0, 1) besides its own.
    """
    from pounding.elements.storey_springs import make_law
    from pounding.framework.model.registry import HYSTERESIS
    from pounding.hysteresis._values import number, positive

    params = {k: v for k, v in spec.items() if k != "name"}
    cls = HYSTERESIS.get(spec["name"], field=f"{where}.name")
    takes = _own_keys(cls)
    own = {k: v for k, v in params.items() if k in takes or k not in SPRING_KEYS}
    probe = make_law(cls, own, where)
    if probe.own_values() is not None:
        extra = [k for k in params if k not in own]
        if extra:
            raise InputError(f"the {cls.name} law sets the link's {extra[0]} from its own parameters; remove {extra[0]}",
                             field=f"{where}.{extra[0]}")
        return probe, np.asarray(probe.pack(*probe.own_values()), dtype=float)
    for key in ("stiffness", "yield_force"):
        if key not in params:
            raise InputError(f"hysteresis {cls.name!r} on a link needs stiffness [N/m] and yield_force [N]: give "
                             f"{{ name = {cls.name!r}, stiffness = ..., yield_force = ..., hardening = ... }}", field=where)
    k0 = positive(f"{where}.stiffness", params["stiffness"], "the link's initial stiffness [N/m]")
    fy = positive(f"{where}.yield_force", params["yield_force"], "the link's yield force [N]")
    b = number(f"{where}.hardening", params.get("hardening", 0.0))
    if not 0.0 <= b < 1.0:
        raise InputError(f"expected the post-yield / initial stiffness ratio in [0, 1), got {b:g}", field=f"{where}.hardening")
    return probe, np.asarray(probe.pack(k0, fy, b), dtype=float)


def _own_keys(cls) -> set:
    """The keyword parameters of the law class's ``__init__`` (its own scene parameters)."""
    import inspect

    return set(inspect.signature(cls.__init__).parameters) - {"self"}


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
