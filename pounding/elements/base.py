"""The planar element plugin contract.

A planar element (a frame, a shear wall, a brace...) is stiff in its own
vertical plane and has no stiffness out of it. It knows nothing of slabs: it
reports

1. ``floors``: the 1-based floor numbers whose lateral displacement it resists,
   counted from the floor it stands on (its base, fixed to that floor: the
   ground unless the framework places it higher, see *Standing on a floor*);
2. ``point`` (2,) and ``direction`` (2,): a point of its plan line and the unit
   vector along it, in global plan coordinates [m];
3. :meth:`lateral_stiffness`: its statically condensed stiffness (n, n) [N/m]
   over the in-plane displacements of those floors along ``direction``;
4. :meth:`plan_segment`: the plan extent (start, end) [m], used to check that
   the element stands on its slabs and to draw it;
5. :meth:`outline`: lines and panels in its own (s along the line, z up from
   its base) coordinates, for drawing;
6. optionally :meth:`point_stiffness`: its local stiffness against a point load
   between two floors (a neighbour's slab striking it), nan where it has none;
7. optionally :meth:`opensees_model`: its OpenSees counterpart, the nodes, materials
   and elements an OpenSees user would build for it, which the OpenSees peer of the
   tests and ``pounding export opensees`` add to their model (:mod:`pounding.peer`);
   without it (the default raises NotImplementedError naming the type) a building
   holding the element cannot be exported. :meth:`opensees_plane` places the nodes of
   a structure in the element's plane.

The framework places it: the displacement along ``direction`` at floor f with
centre of mass c is ``d . (u, v) + phi * ((p - c) x d)`` (phi counter-clockwise,
a x b = a_x b_y - a_y b_x), and ``K += T^T k T``.

Standing on a floor
-------------------
Every element takes ``first_storey`` (1-based, default 1: on the ground) from the
framework, not from its own table: it then spans the building's storeys
``first_storey .. first_storey + n - 1`` and stands on floor ``first_storey - 1``
(an isolated building's superstructure on its base slab). The element sees none
of it: :meth:`build` parses and checks ``first_storey``, hands :meth:`from_table`
the storey heights from its first storey up, and sets ``first_storey`` on the
built element; the framework then maps its floors with :attr:`building_floors`
and places its stiffness with :meth:`placed_stiffness`, where the base floor's
displacement is subtracted from every floor's (the element resists relative
displacements only). ``dataclasses.replace`` of an element returns one on the
ground: use :meth:`replaced`.

To add an element type: subclass :class:`PlanarElement`, set ``name``, give a
JSON ``schema`` for its scene table (validated before :meth:`from_table` is
called), implement the abstract methods, and register the class under the
entry-point group ``pounding.elements``.

The schema is also the element's documentation: the scene reference page
(``docs/scene-reference.md``, ``pounding reference``) is generated from it.
Give every property a ``description`` and, for numbers, ``units`` (a keyword
validators ignore), and an ``examples`` list; a ``description`` of the whole
table; and, at the top level, ``examples``: element tables that stand on the
12 m x 8 m template slab (corners (0, 0) and (12, 8)) and together make it
stable, which ``pounding template --element NAME`` prints.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any, ClassVar, Mapping, Sequence

import numpy as np


class PlanarElement(ABC):
    """Base class of every planar element plugin (see the module docstring)."""

    name: ClassVar[str] = ""
    #: JSON schema of the element's table in the scene (without the "type" key).
    schema: ClassVar[dict[str, Any]] = {"type": "object"}

    floors: tuple[int, ...]
    point: np.ndarray
    direction: np.ndarray
    #: The building's storey (1-based) of the element's lowest storey; set by :meth:`build` (default 1: on the ground).
    first_storey: int = 1
    #: True for a line of storey springs (one spring per storey between its floor and the one below, nothing
    #: else): one such line spanning storey 1 alone, under elements standing on floor 1, is an isolation layer
    #: (:mod:`pounding.framework.model.isolation`: no soft-storey warning, isolator outputs per line).
    spring_line: ClassVar[bool] = False

    @classmethod
    def build(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float], first_storey: Any = 1) -> "PlanarElement":
        """The element of ``table`` standing on floor ``first_storey - 1`` of a building of ``storey_heights``.

        The template the framework calls (the scene loader, :func:`pounding.io.scene.load_scene`):
        checks ``first_storey`` (:func:`check_first_storey`) and, when the table gives ``storeys``, that
        the element ends at or below the building's top; calls :meth:`from_table` with the storey
        heights from ``first_storey`` up (so ``storeys`` omitted means every storey above its base);
        sets ``first_storey`` on the result.

        Parameters
        ----------
        table : mapping
            The element's table, without ``type`` and the framework's keys.
        storey_heights : sequence of float
            The building's storey heights [m], bottom first.
        first_storey : int
            1-based storey of the element's lowest storey.

        Raises
        ------
        pounding.errors.InputError
            With ``field`` set to ``first_storey``, ``storeys`` or the plugin's own key.
        """
        n = len(storey_heights)
        first = check_first_storey(first_storey, n)
        storeys = table.get("storeys")
        if isinstance(storeys, int) and not isinstance(storeys, bool) and first + storeys - 1 > n:
            from pounding.errors import InputError

            raise InputError(f"with first_storey = {first} the element would span storeys {first} to {first + storeys - 1}, "
                             f"but the building has {n}: at most storeys = {n - first + 1}", field="storeys")
        return cls.from_table(table, storey_heights=tuple(storey_heights[first - 1:])).replaced(first_storey=first)

    def replaced(self, **changes: Any) -> "PlanarElement":
        """A copy with ``changes``: dataclass fields (``dataclasses.replace``, for dataclass elements) and
        ``first_storey``, which the copy keeps unless changed. The element itself is not modified."""
        import copy
        from dataclasses import is_dataclass, replace

        first = changes.pop("first_storey", self.first_storey)
        if is_dataclass(self):
            out = replace(self, **changes)
        elif changes:
            raise TypeError(f"element type {self.name!r} is not a dataclass: only first_storey can be replaced")
        else:
            out = copy.copy(self)
        object.__setattr__(out, "first_storey", int(first))  # frozen dataclasses too: set once, on a new copy
        return out

    @property
    def base_floor(self) -> int:
        """The building's floor the element stands on (0: the ground)."""
        return self.first_storey - 1

    @property
    def building_floors(self) -> tuple[int, ...]:
        """``floors`` in the building's numbering (1-based): each shifted by :attr:`base_floor`."""
        return tuple(self.base_floor + int(f) for f in self.floors)

    def placed_stiffness(self) -> tuple[tuple[int, ...], np.ndarray]:
        """(building floors, stiffness [N/m] (m, m)) over which the framework places the element.

        On the ground: :attr:`building_floors` and :meth:`lateral_stiffness`. Standing on floor b > 0:
        the element resists its floors' displacements relative to floor b, d = u_f - u_b, so with
        E = [-1 | I] ((n, n + 1), columns (b, floors)) its stiffness is E^T k E over (b, floors): a
        rigid translation of the element with its base floor (E 1 = 0) costs nothing.
        """
        k = np.asarray(self.lateral_stiffness(), dtype=float)
        if self.base_floor == 0:
            return self.building_floors, k
        n = k.shape[0]
        E = np.hstack([-np.ones((n, 1)), np.eye(n)])
        return (self.base_floor, *self.building_floors), E.T @ k @ E

    def base_elevation(self, storey_heights: Sequence[float]) -> float:
        """Height [m] above the ground of the floor the element stands on, in a building of ``storey_heights``
        [m]: what lifts its :meth:`outline` (drawn from its base) to the building's."""
        return float(np.sum(storey_heights[: self.base_floor]))

    def building_point_stiffness(self, storey: int, a: float, normal: np.ndarray) -> float:
        """:meth:`point_stiffness` at the building's (0-based) ``storey``: nan below the element's first storey."""
        own = int(storey) - self.base_floor
        return self.point_stiffness(own, a, normal) if own >= 0 else float("nan")

    def storey_floors(self) -> list[tuple[int, int]]:
        """(floor below, floor above) in the building's numbering (0: the ground) of each of the element's
        own storeys 1..len(floors), bottom first: the two floors a storey spring acts between."""
        return [(self.base_floor + f - 1, self.base_floor + f) for f in range(1, len(self.floors) + 1)]

    @classmethod
    @abstractmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "PlanarElement":
        """Build the element from its (schema-validated) scene table.

        Parameters
        ----------
        table : mapping
            The ``[[building.element]]`` table, without ``type``.
        storey_heights : sequence of float
            Heights [m] of the building's storeys from the element's first storey up, bottom first
            (all of them for an element on the ground; :meth:`build` slices them).

        Raises
        ------
        pounding.errors.InputError
            With ``field`` set to the offending key.
        """

    @abstractmethod
    def lateral_stiffness(self) -> np.ndarray:
        """Condensed lateral stiffness over ``floors`` [N/m], shape (n, n), symmetric."""

    @abstractmethod
    def plan_segment(self) -> tuple[np.ndarray, np.ndarray]:
        """Plan extent (start, end), each shape (2,) [m]."""

    def to_table(self) -> dict[str, Any]:
        """The element's scene table (without ``type``): :meth:`from_table` of it, with the building's storey
        heights, gives this element back (plan directions to rounding). Used to write a scene
        (:func:`pounding.io.scene_writer.write_scene`); an element type without it cannot be written."""
        raise NotImplementedError(f"element type {self.name!r} cannot be written to a scene file (it has no to_table)")

    def outline(self) -> dict[str, list[tuple[float, float, float, float]]]:
        """Drawing in the element plane: ``{"lines": [(s0, z0, s1, z1)], "panels": [(s0, s1, z0, z1)]}``.

        s is measured from ``point`` along ``direction`` [m], z from the ground [m].
        """
        return {"lines": [], "panels": []}

    def point_stiffness(self, storey: int, a: float, normal: np.ndarray) -> float:
        """Stiffness [N/m] against a point load along the plan unit ``normal`` (2,) at a [m] above the
        bottom of its (0-based) ``storey``, relative to the floors at its ends: what a slab of a
        neighbour striking it between floors meets (:mod:`pounding.framework.model.facade`).
        nan (the default): no local stiffness known, the struck point is as stiff as a slab edge."""
        return float("nan")

    def opensees_model(self, ops, place) -> list[int]:
        """Add the element to an OpenSees model (3-D, ``ndm 3, ndf 6``, SI units); return the tags of the
        elements it added.

        ``ops`` takes OpenSees' commands (``openseespy.opensees``, or a recorder that writes them
        as a script). ``place`` is the peer's placement of this building
        (:class:`pounding.peer.opensees.Placement`): ``place.tag()`` the next free tag (nodes,
        elements, materials and transformations share it), ``place.node(x, y, z)`` a new node
        [m], ``place.stand_on(tag, floor)`` a base node on the floor the element stands on
        (:attr:`base_floor`; 0 the ground), ``place.on_floor(tag, floor)`` a node that moves with
        a floor (1-based, the building's numbering: :attr:`building_floors`) through its rigid
        diaphragm; ``place.storey_heights`` [m], ``place.out_of_plane`` (the fraction [-] of a
        member's in-plane inertia to give it out of plane: a planar element has no out-of-plane
        stiffness, OpenSees needs some) and ``place.boucwen_tol`` (for
        :meth:`pounding.hysteresis.base.HysteresisLaw.opensees_material`); ``place.building`` is the
        building's name. The peer adds the floors' master nodes, masses and diaphragms afterwards.

        The returned elements get the building's stiffness-proportional Rayleigh damping. An
        element that :attr:`yields` returns exactly its storey springs, one per storey, bottom
        first: the peers read their forces in that order
        (:func:`pounding.framework.engine.inelastic.spring_set`'s).

        The default raises NotImplementedError: no OpenSees model for this element type.
        """
        raise NotImplementedError(
            f"building {place.building!r}: no OpenSees model for element type {self.name or type(self).__name__!r} "
            "(an element type gives one with PlanarElement.opensees_model; frame, shear_wall and storey_springs do)"
        )

    def opensees_plane(self, ops, place, positions: Sequence[float], heights: Sequence[float]) -> tuple[int, list[list[int]]]:
        """The nodes of a structure in the element's plane, for :meth:`opensees_model`.

        A ``geomTransf Linear`` whose vecxz is the plane's horizontal normal (for a column, local
        x up, local y = +-direction; for a beam, local x = direction, local y vertical: bending
        about local z, ``Iz``, is in the plane in both cases and ``Iy`` out of it), then a node at
        every position s [m] along the line from ``point`` and at every level of the element
        (its base, then the top of each of its storeys of ``heights`` [m], bottom first), level
        by level: the base nodes stand on :attr:`base_floor` (``place.stand_on``), the others
        move with their floors (``place.on_floor``).

        Returns
        -------
        (transformation tag, grid) : grid[level][j] the node of level ``level`` (0: the base) at
        ``positions[j]``.
        """
        p = np.asarray(self.point, dtype=float)
        d = np.asarray(self.direction, dtype=float)
        d = d / np.hypot(*d)
        n_hat = (-d[1], d[0], 0.0)  # horizontal normal of the element plane
        z = self.base_elevation(place.storey_heights) + np.concatenate([[0.0], np.cumsum(heights)])
        transf = place.tag()
        ops.geomTransf("Linear", transf, *n_hat)
        floors = self.building_floors
        grid = []
        for level, zl in enumerate(z):
            row = []
            for s in positions:
                x, y = p + s * d
                tag = place.node(x, y, zl)
                if level == 0:
                    place.stand_on(tag, self.base_floor)
                else:
                    place.on_floor(tag, floors[level - 1])
                row.append(tag)
            grid.append(row)
        return transf, grid

    @property
    def yields(self) -> bool:
        """True when the element is a line of yielding storey springs, one per floor of ``floors``,
        each between its floor and the one below along ``direction`` at ``point``: the engine then
        steps it with its hysteresis law (:func:`pounding.framework.engine.inelastic.spring_set`)
        and reads ``law`` (a hysteresis law instance), ``heights`` (the storeys' heights [m]) and
        ``spring_parameters()`` ((len(floors), n_params) the law's parameters per storey).
        False (the default): the element is linear, its ``lateral_stiffness()`` is all it gives."""
        return False


