"""The stacked modal model of a scene: every building's modes side by side, and the slab pairs that
can touch, as the engine steps and queries them.

:class:`Model` is built once per run from the scene and its buildings' assembled systems
(:mod:`pounding.framework.model.assembly`): the modes stacked into one modal vector (n,), each
slab's rows over its building's modes, the slab pairs at common levels (with facades, walls and
bumpers), and the compiled pair queries over them (gaps, touching features and their modal rows,
:mod:`pounding.framework.engine.pairs`). It holds no state of a run: the driver
(:mod:`pounding.framework.engine.driver`) owns time and the state.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pounding.contact import geometry as geo
from pounding.framework.engine import pairs as pg
from pounding.framework.engine.bundles import Modes, PairArrays
from pounding.framework.model.assembly import System, assemble
from pounding.framework.model.levels import common_levels
from pounding.framework.model.registry import watches_contact
from pounding.framework.model.scene import Scene


@dataclass
class Feature:
    """One touching feature of a slab pair, with its modal row w (ntot,)."""

    pair: int
    point: np.ndarray
    normal: np.ndarray  # unit, from slab a towards slab b
    striker: int  # 0: a vertex of slab a hits, 1: a vertex of slab b hits
    vertex: int  # index in the striking slab's polygon, -1 face to face
    gap: float
    w: np.ndarray = field(repr=False)


class Model:
    """The stacked modal model of all buildings and their slab pairs (read-only during a run)."""

    def __init__(self, scene: Scene, systems: list[System] | None = None):
        self.scene = scene
        self.systems = systems or [assemble(b) for b in scene.buildings]
        gm = scene.ground_motion
        # one column of L per ground-motion component: L (n, c), p = -L @ ag (c = 1 or 2)
        self.directions = np.asarray(gm.directions(), dtype=float).reshape(-1, 2)
        sizes = [s.n_dof for s in self.systems]
        self.mode_start = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.n = int(sum(sizes))
        self.omega = np.concatenate([s.omega for s in self.systems])
        self.zeta = np.concatenate([s.zeta for s in self.systems])
        self.c2 = 2.0 * self.zeta * self.omega
        self.om2 = self.omega**2
        #: (n, c) modal load per unit ground acceleration of each component, p = -L ag
        self.L = np.ascontiguousarray(np.stack(
            [np.concatenate([s.participation(s.influence(d)) for s in self.systems]) for d in self.directions], axis=1))
        self.bidx = np.concatenate([[i] * n for i, n in enumerate(sizes)]).astype(np.int64)
        # slabs, numbered building by building
        self.slab_off = np.concatenate([[0], np.cumsum([s.n_storeys for s in self.systems])[:-1]]).astype(np.int64)
        slabs = [(b, f, slab) for b, s in enumerate(self.systems) for f, slab in enumerate(s.slabs)]
        nmax, kmax = max(sizes), max(len(sl.vertices) for _, _, sl in slabs)
        S = len(slabs)
        self.rows = np.zeros((S, 3, nmax))
        self.verts = np.zeros((S, kmax, 2))
        self.nvert = np.zeros(S, dtype=np.int64)
        self.centres = np.zeros((S, 2))
        self.radii = np.zeros(S)
        for s, (b, f, slab) in enumerate(slabs):
            self.rows[s, :, : sizes[b]] = self.systems[b].modes[3 * f : 3 * f + 3, :]
            k = len(slab.vertices)
            self.verts[s, :k] = slab.vertices
            self.nvert[s] = k
            self.centres[s] = slab.centre
            self.radii[s] = slab.radius
        self.n_modes = np.stack([self.mode_start, np.array(sizes, dtype=np.int64)], axis=1)
        self.slab_building = np.array([b for b, _, _ in slabs], dtype=np.int64)
        self.pairs = self._pairs()
        #: facade slabs of the pairs where a slab strikes a neighbour between its floors:
        #: {pair index: :class:`~pounding.framework.model.facade.Facade`}
        self.facades = {}
        pa = [[a, fa] for a, fa, _, _, _ in self.pairs]
        pb = [[b, fb] for _, _, b, fb, _ in self.pairs]
        axes = [self._rest_axis(p) for p in range(len(self.pairs))]
        # the pair arrays hold the facade slabs after the real ones (slab index S + v: a pair's
        # "storey" there is S + v - off[building]); the real slabs' arrays stay as they are
        facades = self._facades()
        # then the wall slabs (pounding.framework.model.walls): fixed rectangles behind the walls'
        # faces, with zero rows (infinite mass); a pair's "b" is the striking building itself, so
        # every mode range it addresses is that building's and the wall side adds nothing
        walls = self._wall_sites()
        # then the bumper slabs (pounding.framework.model.bumpers): a slab's own rows with its faces
        # towards the neighbour moved out by the layer's thickness, in place of the bare slab
        bumpers = self._bumper_sites(axes)
        V = len(facades) + len(walls) + len(bumpers)
        grows = np.zeros((S + V, 3, nmax))
        grows[:S] = self.rows
        gverts = np.zeros((S + V, kmax, 2))
        gverts[:S] = self.verts
        gnvert, gcentres, gradii = np.zeros(S + V, dtype=np.int64), np.zeros((S + V, 2)), np.zeros(S + V)
        gnvert[:S], gcentres[:S], gradii[:S] = self.nvert, self.centres, self.radii
        floors = np.full((S + V, 2), -1, dtype=np.int64)
        floors[:S, 0] = np.arange(S)
        weights = np.zeros((S + V, 2))
        weights[:S, 0] = 1.0
        for v, (a, fa, F) in enumerate(facades):
            s = S + v
            grows[s, :, : sizes[F.building]] = F.rows
            gverts[s, : len(F.vertices)] = F.vertices
            gnvert[s], gcentres[s], gradii[s] = len(F.vertices), F.centre, F.radius
            top = int(self.slab_off[F.building]) + F.storey
            floors[s] = (top - 1 if F.storey > 0 else -1, top)
            weights[s] = F.shape
            A = self.systems[a].slabs[fa].vertices
            rest = geo.rest_gap(A, F.vertices)
            self.facades[len(self.pairs)] = F
            self.pairs.append((a, fa, F.building, F.storey, rest))
            pa.append([a, fa])
            pb.append([F.building, s - int(self.slab_off[F.building])])
            axes.append(pg.rest_axis(np.asarray(A, float), F.vertices, rest))
        #: {pair index: the scene's :class:`~pounding.framework.model.scene.Wall`} of the pairs where a slab meets a wall
        self.walls = {}
        for v, (a, fa, ws) in enumerate(walls, start=len(facades)):
            s = S + v  # (rows, floors and weights stay zero, -1 and 0: the wall never moves)
            gverts[s, : len(ws.vertices)] = ws.vertices
            gnvert[s], gcentres[s], gradii[s] = len(ws.vertices), ws.centre, ws.radius
            A = np.asarray(self.systems[a].slabs[fa].vertices, float)
            rest = geo.rest_gap(A, ws.vertices)
            self.walls[len(self.pairs)] = self.scene.walls[ws.wall]
            self.pairs.append((a, fa, a, fa, rest))
            pa.append([a, fa])
            pb.append([a, s - int(self.slab_off[a])])
            axes.append(pg.rest_axis(A, ws.vertices, rest))
        #: {pair index: the :class:`~pounding.framework.model.scene.ContactRule` whose bumper stands in it}
        self.bumpers = {}
        for v, (p, side, poly, rule) in enumerate(bumpers, start=len(facades) + len(walls)):
            s, (a, fa, b, fb, _) = S + v, self.pairs[p]
            real = self.slab_index(*((a, fa) if side == 0 else (b, fb)))
            grows[s] = self.rows[real]
            gverts[s, : len(poly)] = poly
            gnvert[s], gcentres[s] = len(poly), self.centres[real]
            gradii[s] = float(np.max(np.hypot(*(poly - self.centres[real]).T)))
            floors[s, 0], weights[s, 0] = real, 1.0  # the real slab's rigid motion (the layer has no mass)
            A, B = (poly, self.verts[self.slab_index(b, fb), : self.nvert[self.slab_index(b, fb)]]) if side == 0 else \
                (self.verts[self.slab_index(a, fa), : self.nvert[self.slab_index(a, fa)]], poly)
            rest = geo.rest_gap(A, B)
            if not rest > 0.0:  # (the scene loader refuses it; a scene moved in Python, e.g. with_gap, may not)
                raise ValueError(f"a bumper layer of {rule.bumper.thickness:g} m on {rule.bumper.on!r} does not fit in the rest gap of "
                                 f"{self.pairs[p][4]:.6g} m at storey {(fa, fb)[side] + 1}: the layer would start compressed")
            self.pairs[p] = (a, fa, b, fb, rest)
            (pa if side == 0 else pb)[p] = [(a, b)[side], s - int(self.slab_off[(a, b)[side]])]
            axes[p] = pg.rest_axis(np.asarray(A, float), np.asarray(B, float), rest)
            self.bumpers[p] = rule
        self.geo = PairArrays(
            np.array(pa, dtype=np.int64).reshape(-1, 2),
            np.array(pb, dtype=np.int64).reshape(-1, 2),
            grows, self.slab_off, self.n_modes, gverts, gnvert, gcentres, gradii,
            np.array([g for *_, g in self.pairs], dtype=float),
            np.array(axes, dtype=float).reshape(-1, 2),
            floors, weights,
        )
        self.all_pairs = np.arange(len(self.pairs), dtype=np.int64)
        self._faces = None  # (faces: worked out on first use)
        self.modes = Modes(self.L, self.c2, self.om2, self.bidx, self.slab_building)

    def _pairs(self) -> list[tuple[int, int, int, int, float]]:
        """Slab pairs at a common level: (building a, storey a, building b, storey b, rest gap).

        The rest gaps run interpreted (0.4 ms a pair): loading the compiled gap would cost more."""
        out = []
        if not watches_contact(self.scene.analysis):
            return out
        for a, sa in enumerate(self.systems):
            for b in range(a + 1, len(self.systems)):
                for fa, fb in common_levels(sa, self.systems[b]):
                    out.append((a, fa, b, fb, geo.rest_gap(sa.slabs[fa].vertices, self.systems[b].slabs[fb].vertices)))
        return out

    def _facades(self) -> list:
        """(building a, storey a, Facade) for every slab whose level lies strictly between two
        floors of another building, below its roof (:mod:`pounding.framework.model.facade`)."""
        from pounding.framework.model.facade import facade

        out = []
        if not watches_contact(self.scene.analysis):
            return out
        for a, sa in enumerate(self.systems):
            for fa, slab in enumerate(sa.slabs):
                for b, sb in enumerate(self.systems):
                    if b != a:
                        F = facade(sb, b, slab.elevation)
                        if F is not None:
                            out.append((a, fa, F))
        return out

    def _wall_sites(self) -> list:
        """(building, storey, :class:`~pounding.framework.model.walls.WallSlab`) of every slab at or below a
        wall's top and every segment of its face (:func:`pounding.framework.model.walls.wall_sites`)."""
        from pounding.framework.model.walls import wall_sites

        if not watches_contact(self.scene.analysis) or not getattr(self.scene, "walls", ()):
            return []
        return wall_sites(self.systems, self.scene.walls, self.scene)

    def _bumper_sites(self, axes: list) -> list:
        """(pair, side (0: the bumper is on slab a, 1: on b), offset polygon (k, 2) [m], rule) of every
        common-level pair a ``[[contact]]`` bumper stands in (:mod:`pounding.framework.model.bumpers`);
        ``axes`` the pairs' rest axes (a to b)."""
        from pounding.framework.model.bumpers import bumper_pairs, offset_facing

        if not watches_contact(self.scene.analysis) or not any(getattr(r, "bumper", None) for r in self.scene.contacts):
            return []
        names = [s.name for s in self.systems]
        out = []
        for p, rule in sorted(bumper_pairs(self.systems, self.pairs, self.scene.contacts).items()):
            a, fa, b, fb, _ = self.pairs[p]
            side = 0 if names[a] == rule.bumper.on else 1
            on = self.slab_index(*((a, fa) if side == 0 else (b, fb)))
            toward = axes[p] if side == 0 else -np.asarray(axes[p])
            out.append((p, side, offset_facing(self.verts[on, : self.nvert[on]], toward, rule.bumper.thickness), rule))
        return out

    def _rest_axis(self, p: int) -> np.ndarray:
        a, fa, b, fb, rest = self.pairs[p]
        sa, sb = self.slab_index(a, fa), self.slab_index(b, fb)
        return pg.rest_axis(self.verts[sa, : self.nvert[sa]], self.verts[sb, : self.nvert[sb]], rest)

    def local_stiffness(self, pair: np.ndarray, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """Local stiffness [N/m] (m,) of the element struck at every contact point (m, 2) [m] with
        unit normal (m, 2) of the pairs ``pair`` (m,): the column or wall a slab strikes between a
        neighbour's floors (:func:`pounding.framework.model.facade.local_stiffness`), inf at a slab."""
        from pounding.framework.model.facade import struck_stiffness

        return struck_stiffness(self.scene, self.systems, self.facades, pair, points, normals)

    def update_peaks(self, z0: np.ndarray, z1: np.ndarray, h: float, peak: np.ndarray) -> None:
        """peak (S, 3) <- max(peak, |(u, v, phi)|) of every slab over a step of h [s] between the
        modal states z0, z1 (n, 3) (:func:`pounding.framework.engine.kernel.update_peaks`; h = 0: at z1)."""
        from pounding.framework.engine.kernel import update_peaks

        update_peaks(self.rows, self.geo.off, np.ascontiguousarray(z0, dtype=float), np.ascontiguousarray(z1, dtype=float), float(h),
                     self.n_modes, self.slab_building, peak)

    def energy(self, z: np.ndarray, E: np.ndarray) -> dict:
        """Energy account per building [J]: the work E (n_buildings, 3) booked by a run, and the
        kinetic and strain energy of the modal state z (n, 3)."""
        out = {}
        for i, s in enumerate(self.systems):
            sl = slice(self.mode_start[i], self.mode_start[i] + s.n_dof)
            out[s.name] = {
                "input": float(E[i, 0]),
                "damping": float(E[i, 1]),
                "contact_forces": float(E[i, 2]),
                "kinetic": float(0.5 * np.sum(z[sl, 1] ** 2)),
                "strain": float(0.5 * np.sum((s.omega * z[sl, 0]) ** 2)),
            }
        return out

    def slab_index(self, building: int, storey: int) -> int:
        return int(self.slab_off[building] + storey)

    def slab_dofs(self, x: np.ndarray, building: int, storey: int) -> np.ndarray:
        """(u, v, phi) (3,) [m, m, rad] of a slab from a stacked modal vector x (n,) (or their rates from
        modal velocities): :func:`pounding.framework.engine.pairs.slab_dofs`, the compiled core's."""
        out = np.empty(3)
        pg.slab_dofs(self.geo.rows, self.geo.off, self.geo.n_modes, int(building), int(storey), np.ascontiguousarray(x, dtype=float), out)
        return out

    def pair_gap(self, q: np.ndarray, p: int, cutoff: float | None = None) -> float:
        """Signed gap [m] of pair p for modal displacements q.

        With ``cutoff``, a cheap lower bound (rest gap minus the relative motion of the
        slabs, :func:`~pounding.contact.geometry.clearance_bound`) is returned whenever it exceeds the
        cutoff: callers that only compare the gap with thresholds <= cutoff get the same
        answers without the polygon test.
        """
        return float(pg.pair_gap(np.ascontiguousarray(q), p, np.inf if cutoff is None else float(cutoff), self.geo))

    def faces(self, p: int) -> bool:
        """Whether the slabs of pair p face each other at rest, with no other building between them at
        their level (:func:`pounding.framework.model.placement.outlines_face`): a slab pair, or a
        slab and a neighbour's facade (a bumper's pair by its bare slabs). The slabs of a pair that does
        not (the ends of a row) strike the building between them first. A slab faces the wall it is
        paired with (a wall that a neighbour screens is not: :mod:`pounding.framework.model.walls`)."""
        if self._faces is None:
            from pounding.framework.model.placement import outlines_face

            out = []
            for q, (a, fa, b, fb, _) in enumerate(self.pairs):
                if q in self.walls:
                    out.append(True)
                    continue
                slab = self.systems[a].slabs[fa]
                other = self.facades[q].vertices if q in self.facades else self.systems[b].slabs[fb].vertices
                out.append(outlines_face(self.scene, a, b, slab.vertices, other, float(slab.elevation)))
            self._faces = out
        return self._faces[p]

    def gaps(self, q: np.ndarray, plist: np.ndarray, cutoff: float | None = None) -> np.ndarray:
        """Signed gaps [m] of the pairs ``plist`` (int array), lower bounds above ``cutoff``."""
        return pg.pair_gaps(np.ascontiguousarray(q), plist, np.inf if cutoff is None else float(cutoff), self.geo)

    def touching(self, q: np.ndarray, plist: np.ndarray, tol: float, deep: bool = False):
        """Touching features of the pairs ``plist``, stacked: a :class:`~pounding.framework.engine.bundles.Features`."""
        return pg.struck_features(np.ascontiguousarray(q), plist, float(tol), bool(deep), self.n, self.geo)

    def touching_shares(self, q: np.ndarray, plist: np.ndarray, tol: float, named: bool = False):
        """:meth:`touching` with ``deep``, and the share (m,) of one whole contact each point stands
        for, fixed by the rest faces (:mod:`pounding.framework.engine.face_shares`); with ``named``,
        each point's identity too (``SharedPoints.point``, for a law that keeps a state by point)."""
        from pounding.framework.engine.face_shares import rest_face_ends, rest_point_names, touching_with_shares

        if getattr(self, "_face_ends", None) is None:  # found once, when a force law first needs them
            self._face_ends = rest_face_ends(self.geo)
        names = None
        if named:  # (only a law that keeps a state by point asks)
            if getattr(self, "_point_names", None) is None:
                self._point_names = rest_point_names(self.geo, self._face_ends)
            names = self._point_names
        return touching_with_shares(q, plist, tol, self.n, self.geo, self._face_ends, names)

    def row(self, q: np.ndarray, p: int, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
        """Modal row w (ntot,) of a contact at ``point`` with ``normal`` from slab a to slab b.

        d gap = w . dq, and an impulse pair I pushing the slabs apart changes q' by w I.
        """
        return pg.pair_row(np.ascontiguousarray(q, dtype=float), p, float(point[0]), float(point[1]), float(normal[0]), float(normal[1]), self.geo)

    def features(self, q: np.ndarray, p: int, tol: float) -> list[Feature]:
        f = pg.pair_features(np.ascontiguousarray(q), p, float(tol), self.n, self.geo)
        return [
            Feature(p, f.Q[j].copy(), f.N[j].copy(), int(f.who[j]), -1 if f.face[j] >= 0 else int(f.idx[j]), float(f.gap[j]),
                    f.W[j].copy())
            for j in range(f.count)
        ]
