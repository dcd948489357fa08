"""ParaView output: both buildings in 3-D, one unstructured grid per written instant.

:func:`write_vtk_series` writes a ``.pvd`` collection (the time series ParaView
opens) and one ``.vtu`` per written instant:

* slabs as polygons at their floor level (z = elevation);
* every planar element's ``outline()``: lines (frame columns and beams) and
  panels (wall quads), placed in 3-D along the element's plan line;
* point coordinates = rest position + ``scale`` x displacement. A point at
  floor f moves with that slab's rigid motion ``(u - phi dy, v + phi dx)``;
  points at z = 0 do not move; a point between two floors (none of the stock
  elements has one) moves by linear interpolation in z between them.

Point data: ``displacement`` and ``velocity`` (3 components, z = 0, true
values, never scaled). Cell data: ``building`` (index in scene order),
``storey`` (1-based; 0 for ground-level items), ``element_type`` (0 slab,
1 frame member / line, 2 wall panel), ``in_contact`` (1 on both slab cells of
a pair whose signed gap is <= the contact tolerance at that instant, computed
from the geometry) and ``gap`` (the smallest signed gap of the slab's pairs
[m], NaN for non-slab cells and unpaired slabs). With yielding storey springs,
``ductility`` (the running peak |u| / u_y of the spring a cell draws, up to
that instant) and ``ductility_peak`` (over the whole run), NaN on cells that
draw no yielding spring (colour by them to see where the buildings yield), and
``element`` (the cell's element index in its building, 0-based; -1 slabs). Field data: ``time`` and
``impact_instant`` (1 when the frame is an impact instant).

Walls and links, when the scene has them, are further parts of the same collection (ParaView
shows the time series as one multiblock):

* part 1, ``<name>_walls.vtu``, written once and listed at every instant: each ``[[wall]]`` as a fixed
  surface, its face polyline extruded from the ground (z = 0) to its top, one quad per face
  segment. Cell data ``wall`` (index in scene order) and ``top`` [m]. Walls never move.
* part 2, ``<name>_links_NNNNNN.vtu``, one per instant: each ``[[link]]`` as a line between its two
  attachment points, each at its slab's elevation and moving with that slab's rigid motion (the
  same rule as every drawn point). Point data ``displacement`` (true, never scaled); cell data
  ``link`` (index in scene order), ``deformation`` [m] (the second point's displacement minus the
  first's along the link's line at rest, computed from the slabs' motion at that instant) and
  ``force`` [N] (the run's recorded force at an output step; NaN at an impact instant between
  output steps, where the run keeps no link state).

Instants written: every ``every``-th output step, plus every impact instant at
its *exact* time, with the driver's own state at that instant (kept in the
Result: ``event_t``, ``event_q``, ``event_qd``); the velocity written at an
impact frame is the one just *before* that instant's impulses. The writer reads
the states the run recorded and never integrates (:class:`StateAt`): an
``impact_times`` entry that is neither an output step nor an impact instant is
an error.

``vtk`` is imported inside the functions that write files only.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from pounding.framework.model.levels import common_levels, same_level

DEFAULT_TOLERANCE = 1e-4  # [m] contact tolerance when neither the result nor the scene gives one

SLAB, LINE, PANEL = 0, 1, 2


# =============================================================================
# Motion: physical slab histories of a run (from a Result or from a run directory)
# =============================================================================


@dataclass
class Motion:
    """Physical slab motion of every building, independent of how it was stored.

    Attributes
    ----------
    t : ndarray (nt,)
        Output times [s].
    names : list of str
        Building names, scene order.
    slabs : list of tuple of Slab
        Slabs of each building.
    cm : list of ndarray (nt, storeys, 3)
        (u, v, phi) of every slab's centre of mass [m, m, rad].
    cm_velocity : list of ndarray (nt, storeys, 3) or None
        Their rates (None when unknown, e.g. read from response.npz).
    pairs : list of (building a, storey a, building b, storey b, rest gap)
        Slab pairs at a common level, 0-based.
    tolerance : float
        Contact tolerance [m].
    impacts : list of Impact
        The impact log (empty when unknown).
    episodes : list of ContactEpisode
        Every contact episode, impacts and force laws' contacts alike (empty when unknown).
    """

    t: np.ndarray
    names: list
    slabs: list
    cm: list
    cm_velocity: list | None
    pairs: list
    tolerance: float = DEFAULT_TOLERANCE
    impacts: list = field(default_factory=list)
    episodes: list = field(default_factory=list)

    @classmethod
    def from_result(cls, result, scene=None) -> "Motion":
        """Motion of a :class:`~pounding.framework.engine.results.Result`."""
        return cls(
            t=np.asarray(result.t, dtype=float),
            names=list(result.names),
            slabs=[tuple(s.slabs) for s in result.systems],
            cm=[result.cm(n) for n in result.names],
            cm_velocity=[result.cm(n, velocity=True) for n in result.names],
            pairs=list(result.pairs),
            tolerance=contact_tolerance(result, scene),
            impacts=list(result.impacts),
            episodes=list(result.episodes()),
        )

    @classmethod
    def from_arrays(cls, scene, t: np.ndarray, cm: dict, cm_velocity: dict | None = None) -> "Motion":
        """Motion from physical arrays: ``cm[name]`` (nt, storeys, 3); pairs recomputed from the scene."""
        names = [b.name for b in scene.buildings]
        missing = [n for n in names if n not in cm]
        if missing:
            raise KeyError(f"no centre-of-mass history for building(s) {', '.join(map(repr, missing))}")
        return cls(
            t=np.asarray(t, dtype=float),
            names=names,
            slabs=[tuple(b.slabs) for b in scene.buildings],
            cm=[np.asarray(cm[n], dtype=float) for n in names],
            cm_velocity=None if cm_velocity is None else [np.asarray(cm_velocity[n], dtype=float) for n in names],
            pairs=scene_pairs(scene),
            tolerance=contact_tolerance(None, scene),
        )

    def building_index(self, building) -> int:
        return building if isinstance(building, (int, np.integer)) else self.names.index(building)

    def polygon(self, building: int, storey: int, k: int, cm: np.ndarray | None = None) -> np.ndarray:
        """Displaced polygon (k, 2) of slab ``storey`` (0-based) at output index k (or for given cm (3,))."""
        slab = self.slabs[building][storey]
        d = self.cm[building][k, storey] if cm is None else cm
        return slab_polygon(slab, d)

    def pair_gaps(self) -> np.ndarray:
        """Signed gap of every pair at every output step [m], shape (nt, n_pairs)."""
        return pair_gap_history(self.slabs, self.cm, self.pairs)


def contact_tolerance(result=None, scene=None) -> float:
    """Contact length tolerance [m]: the run's (the largest of its laws': ``[analysis] contact``'s, the
    ``[[contact]]`` tables' and the walls', as the run watches its pairs), else the scene's, else 1e-4."""
    if result is not None:
        contact = getattr(result, "contact", None) or {}
        laws = [contact, contact.get("impulses") or {}, *contact.get("between", ()), *contact.get("walls", ())]
        tols = [float(law["tolerance"]) for law in laws if law.get("tolerance") is not None]
        if tols:
            return max(tols)
    if scene is not None:
        tol = (scene.analysis.contact_params or {}).get("tolerance")
        if tol is not None:
            return float(tol)
    return DEFAULT_TOLERANCE


