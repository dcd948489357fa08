"""Slabs that strike a neighbour between its floors: the neighbour's facade at that height.

When a slab's level lies strictly between two floors of a neighbour (unequal storey
heights), the slab's edge strikes the neighbour's columns and walls there, not a slab. The
neighbour gets a *facade slab* at that height: a virtual slab whose plan motion is the
neighbour's storey deformed shape at that height, written as modal rows like a real slab's,
so that the whole pair machinery (screening bounds, compiled gaps, impulses, held contact,
penalty forces) works on it unchanged.

Shape of the storey
-------------------
A storey of a shear building is columns (and walls) between rigid floors that do not
rotate about horizontal axes: that is the shear-building assumption the lateral stiffness
rests on (every element is condensed to its floors' lateral displacements, joints share the
floor's motion). A prismatic member with both ends translated and no end rotation, and no
load between them, deflects as the cubic Hermite shape of a fixed-fixed member:

    u(eta) = N1(eta) u_below + N2(eta) u_above,   N2 = 3 eta^2 - 2 eta^3,   N1 = 1 - N2,

with eta = (z - z_below) / h the fraction of the storey height. Every column point of the
storey moves so; a plan point's motion at a floor is linear in that floor's (u, v, phi), so
the facade moves rigidly in plan with the blend of the two floors' motions, each first carried
to a common reference point (the upper floor's centre of mass). Below the first floor the
lower "floor" is the ground (no relative motion).

The same shape carries an impulse or force at the facade back to the floors (N1 to the floor
below, N2 to the floor above, each as the force at the contact point with its moment about
that floor's own displaced centre: the contact row of a facade is the floors' rows so weighted,
:func:`pounding.framework.engine.pairs.contact_row`, while ``rows`` here, carried to one reference
point, move the facade's outline for gaps and bounds). The virtual work of the contact is the
same on the facade and on the floors, so the momentum and energy of the impact are those of
the floors (N1 + N2 = 1: the linear momentum given to the struck building equals the impulse;
below the first floor the ground takes the N1 share).
The facade's own mass is not modelled (it is lumped in the floors, as everywhere in a shear
building): the impact sees the effective mass of the floors at that height,
1 / (N1^2 / m_below + N2^2 / m_above) for a head-on central impact on a building moving in
plan only.

Local stiffness
---------------
A rigid impact on a column point is a strong idealisation: the column deflects locally
under the blow. A fixed-fixed member of length L with a point load at a from its bottom
(b = L - a) deflects there, relative to its ends, by

    delta = P a^3 b^3 / (3 E I L^3)     (bending; Roark's table 8.1 case 1e)
          + P a b / (G A_s L)           (shear, walls: Timoshenko)

so k = 1 / (a^3 b^3 / (3 E I L^3) + a b / (G A_s L)) for the struck column or wall
(:func:`local_stiffness`). The penalty law ``facade_penalty``
(:class:`pounding.contact.penalty.FacadePenalty`) puts it in series with the slab-edge
contact spring.

Reference: Karayannis, C. G. and Favvata, M. J. (2005), Earthquake Eng. Struct. Dyn. 34,
1-20 (slab-to-column pounding between buildings with unequal storey heights).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.model.levels import same_level


def hermite(eta: float) -> tuple[float, float]:
    """(N1, N2) of the fixed-fixed storey shape at the fraction eta in [0, 1] of the storey height."""
    n2 = 3.0 * eta**2 - 2.0 * eta**3
    return 1.0 - n2, n2


@dataclass(frozen=True)
class Facade:
    """A facade slab: where a neighbour's slab strikes a building between its floors.

    Attributes
    ----------
    building : int
        The struck building (scene order).
    storey : int
        0-based storey whose columns and walls are struck (between floor ``storey - 1``, or the
        ground, and floor ``storey``).
    height : float
        Elevation of the contact level [m].
    eta : float
        Fraction of the storey height from its bottom, in (0, 1).
    rows : ndarray (3, n_modes)
        Modal rows of the facade's (u, v, phi) about ``centre``.
    vertices : ndarray (k, 2)
        Plan outline: the upper floor's polygon [m].
    centre : ndarray (2,)
        Reference point: the upper floor's centre of mass [m].
    """

    building: int
    storey: int
    height: float
    eta: float
    rows: np.ndarray
    vertices: np.ndarray
    centre: np.ndarray

    @property
    def radius(self) -> float:
        return float(np.max(np.hypot(*(self.vertices - self.centre).T)))

    @property
    def shape(self) -> tuple[float, float]:
        return hermite(self.eta)


def carried_rows(rows: np.ndarray, centre: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Rows (3, n) of a slab's (u, v, phi) about its ``centre`` carried to the plan point
    ``reference`` of the same rigid slab: u_r = u - phi (y_r - y_c), v_r = v + phi (x_r - x_c)."""
    dx, dy = reference - centre
    out = rows.copy()
    out[0] = rows[0] - dy * rows[2]
    out[1] = rows[1] + dx * rows[2]
    return out


