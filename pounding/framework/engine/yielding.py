"""Yielding storey springs inside the pounding driver (the Python path).

The same equations as :mod:`pounding.framework.engine.inelastic` (contact off), on the driver's stacked
modal model: every spring's force is its initial elastic part (in the modes) plus a remainder
f = r - k0 u, a modal load g = G^T f. A step of any length h from (z, t) (a grid step, the rest of
one after an impact, a trial of the impact locator) is

    z_lin = step with loads p(t) + fc - g0 at the start and p(t + h) + fc1 at the end,
    u1 + S(h) f(u1) = G q_lin          (Newton, as in the contact-free stepping),
    z1 = z_lin - B1 G^T f(u1),

with S(h) = G diag(B1(h)) G^T per Newton group: a building's springs, or those of the buildings
that links between slabs (the scene's ``[[link]]`` tables, :mod:`pounding.framework.engine.link_table`)
join, which are coupled; groups are uncoupled. A link between slabs has no split (k0 = 0): its whole
force is the remainder. A trial
writes only a trial buffer (:class:`~pounding.framework.engine.bundles.LinkTrial`); the driver commits it with the step it
accepts, so a rejected or bisected step leaves the springs as they were. Impulses change
velocities only, so the springs' states stay valid across impacts.

Steps in which forces act that depend on the end state (pairs held in sustained contact, a
force law's points pressed) solve the springs by an outer fixed-point loop on their end remainders around
the contact solve, compiled (:func:`pounding.framework.engine.spring_core.contact_fixed_point` for
force laws, :meth:`Yielding.with_contact`; :func:`pounding.framework.engine.held.held_fixed_point` for
held contact): the map's contraction is the share of a
spring's end deformation its own remainder takes back in the step (S k0, below 1; ~1e-2 for
storeys at dt = 0.01 s), so it converges in a few passes; it is solved to the same tolerance. A
link between slabs has k0 = 0, so its share is S k_t: a link much stiffer than the step's inertia
(S k_t >> 1) makes the plain map expand, and the relaxed passes below are then what converge.

Between contact events the driver's grid steps run compiled (:meth:`Yielding.advance`,
:func:`pounding.framework.engine.spring_core.stretch`): the same step, and the slab pairs' check of the
elastic kernel after it; a step ending with a pair within the contact tolerance is rolled back for
the driver's Python step, which handles every contact event. Grid steps with pairs held in
sustained contact run compiled too (:meth:`Yielding.advance_held`,
:func:`pounding.framework.engine.held.held_stretch` with the links), each the held step's fixed point, until
an event the driver handles. The springs are links with laws in flat arrays
over every building (:class:`Yielding`); both paths solve them with the same compiled functions,
which take the scene's laws as arguments (:mod:`pounding.framework.engine.links`), so they agree to
rounding (bit for bit measured where no contact force acts at a step's end).
"""

from __future__ import annotations

import numpy as np

from pounding.framework.engine.bundles import HeldPairs, LinkPass, LinkRecord, Links, LinkStepping, LinkTrial, PressedPoints, Status
from pounding.framework.engine.inelastic import NEWTON_TOL, SpringSet, spring_set

#: what a diverged Newton of the links suggests: a smaller step, or, for a damper whose force rises
#: with an infinite slope at rest (a viscous exponent below 0.1), its brace (docs/modelling.md)
NEWTON_HINT = ("try a smaller dt; a viscous damper with an exponent below 0.1 converges modelled with its brace "
               "stiffness as `maxwell`")


class Block:
    """The yielding storey springs of one building: its slice of the flat link arrays, its own modal
    slice ``sl``, and the Newton group it is solved in (``group``)."""

    def __init__(self, springs, building: int, lo: int, sl: slice, group: int):
        self.springs = springs
        self.building = building
        self.lo, self.hi = lo, lo + springs.size
        self.sl = sl
        self.group = group


