"""Storey springs: one uniaxial spring per storey along a plan line, elastic or yielding.

Storey f's spring resists the relative displacement along the line between
floor f and floor f - 1 (the ground below floor 1) at the line's position, so
eccentric yielding couples translation and torsion. Its initial stiffnesses
k_f [N/m] give the tridiagonal lateral stiffness over the floors,

    K[f, f] = k_f + k_{f+1},    K[f, f+1] = K[f+1, f] = -k_{f+1}    (k_{n+1} = 0),

so elastic assembly, modal analysis and plan placement treat it like any other
element. With ``yield_force`` each spring follows a hysteresis law (a plugin
of the ``pounding.hysteresis`` family, :mod:`pounding.hysteresis.base`) and the
nonlinear stepping of :mod:`pounding.framework.engine.inelastic` applies; without it
the springs are elastic.

Scene table::

    [[building.element]]
    type = "storey_springs"
    start = [0.0, 0.0]                   # plan line [m]
    end = [15.0, 0.0]
    stiffness = [6.0e7, 5.0e7, 4.0e7]    # initial storey stiffness [N/m]: one value or one per storey, bottom first
    yield_force = [9.0e5, 7.5e5, 6.0e5]  # storey yield shear [N]: one value or one per storey; omitted = elastic
    hardening = 0.02                     # post-yield / initial stiffness, in [0, 1)
    hysteresis = "bilinear"              # or {name = "bouc_wen", n = 2, beta = 0.5, gamma = 0.5}

A law that sets the springs' k0, Fy and b from its own parameters (``own_values``: the
``friction_pendulum`` isolator, from its weight, radius, friction and yield displacement; the
dampers and linear links ``viscous``, ``maxwell``, ``kelvin``, ``elastic``) takes the place of
``stiffness``, ``yield_force`` and ``hardening``, which the table then omits::

    [[building.element]]
    type = "storey_springs"
    start = [0.0, 0.0]
    end = [12.0, 0.0]
    storeys = 1
    hysteresis = {name = "friction_pendulum", weight = 3.0e6, radius = 2.0, friction = 0.06}

Supplemental dampers in every storey, beside the element that is the storey's frame::

    [[building.element]]
    type = "storey_springs"
    start = [0.0, 5.0]
    end = [15.0, 5.0]
    hysteresis = {name = "viscous", coefficient = 2.0e6, exponent = 0.5}
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Mapping, Sequence

import numpy as np

from pounding.elements.base import POINT_SCHEMA, PlanarElement, documented
from pounding.elements.frame import _spanned_storeys, line_from_table
from pounding.errors import InputError
from pounding.framework.model.law_tables import make_law

_PER_STOREY = {"oneOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}, "minItems": 1}]}


def _per_storey_positive(table: Mapping[str, Any], key: str, n: int, what: str) -> tuple[float, ...]:
    """One positive value for all n storeys, or a list of n positive values (InputError naming the item)."""
    value = table[key]
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(f"expected one value or a list of {n} (one per storey, bottom first), got a list of {len(value)}", field=key)
        items = [(f"{key}[{i}]", v) for i, v in enumerate(value)]
    else:
        items = [(key, value)] * n
    out = []
    for field, v in items:
        if not float(v) > 0.0:
            raise InputError(f"{what} must be > 0, got {v!r}", field=field)
        out.append(float(v))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class StoreySprings(PlanarElement):
    """One spring per storey along a plan line (see the module docstring).

    Attributes
    ----------
    point, direction : ndarray (2,)
        Start of the line and its unit direction [m].
    length : float
        Plan length of the line [m] (for drawing and the on-slab check).
    heights : tuple of float
        Storey heights spanned, bottom first [m].
    stiffness : tuple of float
        Initial stiffness of every storey spring [N/m].
    yield_force : tuple of float or None
        Yield shear of every storey spring [N]; None for elastic springs.
    hardening : float
        Post-yield over initial stiffness [-], in [0, 1).
    law : HysteresisLaw or None
        The hysteresis law (None for elastic springs).
    """

    name: ClassVar[str] = "storey_springs"
    spring_line: ClassVar[bool] = True
    schema: ClassVar[dict[str, Any]] = {
        "type": "object",
        "required": ["start", "end"],  # and stiffness, unless the law sets it (from_table)
        "additionalProperties": False,
        "description": "Storey springs along a plan line: storey f's spring resists the relative displacement "
        "between floor f and floor f-1 (the ground below floor 1) along the line; elastic, or yielding by a "
        "hysteresis law (see *Yielding storeys* in docs/modelling.md).",
        "properties": {
            "start": documented(POINT_SCHEMA, "One end of the springs' plan line [x, y].", [0.0, 0.0]),
            "end": documented(POINT_SCHEMA, "The other end; the springs act along the line from start to end.", [12.0, 0.0]),
            "stiffness": documented(_PER_STOREY, "Initial storey stiffness: one value, or one per storey, bottom first. "
                                    "Required, unless the hysteresis law sets it (`friction_pendulum`, the dampers and links).",
                                    [6.0e7, 5.0e7, 4.0e7], units="N/m"),
            "yield_force": documented(_PER_STOREY, "Storey yield shear: one value or one per storey; omitted = elastic.",
                                      [9.0e5, 7.5e5, 6.0e5], units="N"),
            "hardening": {"type": "number", "units": "-", "default": 0.0, "examples": [0.02],
                          "description": "Post-yield over initial stiffness ratio, at least 0 and below 1."},
            "hysteresis": {"oneOf": [{"type": "string"}, {"type": "object", "required": ["name"]}], "default": "bilinear",
                           "examples": ["bilinear", {"name": "bouc_wen", "n": 2.0}],
                           "description": "Hysteresis law: a name (`bilinear`, `bouc_wen`, or a plugin's), or a table "
                           "`{ name = ..., parameter = ... }` with the law's parameters; `friction_pendulum` (weight, "
                           "radius, friction), the dampers `viscous`, `maxwell`, `kelvin` (coefficient, exponent, "
                           "stiffness) and `elastic` (stiffness) set stiffness, yield_force and hardening themselves."},
            "storeys": {"type": "integer", "minimum": 1, "units": "-", "examples": [3],
                        "description": "Number of storeys the springs span from their first storey (default: all above it; "
                        "`storeys = 1` with `first_storey = 1`: an isolation layer when the rest stands on floor 1)."},
        },
        # On the template slab (12 m x 8 m, corners (0, 0) and (12, 8)): a yielding line along each edge, so
        # that the building resists x, y and torsion (4e7 N/m a line, yielding at 16 mm, 0.5 % of a 3.2 m storey)
        "examples": [
            {"start": [0.0, 0.0], "end": [12.0, 0.0], "stiffness": 4.0e7, "yield_force": 6.4e5, "hardening": 0.02, "hysteresis": "bilinear"},
            {"start": [0.0, 8.0], "end": [12.0, 8.0], "stiffness": 4.0e7, "yield_force": 6.4e5, "hardening": 0.02},
            {"start": [0.0, 0.0], "end": [0.0, 8.0], "stiffness": 4.0e7, "yield_force": 6.4e5, "hardening": 0.02},
            {"start": [12.0, 0.0], "end": [12.0, 8.0], "stiffness": 4.0e7, "yield_force": 6.4e5, "hardening": 0.02},
        ],
    }

    point: np.ndarray
    direction: np.ndarray
    length: float
    heights: tuple[float, ...]
    stiffness: tuple[float, ...]
    yield_force: tuple[float, ...] | None
    hardening: float
    law: Any

    @property
    def floors(self) -> tuple[int, ...]:
        return tuple(range(1, len(self.heights) + 1))

    @property
    def yields(self) -> bool:
        """True when the springs follow a hysteresis law (``yield_force`` given)."""
        return self.yield_force is not None

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "StoreySprings":
        from pounding.framework.model.registry import HYSTERESIS

        point, direction = line_from_table(table)
        length = float(np.hypot(*(np.asarray(table["end"], float) - point)))
        n = _spanned_storeys(table, storey_heights)
        heights = tuple(float(h) for h in storey_heights[:n])
        law = _law_setting_its_values(table)
        if law is not None:  # an isolator law: k0, Fy and b follow from its own parameters
            k0, fy, b = law.own_values()
            return cls(point, direction, length, heights, (k0,) * n, (fy,) * n, b, law)
        if "stiffness" not in table:
            raise InputError("missing the initial storey stiffness [N/m] (one value or one per storey)", field="stiffness")
        k = _per_storey_positive(table, "stiffness", n, "the initial storey stiffness [N/m]")
        hardening = table.get("hardening", 0.0)
        if not (isinstance(hardening, (int, float)) and math.isfinite(hardening) and 0.0 <= hardening < 1.0):
            raise InputError(f"expected the post-yield / initial stiffness ratio in [0, 1), got {hardening!r}", field="hardening")
        spec = table.get("hysteresis", "bilinear")
        if "yield_force" not in table:
            if "hysteresis" in table or "hardening" in table:
                key = "hysteresis" if "hysteresis" in table else "hardening"
                raise InputError("elastic springs (no yield_force) take no hysteresis or hardening; give yield_force [N] to make them yield", field=key)
            return cls(point, direction, length, tuple(float(h) for h in storey_heights[:n]), k, None, 0.0, None)
        fy = _per_storey_positive(table, "yield_force", n, "the storey yield shear [N]")
        name, params = (spec, {}) if isinstance(spec, str) else (spec["name"], {a: b for a, b in spec.items() if a != "name"})
        law_cls = HYSTERESIS.get(name, field="hysteresis" if isinstance(spec, str) else "hysteresis.name")
        law = make_law(law_cls, params, "hysteresis")
        return cls(point, direction, length, tuple(float(h) for h in storey_heights[:n]), k, fy, float(hardening), law)

    def lateral_stiffness(self) -> np.ndarray:
        k = np.asarray(self.stiffness, dtype=float)
        below = np.append(k[1:], 0.0)  # the spring of the storey above each floor
        K = np.diag(k + below)
        off = -k[1:]
        return K + np.diag(off, 1) + np.diag(off, -1)

    def spring_parameters(self) -> np.ndarray:
        """Parameter vectors of the storey springs, shape (n_storeys, law.n_params) (yielding springs only)."""
        if self.law is None:
            raise ValueError("elastic storey springs have no hysteresis parameters")
        return np.array([self.law.pack(k, f, self.hardening) for k, f in zip(self.stiffness, self.yield_force)])

    def opensees_model(self, ops, place) -> list[int]:
        """The springs as an OpenSees user builds them (see the base class for ``ops`` and ``place``): one
        ``twoNodeLink`` per storey between a node on the line at the floor below and one at the floor
        above (each standing on its floor, ``place.stand_on``: fixed at the ground, else a slave of the
        floor's diaphragm restrained in uz, rx, ry, which nothing else stiffens), acting along the line
        only (``-dir 1 -orient d_x d_y 0 -d_y d_x 0``) with ``-doRayleigh``. Its material: ``Elastic(k0)``
        for elastic springs, else the hysteresis law's
        (:meth:`pounding.hysteresis.base.HysteresisLaw.opensees_material` with the storey's k0, Fy and b).
        Returns the links' tags, bottom first."""
        d = np.asarray(self.direction, dtype=float)
        x, y = (float(c) for c in self.point)
        z = np.concatenate([[0.0], np.cumsum(self.heights)]) + self.base_elevation(place.storey_heights)
        links = []
        for f, floors in enumerate(self.storey_floors()):  # (below, above) in the building's numbering, 0 = the ground
            ends = []
            for level, floor in zip((f, f + 1), floors):
                tag = place.node(x, y, z[level])
                place.stand_on(tag, floor)
                ends.append(tag)
            mat = place.tag()
            k0 = float(self.stiffness[f])
            if self.yields:
                self.law.opensees_material(ops, mat, k0, float(self.yield_force[f]), float(self.hardening),
                                           tags=place.tag, boucwen_tol=place.boucwen_tol)
            else:
                ops.uniaxialMaterial("Elastic", mat, k0)
            tag = place.tag()
            ops.element("twoNodeLink", tag, *ends, "-mat", mat, "-dir", 1,
                        "-orient", float(d[0]), float(d[1]), 0.0, float(-d[1]), float(d[0]), 0.0, "-doRayleigh")
            links.append(tag)
        return links

    def plan_segment(self) -> tuple[np.ndarray, np.ndarray]:
        return self.point, self.point + self.length * self.direction

    def to_table(self) -> dict[str, Any]:
        end = self.point + self.length * self.direction
        table = {"start": [float(c) for c in self.point], "end": [float(c) for c in end], "storeys": len(self.heights),
                 "stiffness": list(self.stiffness)}
        if self.law is not None and self.law.own_values() is not None:  # the law's parameters give the rest
            del table["stiffness"]
            table["hysteresis"] = self.law.describe()
        elif self.yield_force is not None:
            table.update(yield_force=list(self.yield_force), hardening=self.hardening, hysteresis=self.law.describe())
        return table

    def outline(self) -> dict[str, list[tuple[float, float, float, float]]]:
        z = np.concatenate([[0.0], np.cumsum(self.heights)])
        # a zig-zag per storey: the spring symbol
        lines = []
        for i in range(len(self.heights)):
            s = [0.0, 0.5 * self.length, self.length]
            lines += [(s[0], z[i], s[1], z[i + 1]), (s[1], z[i + 1], s[2], z[i])]
        return {"lines": lines, "panels": []}


def _law_setting_its_values(table: Mapping[str, Any]):
    """The element's law when it sets k0, Fy and b from its own parameters (``own_values``), else None.

    Such a law (an isolator's: weight, radius, friction) leaves the element nothing to give: its
    ``stiffness``, ``yield_force`` or ``hardening`` would say the same thing twice, possibly
    differently, so they are refused (InputError naming the key)."""
    from pounding.framework.model.registry import HYSTERESIS

    spec = table.get("hysteresis")
    if spec is None:
        return None
    name, params = (spec, {}) if isinstance(spec, str) else (spec["name"], {a: b for a, b in spec.items() if a != "name"})
    law = make_law(HYSTERESIS.get(name, field="hysteresis" if isinstance(spec, str) else "hysteresis.name"), params, "hysteresis")
    if law.own_values() is None:
        return None
    for key in ("stiffness", "yield_force", "hardening"):
        if key in table:
            raise InputError(f"the {law.name} law sets the storey's {key} from its own parameters; remove {key}", field=key)
    return law