def facade(system, building: int, height: float) -> Facade | None:
    """The facade slab of ``system`` (an assembled building) at ``height`` [m], or None when
    the height is at a floor (the same-level rule, :func:`~pounding.framework.model.levels.same_level`),
    at or below the ground or above the roof."""
    levels = np.concatenate([[0.0], [s.elevation for s in system.slabs]])
    if height <= levels[0] or height >= levels[-1] or np.any(same_level(levels, height)):
        return None
    j = int(np.searchsorted(levels, height)) - 1  # storey j spans levels[j] .. levels[j + 1]
    eta = (height - levels[j]) / (levels[j + 1] - levels[j])
    n1, n2 = hermite(eta)
    top = system.slabs[j]
    rows = n2 * carried_rows(system.modes[3 * j : 3 * j + 3, :], top.centre, top.centre)
    if j > 0:
        below = system.slabs[j - 1]
        rows = rows + n1 * carried_rows(system.modes[3 * (j - 1) : 3 * j, :], below.centre, top.centre)
    return Facade(building, j, float(height), float(eta), rows, np.asarray(top.vertices, float), np.asarray(top.centre, float))


# --------------------------------------------------------------------------- the struck element
def struck_element(elements, point: np.ndarray) -> int:
    """Index of the element (scene order) whose plan segment passes nearest the plan ``point``."""
    best, where = np.inf, -1
    for i, e in enumerate(elements):
        p0, p1 = (np.asarray(x, float) for x in e.plan_segment())
        d = p1 - p0
        s = 0.0 if not d.any() else float(np.clip((point - p0) @ d / (d @ d), 0.0, 1.0))
        dist = float(np.hypot(*(point - (p0 + s * d))))
        if dist < best:
            best, where = dist, i
    return where


def struck(building, storey: int, a: float, point: np.ndarray, normal: np.ndarray) -> tuple[int, object, float]:
    """(index, element, local stiffness [N/m]) of the element of ``building`` (a scene
    :class:`~pounding.framework.model.scene.Building`) struck at the plan ``point`` [m] with unit
    ``normal``, a [m] above the bottom of its 0-based ``storey``: the element nearest the point
    (:func:`struck_element`), its :func:`local_stiffness` times its stiffness modifier."""
    elements = building.elements
    i = struck_element(elements, np.asarray(point, float))
    mod = building.modifiers[i] if building.modifiers else 1.0
    return i, elements[i], mod * local_stiffness(elements[i], storey, a, np.asarray(normal, float))


def local_stiffness(element, storey: int, a: float, normal: np.ndarray) -> float:
    """Stiffness [N/m] of ``element`` against a point load along the plan unit ``normal`` at a [m]
    above the bottom of the building's (0-based) ``storey``, relative to its ends (the floors): the element's
    own :meth:`~pounding.elements.base.PlanarElement.point_stiffness` at its own storey there (nan where it
    knows none, and below the storeys it spans: :meth:`~pounding.elements.base.PlanarElement.building_point_stiffness`)."""
    return float(element.building_point_stiffness(storey, a, np.asarray(normal, dtype=float)))