def scene_pairs(scene) -> list:
    """Slab pairs at a common level, as the analysis builds them: (a, storey a, b, storey b, rest gap)."""
    return level_pairs(scene.buildings)


def level_pairs(buildings) -> list:
    """Slab pairs at a common level of objects with ``.slabs`` (Buildings or Systems), as the analysis builds them."""
    from pounding.contact.geometry import signed_gap

    out = []
    bs = list(buildings)
    for a in range(len(bs)):
        for b in range(a + 1, len(bs)):
            for fa, fb in common_levels(bs[a], bs[b]):
                sa, sb = bs[a].slabs[fa], bs[b].slabs[fb]
                out.append((a, fa, b, fb, float(signed_gap(_f64(sa.vertices), _f64(sb.vertices)))))
    return out


def _f64(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64)


def slab_polygon(slab, d) -> np.ndarray:
    """Polygon (k, 2) of a slab displaced by its centre-of-mass motion d = (u, v, phi)."""
    r = slab.vertices - slab.centre
    out = np.array(slab.vertices, dtype=float, copy=True)
    out[:, 0] += d[0] - d[2] * r[:, 1]
    out[:, 1] += d[1] + d[2] * r[:, 0]
    return out


def pair_gap_history(slabs: Sequence, cm: Sequence[np.ndarray], pairs: Sequence) -> np.ndarray:
    """Signed gap of every pair at every step [m], shape (nt, n_pairs), from cm histories."""
    from pounding.contact.geometry import signed_gap

    nt = cm[0].shape[0] if cm else 0
    out = np.empty((nt, len(pairs)))
    for p, (a, fa, b, fb, _) in enumerate(pairs):
        sa, sb = slabs[a][fa], slabs[b][fb]
        for k in range(nt):
            out[k, p] = signed_gap(_f64(slab_polygon(sa, cm[a][k, fa])), _f64(slab_polygon(sb, cm[b][k, fb])))
    return out


