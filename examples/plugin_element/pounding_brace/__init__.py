"""A diagonal brace: an axial bar across one storey, in a vertical plane.

Its lower end sits on the floor below (or the ground) and its upper end on
the floor above. For a storey drift delta along the brace's plan direction the
bar lengthens by delta cos(theta) (theta its angle to the horizontal), so the
storey gets a drift spring

    k = E A cos^2(theta) / L,   L = sqrt(b^2 + h^2),  cos(theta) = b / L

with b the plan length. Over the floors (storey - 1, storey) the stiffness is
k [[1, -1], [-1, 1]]; in the first storey only the top floor moves.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Mapping, Sequence

import numpy as np

from pounding.elements.base import POINT_SCHEMA, PlanarElement
from pounding.errors import InputError


@dataclass(frozen=True, eq=False)
class Brace(PlanarElement):
    """Diagonal brace from ``start`` to ``end`` in plan, in storey ``storey`` (1-based)."""

    name: ClassVar[str] = "brace"
    schema: ClassVar[dict[str, Any]] = {
        "type": "object",
        "required": ["start", "end", "storey", "E", "A"],
        "additionalProperties": False,
        "description": "Diagonal bar across one storey, in a vertical plane: a drift spring E A cos^2(theta) / L.",
        # every key documented: the scene reference page (docs/scene-reference.md) is generated from these
        "properties": {
            "start": {**POINT_SCHEMA, "description": "Plan position of the lower end [x, y].", "examples": [[0.0, 0.0]]},
            "end": {**POINT_SCHEMA, "description": "Plan position of the upper end [x, y].", "examples": [[6.0, 0.0]]},
            "storey": {"type": "integer", "minimum": 1, "units": "-", "description": "The storey it braces (1 = ground to first floor).", "examples": [1]},
            "E": {"type": "number", "exclusiveMinimum": 0, "units": "Pa", "description": "Young's modulus of the bar.", "examples": [200e9]},
            "A": {"type": "number", "exclusiveMinimum": 0, "units": "m2", "description": "Cross-section area of the bar.", "examples": [0.002]},
        },
    }

    point: np.ndarray
    direction: np.ndarray
    length: float
    height: float
    storey: int
    E: float
    A: float

    @property
    def floors(self) -> tuple[int, ...]:
        return (self.storey,) if self.storey == 1 else (self.storey - 1, self.storey)

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "Brace":
        start, end = np.asarray(table["start"], float), np.asarray(table["end"], float)
        b = float(np.hypot(*(end - start)))
        if b <= 0:
            raise InputError("end must differ from start", field="end")
        storey = int(table["storey"])
        if storey > len(storey_heights):
            raise InputError(f"storey {storey} does not exist (the building has {len(storey_heights)})", field="storey")
        return cls(start, (end - start) / b, b, float(storey_heights[storey - 1]), storey, float(table["E"]), float(table["A"]))

    def lateral_stiffness(self) -> np.ndarray:
        L = float(np.hypot(self.length, self.height))
        k = self.E * self.A * (self.length / L) ** 2 / L
        if self.storey == 1:
            return np.array([[k]])
        return k * np.array([[1.0, -1.0], [-1.0, 1.0]])

    def plan_segment(self):
        return self.point, self.point + self.length * self.direction
