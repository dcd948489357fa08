"""Separation-gap design: the smallest clear distance at which no slabs ever touch.

Method
------
One run of the scene without contact (``contact = "none"``; both buildings
are then independent, so this is one no-contact run of each building) gives
the displaced slab polygons of every common storey (and facade, below) at every step (rotations
included, any simple polygon). For a plan unit vector d pointing from the
first building towards the second, define for two polygons A, B

    D(A, B, d) = max { delta : A and B + delta d touch }        (-inf if none)

the signed translation of B along d at which the two polygons last touch:
``-D`` is the clear distance between them measured along d (negative when
they overlap). It is computed exactly by casting every vertex of B along d
onto every edge of A and every vertex of A along -d onto every edge of B
(:func:`translation_to_contact`): the last contact of two polygons sliding
along a line is always a vertex of one on an edge of the other. Moving the
second building by ``(s - g0) d``, where ``g0`` is the clear distance along d
at rest in the scene as given (smallest over the sites), keeps every
pair apart at every instant if and only if

    s > min_gap = g0 + max over storeys and time of D(A_f(t), B_f(t), d).

On the output grid of the no-contact run this is exact (``min_gap_grid``: the
full runs check contact on the same grid); ``min_gap`` is the maximum over the
continuous trajectory, refined inside the steps next to the largest step-end
values on the integrator's own interpolant (:mod:`pounding.framework.engine.peaks`).
:func:`verify_gap` checks it with two full runs at 0.99 and 1.01 times the answer.

Slabs between a neighbour's floors
----------------------------------
A slab whose level lies strictly between two floors of the other building (or between the
ground and its first floor), below its roof, strikes that building's facade (its columns and
walls) there. The facade is the one the run with contact uses
(:func:`pounding.framework.model.facade.facade`): the outline of the floor above, moving rigidly in
plan with the Hermite blend N1 u_below + N2 u_above of the two floors' motions. Such a
slab-facade pair is one more site, treated exactly like a pair of slabs at a common level
(translation to contact along d at every step, refined inside the steps); a pair of buildings
with no common level but such a site is adjacent.

Building-code estimates
-----------------------
From the same run, at the governing storey, with u_a and u_b the peak
displacements along d of the facing slab points (the material points of each
slab at the governing contact, rotation included):

* ABS  = u_a + u_b (absolute sum);
* SRSS = sqrt(u_a^2 + u_b^2);
* DDC  = sqrt(u_a^2 + u_b^2 - 2 rho u_a u_b), the double difference combination
  (Jeng, Kasai and Maison 1992; Penzien 1997; Lopez-Garcia and Soong 2009),
  with the CQC correlation of two oscillators (Der Kiureghian 1981)

      rho = 8 sqrt(z_a z_b) (z_a + r z_b) r^1.5
            / ((1 - r^2)^2 + 4 z_a z_b r (1 + r^2) + 4 (z_a^2 + z_b^2) r^2),

  r = T_a / T_b, using each building's fundamental period along d (the mode
  with the largest effective mass along d) and that mode's damping ratio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.placement import (
    _oriented,
    _pair_of,
    _site_facade,
    _site_level,
    adjacent_pairs,
    facing_storeys,
    pair_scene,
    translation_to_contact,
)
from pounding.framework.model.scene import Scene

CHUNK = 2048  # time steps per vectorised block (bounds memory for large polygons)
BOUND_BLOCK = 64  # steps per block when only the steps that can govern are evaluated (full=False)

__all__ = [
    "GapCheck",
    "GapReport",
    "correlation",
    "gap_from_result",
    "minimum_gap",
    "verify_gap",
]


# =============================================================================
# The report
# =============================================================================


def correlation(T_a: float, T_b: float, z_a: float, z_b: float) -> float:
    """CQC correlation of two damped oscillators (Der Kiureghian 1981), r = T_a / T_b; symmetric in (a, b)."""
    r = T_a / T_b
    num = 8.0 * math.sqrt(z_a * z_b) * (z_a + r * z_b) * r**1.5
    den = (1.0 - r * r) ** 2 + 4.0 * z_a * z_b * r * (1.0 + r * r) + 4.0 * (z_a * z_a + z_b * z_b) * r * r
    return num / den


@dataclass
class GapCheck:
    """Two full runs with pounding at ``factors`` times the minimum gap."""

    factors: tuple[float, float]
    gaps: tuple[float, float]
    n_impacts: tuple[int, int]
    tolerance: float  # the contact law's length tolerance [m]

    @property
    def ok(self) -> bool:
        """Impacts below the answer and none above it."""
        return self.n_impacts[0] > 0 and self.n_impacts[1] == 0

    def to_dict(self) -> dict:
        return {
            "below": {"factor": self.factors[0], "gap": self.gaps[0], "n_impacts": self.n_impacts[0]},
            "above": {"factor": self.factors[1], "gap": self.gaps[1], "n_impacts": self.n_impacts[1]},
            "contact_tolerance": self.tolerance,
            "ok": self.ok,
        }


@dataclass
class GapReport:
    """The minimum separation gap of a pair and the code estimates (lengths in m, times in s).

    ``buildings`` = (fixed, moved): the second building is the one moved along
    ``direction`` (a unit vector from the first towards the second). Storeys are
    1-based, of the first building (``storey_b`` of the second); vertices and
    edges 0-based in the slab polygons' order (edge j from vertex j to j + 1).
    """

    min_gap: float
    current_gap: float
    direction: np.ndarray
    buildings: tuple[str, str]
    storey: int
    storey_b: int
    time: float
    striking: str  # building whose corner touches
    vertex: int
    struck: str
    edge: int
    point: np.ndarray  # contact point in plan at the governing instant, second building at min_gap
    required: list  # per site (:func:`~pounding.framework.model.placement.pair_sites`): (storey a, storey b, required gap, time); see ``facades``
    periods: tuple[float, float]
    damping: tuple[float, float]
    peaks: tuple[float, float]  # peak displacement along d of the facing points at the governing storey
    rho: float
    abs: float
    srss: float
    ddc: float
    t: np.ndarray = field(repr=False)
    clearance: np.ndarray = field(repr=False)  # (nt, sites) clear distance along d in the scene as given, at the step ends
    check: GapCheck | None = None
    #: the minimum gap over the step ends only (what a run with contact, which checks after each step, sees);
    #: ``min_gap`` is over the continuous trajectory (:mod:`pounding.framework.engine.peaks`)
    min_gap_grid: float | None = None
    #: the governing site when a slab strikes the other building's facade between two of its floors:
    #: {"striking", "slab_storey", "height" [m], "struck", "struck_storey", "eta"} (storeys 1-based), else None
    facade: dict | None = None
    #: per row of ``required``: the same for slab-facade rows, None at a common level
    facades: list = field(default_factory=list)
    #: the clearance each building needs to each retaining wall (:mod:`pounding.framework.studies.wall_gap`)
    walls: list = field(default_factory=list)
    #: the gaps above are between the bare slabs; per storey that carries a bumper (:func:`bumper_gaps`):
    #: {"on", "storey", "thickness", "gap"} with ``gap`` the bare gap that keeps the layer untouched
    bumpers: list = field(default_factory=list)

    def to_dict(self) -> dict:
        out = {
            "min_gap": self.min_gap,
            "min_gap_step_ends": self.min_gap_grid,
            "current_gap": self.current_gap,
            "direction": [float(self.direction[0]), float(self.direction[1])],
            "storey": self.storey,
            "time": self.time,
            "abs": self.abs,
            "srss": self.srss,
            "ddc": self.ddc,
            "buildings": {"fixed": self.buildings[0], "moved": self.buildings[1]},
            "storey_b": self.storey_b,
            "corner": {"building": self.striking, "vertex": self.vertex},
            "edge": {"building": self.struck, "edge": self.edge},
            "point": [float(self.point[0]), float(self.point[1])],
            "required_per_storey": [self._row(k, fa, fb, g, t) for k, (fa, fb, g, t) in enumerate(self.required)],
            "periods": {self.buildings[0]: self.periods[0], self.buildings[1]: self.periods[1]},
            "damping_ratios": {self.buildings[0]: self.damping[0], self.buildings[1]: self.damping[1]},
            "peak_displacements": {self.buildings[0]: self.peaks[0], self.buildings[1]: self.peaks[1]},
            "rho": self.rho,
        }
        if self.facade is not None:
            out["facade"] = dict(self.facade)
        if self.check is not None:
            out["check"] = self.check.to_dict()
        if self.walls:
            out["walls"] = [w.to_dict() for w in self.walls]
        if self.bumpers:
            out["bumpers"] = [dict(b) for b in self.bumpers]
        return out

    def _row(self, k: int, fa: int, fb: int, g, t) -> dict:
        row = {"storey": fa, "storey_b": fb, "gap": g, "time": t}
        if k < len(self.facades) and self.facades[k] is not None:
            row["facade"] = dict(self.facades[k])
        return row


def _fundamental(system, d: np.ndarray) -> tuple[float, float]:
    """(period, damping ratio) of the mode with the largest effective mass along d."""
    gamma = system.participation(system.influence(d))
    i = int(np.argmax(gamma**2))
    return float(system.periods[i]), float(system.zeta[i])


def _point_history(cm: np.ndarray, centre: np.ndarray, point: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Displacement along d of a slab's material point (rest position ``point``), shape (nt,)."""
    r = point - centre
    ux = cm[:, 0] - cm[:, 2] * r[1]
    uy = cm[:, 1] + cm[:, 2] * r[0]
    return ux * d[0] + uy * d[1]