def check_first_storey(value: Any, n_storeys: int) -> int:
    """``value`` as the first storey of an element in a building of ``n_storeys`` storeys: an int in
    1..n_storeys (a float, even 2.0, or a bool is refused). InputError with ``field = "first_storey"``."""
    from pounding.errors import InputError

    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"expected a whole storey number (1 = on the ground), got {value!r}", field="first_storey")
    if not 1 <= int(value) <= n_storeys:
        raise InputError(f"expected a storey from 1 (on the ground) to {n_storeys} (the building has {n_storeys}), "
                         f"got {int(value)}", field="first_storey")
    return int(value)


def point_compliance(E: float, I: float, L: float, a: float, GAs: float = np.inf) -> float:
    """Deflection per unit load [m/N] under a point load at a [m] from the bottom of a fixed-fixed
    member of length L [m]: a^3 b^3 / (3 E I L^3) + a b / (G A_s L), b = L - a."""
    b = L - a
    return a**3 * b**3 / (3.0 * E * I * L**3) + (a * b / (GAs * L) if np.isfinite(GAs) else 0.0)


def line_table(point: np.ndarray, direction: np.ndarray) -> dict[str, Any]:
    """``start`` and ``angle`` [deg] of an element line (the inverse of ``frame.line_from_table``)."""
    return {"start": [float(point[0]), float(point[1])], "angle": float(np.degrees(np.arctan2(direction[1], direction[0])))}


