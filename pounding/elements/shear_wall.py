"""Planar shear wall: a Timoshenko cantilever fixed at the base.

The flexibility between floors i and j at heights z_i <= z_j (unit loads along
the wall) is the sum of bending and shear parts:

    f_ij = z_i^2 (3 z_j - z_i) / (6 E I) + z_i / (G A_s)

with I = t L^3 / 12 (in-plane), A = t L and the shear area A_s = 5/6 A unless
given. The stiffness over the floors is the inverse of that flexibility.
Reference: Timoshenko & Gere, *Mechanics of Materials*; for the tip:
h^3/(3EI) + h/(G A_s).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Mapping, Sequence

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from pounding.elements.base import POINT_SCHEMA, PlanarElement, documented, point_compliance
from pounding.elements.frame import _spanned_storeys, line_from_table
from pounding.errors import InputError


@dataclass(frozen=True, eq=False)
class ShearWall(PlanarElement):
    """Cantilever wall from ``start`` to ``end`` in plan.

    Attributes
    ----------
    point, direction : ndarray (2,)
        Start of the wall and its unit direction [m].
    length, thickness : float
        Plan length and thickness [m].
    E, G : float
        Young's and shear moduli [Pa].
    shear_area : float
        Effective shear area [m^2].
    heights : tuple of float
        Storey heights spanned [m].
    """

    name: ClassVar[str] = "shear_wall"
    schema: ClassVar[dict[str, Any]] = {
        "type": "object",
        "required": ["start", "end", "thickness", "E"],
        "additionalProperties": False,
        "description": "Planar shear wall: a Timoshenko cantilever (bending and shear) fixed at its base (the ground, or the floor it stands on).",
        "properties": {
            "start": documented(POINT_SCHEMA, "One end of the wall in plan [x, y].", [0.0, 0.0]),
            "end": documented(POINT_SCHEMA, "The other end; the wall's length is the distance between them.", [0.0, 8.0]),
            "thickness": {"type": "number", "exclusiveMinimum": 0, "units": "m", "description": "Wall thickness.", "examples": [0.25]},
            "E": {"type": "number", "exclusiveMinimum": 0, "units": "Pa", "description": "Young's modulus.", "examples": [30e9]},
            "G": {"type": "number", "exclusiveMinimum": 0, "units": "Pa", "description": "Shear modulus; or `nu`.", "examples": [12.5e9]},
            "nu": {
                "type": "number", "exclusiveMinimum": -1, "exclusiveMaximum": 0.5, "units": "-",
                "description": "Poisson's ratio, G = E / (2 (1 + nu)); or `G`.", "examples": [0.2],
            },
            "shear_area": {
                "type": "number", "exclusiveMinimum": 0, "units": "m2",
                "description": "Effective shear area (default: 5/6 of thickness x length).", "examples": [1.5],
            },
            "storeys": {
                "type": "integer", "minimum": 1, "units": "-",
                "description": "Number of storeys the wall spans from its first storey (default: all above it).", "examples": [3],
            },
        },
        "oneOf": [{"required": ["G"], "not": {"required": ["nu"]}}, {"required": ["nu"], "not": {"required": ["G"]}}],
        # On the template slab (12 m x 8 m, corners (0, 0) and (12, 8)): short walls at the four sides.
        "examples": [
            {"start": [0.0, 0.0], "end": [3.0, 0.0], "thickness": 0.2, "E": 30e9, "nu": 0.2},
            {"start": [9.0, 8.0], "end": [12.0, 8.0], "thickness": 0.2, "E": 30e9, "nu": 0.2},
            {"start": [0.0, 5.0], "end": [0.0, 8.0], "thickness": 0.2, "E": 30e9, "nu": 0.2},
            {"start": [12.0, 0.0], "end": [12.0, 3.0], "thickness": 0.2, "E": 30e9, "nu": 0.2},
        ],
    }

    point: np.ndarray
    direction: np.ndarray
    length: float
    thickness: float
    E: float
    G: float
    shear_area: float
    heights: tuple[float, ...]

    @property
    def floors(self) -> tuple[int, ...]:
        return tuple(range(1, len(self.heights) + 1))

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "ShearWall":
        point, direction = line_from_table(table)
        length = float(np.hypot(*(np.asarray(table["end"], float) - point)))
        t, E = float(table["thickness"]), float(table["E"])
        G = float(table["G"]) if "G" in table else E / (2.0 * (1.0 + float(table["nu"])))
        As = float(table.get("shear_area", 5.0 / 6.0 * t * length))
        n = _spanned_storeys(table, storey_heights)
        if length <= 0:
            raise InputError("a wall needs a positive length", field="end")
        return cls(point, direction, length, t, E, G, As, tuple(float(h) for h in storey_heights[:n]))

    @property
    def second_moment(self) -> float:
        """In-plane second moment of area t L^3 / 12 [m^4]."""
        return self.thickness * self.length**3 / 12.0

    def flexibility(self) -> np.ndarray:
        """Flexibility matrix over the floors [m/N], shape (n, n)."""
        z = np.cumsum(self.heights)
        zi, zj = np.minimum.outer(z, z), np.maximum.outer(z, z)
        return zi**2 * (3 * zj - zi) / (6 * self.E * self.second_moment) + zi / (self.G * self.shear_area)

    def lateral_stiffness(self) -> np.ndarray:
        F = self.flexibility()
        K = cho_solve(cho_factor(F), np.eye(len(F)))
        return 0.5 * (K + K.T)

    def point_stiffness(self, storey: int, a: float, normal: np.ndarray) -> float:
        """The wall as one member, fixed-fixed between the floors: bending and shear in its plane
        (I = t l^3 / 12, A_s), bending out of it (I = l t^3 / 12); an oblique load has the compliance
        cos^2 c_in + sin^2 c_out (see the base class for the rest)."""
        if storey >= len(self.heights):
            return float("nan")
        c2 = float(np.dot(normal, self.direction)) ** 2  # cos^2 of the load to the wall's line
        L = self.heights[storey]
        I_in = self.thickness * self.length**3 / 12.0
        I_out = self.length * self.thickness**3 / 12.0
        GAs = self.G * self.shear_area
        return 1.0 / (c2 * point_compliance(self.E, I_in, L, a, GAs) + (1.0 - c2) * point_compliance(self.E, I_out, L, a, GAs))

    def opensees_model(self, ops, place) -> list[int]:
        """The wall as an OpenSees user builds it (see the base class for ``ops`` and ``place``): a chain of
        ``ElasticTimoshenkoBeam`` elements, one per storey, on the wall's centre line (any point of the
        line moves alike in its plane; :meth:`opensees_plane`) with E, G, A = t L, ``Iz`` = t L^3 / 12
        and the shear area in plane, ``Iy = J = place.out_of_plane * Iz`` out of it: the exact Timoshenko
        cantilever that :meth:`flexibility` condenses. Returns the elements' tags, bottom first."""
        eps = place.out_of_plane
        transf, grid = self.opensees_plane(ops, place, [0.5 * self.length], self.heights)
        I = self.second_moment
        A = self.thickness * self.length
        chain = []
        for i in range(len(self.heights)):
            tag = place.tag()
            ops.element("ElasticTimoshenkoBeam", tag, grid[i][0], grid[i + 1][0],
                        self.E, self.G, A, eps * I, eps * I, I, self.shear_area, self.shear_area, transf)
            chain.append(tag)
        return chain

    def plan_segment(self) -> tuple[np.ndarray, np.ndarray]:
        return self.point, self.point + self.length * self.direction

    def to_table(self) -> dict[str, Any]:
        end = self.point + self.length * self.direction
        return {"start": [float(c) for c in self.point], "end": [float(c) for c in end], "thickness": self.thickness,
                "E": self.E, "G": self.G, "shear_area": self.shear_area, "storeys": len(self.heights)}

    def outline(self) -> dict[str, list[tuple[float, float, float, float]]]:
        z = np.concatenate([[0.0], np.cumsum(self.heights)])
        return {"lines": [], "panels": [(0.0, self.length, z[i], z[i + 1]) for i in range(len(self.heights))]}