def pair_gaps(result, pairs: Sequence | None = None) -> np.ndarray:
    """Signed gap of every pair (default ``result.pairs``) at every output step [m], shape (nt, n_pairs)."""
    slabs = [tuple(s.slabs) for s in result.systems]
    cm = [result.cm(n) for n in result.names]
    out = pair_gap_history(slabs, cm, result.pairs if pairs is None else pairs)
    own = pairs is None or list(pairs) == list(result.pairs)
    # a slab against a neighbour's facade between floors (the facade's own motion, its storey shape) or
    # against a wall (fixed): the run's own pair geometry
    special = list(getattr(result, "facades", None) or {}) + list(getattr(result, "walls", None) or {})
    if own and special and result.geo is not None:
        from pounding.framework.engine.pairs import pair_gap

        for p in special:
            out[:, p] = [pair_gap(np.ascontiguousarray(q), p, np.inf, result.geo) for q in result.q]
    return out


# =============================================================================
# The drawing: rest geometry and its topology, displaced per instant
# =============================================================================


@dataclass
class Drawing:
    """3-D drawing of all buildings at rest, with the data to displace it.

    Attributes
    ----------
    points : ndarray (np, 3)
        Rest coordinates [m].
    point_building : ndarray (np,) int
    lo, hi : ndarray (np,) int
        Floor below / above each point (0-based storey, -1 = ground).
    w : ndarray (np,)
        Weight of ``hi`` in the linear interpolation (1 at a floor).
    cells : list of tuple of int
        Point indices of every cell.
    cell_kind : ndarray (nc,) int
        0 slab, 1 line, 2 panel.
    cell_building, cell_storey : ndarray (nc,) int
    slab_cell : dict (building, storey 0-based) -> cell index
    cell_element : ndarray (nc,) int
        Index of the cell's element in its building's list (0-based), -1 for slabs.
    """

    points: np.ndarray
    point_building: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    w: np.ndarray
    cells: list
    cell_kind: np.ndarray
    cell_building: np.ndarray
    cell_storey: np.ndarray
    slab_cell: dict
    cell_element: np.ndarray | None = None

    @classmethod
    def build(cls, scene, names: Sequence[str] | None = None) -> "Drawing":
        """Drawing of the scene's buildings (in the order of ``names``, default scene order)."""
        names = [b.name for b in scene.buildings] if names is None else list(names)
        pts: list = []
        pbld: list = []
        index: dict = {}
        cells, kinds, cb, cs, ce = [], [], [], [], []
        slab_cell = {}

        def point(b: int, x: float, y: float, z: float) -> int:
            key = (b, round(x, 9), round(y, 9), round(z, 9))
            j = index.get(key)
            if j is None:
                j = index[key] = len(pts)
                pts.append((x, y, z))
                pbld.append(b)
            return j

        levels_of = []
        for b, name in enumerate(names):
            bld = scene.building(name)
            levels = np.concatenate([[0.0], [s.elevation for s in bld.slabs]])
            levels_of.append(levels)
            for f, slab in enumerate(bld.slabs):
                slab_cell[(b, f)] = len(cells)
                cells.append(tuple(point(b, float(x), float(y), float(slab.elevation)) for x, y in slab.vertices))
                kinds.append(SLAB)
                cb.append(b)
                cs.append(f + 1)
                ce.append(-1)
            for e_idx, el in enumerate(bld.elements):
                p0, d = np.asarray(el.point, float), np.asarray(el.direction, float)
                out = el.outline()
                z_base = el.base_elevation(bld.storey_heights)  # the outline is drawn from the element's base

                def at(s: float, z: float, p0=p0, d=d, z_base=z_base) -> int:
                    x, y = p0 + s * d
                    return point(b, float(x), float(y), float(z + z_base))

                for s0, z0, s1, z1 in out.get("lines", []):
                    cells.append((at(s0, z0), at(s1, z1)))
                    kinds.append(LINE)
                    cb.append(b)
                    cs.append(_storey_of(levels, max(z0, z1) + z_base))
                    ce.append(e_idx)
                for s0, s1, z0, z1 in out.get("panels", []):
                    cells.append((at(s0, z0), at(s1, z0), at(s1, z1), at(s0, z1)))
                    kinds.append(PANEL)
                    cb.append(b)
                    cs.append(_storey_of(levels, max(z0, z1) + z_base))
                    ce.append(e_idx)

        points = np.array(pts, dtype=float).reshape(-1, 3)
        pb = np.array(pbld, dtype=np.int64)
        lo = np.empty(len(points), dtype=np.int64)
        hi = np.empty(len(points), dtype=np.int64)
        w = np.empty(len(points))
        for j, (z, b) in enumerate(zip(points[:, 2], pb)):
            lo[j], hi[j], w[j] = _bracket(levels_of[b], z)
        return cls(points, pb, lo, hi, w, cells, np.array(kinds, np.int64), np.array(cb, np.int64), np.array(cs, np.int64), slab_cell,
                   np.array(ce, np.int64))

    def ductility(self, result, names: Sequence[str]) -> "CellDuctility":
        """The yielding storey springs' ductility demand on the cells that draw them
        (:class:`CellDuctility`; ``result.springs`` as the run kept them, buildings in ``names`` order)."""
        return CellDuctility.of(self, result, names)

    # ------------------------------------------------------------------ motion
    def displacement(self, slabs: Sequence, cm: Sequence[np.ndarray]) -> np.ndarray:
        """Displacement (np, 3) of every point for slab motions ``cm[b]`` (storeys, 3) (or their rates)."""
        out = np.zeros((len(self.points), 3))
        for b, (sl, d) in enumerate(zip(slabs, cm)):
            m = self.point_building == b
            if not np.any(m):
                continue
            x, y = self.points[m, 0], self.points[m, 1]
            centres = np.array([s.centre for s in sl], dtype=float).reshape(-1, 2)
            lo, hi, w = self.lo[m], self.hi[m], self.w[m]
            dl = _floor_motion(d, centres, lo, x, y)
            dh = _floor_motion(d, centres, hi, x, y)
            out[m, :2] = (1.0 - w)[:, None] * dl + w[:, None] * dh
        return out

    def contact(self, slabs: Sequence, cm: Sequence[np.ndarray], pairs: Sequence, tol: float):
        """(in_contact (nc,) int, gap (nc,) float) of the slab cells for slab motions cm[b] (storeys, 3)."""
        from pounding.contact.geometry import signed_gap

        nc = len(self.cells)
        flag = np.zeros(nc, dtype=np.int64)
        gap = np.full(nc, np.nan)
        for a, fa, b, fb, _ in pairs:
            if (a, fa) == (b, fb):  # a slab against a fixed wall (its pair's second body): no slab's gap to draw
                continue
            g = float(signed_gap(_f64(slab_polygon(slabs[a][fa], cm[a][fa])), _f64(slab_polygon(slabs[b][fb], cm[b][fb]))))
            for key in ((a, fa), (b, fb)):
                c = self.slab_cell.get(key)
                if c is None:
                    continue
                gap[c] = g if np.isnan(gap[c]) else min(gap[c], g)
                if g <= tol:
                    flag[c] = 1
        return flag, gap

    # ------------------------------------------------------------------ vtk
    def vtk_grid(self):
        """A vtkUnstructuredGrid with the topology and rest points (no data arrays)."""
        from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
        from vtkmodules.vtkCommonCore import vtkPoints
        from vtkmodules.vtkCommonDataModel import VTK_LINE, VTK_POLYGON, VTK_QUAD, vtkCellArray, vtkUnstructuredGrid

        types = np.array([{SLAB: VTK_POLYGON, LINE: VTK_LINE, PANEL: VTK_QUAD}[int(k)] for k in self.cell_kind], dtype=np.uint8)
        offsets = np.concatenate([[0], np.cumsum([len(c) for c in self.cells])]).astype(np.int64)
        conn = np.array([j for c in self.cells for j in c], dtype=np.int64)
        ca = vtkCellArray()
        ca.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True), numpy_to_vtkIdTypeArray(conn, deep=True))
        grid = vtkUnstructuredGrid()
        pts = vtkPoints()
        pts.SetData(numpy_to_vtk(self.points.copy(), deep=True))
        grid.SetPoints(pts)
        grid.SetCells(numpy_to_vtk(types, deep=True, array_type=3), ca)  # 3 = VTK_UNSIGNED_CHAR
        return grid