class Group:
    """A Newton group: the links of consecutive buildings ``first..last`` solved together (buildings
    joined by a ``[[link]]``, or one building), their slice ``lo:hi`` of the flat link arrays, and
    their modes ``sl`` of the stacked model (one contiguous range)."""

    def __init__(self, first: int, last: int, lo: int, hi: int, sl: slice, tol: float):
        self.first, self.last = first, last
        self.lo, self.hi = lo, hi
        self.sl = sl
        self.tol = tol

    @property
    def building(self) -> int:
        """The group's first building (its only one unless links join it to the next)."""
        return self.first


#: drift ratio [-] that scales the Newton tolerance of a building whose links have no yield deformation
#: (dampers, linear springs): 1/1000 of the storey height, the order of a frame's yield drift
NO_YIELD_DRIFT = 1e-3


def newton_scale(scales: np.ndarray, heights: np.ndarray) -> float:
    """The deformation [m] that scales a group's Newton tolerance: its links' smallest yield
    deformation (the laws' ``deformation_scale``, ``scales``), or, when none yields, NO_YIELD_DRIFT of
    the lowest storey height of its buildings (``heights``)."""
    finite = scales[np.isfinite(scales)]
    return float(finite.min()) if finite.size else NO_YIELD_DRIFT * float(np.min(heights))