def section_properties(sec: Mapping[str, float]) -> tuple[float, float, float]:
    """(E [Pa], A [m^2], I [m^4]) of a section given as {E, A, I} or rectangular {E, b, h}.

    For a rectangle h is the depth in the element's plane and b the width out
    of it, so A = b h and I = b h^3 / 12.
    """
    if "b" in sec:
        b, h = float(sec["b"]), float(sec["h"])
        return float(sec["E"]), b * h, b * h**3 / 12.0
    return float(sec["E"]), float(sec["A"]), float(sec["I"])


_SECTION_KEYS = {
    "E": ("Young's modulus", "Pa", 30e9),
    "A": ("cross-section area", "m2", 0.16),
    "I": ("second moment of area for bending in the element's plane", "m4", 2.13e-3),
    "b": ("width of a rectangular section, out of the element's plane", "m", 0.4),
    "h": ("depth of a rectangular section, in the element's plane", "m", 0.4),
}


def _section(keys: tuple[str, ...]) -> dict[str, Any]:
    return {
        "type": "object",
        "required": list(keys),
        "additionalProperties": False,
        "properties": {
            k: {"type": "number", "exclusiveMinimum": 0, "description": _SECTION_KEYS[k][0].capitalize() + ".", "units": _SECTION_KEYS[k][1], "examples": [_SECTION_KEYS[k][2]]}
            for k in keys
        },
    }


#: A beam-column section: { E, A, I }, or a rectangle { E, b, h } (A = b h, I = b h^3 / 12).
SECTION_SCHEMA: dict[str, Any] = {"oneOf": [_section(("E", "A", "I")), _section(("E", "b", "h"))]}

POINT_SCHEMA: dict[str, Any] = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2, "units": "m"}


def documented(schema: dict[str, Any], description: str, example: Any = None, **extra: Any) -> dict[str, Any]:
    """A copy of ``schema`` with its documentation keywords (read by the scene reference page)."""
    out = {**schema, "description": description, **extra}
    if example is not None:
        out["examples"] = [example]
    return out


def per_storey(value: Any, n: int, field: str) -> list[Any]:
    """One value for all n storeys, or a list of n values (InputError otherwise)."""
    from pounding.errors import InputError

    if isinstance(value, list):
        if len(value) != n:
            raise InputError(f"expected one value for all storeys or a list of {n}, got a list of {len(value)}", field=field)
        return list(value)
    return [value] * n