def struck_stiffness(scene, systems, facades: dict, pair, points, normals) -> np.ndarray:
    """Local stiffness [N/m] (m,) of the element struck at every contact point (m, 2) [m] with unit
    normal (m, 2) of the pairs ``pair`` (m,): for a pair in ``facades`` ({pair: :class:`Facade`}), the
    column or wall a slab strikes between the neighbour's floors (:func:`struck`, whose third figure is
    :func:`local_stiffness`), inf at a slab. ``scene``'s buildings and the assembled ``systems`` (their
    slabs' elevations) in scene order. The one rule of the run (:meth:`pounding.framework.engine.stacked_model.Model.local_stiffness`)
    and of the forces rebuilt after it (:mod:`pounding.framework.post.contact_forces`)."""
    out = np.full(len(pair), np.inf)
    if not facades:
        return out
    for j, p in enumerate(np.asarray(pair).tolist()):
        F = facades.get(p)
        if F is None:
            continue
        levels = [0.0] + [s.elevation for s in systems[F.building].slabs]
        out[j] = struck(scene.buildings[F.building], F.storey, F.height - levels[F.storey], points[j], normals[j])[2]
    return out


def end_shears(a: float, L: float) -> tuple[float, float]:
    """Shares (below, above) of a point load at a [m] on a fixed-fixed member of length L [m] taken
    by its segments below and above the load (the end reactions): b^2 (3 a + b) / L^3 and
    a^2 (a + 3 b) / L^3, b = L - a (they sum to 1)."""
    b = L - a
    return b**2 * (3.0 * a + b) / L**3, a**2 * (a + 3.0 * b) / L**3


# --------------------------------------------------------------------------- what each impact struck
#: impacts.csv columns of :func:`impact_sites`, after the striking building
SITE_COLUMNS = ["struck_building", "struck_storey", "struck_height [m]", "struck_element", "struck_fraction",
                "local_stiffness [N/m]", "struck_shear_below [N]", "struck_shear_above [N]"]


def impact_sites(result, peak_force: np.ndarray) -> list[list]:
    """What every impact of ``result`` struck, one row of :data:`SITE_COLUMNS` per impact.

    A slab against a fixed wall: the wall's name, storey 0 (the ground it stands on), the slab's
    elevation [m], element ``wall``, fraction 1 and nan for the rest.
    A slab against a slab at a common level: the other building, its storey (1-based), the
    slab's elevation [m], element ``slab``, fraction 1, no local stiffness and no local shear
    (nan). A slab against a facade: the struck building, the 1-based storey whose columns and
    walls were hit, the contact height [m], the element whose plan line passes nearest the
    contact point (``index:type``, scene order), eta (fraction of the storey height), its local
    stiffness [N/m] (:func:`local_stiffness`, nan for element types without one) and the
    shear demand the impact's equivalent peak force ``peak_force`` (n_impacts,) [N] puts on
    the struck member's segments below and above the contact point (:func:`end_shears`,
    fixed-fixed member with a point load), beyond the storey shear of the floors' drift.
    """
    out = []
    for imp, force in zip(result.impacts, peak_force):
        a, fa, b, fb, _ = result.pairs[imp.pair]
        F = result.facades.get(imp.pair)
        nan = float("nan")
        wall = getattr(result, "walls", {}).get(imp.pair)
        if wall is not None:
            out.append([wall.name, 0, float(result.systems[a].slabs[fa].elevation), "wall", 1.0, nan, nan, nan])
            continue
        if F is None:
            other, storey = (b, fb) if imp.striker == 0 else (a, fa)
            z = float(result.systems[other].slabs[storey].elevation)
            out.append([result.names[other], storey + 1, z, "slab", 1.0, nan, nan, nan])
            continue
        system = result.systems[F.building]
        levels = np.concatenate([[0.0], [s.elevation for s in system.slabs]])
        L = float(levels[F.storey + 1] - levels[F.storey])
        a_height = F.height - float(levels[F.storey])
        element, k, below, above = "", nan, nan, nan
        if result.buildings:
            i, e, k = struck(result.buildings[F.building], F.storey, a_height, imp.point, imp.normal)
            element = f"{i}:{e.name}"
            sb, sa = end_shears(a_height, L)
            below, above = sb * float(force), sa * float(force)
        out.append([result.names[F.building], F.storey + 1, F.height, element, F.eta, k, below, above])
    return out