class Yielding:
    """The links with laws of a driver's model, in flat arrays
    (:class:`~pounding.framework.engine.bundles.Links`, stepped by :mod:`pounding.framework.engine.spring_core`):
    every building's yielding storey springs (``blocks``) and the scene's links between slabs
    (``joined``: (Link, flat index) pairs, :mod:`pounding.framework.engine.link_table`), solved in
    Newton groups of the buildings the links join (``groups``). ``Yielding.of`` is None when there are none.

    Attributes
    ----------
    laws : tuple of type
        The run's law classes; ``updates`` their compiled updates, the tuple the stepping takes.
    links : Links
    now : LinkTrial
        The committed links (remainders f (ns,), law states, modal load g (n,)).
    rec : LinkRecord
        Peaks, last tangents, the remainders' work per building (and the links between slabs' part of
        it), Newton counts per group, and the output rows' histories (allocated by :meth:`record_rows`).
    """

    def __init__(self, groups: list[Group], blocks: list[Block], joined: list, laws: tuple, law: np.ndarray,
                 G: np.ndarray, params: np.ndarray, k0: np.ndarray, n: int, n_buildings: int):
        from pounding.framework.engine.links import law_tuple

        self.groups, self.blocks, self.joined = groups, blocks, joined
        self.n = n
        self.laws = laws
        self.updates = law_tuple(self.laws)
        ns = law.shape[0]
        self.n_state = max(cls.n_state for cls in laws)
        joins = np.zeros(ns)
        joins[[s for _, s in joined]] = 1.0
        self.links = Links(
            law, G, np.array([grp.lo for grp in groups] + [ns], dtype=np.int64),
            np.array([[grp.sl.start, grp.sl.stop - grp.sl.start] for grp in groups], dtype=np.int64).reshape(-1, 2),
            k0, np.array([grp.tol for grp in groups]), params, joins,
        )
        self.now = LinkTrial(np.zeros(ns), np.zeros((ns, self.n_state)), np.zeros(n))
        self.rec = LinkRecord(np.zeros(ns), self.links.k0.copy(), np.zeros(n_buildings),
                              np.zeros((len(groups), 3), dtype=np.int64), np.zeros((3, 1, ns)), np.zeros(n_buildings))
        # the committed links and the records, by name (the driver and the energy account read them;
        # the same arrays as the bundles', which the compiled stretch updates in place)
        self.f, self.state, self.g = self.now.f, self.now.state, self.now.g
        self.peak, self.work, self.joined_work = self.rec.peak, self.rec.work, self.rec.joined_work
        self._S: dict = {}
        self._no_S = np.zeros((0, 0))  # the booking reads no compliance
        self._buffers = None

    @classmethod
    def of(cls, scene, model, tolerance: float = NEWTON_TOL) -> "Yielding | None":
        """The links of ``scene`` on the driver's ``model`` (storey springs and links between slabs);
        ``tolerance`` is the Newton residual's, as a fraction of every group's smallest yield deformation."""
        from pounding.errors import InputError
        from pounding.framework.engine.link_table import link_groups, link_row

        names = [b.name for b in scene.buildings]
        sets = []
        for i, b in enumerate(scene.buildings):
            try:
                sets.append(spring_set(b, i))
            except InputError as exc:
                raise exc.located(file=str(scene.source) if scene.source else None) from None
        ends = [tuple(names.index(nm) for nm in k.between) for k in scene.links]
        active = [i for i, sp in enumerate(sets) if sp.size] + [i for e in ends for i in e]
        if not active:
            return None
        laws: list = []
        for cls_ in [c for sp in sets if sp.size for c in sp.laws] + [type(k.law) for k in scene.links]:
            if cls_ not in laws:
                laws.append(cls_)
        lay = _Layout(scene, model, tuple(laws), tolerance)
        for first, last in link_groups(len(names), ends, active):
            lay.open(first, last)
            for i in range(first, last + 1):
                if sets[i].size:
                    lay.add_springs(i, sets[i])
            for k, link in enumerate(scene.links):
                if first <= ends[k][0] <= last:
                    lay.add_link(link, link_row(scene, model, link))
            lay.close()
        return cls(lay.groups, lay.blocks, lay.joined, lay.laws, *lay.arrays(), model.n, len(model.systems))

    @property
    def size(self) -> int:
        return self.now.f.shape[0]

    def record_rows(self, n_out: int) -> np.ndarray:
        """Allocate the output rows' histories (3, n_out, ns) and return them."""
        self.rec = self.rec._replace(hist=np.zeros((3, n_out, self.size)))
        return self.rec.hist

    def S(self, B1: np.ndarray) -> np.ndarray:
        """The step's compliance (ns, ns), block diagonal by Newton group: G diag(B1) G^T for the
        stacked B1 = B[:, 0, 1] (n,) of the step (:func:`pounding.framework.engine.spring_core.compliance`),
        kept per distinct B1."""
        from pounding.framework.engine.spring_core import compliance

        key = B1.tobytes()
        out = self._S.get(key)
        if out is None:
            if len(self._S) > 256:
                self._S.clear()
            # the compiled compliance, which the compiled impact search forms at its trial steps too
            out = self._S[key] = compliance(self.links, np.ascontiguousarray(B1, dtype=float))
        return out

    def record(self, k: int, every: int) -> None:
        """Record grid instant k, every ``every``-th, into the output rows' histories
        (:func:`~pounding.framework.engine.spring_core.record_links`: deformation, force and dissipated
        energy of every link, groups in order)."""
        from pounding.framework.engine.spring_core import record_links

        record_links(self.state, int(k), int(every), self.rec.hist)

    def block_rows(self, blk: Block) -> np.ndarray:
        """The rows (ns_b, n_b) of a building's storey springs over its own modes."""
        off = blk.sl.start - self.groups[blk.group].sl.start
        return np.ascontiguousarray(self.links.G[blk.lo:blk.hi, off : off + blk.sl.stop - blk.sl.start])

    def histories(self, hist: np.ndarray, names: list) -> dict:
        """Per building name with yielding springs: :func:`spring_record` of its springs."""
        out = {}
        for blk in self.blocks:
            lo, hi = blk.lo, blk.hi
            out[names[blk.building]] = spring_record(blk.springs, hist[0, :, lo:hi], hist[1, :, lo:hi], hist[2, :, lo:hi],
                                                     self.peak[lo:hi].copy(), self.block_rows(blk))
        return out

    def joined_histories(self, hist: np.ndarray, names: list, mode_start, n_modes) -> dict:
        """Per link between slabs (by name): :func:`link_record` of its histories and totals, with its
        row over each building's own modes (``names``, their first stacked modes and mode counts)."""
        out = {}
        for link, s in self.joined:
            grp = next(g for g in self.groups if g.lo <= s < g.hi)
            row = np.zeros(self.n)
            row[grp.sl] = self.links.G[s, : grp.sl.stop - grp.sl.start]
            rows = {nm: row[int(mode_start[names.index(nm)]) : int(mode_start[names.index(nm)]) + n_modes[names.index(nm)]].copy()
                    for nm in dict.fromkeys(link.between)}
            out[link.name] = link_record(link, hist[0, :, s], hist[1, :, s], hist[2, :, s], float(self.peak[s]), self.state[s], rows)
        return out

    def joined_energy(self) -> dict:
        """The links between slabs' own account [J]: ``dissipated`` (their laws' own dissipation along
        their paths) and ``stored`` (what their laws store now)."""
        dissipated = sum(float(self.state[s, 2]) for _, s in self.joined)
        stored = sum(float(type(link.law).stored_energy(self.state[s], self.links.params[s])) for link, s in self.joined)
        return {"dissipated": dissipated, "stored": stored}

    def _diverged(self, j: int, t: float | None = None) -> FloatingPointError:
        when = "" if t is None else f" in the step starting at t = {t:g} s"
        grp = self.groups[j]
        who = f"building {grp.first}" if grp.first == grp.last else f"buildings {grp.first} to {grp.last} (joined by links)"
        return FloatingPointError(f"{who}: the links' Newton iteration did not converge{when} ({NEWTON_HINT})")

    def _trial(self) -> LinkTrial:
        # slots a narrower law does not write keep their committed values
        return LinkTrial(np.empty(self.size), self.state.copy(), np.empty(self.n))

    def step(self, z: np.ndarray, p0: np.ndarray, p1: np.ndarray, tr, h: float):
        """A step of h [s] from z (n, 3) with the modal loads p0 (the links' -g0 in it) and p1 (n,) at
        its ends, no force depending on its end (:func:`pounding.framework.engine.spring_core.spring_step`,
        the compiled stretch's step); tr the integrator's transition for h (A, B). Returns (z1, trial)."""
        from pounding.framework.engine.spring_core import spring_step

        out = self._trial()
        B = np.ascontiguousarray(tr.B)
        j, z1 = spring_step(self.updates, np.ascontiguousarray(tr.A), B, z, p0, p1, float(h), self.links,
                            self.S(np.ascontiguousarray(B[:, 0, 1])), self.now, out)
        if j >= 0:
            raise self._diverged(j)
        return z1, out

    def at(self, q1: np.ndarray, h: float) -> LinkTrial:
        """Remainders and trial states of a step of h [s] ending at displacements q1 (n,) (the fixed-point pass)."""
        from pounding.framework.engine.spring_core import forces_at

        out = self._trial()
        forces_at(self.updates, self.links, float(h), np.ascontiguousarray(q1, dtype=float), self.now, out)
        return out

    def with_contact(self, h: float, B: np.ndarray, z1: np.ndarray, trial: LinkTrial, W: np.ndarray, gap: np.ndarray,
                     rate: np.ndarray, solve, args):
        """The links and the contact forces of a step of h [s] solved together
        (:func:`pounding.framework.engine.spring_core.contact_fixed_point`), from the links' own step
        (:meth:`step`: end state z1 (n, 3), trial ``trial``) and the points it presses: rows W (m, n),
        end gaps [m] and rates [m/s] (m,) without contact forces, and the contact law's solve
        ``solve(args, gap, rate)`` (:meth:`~pounding.contact.base.ContactLaw.forces_solver`: compiled,
        the whole solve runs compiled; else the same function as Python). B (n, 3, 2) the step's
        end-load maps. Returns (z1, lambda, gap, rate, trial): the step's end state with the forces,
        the forces (m,) [N], the points' end gaps and rates without them, and the links' trial."""
        from pounding.compiler import is_compiled
        from pounding.framework.engine.spring_core import contact_fixed_point

        out = self._trial()
        g = trial.g.copy()
        solver = contact_fixed_point if is_compiled(solve) else contact_fixed_point.py_func
        pressed = PressedPoints(np.ascontiguousarray(W), np.ascontiguousarray(gap, dtype=float),
                                np.ascontiguousarray(rate, dtype=float))
        fixed = solver(self.updates, LinkPass(self.links, self.now, out), float(h), np.ascontiguousarray(B[:, 0, 1]),
                       np.ascontiguousarray(B[:, 1, 1]), pressed, np.ascontiguousarray(z1[:, 0]),
                       np.ascontiguousarray(trial.state[:, 0]), g, solve, args)
        if fixed.status != Status.DONE:
            raise self.fixed_point_error()
        load = W.T @ fixed.lam - (g - trial.g)  # the forces' modal load and the links' change of end load
        return z1 + B[:, :, 1] * load[:, None], fixed.lam, fixed.gap, fixed.rate, out

    @staticmethod
    def fixed_point_error() -> FloatingPointError:
        """What a fixed point that did not converge raises."""
        return FloatingPointError("the fixed point between the links (yielding storey springs, dampers, links between slabs) "
                                  f"and the contact forces did not converge ({NEWTON_HINT})")

    def held_step(self, z, p0, p1, A, B, h: float, modes, held, geo):
        """A held step of h [s] with the links' end remainders by the fixed point around it
        (:func:`pounding.framework.engine.held.held_fixed_point`; arguments as there).
        Returns (step, trial): the :class:`~pounding.framework.engine.bundles.HeldStep` (contact forces
        only) and the links' trial (:class:`~pounding.framework.engine.bundles.LinkTrial`)."""
        from pounding.framework.engine.held import held_fixed_point

        out = self._trial()
        fixed = held_fixed_point(self.updates, z, p0, p1, A, B, h, modes, held, geo, LinkPass(self.links, self.now, out))
        if fixed.status != Status.DONE:
            raise self.fixed_point_error()
        return fixed.step, out

    def stepping(self) -> LinkStepping:
        """The links as the compiled booking and stretches read them (the compliance is the stretch's
        own: none here)."""
        return LinkStepping(self.links, self._no_S, self.now, self.rec)

    def booking_buffers(self) -> tuple:
        """Work arrays of :func:`~pounding.framework.engine.spring_core.book_links` (per building, five
        per mode, four), made once."""
        if self._buffers is None:
            n, nb = self.n, self.rec.work.shape[0]
            self._buffers = (np.empty(nb), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(4))
        return self._buffers

    def commit(self, sp: LinkTrial) -> None:
        """Commit the links' trial ``sp`` of a step the driver took in Python (:func:`~pounding.framework.engine.spring_core.commit_trial`)."""
        from pounding.framework.engine.spring_core import commit_trial

        commit_trial(self.now, sp, self.peak)

    def energy(self, building: int, q: np.ndarray, omega: np.ndarray, start: int) -> dict:
        """Strain and hysteretic energy of a building's storey springs [J] at modal displacements q (n,),
        and ``links``: the work the links between slabs did on it (minus the part of the remainders'
        work they took, which is not its springs')."""
        links = -float(self.joined_work[building])
        for blk in self.blocks:
            if blk.building != building:
                continue
            u = self.block_rows(blk) @ q[blk.sl]
            stored = float(blk.springs.stored_energy(self.state[blk.lo:blk.hi]).sum())
            k0 = self.links.k0[blk.lo:blk.hi]
            elastic = 0.5 * float(np.sum(k0 * u * u))
            return {"elastic_springs": elastic, "stored": stored, "links": links,
                    "hysteretic": elastic + float(self.work[building]) + links - stored}
        return {"elastic_springs": 0.0, "stored": 0.0, "hysteretic": float(self.work[building]) + links, "links": links}

    # ------------------------------------------------------------ the compiled stretch
    def advance(self, driver, k0: int, k1: int):
        """Grid steps k0 -> k1 compiled (:func:`pounding.framework.engine.spring_core.stretch`), until a slab
        pair comes within the contact tolerance: then (k, OVERLAP, pair) with the state at the start
        of step k, which the driver takes in Python (``Driver.python_step``). Same answers as
        :func:`pounding.framework.engine.free_stretch.advance` (DONE or OVERLAP)."""
        from pounding.framework.engine.spring_core import stretch

        tr = driver.transition(driver.dt)
        S = self.S(np.ascontiguousarray(tr.B[:, 0, 1]))
        run = LinkStepping(self.links, S, self.now, self.rec)
        end = stretch(self.updates, tr, driver.model.modes, driver.ground, driver.z, int(k0), int(k1), driver.rec,
                      driver.kgeo, float(driver.tol), run)
        if end.status == Status.DIVERGED:
            raise FloatingPointError(f"the links' Newton iteration did not converge in the step starting at "
                                     f"t = {end.k * driver.dt:g} s ({NEWTON_HINT})")
        return end

    def advance_held(self, driver, mask: np.ndarray, k0: int, k1: int):
        """Grid steps k0 -> k1 with the pairs ``mask`` (P,) bool held (updated in place), compiled
        (:func:`pounding.framework.engine.held.held_stretch` with the links): the driver's held Python step
        with the links, until an event the driver handles."""
        from pounding.framework.engine.held import held_stretch

        tr = driver.transition(driver.dt)
        run = LinkStepping(self.links, self.S(np.ascontiguousarray(tr.B[:, 0, 1])), self.now, self.rec)
        end = held_stretch(tr, driver.model.modes, driver.ground, driver.z, HeldPairs(driver.fc, mask), int(k0),
                           int(k1), driver.rec, driver.model.geo, driver.settings, driver.rules, self.updates, run)
        if end.status == Status.DIVERGED:
            raise self.fixed_point_error()
        return end