@dataclass
class _Side:
    """One side of a site in a run: a slab or a facade, as modal rows (3, n) of its (u, v, phi) about
    ``centre``, its rest outline, and its displaced-vertex offsets (nt, k, 2) at the output steps."""

    name: str
    vertices: np.ndarray
    centre: np.ndarray
    rows: np.ndarray
    offsets: np.ndarray
    facade: bool

    def at(self, q: np.ndarray) -> np.ndarray:
        """The displaced outline (k, 2) for the building's modal coordinates q (n,): the contact
        geometry's exact turn (:func:`~pounding.contact.geometry.displaced`, compiled: the study's
        maximisation asks it some thousand times a run)."""
        from pounding.contact.geometry import displaced

        u, v, phi = self.rows @ q
        return displaced(np.ascontiguousarray(self.vertices, dtype=float), np.ascontiguousarray(self.centre, dtype=float),
                         float(u), float(v), float(phi))


def _sides(result, a, b, site) -> tuple[_Side, _Side]:
    """The two sides of ``site`` (:func:`~pounding.framework.model.placement.pair_sites`) in ``result``: the slabs' motion
    as the contact geometry takes it (``Result.contact_offsets``), or the facade the driver uses
    (:func:`pounding.framework.model.facade.facade`, from the run's assembled system)."""
    from pounding.contact.geometry import turned
    from pounding.framework.model.facade import facade

    z = _site_level(a, b, site)
    out = []
    for building, f, struck in ((a, site[0], len(site) == 3 and site[2] == "a"), (b, site[1], len(site) == 3 and site[2] == "b")):
        i = result.names.index(building.name)
        system = result.systems[i]
        if not struck:
            out.append(_Side(building.name, building.slabs[f].vertices, system.slabs[f].centre,
                             np.asarray(system.modes, dtype=float)[3 * f: 3 * f + 3], result.contact_offsets(building.name, f), False))
            continue
        F = facade(system, i, z)
        uvp = result.modal(building.name) @ F.rows.T  # (nt, 3) about the facade's centre
        off = uvp[:, None, 0:2] + turned(F.vertices - F.centre, uvp[:, 2:3])
        out.append(_Side(building.name, F.vertices, F.centre, F.rows, off, True))
    return out[0], out[1]


