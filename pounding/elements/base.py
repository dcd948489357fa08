"""The planar element plugin contract.

A planar element (a frame, a shear wall, a brace...) is stiff in its own
vertical plane and has no stiffness out of it. It knows nothing of slabs: it
reports

1. ``floors``: the 1-based floor numbers whose lateral displacement it resists
   (its base is fixed to the ground);
2. ``point`` (2,) and ``direction`` (2,): a point of its plan line and the unit
   vector along it, in global plan coordinates [m];
3. :meth:`lateral_stiffness`: its statically condensed stiffness (n, n) [N/m]
   over the in-plane displacements of those floors along ``direction``;
4. :meth:`plan_segment`: the plan extent (start, end) [m], used to check that
   the element stands on its slabs and to draw it;
5. :meth:`outline`: lines and panels in its own (s along the line, z up)
   coordinates, for drawing;
6. optionally :meth:`point_stiffness`: its local stiffness against a point load
   between two floors (a neighbour's slab striking it), nan where it has none.

The framework places it: the displacement along ``direction`` at floor f with
centre of mass c is ``d . (u, v) + phi * ((p - c) x d)`` (phi counter-clockwise,
a x b = a_x b_y - a_y b_x), and ``K += T^T k T``.

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

    @classmethod
    @abstractmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "PlanarElement":
        """Build the element from its (schema-validated) scene table.

        Parameters
        ----------
        table : mapping
            The ``[[building.element]]`` table, without ``type``.
        storey_heights : sequence of float
            Storey heights of the building [m], bottom first.

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

    @property
    def yields(self) -> bool:
        """True when the element is a line of yielding storey springs, one per floor of ``floors``,
        each between its floor and the one below along ``direction`` at ``point``: the engine then
        steps it with its hysteresis law (:func:`pounding.framework.engine.inelastic.spring_set`)
        and reads ``law`` (a hysteresis law instance), ``heights`` (the storeys' heights [m]) and
        ``spring_parameters()`` ((len(floors), n_params) the law's parameters per storey).
        False (the default): the element is linear, its ``lateral_stiffness()`` is all it gives."""
        return False


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