class _Layout:
    """The flat link arrays of a run, built group by group (:meth:`Yielding.of`): every group's storey
    springs, building by building, then the links between slabs it holds; each link's row over its
    group's modes, law index, parameters and split k0 (a storey spring's initial stiffness; 0 for a
    link between slabs, whose stiffness cannot go into the per-building modes)."""

    def __init__(self, scene, model, laws: tuple, tolerance: float):
        self.scene, self.model, self.laws, self.tolerance = scene, model, laws, tolerance
        self.start = [int(m) for m in model.mode_start]
        self.nm = [system.modes.shape[1] for system in model.systems]
        self.rows, self.pars, self.law_ids, self.k0s = [], [], [], []
        self.groups, self.blocks, self.joined = [], [], []
        self.lo = 0

    def open(self, first: int, last: int) -> None:
        """Start the group of buildings first..last (their modes: one contiguous range)."""
        self.first, self.last, self.g_lo, self.scales = first, last, self.lo, []
        self.sl = slice(self.start[first], self.start[last] + self.nm[last])

    def add_springs(self, i: int, sp: SpringSet) -> None:
        """Building i's storey springs: their rows on its own modes, placed in the group's range."""
        r = np.zeros((sp.size, self.sl.stop - self.sl.start))
        off = self.start[i] - self.sl.start
        r[:, off : off + self.nm[i]] = sp.T @ self.model.systems[i].modes
        self.rows.append(r)
        self.pars += list(sp.params)
        self.law_ids += [self.laws.index(sp.laws[t]) for t in sp.law_id]
        self.k0s += list(sp.k0)
        self.scales += list(sp.yield_deformation)
        self.blocks.append(Block(sp, i, self.lo, slice(self.start[i], self.start[i] + self.nm[i]), len(self.groups)))
        self.lo += sp.size

    def add_link(self, link, row: np.ndarray) -> None:
        """A link between slabs with its row (n,) over the stacked modes."""
        self.rows.append(row[None, self.sl])
        self.pars.append(link.params)
        self.law_ids.append(self.laws.index(type(link.law)))
        self.k0s.append(0.0)  # its whole force is the stepping's remainder
        self.scales.append(type(link.law).deformation_scale(link.params))
        self.joined.append((link, self.lo))
        self.lo += 1

    def close(self) -> None:
        """End the group: its Newton tolerance from its links' deformation scales (or its storeys)."""
        heights = np.concatenate([self.scene.buildings[i].storey_heights for i in range(self.first, self.last + 1)])
        tol = self.tolerance * newton_scale(np.array(self.scales), heights)
        self.groups.append(Group(self.first, self.last, self.g_lo, self.lo, self.sl, tol))

    def arrays(self) -> tuple:
        """(law (ns,), G (ns, nmax), params (ns, width), k0 (ns,)): the flat arrays, zero-padded."""
        G = np.zeros((self.lo, max(g.sl.stop - g.sl.start for g in self.groups)))
        params = np.zeros((self.lo, max(c.n_params for c in self.laws)))
        at = 0
        for r in self.rows:
            G[at : at + r.shape[0], : r.shape[1]] = r
            at += r.shape[0]
        for s, p in enumerate(self.pars):
            params[s, : len(p)] = p
        return np.array(self.law_ids, dtype=np.int64), G, params, np.array(self.k0s, dtype=float)