def _storey_of(levels: np.ndarray, z: float) -> int:
    """Storey number of an item whose top is at z: the floor there (1-based), 0 at ground."""
    j = int(np.argmin(np.abs(levels - z)))
    if same_level(levels[j], z):
        return j
    return int(np.searchsorted(levels, z))  # inside storey i: between floors i-1 and i


def _bracket(levels: np.ndarray, z: float) -> tuple[int, int, float]:
    """(floor below, floor above, weight of above) of height z; floors 0-based, -1 ground."""
    j = int(np.argmin(np.abs(levels - z)))
    if same_level(levels[j], z):
        return j - 1, j - 1, 1.0
    if z >= levels[-1]:
        return len(levels) - 2, len(levels) - 2, 1.0
    i = int(np.searchsorted(levels, z)) - 1  # levels[i] < z < levels[i + 1]
    w = (z - levels[i]) / (levels[i + 1] - levels[i])
    return i - 1, i, float(w)


def _floor_motion(d: np.ndarray, centres: np.ndarray, f: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Plan motion (m, 2) of points (x, y) rigidly attached to floors f (-1: ground, no motion)."""
    out = np.zeros((len(f), 2))
    live = f >= 0
    if np.any(live):
        ff = f[live]
        u, v, phi = d[ff, 0], d[ff, 1], d[ff, 2]
        out[live, 0] = u - phi * (y[live] - centres[ff, 1])
        out[live, 1] = v + phi * (x[live] - centres[ff, 0])
    return out


# =============================================================================
# State at an arbitrary instant (impact frames)
# =============================================================================


class StateAt:
    """Modal state of a Result at the instants the run recorded (see the module docstring).

    Writers read states, they do not integrate: an impact instant gives the driver's own
    state just before its impulses (``Result.event_t``, ``event_q``, ``event_qd``), an output
    step the recorded one. Any other instant is refused.
    """

    def __init__(self, scene, result):
        self.r = result

    def __call__(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(q, q') (n,) at time t [s]; q' just before the impulses of impacts at exactly t."""
        r = self.r
        eps = 1e-12 * max(1.0, abs(t))
        ev_t = np.asarray(getattr(r, "event_t", np.zeros(0)), dtype=float)
        if len(ev_t):
            j = int(np.argmin(np.abs(ev_t - t)))
            if abs(ev_t[j] - t) <= eps:
                return r.event_q[j].astype(float), r.event_qd[j].astype(float)
        tt = np.asarray(r.t, dtype=float)
        k = int(np.argmin(np.abs(tt - t))) if len(tt) else -1
        if k >= 0 and abs(tt[k] - t) <= eps:
            return r.q[k].astype(float), r.qd[k].astype(float)
        raise ValueError(f"t = {t!r} s is neither an output step nor an impact instant of the run: no state was recorded there")

    def cm(self, q: np.ndarray) -> list[np.ndarray]:
        """(storeys, 3) centre-of-mass motion of every building for a stacked modal vector q."""
        out = []
        for b, s in enumerate(self.r.systems):
            i0 = self.r.mode_start[b]
            out.append((s.modes @ q[i0 : i0 + s.n_dof]).reshape(s.n_storeys, 3))
        return out


# =============================================================================
# Writing
# =============================================================================


def _impact_instants(result, impact_times) -> np.ndarray:
    times = [i.time for i in result.impacts] if impact_times is None else list(impact_times)
    times = np.unique(np.asarray(times, dtype=float))
    t = np.asarray(result.t, float)
    if t.size == 0:
        return times[:0]
    times = times[(times >= t[0] - 1e-12) & (times <= t[-1] + 1e-12)]
    # merge instants closer than 1e-12 s
    out: list[float] = []
    for x in times:
        if not out or x - out[-1] > 1e-12 * max(1.0, abs(x)):
            out.append(float(x))
    return np.array(out)


def frame_plan(result, *, every: int = 1, impact_times: Iterable[float] | None = None) -> list[tuple[float, int | None, bool]]:
    """The instants :func:`write_vtk_series` writes: (time, output index or None, is an impact instant).

    Output steps 0, every, 2 every, ...; plus each impact instant at its exact
    time (an impact on an output step uses that step, index given).
    """
    if every < 1:
        raise ValueError(f"every must be >= 1, got {every}")
    t = np.asarray(result.t, float)
    frames: dict = {}
    for k in range(0, len(t), every):
        frames[k] = (float(t[k]), k, False)
    extra = []
    for ti in _impact_instants(result, impact_times):
        k = int(np.argmin(np.abs(t - ti)))
        if abs(t[k] - ti) <= 1e-12 * max(1.0, abs(ti)):
            frames[k] = (float(t[k]), k, True)
        else:
            extra.append((float(ti), None, True))
    return sorted(list(frames.values()) + extra, key=lambda f: f[0])


@dataclass
class CellDuctility:
    """Ductility demand of the yielding storey springs, per drawn cell (NaN on cells without one).

    The cells of a storey-spring element in storey s draw its spring of that storey; its ductility
    is peak |u| / u_y (u the spring's deformation, the storey drift along the line; u_y = Fy / k0).

    Attributes
    ----------
    spring : ndarray (nc,) int
        Index of the cell's spring in the run's springs of every building, concatenated, -1: none.
    running : ndarray (nt, ns)
        Peak |u| / u_y up to every output row (the recorded rows).
    peak : ndarray (ns,)
        Peak |u| / u_y over every step of the run.
    """

    spring: np.ndarray
    running: np.ndarray
    peak: np.ndarray

    @classmethod
    def of(cls, drawing: "Drawing", result, names: Sequence[str]) -> "CellDuctility":
        springs = getattr(result, "springs", None) or {}
        nc = len(drawing.cells)
        cell_spring = np.full(nc, -1, dtype=np.int64)
        running, peak, start = [], [], 0
        for b, name in enumerate(names):
            sp = springs.get(name)
            if not sp:
                continue
            uy = np.asarray(sp["yield_deformation"], dtype=float)
            running.append(np.maximum.accumulate(np.abs(np.asarray(sp["deformation"], dtype=float)), axis=0) / uy)
            peak.append(np.asarray(sp["peak"], dtype=float) / uy)
            index = {(int(e), int(f)): start + j for j, (e, f) in enumerate(zip(sp["element"], sp["storey"]))}
            for c in np.flatnonzero(drawing.cell_building == b):
                cell_spring[c] = index.get((int(drawing.cell_element[c]), int(drawing.cell_storey[c])), -1)
            start += len(uy)
        nt = len(result.t)
        return cls(cell_spring, np.concatenate(running, axis=1) if running else np.zeros((nt, 0)),
                   np.concatenate(peak) if peak else np.zeros(0))

    def at_row(self, row: int) -> np.ndarray:
        """Running peak ductility (nc,) of every cell at output row ``row`` (NaN: no yielding spring)."""
        return self._cells(self.running[row] if self.running.shape[1] else np.zeros(0))

    def final(self) -> np.ndarray:
        """Peak ductility (nc,) of every cell over the whole run (NaN: no yielding spring)."""
        return self._cells(self.peak)

    def _cells(self, values: np.ndarray) -> np.ndarray:
        out = np.full(self.spring.shape[0], np.nan)
        has = self.spring >= 0
        out[has] = values[self.spring[has]]
        return out


def write_vtk_series(scene, result, out_dir, *, every: int = 1, scale: float = 1.0, impact_times: Iterable[float] | None = None, name: str = "pounding") -> Path:
    """Write a ParaView time series of the run: ``<name>.pvd`` + one ``<name>_NNNNNN.vtu`` per instant.

    Parameters
    ----------
    scene : Scene
        The scene that was run (for the elements' drawing and the ground motion).
    result : Result
    out_dir : path
        Created if missing.
    every : int
        Write every ``every``-th output step (plus the impact instants).
    scale : float
        Displacement magnification of the point coordinates (the ``displacement``
        and ``velocity`` arrays are never scaled).
    impact_times : iterable of float, optional
        Instants written at their exact time [s]; default the times of
        ``result.impacts``. Pass ``()`` to write the output steps only.
    name : str
        File stem.

    Returns
    -------
    Path
        The ``.pvd`` file.
    """
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    motion = Motion.from_result(result, scene)
    drawing = Drawing.build(scene, motion.names)
    grid = drawing.vtk_grid()
    plan = frame_plan(result, every=every, impact_times=impact_times)
    state = StateAt(scene, result) if any(imp for _, _, imp in plan) else None

    cd = grid.GetCellData()
    for nm, arr in (("building", drawing.cell_building), ("storey", drawing.cell_storey), ("element_type", drawing.cell_kind)):
        a = numpy_to_vtk(arr.astype(np.int32), deep=True)
        a.SetName(nm)
        cd.AddArray(a)
    duct = drawing.ductility(result, motion.names) if getattr(result, "springs", None) else None
    if duct is not None:  # yielding storey springs: colour their cells by ductility demand
        for nm, arr in (("element", drawing.cell_element.astype(np.int32)), ("ductility_peak", duct.final())):
            a = numpy_to_vtk(arr, deep=True)
            a.SetName(nm)
            cd.AddArray(a)

    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetCompressorTypeToZLib()

    rest = drawing.points
    entries = []
    walls = _write_grid(wall_grid(scene.walls), out_dir / f"{name}_walls.vtu") if scene.walls else None
    links = LinkDrawing.build(scene, motion.names, getattr(result, "links", None) or {}) if scene.links else None
    for j, (t, k, is_impact) in enumerate(plan):
        if k is not None:
            cm = [c[k] for c in motion.cm]
            cmv = [c[k] for c in motion.cm_velocity]
            if is_impact:  # report the velocity before the impulses, as for off-grid instants
                cmv = state.cm(state(t)[1])
        else:
            q, qd = state(t)
            cm, cmv = state.cm(q), state.cm(qd)
        disp = drawing.displacement(motion.slabs, cm)
        vel = drawing.displacement(motion.slabs, cmv)
        flag, gap = drawing.contact(motion.slabs, cm, motion.pairs, motion.tolerance)

        pts = vtkPoints()
        pts.SetData(numpy_to_vtk(rest + scale * disp, deep=True))
        grid.SetPoints(pts)
        pd = grid.GetPointData()
        for nm, arr in (("displacement", disp), ("velocity", vel)):
            a = numpy_to_vtk(np.ascontiguousarray(arr), deep=True)
            a.SetName(nm)
            pd.AddArray(a)
        cell_arrays = [("in_contact", flag.astype(np.int32)), ("gap", gap)]
        if duct is not None:  # running peak up to the frame (an off-grid instant: the output row before it)
            row = k if k is not None else max(int(np.searchsorted(result.t, t, side="right")) - 1, 0)
            cell_arrays.append(("ductility", duct.at_row(row)))
        for nm, arr in cell_arrays:
            a = numpy_to_vtk(arr, deep=True)
            a.SetName(nm)
            cd.AddArray(a)
        fd = grid.GetFieldData()
        for nm, arr in (("time", np.array([t])), ("impact_instant", np.array([int(is_impact)], dtype=np.int32))):
            a = numpy_to_vtk(arr, deep=True)
            a.SetName(nm)
            fd.AddArray(a)

        fname = f"{name}_{j:06d}.vtu"
        writer.SetFileName(str(out_dir / fname))
        if writer.Write() != 1:
            raise OSError(f"could not write {out_dir / fname}")
        entries.append((t, fname, 0))
        if walls is not None:
            entries.append((t, walls.name, 1))
        if links is not None:
            lname = f"{name}_links_{j:06d}.vtu"
            _write_grid(links.grid(motion.slabs, cm, k, scale), out_dir / lname)
            entries.append((t, lname, 2))

    return write_pvd(out_dir / f"{name}.pvd", entries)


def wall_grid(walls):
    """A vtkUnstructuredGrid of fixed walls: each face polyline (k, 2) extruded from z = 0 to its top,
    one quad per segment; cell data ``wall`` (index) and ``top`` [m]."""
    from vtkmodules.vtkCommonDataModel import VTK_QUAD

    pts, cells, index, tops = [], [], [], []
    for w, wall in enumerate(walls):
        face = np.asarray(wall.face, dtype=float)
        first = len(pts)
        for z in (0.0, float(wall.top)):  # the foot row, then the top row
            pts.extend((float(x), float(y), z) for x, y in face)
        n = len(face)
        for i in range(n - 1):
            cells.append((first + i, first + i + 1, first + n + i + 1, first + n + i))
            index.append(w)
            tops.append(float(wall.top))
    return _grid(np.array(pts, dtype=float).reshape(-1, 3), cells, VTK_QUAD,
                 {"wall": np.array(index, np.int32), "top": np.array(tops)})


@dataclass
class LinkDrawing:
    """The ``[[link]]`` tables as lines between their attachment points, moving with their slabs.

    Attributes
    ----------
    ends : list of ((building, storey 0-based), (building, storey 0-based))
        The slab of each end (building index in the writer's order).
    points : ndarray (n_links, 2, 3)
        Rest coordinates of the two ends [m] (z = the slab's elevation).
    direction : ndarray (n_links, 2)
        Unit vector of each link's line at rest (first point to second).
    force : list of ndarray (nt,) or None
        The run's force history of each link [N] (None when the result has none).
    """

    ends: list
    points: np.ndarray
    direction: np.ndarray
    force: list

    @classmethod
    def build(cls, scene, names: Sequence[str], records: dict) -> "LinkDrawing":
        ends, points = [], []
        for link in scene.links:
            ab = tuple((list(names).index(b), s - 1) for b, s in zip(link.between, link.storeys))
            ends.append(ab)
            points.append([(float(x), float(y), float(scene.building(b).slabs[s - 1].elevation))
                           for (x, y), b, s in zip(link.points, link.between, link.storeys)])
        return cls(ends, np.array(points, dtype=float).reshape(-1, 2, 3),
                   np.array([link.direction for link in scene.links], dtype=float).reshape(-1, 2),
                   [np.asarray(records[link.name]["force"], float) if link.name in records else None for link in scene.links])

    def displacement(self, slabs: Sequence, cm: Sequence[np.ndarray]) -> np.ndarray:
        """Displacement (n_links, 2, 3) of both ends for slab motions ``cm[b]`` (storeys, 3): each end moves
        with its slab, (u - phi (y - y_c), v + phi (x - x_c), 0)."""
        out = np.zeros_like(self.points)
        for i, pair in enumerate(self.ends):
            for e, (b, f) in enumerate(pair):
                x, y = self.points[i, e, :2]
                centre = np.asarray(slabs[b][f].centre, dtype=float)
                u, v, phi = cm[b][f]
                out[i, e, :2] = (u - phi * (y - centre[1]), v + phi * (x - centre[0]))
        return out

    def grid(self, slabs: Sequence, cm: Sequence[np.ndarray], row: int | None, scale: float):
        """The links' vtkUnstructuredGrid at one instant (slab motions ``cm``; ``row`` the output row, None
        between output steps): coordinates rest + ``scale`` x displacement, data as the module docstring says."""
        from vtkmodules.vtkCommonDataModel import VTK_LINE

        disp = self.displacement(slabs, cm)
        stretch = np.einsum("ij,ij->i", disp[:, 1, :2] - disp[:, 0, :2], self.direction)
        force = np.array([np.nan if f is None or row is None else float(f[row]) for f in self.force])
        cells = [(2 * i, 2 * i + 1) for i in range(len(self.ends))]
        grid = _grid((self.points + scale * disp).reshape(-1, 3), cells, VTK_LINE,
                     {"link": np.arange(len(self.ends), dtype=np.int32), "deformation": stretch, "force": force})
        _add(grid.GetPointData(), "displacement", disp.reshape(-1, 3))
        return grid


def _grid(points: np.ndarray, cells: Sequence[tuple], cell_type: int, cell_data: dict):
    """A vtkUnstructuredGrid of ``points`` (np, 3) and cells of one type, with the given cell arrays."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkIdList, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=True))
    grid.SetPoints(pts)
    for c in cells:
        ids = vtkIdList()
        for j in c:
            ids.InsertNextId(int(j))
        grid.InsertNextCell(cell_type, ids)
    for nm, arr in cell_data.items():
        _add(grid.GetCellData(), nm, arr)
    return grid


def _add(data, name: str, arr: np.ndarray) -> None:
    """Add ``arr`` as the named array of a vtk point, cell or field data."""
    from vtkmodules.util.numpy_support import numpy_to_vtk

    a = numpy_to_vtk(np.ascontiguousarray(arr), deep=True)
    a.SetName(name)
    data.AddArray(a)


def _write_grid(grid, path: Path) -> Path:
    """Write ``grid`` to ``path`` (VTK XML, appended raw, zlib), raising OSError when it cannot."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    writer = vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetCompressorTypeToZLib()
    writer.SetFileName(str(path))
    if writer.Write() != 1:
        raise OSError(f"could not write {path}")
    return path


def write_pvd(path, entries: Sequence[tuple]) -> Path:
    """A ParaView collection file listing (time, relative file name[, part]) entries (part 0 by default)."""
    path = Path(path)
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for t, fname, *part in entries:
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part=str(part[0] if part else 0), file=str(fname))
    tree = ET.ElementTree(root)
    ET.indent(tree, space=" ")
    tree.write(path, encoding="utf-8", xml_declaration=True)
    return path


def read_pvd(path, part: int = 0) -> list[tuple[float, Path]]:
    """(time, file) entries of one part of a ``.pvd`` collection (0: the buildings, 1: the walls, 2: the
    links), files resolved next to it."""
    path = Path(path)
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), path.parent / d.get("file")) for d in root.iter("DataSet")
            if int(d.get("part", 0)) == part]