def gap_from_result(scene: Scene, result, direction=None, *, full: bool = True, storeys=None) -> GapReport:
    """The :class:`GapReport` from a run of ``scene`` (normally without contact; output every step).

    ``full=False`` evaluates the exact translation to contact only at the steps that can govern:
    per site, steps are taken in decreasing order of the bound
    ``max_i A_i . d - min_j B_j . d`` (two polygons that touch overlap in their projections on d),
    block by block, until the bound (raised by 1e-12 of the coordinates against rounding) falls
    below the best exact value found. The answer is the same (same values, same governing step on
    ties); ``clearance`` then holds ``inf`` at the steps not evaluated. ``storeys``: only these
    sites (:func:`~pounding.framework.model.placement.pair_sites`; a pair of a row, where it faces). Sites are slabs at a common level
    and slabs against the other building's facade between two of its floors.
    """
    a, b, common = _pair_of(scene, storeys)
    d, g0 = _oriented(scene, direction, storeys)
    cm_a, cm_b = result.cm(a.name), result.cm(b.name)
    nt = len(result.t)
    D = np.full((nt, len(common)), -np.inf)
    infos = []
    sides = [_sides(result, a, b, site) for site in common]
    for c, site in enumerate(common):
        side_a, side_b = sides[c]
        A = side_a.vertices + side_a.offsets
        B = side_b.vertices + side_b.offsets
        info = {k: np.zeros(nt, dtype=float if k == "s" else int) for k in ("who", "vertex", "edge", "s")}
        if full:
            blocks = [slice(i0, min(nt, i0 + CHUNK)) for i0 in range(0, nt, CHUNK)]
            bound = None
        else:
            # >= the translation to contact at each step; raised by far more than the rounding of either
            # computation (~1e-16 of the coordinates) so that rounding never skips a governing step
            bound = (A @ d).max(axis=-1) - (B @ d).min(axis=-1) + 1e-12 * (1.0 + float(np.max(np.abs(A))) + float(np.max(np.abs(B))))
            order = np.argsort(-bound, kind="stable")
            blocks = (np.sort(order[i0:i0 + BOUND_BLOCK]) for i0 in range(0, nt, BOUND_BLOCK))
        best = -np.inf
        for sl in blocks:
            if bound is not None and np.max(bound[sl]) < best:
                break  # no step left can reach the best value (ties are still evaluated)
            D[sl, c], inf = translation_to_contact(A[sl], B[sl], d)
            best = max(best, float(np.max(D[sl, c])))
            for key in info:
                info[key][sl] = inf[key]
        infos.append(info)
    if not np.any(np.isfinite(D)):
        raise InputError("the slabs never face each other along the direction", field="direction")
    # true peaks: the translation to contact over the continuous trajectory, refined inside the steps
    # around each storey's governing step (pounding.framework.engine.peaks)
    # (D itself, and the clearance history, stay at the step ends: what a run with contact checks)
    t_best = np.asarray(result.t, dtype=float)[np.argmax(D, axis=0)]
    cont = np.max(D, axis=0)
    refined = _refine_inside_steps(result, a, b, sides, d, D)
    if refined is not None:
        for cc, (val, tc) in enumerate(refined):
            if val > cont[cc]:
                cont[cc], t_best[cc] = val, tc
    c = int(np.argmax(cont))
    k_t = int(np.argmax(D[:, c]))  # the governing step: the contact features are read there
    min_gap = g0 + float(cont[c])
    fa, fb = common[c][:2]
    side_a, side_b = sides[c]
    info = {key: val[k_t] for key, val in infos[c].items()}
    who, vertex, edge, s = int(info["who"]), int(info["vertex"]), int(info["edge"]), float(info["s"])
    # the facing material points (rest positions) and the contact point at min_gap
    Va, Vb, oa = side_a.vertices, side_b.vertices, side_a.offsets
    if who == 1:  # a corner of b on an edge of a
        striking, struck = b.name, a.name
        rest_b = Vb[vertex]
        ea0, ea1 = Va[edge], Va[(edge + 1) % len(Va)]
        rest_a = ea0 + s * (ea1 - ea0)
        point = rest_a + oa[k_t, edge] + s * (oa[k_t, (edge + 1) % len(Va)] - oa[k_t, edge])
    else:  # a corner of a on an edge of b
        striking, struck = a.name, b.name
        rest_a = Va[vertex]
        eb0, eb1 = Vb[edge], Vb[(edge + 1) % len(Vb)]
        rest_b = eb0 + s * (eb1 - eb0)
        point = rest_a + oa[k_t, vertex]
    u_a, u_b = _point_peaks(result, (side_a, fa, rest_a), (side_b, fb, rest_b), d, cm_a, cm_b)
    sys_a, sys_b = (result.systems[result.names.index(n)] for n in (a.name, b.name))
    (T_a, z_a), (T_b, z_b) = _fundamental(sys_a, d), _fundamental(sys_b, d)
    rho = correlation(T_a, T_b, z_a, z_b)
    required = []
    for cc, site in enumerate(common):
        ga, gb = site[:2]
        required.append((ga + 1, gb + 1, float(g0 + cont[cc]) if np.isfinite(cont[cc]) else None, float(t_best[cc])))
    return GapReport(
        min_gap=float(min_gap),
        min_gap_grid=float(g0 + np.max(D)),
        current_gap=float(g0),
        direction=d,
        buildings=(a.name, b.name),
        storey=fa + 1,
        storey_b=fb + 1,
        time=float(t_best[c]),
        striking=striking,
        vertex=vertex,
        struck=struck,
        edge=edge,
        point=np.asarray(point, dtype=float),
        required=required,
        periods=(T_a, T_b),
        damping=(z_a, z_b),
        peaks=(u_a, u_b),
        rho=float(rho),
        abs=u_a + u_b,
        srss=math.hypot(u_a, u_b),
        ddc=math.sqrt(max(0.0, u_a * u_a + u_b * u_b - 2.0 * rho * u_a * u_b)),
        t=np.asarray(result.t),
        clearance=-D,
        facade=_site_facade(a, b, common[c]),
        facades=[_site_facade(a, b, site) for site in common],
    )