def spring_record(springs: SpringSet, d, r, h, peak, G) -> dict:
    """What a run keeps of one building's yielding springs (arrays at the output rate unless stated).

    Keys: ``element``, ``storey`` (ns,) int (0-based element index, 1-based storey),
    ``height`` (ns,) [m], ``k0`` (ns,) [N/m], ``yield_deformation`` (ns,) [m], ``G`` (ns, n_b)
    spring rows over the building's modes, ``deformation`` (nt, ns) [m], ``force`` (nt, ns) [N],
    ``dissipated`` (nt, ns) [J] (the law's own), ``peak`` (ns,) [m] peak |deformation| over every
    step.
    """
    return {"element": springs.element.copy(), "storey": springs.storey.copy(), "height": springs.height.copy(),
            "k0": springs.k0.copy(), "yield_deformation": springs.yield_deformation.copy(), "G": G,
            "deformation": np.ascontiguousarray(d), "force": np.ascontiguousarray(r), "dissipated": np.ascontiguousarray(h),
            "peak": peak}


def link_record(link, d, r, h, peak: float, state: np.ndarray, rows: dict) -> dict:
    """What a run keeps of one link between slabs: ``between``, ``storeys``, ``points`` (2, 2) [m],
    ``deformation``, ``force``, ``dissipated`` (nt,) at the output rate [m, N, J] (the law's own
    dissipation), ``peak`` [m] peak |deformation| over every step, ``peak_force`` [N] over the
    output rows, ``energy_dissipated`` [J] at the end, ``rows`` {building name: (n_b,) its row over
    that building's modes} (the force's modal load on building b is -force x rows[b])."""
    force = np.ascontiguousarray(r)
    return {"between": list(link.between), "storeys": list(link.storeys), "points": link.points.copy(), "rows": rows,
            "law": link.law.describe(), "deformation": np.ascontiguousarray(d), "force": force,
            "dissipated": np.ascontiguousarray(h), "peak": peak,
            "peak_force": float(np.max(np.abs(force), initial=abs(float(state[1])))), "energy_dissipated": float(state[2])}


def check_springs(scene) -> None:
    """Raise InputError (naming the scene's file) if a building's yielding springs cannot be stepped."""
    from pounding.errors import InputError

    for i, b in enumerate(scene.buildings):
        try:
            spring_set(b, i)
        except InputError as exc:
            raise exc.located(file=str(scene.source) if scene.source else None) from None
