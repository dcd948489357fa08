"""Planar moment-resisting frame, condensed to its floors' lateral stiffness.

A real beam-column model: Euler-Bernoulli elements with axial and bending
stiffness, columns fixed at the base, every joint of a floor sharing that
floor's lateral displacement (the slab is rigid in its plane, so beams do not
change length). All vertical displacements and rotations are condensed out
statically:

    K_lat = K_ll - K_lo K_oo^{-1} K_ol

Reference: Chopra, *Dynamics of Structures*, sec. 9.3 (static condensation);
Przemieniecki, *Theory of Matrix Structural Analysis* (beam-column stiffness).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Mapping, Sequence

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from pounding.elements.base import POINT_SCHEMA, SECTION_SCHEMA, PlanarElement, documented, per_storey, point_compliance, section_properties
from pounding.errors import InputError


#: Poisson's ratio of the shear modulus G = E / (2 (1 + nu)) the frame's members get in OpenSees
#: (:meth:`Frame.opensees_model`). G only multiplies the (negligible) torsional constant, so its
#: value does not affect the in-plane response.
OPENSEES_NU = 0.2


def beam_column_stiffness(E: float, A: float, I: float, x0, x1) -> np.ndarray:
    """Global 6x6 stiffness of a 2-D beam-column from point x0 to x1 [m].

    DOFs per end (s, z, theta): along the frame line, vertical, rotation.
    """
    dx, dz = x1[0] - x0[0], x1[1] - x0[1]
    L = float(np.hypot(dx, dz))
    c, s = dx / L, dz / L
    ea, ei = E * A / L, E * I / L**3
    k = np.array(
        [
            [ea, 0, 0, -ea, 0, 0],
            [0, 12 * ei, 6 * ei * L, 0, -12 * ei, 6 * ei * L],
            [0, 6 * ei * L, 4 * ei * L**2, 0, -6 * ei * L, 2 * ei * L**2],
            [-ea, 0, 0, ea, 0, 0],
            [0, -12 * ei, -6 * ei * L, 0, 12 * ei, -6 * ei * L],
            [0, 6 * ei * L, 2 * ei * L**2, 0, -6 * ei * L, 4 * ei * L**2],
        ]
    )
    r = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1.0]])
    T = np.zeros((6, 6))
    T[:3, :3] = r
    T[3:, 3:] = r
    return T.T @ k @ T


def condense(K: np.ndarray, keep: int) -> np.ndarray:
    """Static condensation onto the first ``keep`` DOFs.

    With K partitioned as [[K_ll, K_lo], [K_ol, K_oo]] (l = kept), returns
    K_ll - K_lo K_oo^{-1} K_ol, solving with a Cholesky factorisation of K_oo
    (symmetric positive definite for a stable structure). Mutates nothing.

    >>> condense(np.array([[2.0, -1.0], [-1.0, 1.0]]), 1)
    array([[1.]])
    """
    if keep == K.shape[0]:
        return K.copy()
    Kll, Klo, Koo = K[:keep, :keep], K[:keep, keep:], K[keep:, keep:]
    factor = cho_factor(Koo)
    Kc = Kll - Klo @ cho_solve(factor, Klo.T)
    return 0.5 * (Kc + Kc.T)


@dataclass(frozen=True, eq=False)
class Frame(PlanarElement):
    """Moment frame: columns at positions along a plan line, beams at every floor.

    Attributes
    ----------
    point, direction : ndarray (2,)
        Start of the frame line and its unit direction [m].
    columns : tuple of float
        Column positions along the line, from ``point`` [m].
    heights : tuple of float
        Storey heights spanned, bottom first [m].
    column_sections, beam_sections : tuple of (E, A, I)
        One per storey [Pa, m^2, m^4]; the beam of storey i is at its top floor.
    """

    name: ClassVar[str] = "frame"
    schema: ClassVar[dict[str, Any]] = {
        "type": "object",
        "required": ["start", "columns", "column"],
        "additionalProperties": False,
        "description": "Planar moment frame: columns fixed at the base, a beam at every floor, condensed to its floors' lateral stiffness.",
        "properties": {
            "start": documented(POINT_SCHEMA, "Start of the frame line in plan [x, y]; `columns` are measured from it.", [0.0, 0.0]),
            "end": documented(POINT_SCHEMA, "A second point of the frame line (its direction); or `angle`.", [12.0, 0.0]),
            "angle": {"type": "number", "units": "deg", "description": "Direction of the frame line, counter-clockwise from x; or `end`.", "examples": [90.0]},
            "columns": {
                "type": "array", "items": {"type": "number"}, "minItems": 1, "units": "m",
                "description": "Column positions along the line from `start`, strictly increasing.", "examples": [[0.0, 6.0, 12.0]],
            },
            "column": documented(
                {"oneOf": [SECTION_SCHEMA, {"type": "array", "items": SECTION_SCHEMA, "minItems": 1}]},
                "Column section, { E, A, I } or rectangular { E, b, h }: one for all storeys or a list of one per storey.",
                {"E": 30e9, "b": 0.4, "h": 0.4},
            ),
            "beam": documented(
                {"oneOf": [SECTION_SCHEMA, {"type": "array", "items": SECTION_SCHEMA, "minItems": 1}]},
                "Beam section (as `column`); needed with more than one column. The beam of storey i is at its top floor.",
                {"E": 30e9, "b": 0.3, "h": 0.5},
            ),
            "storeys": {
                "type": "integer", "minimum": 1, "units": "-",
                "description": "Number of storeys the frame spans from its first storey (default: all above it).", "examples": [3],
            },
        },
        "oneOf": [{"required": ["angle"], "not": {"required": ["end"]}}, {"required": ["end"], "not": {"required": ["angle"]}}],
        # On the template slab (12 m x 8 m, corners (0, 0) and (12, 8)): two frames along x, two along y.
        "examples": [
            {"start": [0.0, 0.0], "angle": 0.0, "columns": [0.0, 6.0, 12.0], "column": {"E": 30e9, "b": 0.45, "h": 0.45}, "beam": {"E": 30e9, "b": 0.3, "h": 0.55}},
            {"start": [0.0, 8.0], "angle": 0.0, "columns": [0.0, 6.0, 12.0], "column": {"E": 30e9, "b": 0.4, "h": 0.4}, "beam": {"E": 30e9, "b": 0.3, "h": 0.5}},
            {"start": [0.0, 0.0], "angle": 90.0, "columns": [0.0, 8.0], "column": {"E": 30e9, "b": 0.4, "h": 0.4}, "beam": {"E": 30e9, "b": 0.3, "h": 0.5}},
            {"start": [12.0, 0.0], "angle": 90.0, "columns": [0.0, 8.0], "column": {"E": 30e9, "b": 0.4, "h": 0.4}, "beam": {"E": 30e9, "b": 0.3, "h": 0.5}},
        ],
    }

    point: np.ndarray
    direction: np.ndarray
    columns: tuple[float, ...]
    heights: tuple[float, ...]
    column_sections: tuple[tuple[float, float, float], ...]
    beam_sections: tuple[tuple[float, float, float], ...]

    @property
    def floors(self) -> tuple[int, ...]:
        return tuple(range(1, len(self.heights) + 1))

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, storey_heights: Sequence[float]) -> "Frame":
        point, direction = line_from_table(table)
        n = _spanned_storeys(table, storey_heights)
        cols = [float(c) for c in table["columns"]]
        if any(b <= a for a, b in zip(cols, cols[1:])):
            raise InputError("column positions must be strictly increasing [m along the frame line]", field="columns")
        if "end" in table:
            length = float(np.hypot(*(np.asarray(table["end"], float) - point)))
            if cols[0] < -1e-9 or cols[-1] > length + 1e-9:
                raise InputError(f"column positions must lie between 0 and the frame length {length:g} m", field="columns")
        if len(cols) > 1 and "beam" not in table:
            raise InputError("a frame with more than one column needs a beam section", field="beam")
        csec = [section_properties(s) for s in per_storey(table["column"], n, "column")]
        bsec = [section_properties(s) for s in per_storey(table["beam"], n, "beam")] if "beam" in table else [(0.0, 0.0, 0.0)] * n
        return cls(point, direction, tuple(cols), tuple(float(h) for h in storey_heights[:n]), tuple(csec), tuple(bsec))

    def plan_segment(self) -> tuple[np.ndarray, np.ndarray]:
        return self.point + self.columns[0] * self.direction, self.point + self.columns[-1] * self.direction

    def to_table(self) -> dict[str, Any]:
        from pounding.elements.base import line_table

        def sections(per_storey):  # one table for all storeys when they agree, as a scene is usually written
            tables = [{"E": E, "A": A, "I": I} for E, A, I in per_storey]
            return tables[0] if all(t == tables[0] for t in tables) else tables

        table = {**line_table(self.point, self.direction), "columns": list(self.columns), "storeys": len(self.heights),
                 "column": sections(self.column_sections)}
        if len(self.columns) > 1:
            table["beam"] = sections(self.beam_sections)
        return table

    def outline(self) -> dict[str, list[tuple[float, float, float, float]]]:
        z = np.concatenate([[0.0], np.cumsum(self.heights)])
        lines = [(s, z[i], s, z[i + 1]) for i in range(len(self.heights)) for s in self.columns]
        lines += [(a, z[i + 1], b, z[i + 1]) for i in range(len(self.heights)) for a, b in zip(self.columns, self.columns[1:])]
        return {"lines": lines, "panels": []}

    def point_stiffness(self, storey: int, a: float, normal: np.ndarray) -> float:
        """The column of the storey nearest the contact point, fixed-fixed (a slab edge meeting the
        frame face to face is two contact points, each on its nearest column): a load along the frame
        line bends it in the frame's plane (I of the section), one across it out of the plane (I of the
        rectangle with the section's A and I: h = sqrt(12 I / A), b = A / h, I_out = h b^3 / 12); an
        oblique load has the compliance cos^2 c_in + sin^2 c_out (see the base class for the rest)."""
        if storey >= len(self.heights):
            return float("nan")
        c2 = float(np.dot(normal, self.direction)) ** 2  # cos^2 of the load to the frame's line
        L = self.heights[storey]
        E, A, I = self.column_sections[storey]
        h = np.sqrt(12.0 * I / A)
        I_out = h * (A / h) ** 3 / 12.0
        return 1.0 / (c2 * point_compliance(E, I, L, a) + (1.0 - c2) * point_compliance(E, I_out, L, a))

    def opensees_model(self, ops, place) -> list[int]:
        """The frame as an OpenSees user builds it (see the base class for ``ops`` and ``place``): a planar
        frame, a node at every column line and floor (:meth:`opensees_plane`), ``elasticBeamColumn``
        columns (storey by storey) and beams (at each storey's top floor) with the sections' (E, A, I)
        for bending in the frame's plane (``Iz``), ``Iy = J = place.out_of_plane * I`` out of it and
        G = E / (2 (1 + :data:`OPENSEES_NU`)). Frames that cross in plan keep their own nodes.
        Returns the members' tags, storey by storey (columns, then beams)."""
        eps = place.out_of_plane
        transf, grid = self.opensees_plane(ops, place, list(self.columns), self.heights)
        members = []
        for i in range(len(self.heights)):
            E, A, I = self.column_sections[i]
            G = E / (2.0 * (1.0 + OPENSEES_NU))
            for j in range(len(self.columns)):
                tag = place.tag()
                ops.element("elasticBeamColumn", tag, grid[i][j], grid[i + 1][j], A, E, G, eps * I, eps * I, I, transf)
                members.append(tag)
            E, A, I = self.beam_sections[i]
            G = E / (2.0 * (1.0 + OPENSEES_NU))
            for j in range(len(self.columns) - 1):
                tag = place.tag()
                ops.element("elasticBeamColumn", tag, grid[i + 1][j], grid[i + 1][j + 1], A, E, G, eps * I, eps * I, I, transf)
                members.append(tag)
        return members

    def lateral_stiffness(self) -> np.ndarray:
        ns, nc = len(self.heights), len(self.columns)
        z = np.concatenate([[0.0], np.cumsum(self.heights)])

        # Global DOF numbering: the ns floor displacements first (kept), then
        # (vertical, rotation) of every joint above the base (condensed out).
        def dofs(j: int, level: int) -> list[int]:
            if level == 0:
                return [-1, -1, -1]  # fixed base
            base = ns + 2 * ((level - 1) * nc + j)
            return [level - 1, base, base + 1]

        ndof = ns + 2 * ns * nc
        K = np.zeros((ndof, ndof))

        def add(ke, d):
            idx = np.array(d)
            live = idx >= 0
            # np.add.at accumulates repeated indices: both ends of a beam share the floor DOF.
            np.add.at(K, np.ix_(idx[live], idx[live]), ke[np.ix_(live, live)])

        for i in range(ns):
            E, A, I = self.column_sections[i]
            for j, s in enumerate(self.columns):
                add(beam_column_stiffness(E, A, I, (s, z[i]), (s, z[i + 1])), dofs(j, i) + dofs(j, i + 1))
            E, A, I = self.beam_sections[i]
            for j in range(nc - 1):
                ke = beam_column_stiffness(E, A, I, (self.columns[j], z[i + 1]), (self.columns[j + 1], z[i + 1]))
                add(ke, dofs(j, i + 1) + dofs(j + 1, i + 1))
        return condense(K, ns)


def line_from_table(table: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """(point, unit direction) of an element line given by start + angle [deg] or start + end."""
    start = np.asarray(table["start"], dtype=float)
    if "end" in table:
        vec = np.asarray(table["end"], dtype=float) - start
        length = float(np.hypot(*vec))
        if length <= 1e-9:
            raise InputError("end must differ from start", field="end")
        return start, vec / length
    a = np.deg2rad(float(table["angle"]))
    return start, np.array([np.cos(a), np.sin(a)])


def _spanned_storeys(table: Mapping[str, Any], storey_heights: Sequence[float]) -> int:
    n = int(table.get("storeys", len(storey_heights)))
    if n > len(storey_heights):
        raise InputError(f"the element spans {n} storeys but the building has {len(storey_heights)}", field="storeys")
    return n