def _point_row(side: _Side, rest: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Row over a building's modes of the displacement along d of a slab's or facade's material point ``rest``."""
    r = np.asarray(rest, dtype=float) - side.centre
    u, v, phi = side.rows
    return d[0] * (u - r[1] * phi) + d[1] * (v + r[0] * phi)


def _point_peaks(result, pa, pb, d, cm_a, cm_b) -> tuple[float, float]:
    """Peak |displacement along d| of the facing points over the continuous trajectory
    (:func:`pounding.framework.engine.peaks.abs_peaks`); over the output steps when the output is thinned."""
    from pounding.framework.engine import peaks

    seg = peaks.segments(result)
    out = []
    for (side, f, rest), cm in ((pa, cm_a), (pb, cm_b)):
        if seg is None:
            hist = result.modal(side.name) @ side.rows.T if side.facade else cm[:, f]
            out.append(float(np.max(np.abs(_point_history(hist, side.centre, rest, d)))))
            continue
        out.append(float(peaks.abs_peaks(peaks.building_segments(seg, result, side.name), _point_row(side, rest, d)[None, :])[0]))
    return out[0], out[1]


def _refine_inside_steps(result, a, b, sides, d, D, top: int = 3):
    """Per site (its two :class:`_Side`): (max of the translation to contact inside the steps next to its ``top``
    largest step-end values, the instant [s]) on the continuous trajectory; None when the output is
    thinned. The translation is piecewise smooth in the displacements (a fixed vertex on a fixed
    edge near its maximum), so a bounded search on each piece finds it."""
    from pounding.framework.engine import peaks

    seg = peaks.segments(result)
    if seg is None:
        return None
    ia, ib = result.names.index(a.name), result.names.index(b.name)
    sys_a, sys_b = result.systems[ia], result.systems[ib]
    sla = slice(int(result.mode_start[ia]), int(result.mode_start[ia]) + sys_a.n_dof)
    slb = slice(int(result.mode_start[ib]), int(result.mode_start[ib]) + sys_b.n_dof)
    t0 = np.asarray(seg.t0)
    out = []
    for c, (side_a, side_b) in enumerate(sides):
        if not np.any(np.isfinite(D[:, c])):
            out.append((-np.inf, 0.0))
            continue

        def D_of(q, side_a=side_a, side_b=side_b):
            val, _ = translation_to_contact(side_a.at(q[sla]), side_b.at(q[slb]), d)
            return float(val) if np.isfinite(val) else -np.inf

        ks = np.argsort(-np.where(np.isfinite(D[:, c]), D[:, c], -np.inf), kind="stable")[:top]
        pieces = set()
        for k in ks:
            tk = float(result.t[k])
            j = int(np.searchsorted(t0, tk))
            pieces.update(i for i in (j - 1, j) if 0 <= i < len(t0))
        val, i, s = peaks.refine_over(seg, sorted(pieces), D_of)
        out.append((val, float(t0[i] + s * seg.h[i]) if i >= 0 else 0.0))
    return out


def bumper_gaps(scene: Scene, report: GapReport) -> list[dict]:
    """The bare gap [m] that keeps each bumper's layer untouched: at every storey of the pair that
    carries one (a ``[[contact]]`` bumper of thickness t), the storey's required gap between the
    bare slabs (``report.required``, common levels only) plus t. The study itself measures the bare
    slabs (its ``min_gap`` and its check runs ignore the layers): a layer only shrinks the gap."""
    out = []
    names = list(report.buildings)
    for rule in scene.contacts:
        b = getattr(rule, "bumper", None)
        if b is None or set(rule.between) != set(names):
            continue
        first = names[0] == b.on  # the rows give the first building's storey first
        for k, (fa, fb, g, _) in enumerate(report.required):
            facade = k < len(report.facades) and report.facades[k] is not None
            if (fa if first else fb) in b.storeys and not facade and g is not None:
                out.append({"on": b.on, "storey": int(fa if first else fb), "thickness": b.thickness, "gap": g + b.thickness})
    return out


def no_contact(scene: Scene) -> Scene:
    """The scene without contact, recording every step."""
    return scene.with_analysis(contact="none", contact_params={}, output_every=1)


def minimum_gap(scene: Scene, direction=None, *, progress=None) -> GapReport:
    """Smallest clear distance at rest along ``direction`` at which no slabs touch under the scene's ground motion.

    Parameters
    ----------
    scene : Scene
        Exactly two buildings that can meet: a storey at a common level, or a slab between
        two floors of the other (:func:`~pounding.framework.model.placement.pair_sites`).
    direction : None, "x", "y", angle [degrees] or (dx, dy)
        The direction the gap is measured and the second building moved along
        (oriented from the first building towards the second). Default: the
        shortest segment between the slabs at rest (the normal of the facing edges).

    Returns
    -------
    GapReport
        Without a check; see :func:`verify_gap`.
    """
    from pounding.framework.post.run import run

    from pounding.framework.studies.wall_gap import wall_clearances

    _oriented(scene, direction)  # bad directions fail before the run
    result = run(no_contact(scene), progress=progress)
    report = gap_from_result(scene, result, direction)
    report.walls = wall_clearances(scene, result)
    report.bumpers = bumper_gaps(scene, report)
    return report


@dataclass
class RowGaps:
    """The required gap of every adjacent pair of a scene of three or more buildings.

    ``reports`` holds one :class:`GapReport` per adjacent pair (scene order), each found from
    one run of the whole scene without contact, over the storeys where the pair faces
    (:func:`~pounding.framework.model.placement.facing_storeys`), and measured as if the pair stood alone (the second building of
    the pair is the one moved); ``screened`` names the pairs with slabs at a
    common level (or slab-facade sites) that never face each other (a building between them
    at every such level).
    """

    reports: list
    screened: list[tuple[str, str]]
    #: the clearance each building needs to each retaining wall (:mod:`pounding.framework.studies.wall_gap`)
    walls: list = field(default_factory=list)

    def to_dict(self) -> dict:
        out = {"pairs": [r.to_dict() for r in self.reports], "screened": [list(p) for p in self.screened]}
        if self.walls:
            out["walls"] = [w.to_dict() for w in self.walls]
        return out


def minimum_gaps(scene: Scene, direction=None, *, progress=None) -> RowGaps:
    """:func:`minimum_gap` of every adjacent pair (:func:`~pounding.framework.model.placement.adjacent_pairs`) from one run without contact.

    ``direction`` applies to every pair (None: each pair's own facing normal).
    """
    from pounding.framework.post.run import run

    adjacent, screened = adjacent_pairs(scene)
    if not adjacent:
        raise InputError("no two buildings have slabs facing each other at a common level or a facade between floors: there is no gap to design", field="building")
    subs = [(pair_scene(scene, i, j), facing_storeys(scene, i, j)) for i, j in adjacent]
    for sub, storeys in subs:
        _oriented(sub, direction, storeys)  # bad directions fail before the run
    from pounding.framework.studies.wall_gap import wall_clearances

    result = run(no_contact(scene), progress=progress)
    names = [b.name for b in scene.buildings]
    return RowGaps([gap_from_result(sub, result, direction, storeys=storeys) for sub, storeys in subs],
                   [(names[i], names[j]) for i, j in screened], wall_clearances(scene, result))


def verify_gap(scene: Scene, report: GapReport, factors=(0.99, 1.01)) -> GapCheck:
    """Two full runs with the second building at ``factors`` times the minimum gap: impacts expected at the first, none at the second.

    The scene's own contact law is used (the impulse law if the scene has none).
    Contact is detected within the law's length tolerance (1e-4 m by default), so
    the check is only meaningful when ``(factors[1] - 1) * min_gap`` exceeds it.
    """
    from pounding.framework.post.run import run
    from pounding.framework.model.registry import CONTACT_LAWS, watches_contact

    if not watches_contact(scene.analysis):
        scene = scene.with_analysis(contact="impulse", contact_params={})
    # the check is about the pair: impacts on walls (which do not move with the building) do not count,
    # and the minimum gap is between the bare slabs: a bumper's layer does not count either
    scene = replace(scene, walls=(), contacts=tuple(replace(r, bumper=None) for r in scene.contacts))
    law = CONTACT_LAWS.get(scene.analysis.contact)(**scene.analysis.contact_params)
    gaps, counts = [], []
    for f in factors:
        g = float(f) * report.min_gap
        counts.append(run(scene.with_gap(g, report.direction)).n_impacts)
        gaps.append(g)
    check = GapCheck(tuple(float(f) for f in factors), tuple(gaps), tuple(counts), float(getattr(law, "tolerance", 0.0)))
    report.check = check
    return check
