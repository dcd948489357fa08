"""The analysis driver: owns time, never physics.

It steps every building with the chosen integrator in modal coordinates (see
:mod:`pounding.solvers.base` for why that is exact here), lets the compiled
kernel run the stretches where no slabs touch, and handles contact events in
Python:

* a step that ends with a pair overlapping is taken again from its start with
  a shorter step until the pair touches within the tolerance (``halving``, the
  paper), or with the root of the gap function (``root``, Brent's method);
* at contact, approaching features get impulses from the contact law, all the
  pairs linked through a shared building solved together (a building struck
  from both sides at once), and the rest of the step is integrated with the
  new velocities;
* a pair whose impacts accumulate (Zeno: ever smaller rebounds with k < 1) or
  that stays pressed together is switched to *sustained contact*: a rigid
  unilateral constraint force solved implicitly with each step on the points that
  touch, released when the pair opens beyond the tolerance; another point of a held
  pair that reaches contact is located and struck like any impact;
* force laws (penalty) get the end-of-step gaps and their compliances and
  return forces, solved implicitly with the step.

Everything the run needs lives in objects created here; nothing is global.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from pounding import compiler
from pounding.contact import geometry as geo
from pounding.contact.geometry import MAX_FEATURES
from pounding.contact.rules import law_name
from pounding.framework.model.units import G
from pounding.framework.engine import held as hold
from pounding.framework.engine import pairs as pg
from pounding.framework.engine.ground_load import modal_loads
from pounding.framework.engine.contact_laws import commit_laws
from pounding.framework.engine.bundles import (EventLog, Ground, HeldContact, HeldPairs, HeldSet, PairArrays, Recorder, Settings, Status,
                                               Transition)
from pounding.framework.model.scene import Scene
from pounding.framework.model.registry import INTEGRATORS
from pounding.framework.engine.results import Impact, Result
from pounding.framework.engine.stacked_model import Model
from pounding.solvers.base import TransitionCache

MAX_EVENTS_PER_STEP = 64  # bounded work per step: beyond this the pair is held in sustained contact
#: linear models of a held step (its compliance at a force law's pressed points) found in one trial step at most
HELD_FORCE_PASSES = 8


@dataclass
class Step:
    """A trial step: the start state it used, its end state, and the modal contact force at both ends.

    ``z0`` differs from the driver's state only in the acceleration, made consistent with ``f0``
    when a pair is held in sustained contact.
    """

    z0: np.ndarray
    z1: np.ndarray
    f0: np.ndarray
    f1: np.ndarray
    sp: object = None  # the yielding springs' trial (:class:`pounding.framework.engine.bundles.LinkTrial`)
    #: what a force law's trial found (:class:`pounding.framework.engine.contact_episodes.StepContacts`)
    contacts: object = None
    #: held pairs: the smallest end gap [m] of a point that was apart at the step's start (inf: none), and its pair
    #: (:func:`pounding.framework.engine.held.held_step`): below zero, that point arrives inside the step
    arrival: float = np.inf
    arriving: int = -1


class Driver:
    """One run: state, events and records. Create, call :meth:`run`, read :attr:`result`."""

    def __init__(self, scene: Scene, *, model: Model | None = None, progress=None, use_kernel: bool = True):
        self.scene = scene
        an = scene.analysis
        self.model = model or Model(scene)
        gm = scene.ground_motion
        self.gm = gm
        from pounding.framework.engine.contact_step import run_dt
        from pounding.contact.rules import events_law, scene_laws
        from pounding.framework.engine.integrator_choice import chosen_integrator

        integrator = chosen_integrator(scene)
        #: every pair's law (:func:`~pounding.contact.rules.scene_laws`): self.laws[self.pair_law[p]]
        self.laws, self.pair_law = scene_laws(scene, self.model.pairs, self.model.walls)
        #: the law of the run's events: [analysis] contact's, or beside a force law there the impulse law a
        #: table or a wall gives (one serves every pair that takes impulses: rules.events_law)
        self.law = events_law(self.laws)
        # the pairs whose law solves forces with the step, and those whose law acts by impulses at events
        # (a force law may serve some pairs of a run whose [analysis] contact acts at events: rules.pair_laws)
        self.force_pairs = self.model.all_pairs[np.array([self.laws[j].with_step for j in self.pair_law], dtype=np.bool_)]
        self.event_pairs = self.model.all_pairs[np.array([self.laws[j].at_events for j in self.pair_law], dtype=np.bool_)]
        # without a dt the step is chosen for accuracy from the significant modes and the shortest
        # contact (pounding.framework.engine.timestep, contact_step); contact_time goes to Result.info
        self.dt, self.contact_time = run_dt(scene, self.model, self.laws, self.pair_law, integrator)
        duration = float(an.duration or gm.duration)
        # cover the whole requested duration: a duration that is not a multiple of dt ends on
        # the first grid point at or after it (summary.json reports the duration covered)
        self.nsteps = max(1, int(np.ceil(duration / self.dt - 1e-9)))
        self.every = an.output_every
        self.integrator = INTEGRATORS.get(integrator)(**an.integrator_params)
        from pounding.framework.engine.contact_episodes import Episodes

        #: the force laws' contact episodes (the pairs' histories and what the run reports)
        self.episodes = Episodes()
        #: the laws (indices into self.laws) whose points pressed at the last accepted step (commit_laws)
        self._pressing_laws: set = set()
        #: whether a law keeps a state by point and so needs the points named (ContactState.point)
        self.named_points = any(law.keeps_state for law in self.laws)
        self.tol = max(float(law.tolerance) for law in self.laws)
        #: the crossing locator: impulses where the gap is zero (to rounding), the tolerance only for
        #: resting contact and chatter (see :mod:`pounding.framework.engine.crossing`)
        self.crossing = self.law.at_events and self.law.locate == "crossing"
        # the crossing locator's one-off step lengths take the integrator's partial maps (equal to
        # rounding, cheaper); the paper's locators keep transition() to the bit
        self.cache = TransitionCache(self.integrator, self.model.omega, self.model.zeta, grid_dt=self.dt, partial=self.crossing)
        self.t_grid = np.arange(self.nsteps + 1) * self.dt
        # (nsteps + 1, c): one column per ground-motion component
        self.ag = np.ascontiguousarray(np.asarray(gm.samples(self.t_grid), dtype=float).reshape(self.nsteps + 1, -1))
        if self.ag.shape[1] != self.model.L.shape[1]:
            raise ValueError(f"the ground motion has {self.ag.shape[1]} components, the modal load {self.model.L.shape[1]}")
        self.progress = progress
        self.use_kernel = use_kernel
        #: the record (times (m,), accelerations (m, c)) when it is interpolated linearly, as ag_at and
        #: the compiled impact search read it (pounding.framework.engine.event_search.record_at); else None
        self.record = _record_arrays(gm, self.ag.shape[1])
        #: the record for the compiled impact search of ``exact``, or None where the driver's own search runs
        self.search_record = self.record if self.crossing and use_kernel and self._compiled_search() else None
        self._search_maps = self.integrator.search_maps() if self.search_record is not None else None
        self._graze = None  # (graze_search: built on first use; False where there is none)
        self._step_search = None  # its bundle (step_search())
        self._no_held = None  # the search's held pairs when none is held (held_search())
        self._link_search = None  # the search's links with laws (link_search())
        n = self.model.n
        self.z = np.zeros((n, 3))
        self.fc = np.zeros(n)  # modal contact force at the current instant (force laws, sustained contact)
        self.fc_law = np.zeros(n)  # the force laws' part of it (a held step finds its own pairs' force at its start)
        n_out = self.nsteps // self.every + 1
        self.Q = np.zeros((n_out, n))
        self.V = np.zeros((n_out, n))
        self.E = np.zeros((len(self.model.systems), 3))  # ground work, damping work, contact-force work [J]
        self.impacts: list[Impact] = []
        self.event_states: list[tuple[float, np.ndarray, np.ndarray]] = []  # (t, q, q' before the impulses)
        self.sustained: set[int] = set()
        self.python_step_until_clear = False  # step in Python until every pair is clear of the tolerance
        # A closing speed below this is rounding, not an impact: it would close less than a
        # billionth of the contact tolerance in a step (identical buildings moving in phase).
        self.v_min = 1e-9 * self.tol / self.dt
        #: [m] the gap up to which a held pair's point touches: the held contact's resolution with the
        #: crossing locator (pounding.framework.engine.held.touch_gap), every point within the tolerance else
        self.touch = float(hold.touch_gap.py_func(self.tol)) if self.crossing else np.inf
        # Peaks at every step, whatever the output rate (the recorded arrays may be thinned).
        self.peak = np.zeros((len(self.model.slab_building), 3))
        self.events_in_step = 0
        self.n_located = 0
        self._quad: dict = {}
        # the energy rule's parts a transition does without (read only by the compiled core): built
        # once, not at each of an event's trial steps
        n = self.model.n
        self._no_maps = (np.zeros((0, 4)), np.zeros((0, 4)), np.zeros((0, 4, 4)))
        self._no_nodes = (np.zeros((0, n, 3, 3)), np.zeros((0, n, 3, 2)), np.zeros(0), np.zeros(0))
        self._closed_form_work = bool(np.all(self.model.omega > 0))
        self._ag_memo: dict[float, np.ndarray] = {}
        self._load_memo: dict[float, np.ndarray] = {}
        # the bundles the compiled core takes (see pounding.framework.engine.bundles)
        self.ground = Ground(self.dt, self.ag)
        self.rec = Recorder(int(self.every), self.Q, self.V, self.E, self.peak)
        # contact "none": no pair is watched
        self.kgeo = self.model.geo if self.law.watches() else _no_pairs(self.model.geo)
        compiled = bool(self.law.compiled_impulses)  # (declared by impulse laws only: ContactLaw.check_contract)
        #: [m] a gap this small is zero: twice the geometry's own zero (EPS_REL of the largest coordinate),
        #: below which the signed gap is not continuous
        self.eps = 2.0 * geo.EPS_REL * max(1.0, 1.5 * float(np.max(np.abs(self.model.verts), initial=0.0)))
        #: the impact search's bracket width where the gap is not smooth [s]
        self.xtol = 1e-14 * max(self.dt, 1.0)
        #: a wall with a restitution of its own: every impulse is the driver's, each point with its pair's
        #: restitution (:meth:`_group_impulses`)
        self.own_restitutions = len({float(law.restitution) for law in self.laws if law.at_events}) > 1
        compiled = compiled and not self.own_restitutions
        self.settings = Settings(
            self.tol, 0.0 if self.law.with_step else (-self.eps if self.crossing else -self.tol), float(self.v_min),
            -1.0 if self.crossing else float(self.law.restitution) if compiled else -1.0,
            bool(compiled and self.law.after_impact == "equilibrium"), bool(self.crossing),
        )
        #: the compiled stretches' rules (free_stretch.advance): None with the crossing locator, else the paper's;
        #: each compiles only its own branch
        self.rules = None if self.crossing else np.True_
        self.log = EventLog.empty(n, len(self.model.pairs), MAX_FEATURES)
        self.timings = {"compile_s": 0.0, "load_s": 0.0}
        from pounding.framework.engine.yielding import Yielding

        #: yielding storey springs (None: every building elastic). Their stretches between contact
        #: events run compiled (:meth:`Yielding.advance`); every contact step is the Python step.
        self.springs = Yielding.of(scene, self.model)
        if self.springs is not None:
            # spring deformation [m], force [N] and the law's dissipated energy [J] at the output rows
            self.spring_hist = self.springs.record_rows(n_out)

    # ---------------------------------------------------------------- stepping
    def _compiled_search(self) -> bool:
        """Whether the impact search can run compiled whole: the integrator has compiled maps to any
        step length (:meth:`pounding.solvers.base.Integrator.search_maps`; None without the compiler)."""
        return self.integrator.search_maps() is not None

    def step(self, z: np.ndarray, t: float, h: float, f0: np.ndarray, f1: np.ndarray | None = None):
        """One integrator step of size h from (z, t); f0, f1 extra modal loads at its ends. Returns z1."""
        tr = self.cache(h)
        p0 = self.load(t) + f0
        p1 = self.load(t + h) if f1 is None else self.load(t + h) + f1
        return hold.step(tr.A, tr.B, np.ascontiguousarray(z), p0, p1)

    def snap(self, h: float) -> float:
        """h [s], or the dyadic fraction m dt / 2**20 it differs from by rounding only (1e-10 dt).

        The rest of a grid step after a located impact is t_end - t, which differs in the
        last bits from one event to the next for the same fraction of dt: snapping gives
        one transition per distinct step size, and steps that end exactly on the grid.
        """
        x = h / self.dt * 1048576.0
        m = float(int(x + 0.5))
        if m > 0 and abs(x - m) <= 1e-4:
            return m / 1048576.0 * self.dt
        return h

    def load(self, t: float) -> np.ndarray:
        """Modal ground-motion load p = -L ag(t) (n,) [N/kg^0.5]
        (:func:`pounding.framework.engine.ground_load.modal_loads`, the compiled core's).

        An event asks for the loads at a few instants a dozen times (its trials, steps, impulses and
        energy): they are formed once per instant. Callers only read the array."""
        key = float(t)
        p = self._load_memo.get(key)
        if p is not None:
            return p
        p = np.empty(self.model.n)
        modal_loads(self.model.L, self.ag_at(t), p)
        if len(self._load_memo) > 64:
            self._load_memo.clear()
        self._load_memo[key] = p
        return p

    def ag_at(self, t: float) -> np.ndarray:
        """Ground acceleration (c,) [m/s^2] at time t (the grid samples at grid times)."""
        k = t / self.dt
        kr = int(k + 0.5)
        if abs(k - kr) < 1e-9 and 0 <= kr <= self.nsteps:
            return self.ag[kr]
        # an event's instant is asked for by its step, its energy, its impulses and the next step: the
        # record is interpolated once per instant (callers only read it, as the grid rows above)
        key = float(t)
        ag = self._ag_memo.get(key)
        if ag is None:
            if len(self._ag_memo) > 64:
                self._ag_memo.clear()
            if self.record is not None:  # the compiled impact search's own interpolation (the same numbers)
                from pounding.framework.engine.event_search import record_at

                ag = self._ag_memo[key] = record_at(key, *self.record)
            else:  # (writable, like the grid rows: a read-only array would be another type for the compiled core)
                ag = self._ag_memo[key] = np.asarray(self.gm.samples(t), dtype=float).reshape(-1)
        return ag

    def quadrature(self, h: float):
        """Energy quadrature for a step of h: (transitions to the points, points, weights)."""
        nq = self.integrator.energy_nodes
        if nq == 0:
            return [], np.zeros(0), np.zeros(0)
        x, w = np.polynomial.legendre.leggauss(nq)
        c, w = 0.5 * (x + 1.0), 0.5 * w
        return [self.cache(cj * h) for cj in c], c, w

    def accumulate(self, z0, z1, t, h, f0, f1):
        """Add one step's input, damping and contact-force work [J] to the energy audit."""
        from pounding.framework.engine.kernel import _accumulate_forces

        if not h > 0.0:  # an impact located at the step's very start: a step of no length books nothing
            return
        _accumulate_forces(self.transition(h), self.model.modes, float(h), self.ag_at(t), self.ag_at(t + h),
                           np.ascontiguousarray(z0), np.ascontiguousarray(z1), np.ascontiguousarray(f0, dtype=float),
                           np.ascontiguousarray(f1, dtype=float), self.E)

    def transition(self, h: float) -> Transition:
        """The integrator's step of h and its energy rule, as the compiled core takes them.

        Closed-form work integrals when the integrator has them (``work_maps``), else Gauss
        points on its own trajectory (``energy_nodes``), else the trapezoidal rule.
        """
        key = float(h)
        out = self._quad.get(key)
        if out is None:
            n = self.model.n
            maps = None
            if self._closed_form_work:
                work = self.integrator.partial_work_maps if self.crossing and key != self.dt else self.integrator.work_maps
                maps = work(self.cache.omega, self.cache.zeta, h)
            if maps is not None:
                WA1, WA2, WM = (np.ascontiguousarray(x, dtype=float) for x in maps)
                GA, GB, gc, gw = self._no_nodes
            else:
                WA1, WA2, WM = self._no_maps
                trs, gc, gw = self.quadrature(h)
                if trs:
                    GA = np.array([t.A for t in trs]).reshape(len(trs), n, 3, 3)
                    GB = np.array([t.B for t in trs]).reshape(len(trs), n, 3, 2)
                    gc, gw = np.asarray(gc, dtype=float), np.asarray(gw, dtype=float)
                else:
                    GA, GB, gc, gw = self._no_nodes
            if len(self._quad) > 256:
                self._quad.clear()
            tr = self.cache(h)
            out = self._quad[key] = Transition(np.ascontiguousarray(tr.A), np.ascontiguousarray(tr.B), GA, GB, gc, gw, WA1, WA2, WM)
        return out

    def gaps(self, q: np.ndarray, pairs=None, cutoff: float | None = None) -> np.ndarray:
        """Signed gaps of the pairs [m] (lower bounds where they exceed ``cutoff``)."""
        plist = self.model.all_pairs if pairs is None else np.asarray(pairs, dtype=np.int64)
        return self.model.gaps(q, plist, cutoff)

    # ---------------------------------------------------------------- the run
    def run(self) -> Result:
        """Integrate the whole record; the solve is timed apart from loading and compiling the core."""
        tc0 = compiler.compile_seconds()
        t_load = time.perf_counter()
        self.prepare()
        t0 = time.perf_counter()
        self.timings["load_s"] = t0 - t_load
        tl1 = compiler.load_seconds()
        k = 0
        self._record(0)
        if self.model.pairs and self.laws[0].watches():
            g0 = self.gaps(self.z[:, 0])
            if np.any(g0 <= self.tol):
                self.python_step_until_clear = True
        while k < self.nsteps:
            if self.use_kernel and self.sustained and not (self.fc_law.any() or self.episodes.open):  # (only impulses hold
                # pairs; a force law's contact is stepped in Python beside them until it ends, force or none)
                k_end = min(self.nsteps, k + 4096)
                end = self.advance_held(k, k_end)
            elif self.needs_python(k):
                self.python_step(k)
                k += 1
                continue
            else:
                k_end = min(self.nsteps, k + 4096)
                end = self.advance(k, k_end)
            self.drain_kernel_events()
            k_new, status = end.k, Status(end.status)
            if status in (Status.DONE, Status.RELEASED):
                k = k_new
            elif status == Status.HELD:  # the kernel applied impulses and a pair's rebounds accumulate: hold it
                self.sustained.update(int(p) for p in np.flatnonzero(self.log.zeno))
                self.log.zeno[:] = False
                k = k_new
            elif status == Status.CONTACT:  # at the end of step k_new - 1 (a closing pair within the tolerance)
                self.contact_at(self.t_grid[k_new])
                self._record(k_new)  # with the velocities after the impulses, as a Python step records
                k = k_new
                if self.force_pairs.size:  # its forces are solved with Python steps while the pair touches
                    self.python_step_until_clear = True
            else:  # OVERLAP in step k_new -> k_new + 1: the state is its start
                self.python_step(k_new)
                k = k_new + 1
            if self.progress:
                self.progress(k, self.nsteps)
        # compiling or loading a function first needed by an event is not solve time
        loaded_in_loop = compiler.load_seconds() - tl1
        runtime = time.perf_counter() - t0 - loaded_in_loop
        self.timings["compile_s"] = compiler.compile_seconds() - tc0
        self.timings["load_s"] += loaded_in_loop
        return self.result(runtime)

    def prepare(self) -> None:
        """Compile, or load from the cache, the compiled stretch this run starts with (a call over
        no steps), so that the solve is timed without it."""
        if self.use_kernel:
            self.advance(0, 0)

    def result(self, runtime: float) -> Result:
        """The run's :class:`Result` (``runtime`` [s]: the solve)."""
        m = self.model
        self.episodes.close_all(float(self.t_grid[-1]))
        k_out = np.arange(0, self.nsteps + 1, self.every)
        gm = self.gm
        ne = len(self.event_states)
        return Result(
            t=self.t_grid[k_out],
            names=[s.name for s in m.systems],
            q=self.Q,
            qd=self.V,
            systems=m.systems,
            mode_start=m.mode_start,
            pairs=m.pairs,
            impacts=self.impacts,
            geo=m.geo,
            facades=m.facades,
            walls=m.walls,
            pair_law_names=[law_name(self.laws[j]) for j in self.pair_law],
            buildings=self.scene.buildings,
            scene=self.scene,
            energy=self.energy(),
            runtime_s=runtime,
            dt=self.dt,
            steps=self.nsteps,
            integrator=self.integrator.describe(),
            contact=self._describe_laws(),
            contacts=self.episodes.ended,
            ground_motion={"name": gm.name, "source": gm.source, "pga_g": gm.pga / G, "angle": gm.angle},
            info={"located_events": self.n_located, "sustained_pairs_at_end": sorted(self.sustained),
                  # the slab pairs watched: slabs at a common level, and slabs against a facade between floors
                  "slab_pairs": {"common_level": len(m.pairs) - len(m.facades) - len(m.walls), "slab_to_facade": len(m.facades),
                                 "slab_to_wall": len(m.walls)},
                  "pair_checks": self._pair_checks(),
                  # the shortest contact and how many steps span it (pounding.framework.engine.contact_step)
                  "contact_time": self.contact_time.report(self.dt)},
            energy_tolerance=self.scene.analysis.energy_tolerance,
            slab_peaks=self.peak.copy() if self.every > 1 else None,
            springs=self.springs.histories(self.spring_hist, [s.name for s in m.systems]) if self.springs is not None else {},
            links=self.springs.joined_histories(self.spring_hist, [s.name for s in m.systems], m.mode_start,
                                                [s.modes.shape[1] for s in m.systems]) if self.springs is not None else {},
            link_energy=self.springs.joined_energy() if self.springs is not None and self.springs.joined else None,
            event_t=np.array([e[0] for e in self.event_states]),
            event_q=np.array([e[1] for e in self.event_states]).reshape(ne, m.n),
            event_qd=np.array([e[2] for e in self.event_states]).reshape(ne, m.n),
            timings={"load_and_compile_s": self.timings["load_s"], "compile_s": self.timings["compile_s"], "solve_s": runtime},
            intra_step=self.intra_step(),
        )

    def _describe_laws(self) -> dict:
        """The contact law (summary.json), with the ``[[contact]]`` laws of single pairs of buildings."""
        out = self.laws[0].describe()
        if self.law is not self.laws[0]:  # beside a force law there, a table's or a wall's impulse law strikes the impulse pairs
            out["impulses"] = self.law.describe()
        if self.scene.contacts:
            out["between"] = [{"between": list(r.between), **law.describe()} for r, law in zip(self.scene.contacts, self.laws[1:])]
            bumpers = iter(self.laws[1 + len(self.scene.contacts):])  # (pair_laws: one per rule with a bumper, in order)
            for entry, rule in zip(out["between"], self.scene.contacts):
                if getattr(rule, "bumper", None) is not None and self.laws[0].watches():
                    entry["bumper"] = {"on": rule.bumper.on, "storeys": list(rule.bumper.storeys), **next(bumpers).describe()}
        walls = self.scene.walls
        if walls:
            out["walls"] = [{"wall": w.name, **law.describe()} for w, law in zip(walls, self.laws[len(self.laws) - len(walls):])]
        return out

    def intra_step(self):
        """The integrator's own solution inside a step for the true peaks
        (:class:`pounding.framework.engine.peaks.ExactIntraStep`), or None: the Hermite cubic."""
        if not self.integrator.exact_within_step or self.springs is not None or self.force_pairs.size:
            return None
        from pounding.framework.engine.peaks import ExactIntraStep

        return ExactIntraStep(self.integrator, self.model.omega, self.model.zeta, self.model.L, self.ag, self.dt)

    def _pair_checks(self) -> dict:
        """How many pair checks the clearance bound settles, counted on the recorded states
        (:func:`pounding.framework.engine.screening.bound_screening`; none watched with contact off)."""
        from pounding.framework.engine.screening import bound_screening

        return bound_screening(self.kgeo, self.Q, self.tol)

    def energy(self) -> dict:
        """The energy account per building [J] (:meth:`Model.energy`); with yielding springs, strain
        is what the springs store and ``hysteretic`` what they dissipated: their whole work (the
        elastic part k0 u^2/2 in the modal strain plus the remainders' work) minus what they store."""
        out = self.model.energy(self.z, self.E)
        if self.springs is None:
            return out
        for i, s in enumerate(self.model.systems):
            e = self.springs.energy(i, self.z[:, 0], s.omega, int(self.model.mode_start[i]))
            out[s.name]["strain"] += e["stored"] - e["elastic_springs"]
            out[s.name]["hysteretic"] = e["hysteretic"]
            if self.springs.joined:  # the work of the links between slabs on this building
                out[s.name]["links"] = e["links"]
        return out

    def needs_python(self, k: int) -> bool:
        """Whether grid step k is the Python step's: contact forces act or a pair is held, a force law's
        contact episode is open (its pair has not let go: it may press with no force, as a dashpot
        on the way out), or a pair starts within the tolerance."""
        if not self.use_kernel or self.sustained or self.fc.any() or self.episodes.open:
            return True
        if self.python_step_until_clear:
            if self.model.pairs and np.all(self.gaps(self.z[:, 0], cutoff=self.tol) > self.tol):
                self.python_step_until_clear = False
                return False
            return True
        return False

    def advance(self, k0: int, k1: int):
        """Free grid steps k0 -> k1, compiled (:func:`pounding.framework.engine.free_stretch.advance`)."""
        from pounding.framework.engine.free_stretch import advance
        from pounding.framework.engine.kernel import advance_free

        if self.springs is not None:  # yielding springs: their own stretch, stopping before any contact
            return self.springs.advance(self, k0, k1)
        if self.kgeo.pa.shape[0] == 0:  # nothing to watch: no contact code
            return advance_free(self.transition(self.dt), self.model.modes, self.ground, self.z, int(k0), int(k1), self.rec, self.kgeo)
        return advance(self.transition(self.dt), self.model.modes, self.ground, self.z, int(k0), int(k1), self.rec, self.kgeo,
                       self.settings, self.log, self.rules, self.graze_search())

    def graze_search(self):
        """The :class:`~pounding.framework.engine.bundles.GrazeSearch` with which the compiled stretch
        searches a suspected step as :meth:`python_step` would (built once), or None where that step's
        search is not the compiled one on the integrator's built-in maps with only the ground acting
        (the paper's locators, links, force laws, an integrator without built-in maps)."""
        if self._graze is None:
            from pounding.framework.engine.bundles import GrazeSearch
            from pounding.framework.engine.event_search import builtin_maps

            maps, params = self._search_maps if self._search_maps is not None else (None, None)
            builtin = builtin_maps(maps)
            if self.search_record is None or self.springs is not None or self.force_pairs.size or builtin < 0:
                self._graze = False
            else:
                self._graze = GrazeSearch(self.step_search(), self.no_held_search(), builtin, params,
                                          np.ascontiguousarray(self.event_pairs, dtype=np.int64), float(self.eps), float(self.tol),
                                          self.xtol, np.array([-1.0, 0.0]), np.zeros(len(self.event_pairs), dtype=np.bool_))
        return self._graze or None

    def drain_kernel_events(self) -> None:
        """Move the impacts and event states the compiled core logged into the run's lists."""
        log = self.log
        n_events, n_impacts = int(log.n_events[0]), int(log.n_impacts[0])
        if n_events == 0 and n_impacts == 0:  # (most calls: a stretch or a step that logged nothing)
            return
        for j in range(n_events):
            self.event_states.append((float(log.t[j]), log.q[j].copy(), log.v[j].copy()))
        for r in log.impacts[:n_impacts]:
            self.impacts.append(Impact.from_record(r))
        log.n_impacts[0] = 0
        log.n_events[0] = 0

    def advance_held(self, k0: int, k1: int):
        """Grid steps with pairs held in sustained contact, compiled (:func:`pounding.framework.engine.held.held_stretch`)."""
        mask = np.zeros(len(self.model.pairs), dtype=np.bool_)
        mask[sorted(self.sustained)] = True
        self.fc = np.ascontiguousarray(self.fc, dtype=float)
        if self.springs is not None:  # yielding springs: the held steps' fixed point, compiled with them
            out = self.springs.advance_held(self, mask, k0, k1)
            self.sustained = {int(p) for p in np.flatnonzero(mask)}
            return out
        out = hold.held_stretch(self.transition(self.dt), self.model.modes, self.ground, self.z, HeldPairs(self.fc, mask), int(k0),
                                int(k1), self.rec, self.model.geo, self.settings, self.rules, None, None)
        self.sustained = {int(p) for p in np.flatnonzero(mask)}
        return out

    def _record(self, k: int) -> None:
        """Record grid instant k (every ``every``-th: the state's displacements and velocities, by the
        compiled stretches' own recorder; the links' states) and update the slabs' running peaks."""
        from pounding.framework.engine.kernel import _record

        if self.every > 1:
            self.model.update_peaks(self.z, self.z, 0.0, self.peak)
        _record(self.z, k, self.rec)
        if self.springs is not None:
            self.springs.record(k, self.every)


    # ---------------------------------------------------------------- one step in Python
    def python_step(self, k: int) -> None:
        """Grid step k -> k+1 with contact handled: locate impacts, impulses, contact forces."""
        t, t_end = self.t_grid[k], self.t_grid[k + 1]
        self.events_in_step = 0
        while t_end - t > 1e-12 * self.dt:
            h = self.snap(t_end - t)
            if self.sustained:
                self.stop_closing(t)
            found = self.found_by_stretch(t, h)
            if found is not None:  # the compiled stretch searched this very step: its zero and its culprits
                st, (hs, culprits) = None, found
            else:
                st = self.trial(self.z, t, h)
                culprits = self.overlapping(st.z1) if not self.crossing else self.crossing_pairs(st, h)
                hs = None
                if culprits:
                    hs = self.locate(t, h, culprits, st) if self.crossing else self.locate(t, h, culprits)
            arrival = self.locate_arrival(t, h, st) if st is not None and st.arrival < self.settings.overlap else None
            if arrival is not None and (hs is None or arrival < hs):  # a point of a held pair reaches contact first
                hs, culprits = arrival, [st.arriving]
            else:
                arrival = None
            if hs is None:  # no contact inside the step (a graze the bound could not exclude did not touch)
                self.commit(st, t, h)
                t = t_end
                self.contact_at(t, self.touching_pairs() if self.crossing else None)
                break
            sub = self.trial(self.z, t, hs)
            self.commit(sub, t, hs)
            t += hs
            self.n_located += 1
            if arrival is not None:
                # the pair that arrives at hs (two held pairs may both arrive within the whole step)
                pair = sub.arriving if sub.arriving >= 0 else culprits[0]
                # beyond the bound on a step's events the law is not asked: the rest of the step starts
                # with the plastic stop of what touches (stop_closing), the limit of the chatter
                if self.events_in_step < MAX_EVENTS_PER_STEP:
                    self.strike_arrival(t, pair)
            elif not self.contact_at(t, culprits):
                # touching but not approaching, yet overlapping before the step ends: pressed together
                self.sustained.update(culprits)
            self.events_in_step += 1
            if self.events_in_step > MAX_EVENTS_PER_STEP:
                self.sustained.update(culprits)
        self._record(k + 1)
        self.release_sustained()

    def found_by_stretch(self, t: float, h: float) -> tuple[float, list[int]] | None:
        """(the step length [s] to the zero, the pairs searched) that the compiled stretch's search found
        in the grid step that starts at t [s] (:func:`~pounding.framework.engine.event_search.step_touches`:
        the same trial step, the same screen and the same search as this driver's step of it: its
        ``crossing_pairs`` and :meth:`locate`'s answer), taken once; None where it found none there."""
        graze = self._graze
        if not graze or graze.found[0] != t or h != self.dt:
            return None
        graze.found[0] = -1.0
        return float(graze.found[1]), graze.plist[graze.culprits].tolist()

    def commit(self, st: Step, t: float, h: float) -> None:
        """Accept a trial step: book its work (contact forces are loads like any other) and move on."""
        if st.z0 is not self.z:
            # a held step may start with the normal velocity of pressed points projected out
            hold.book_velocity_change(self.E, self.model.bidx, self.z[:, 1].copy(), st.z0[:, 1].copy())
        if self.springs is None:
            self.accumulate(st.z0, st.z1, t, h, st.f0, st.f1)
        else:
            self.accumulate_with_springs(st, t, h)
            self.springs.commit(st.sp)
        if self.every > 1:  # the step's extremes, before any impulse at its end (true peaks)
            self.model.update_peaks(st.z0, st.z1, h, self.peak)
        if st.contacts is not None or self.episodes.open:
            self.episodes.commit(t, h, st.contacts, st.z1[:, 0] - st.z0[:, 0], lambda p: self.model.pair_gap(st.z1[:, 0], p))
        if self.named_points and (st.contacts is not None or self._pressing_laws):  # (laws that keep a state)
            state = st.contacts.state if st.contacts is not None else None
            self._pressing_laws = commit_laws(self.laws, self.pair_law, state, st.contacts.force if state is not None else None,
                                              self._pressing_laws, t + h, h)
        self.fc = np.ascontiguousarray(st.f1, dtype=float)
        law_force = None if st.contacts is None else st.contacts.modal
        self.fc_law = np.ascontiguousarray(law_force, dtype=float) if law_force is not None else np.zeros(self.model.n)
        self.z = np.ascontiguousarray(st.z1)

    def accumulate_with_springs(self, st: Step, t: float, h: float) -> None:
        """Book a step with yielding springs: their remainders' modal loads -g are loads like the
        contact forces; their work goes to the springs' account, not the contact column
        (:func:`~pounding.framework.engine.spring_core.book_links`, the compiled stretches' own booking)."""
        from pounding.framework.engine.bundles import StepEnds
        from pounding.framework.engine.spring_core import book_links

        if not h > 0.0:  # an impact located at the step's very start: a step of no length books nothing
            return
        c = np.ascontiguousarray
        ends = StepEnds(c(st.z0), c(st.z1), c(st.f0, dtype=float), c(st.f1, dtype=float))
        book_links(self.transition(h), self.model.modes, float(h), self.ag_at(t), self.ag_at(t + h), self.load(t),
                   self.load(t + h), ends, self.E, self.springs.stepping(), st.sp, self.springs.booking_buffers())

    def overlapping(self, z1) -> list[int]:
        """Pairs that end the trial overlapping beyond the tolerance and are not held by forces."""
        if not self.law.at_events:
            return []
        free = self.free_pairs()
        g = self.model.gaps(z1[:, 0], free, self.tol)
        return [int(p) for p in free[g < -self.tol]]

    def crossing_pairs(self, st: Step, h: float) -> list[int]:
        """Free pairs that may touch inside the trial step ``st`` of h [s] (the crossing locator):
        ending it overlapping, or grazing by :func:`pounding.framework.engine.crossing.suspect`'s bound."""
        from pounding.framework.engine.crossing import suspects

        z0, z1 = np.ascontiguousarray(st.z0), np.ascontiguousarray(st.z1)
        free = self.free_pairs()
        return free[suspects(z0, z1, free, float(h), self.eps, self.tol, self.model.geo)].tolist()

    def touching_pairs(self) -> np.ndarray:
        """Free pairs whose gap is zero to rounding (the crossing locator strikes only these at a step's end)."""
        free = self.free_pairs()
        return free[self.model.gaps(self.z[:, 0], free, self.tol) <= self.eps]

    def free_pairs(self) -> np.ndarray:
        """The pairs struck by impulses at events that are not held (k,) int64."""
        if not self.sustained:
            return self.event_pairs
        return np.array([p for p in self.event_pairs if p not in self.sustained], dtype=np.int64)

    def forces_act(self, st: Step | None) -> bool:
        """Whether a force law's points press at the start of the trial step ``st`` or at its end: then
        the step's trajectory is the forces' too, and an impact inside it is searched on trial steps."""
        if not self.force_pairs.size:
            return False
        return bool(self.fc_law.any()) or (st is not None and st.contacts is not None and st.contacts.state is not None)

    def trial(self, z, t, h) -> Step:
        """A step of h from (z, t) with the contact forces of the pairs that are held by forces."""
        if self.springs is not None:
            return self.spring_trial(z, t, h)
        if self.sustained:  # (only impulses hold pairs)
            return self.held_trial(z, t, h)
        if self.force_pairs.size:
            return self.force_trial(z, t, h)
        return Step(z, self.step(z, t, h, self.fc), self.fc, np.zeros(self.model.n))

    def spring_trial(self, z, t, h) -> Step:
        """A trial step with yielding springs (:mod:`pounding.framework.engine.yielding`): Newton on the
        springs' end remainders where no force depends on the step's end; with a force law's points
        pressed, the links and the contact forces solved together (:meth:`Yielding.with_contact`); with
        held pairs the fixed point around the held step."""
        from pounding.framework.engine.contact_laws import forces_solver

        sp, tr = self.springs, self.cache(h)
        if self.sustained:  # (only impulses hold pairs)
            return self.held_trial(z, t, h)
        z1, new = sp.step(np.ascontiguousarray(z), self.load(t) + (self.fc - sp.g), self.load(t + h), tr, h)
        if not self.force_pairs.size:
            return Step(z, z1, self.fc, np.zeros(self.model.n), new)
        near, near_gap, near_rows, pressed = self.pressed(z, z1, t, h)
        if pressed is None:
            return self.force_step(z, z1, near, near_gap, None, None, new)
        state, W = pressed[0], pressed[1]
        g = new.g
        z1, lam, gap, rate, new = sp.with_contact(h, tr.B, z1, new, W, state.gap, state.rate,
                                                  *forces_solver(self.laws, self.pair_law[state.pair], state))
        # the watched features' end gaps without contact forces, moved by the links' change of end load
        near_gap = near_gap - near_rows @ (tr.B[:, 0, 1] * (new.g - g))
        return self.force_step(z, z1, near, near_gap, (state._replace(gap=gap, rate=rate), *pressed[1:]), lam, new)

    def force_trial(self, z, t, h) -> Step:
        """A force-law step of elastic buildings: every pair's law gives its forces, solved implicitly
        with the step."""
        from pounding.framework.engine.contact_laws import solve_forces

        zf = self.step(z, t, h, self.fc)
        near, near_gap, _, pressed = self.pressed(z, zf, t, h)
        if pressed is None:
            return self.force_step(z, zf, near, near_gap, None, None)
        lam = solve_forces(self.laws, self.pair_law[pressed[0].pair], pressed[0])
        return self.force_step(z, zf + self.cache(h).B[:, :, 1] * (pressed[1].T @ lam)[:, None], near, near_gap, pressed, lam)

    def pressed(self, z, zf, t, h):
        """The points a force law acts on in a step of h [s] from (z, t) whose end without contact
        forces at its end is zf (n, 3): (near, near_gap, near_rows, pressed), the pairs, end gaps [m] and
        modal rows of every feature within the watch tolerance, and None where none overlaps, else (state, W, Q, N): the
        overlapping points' :class:`~pounding.contact.base.ContactState`, modal rows (m, n), points
        and normals (m, 2)."""
        from pounding.contact.base import ContactState

        pts = self.model.touching_shares(zf[:, 0], self.force_pairs, self.tol, named=self.named_points)
        near, near_gap, near_rows = pts.pair, pts.gap, pts.W
        keep = pts.gap < 0
        if not keep.any():
            return near, near_gap, near_rows, None
        if not keep.all():
            pts = pts.take(keep)
        pair, gap, Wr, Qf, Nf, share, point = pts.pair, pts.gap, pts.W, pts.Q, pts.N, pts.share, pts.point
        tr = self.cache(h)
        S_q = (Wr * tr.B[:, 0, 1]) @ Wr.T
        S_v = (Wr * tr.B[:, 1, 1]) @ Wr.T
        rate = Wr @ zf[:, 1]
        # the history: each pair's episode, or where its gap closes in this step (from its start, linear in q)
        start, approach = self.episodes.history(t, h, pair, lambda: (gap - Wr @ (zf[:, 0] - z[:, 0]), gap, -(Wr @ z[:, 1]), -rate))
        state = ContactState(t + h, h, gap, rate, S_q, S_v, Wr @ Wr.T, pair, start, approach,
                             self.model.local_stiffness(pair, Qf, Nf), share, point)
        return near, near_gap, near_rows, (state, Wr, Qf[:, :2], Nf[:, :2])

    def force_step(self, z, z1, near, near_gap, pressed, lam, sp=None) -> Step:
        """The trial :class:`Step` from z to z1 (n, 3) of a force law whose points ``pressed`` (as
        :meth:`pressed` gives them; None: none) carry the forces lam (m,) [N]; sp the links' trial."""
        from pounding.framework.engine.contact_episodes import StepContacts

        if pressed is None:
            return Step(z, z1, self.fc, np.zeros(self.model.n), sp, contacts=StepContacts.empty(near, near_gap, self.model.n))
        state, Wr, Q, N = pressed
        f1 = Wr.T @ lam
        contacts = StepContacts(state.pair, lam, state.gap + state.S_q @ lam, Q, N, Wr, state.start, state.approach,
                                near, near_gap, f1, state)
        return Step(z, z1, self.fc, f1, sp, contacts=contacts)

    def held_pairs(self) -> np.ndarray:
        """The pairs held in sustained contact (k,) int64, in order."""
        return np.array(sorted(self.sustained), dtype=np.int64)

    def held_trial(self, z, t, h) -> Step:
        """A step with the held pairs in rigid sustained contact (see :func:`pounding.framework.engine.held.held_step`;
        with yielding springs :func:`pounding.framework.engine.held.held_fixed_point`, their trial in ``Step.sp``);
        with a force law's points pressed beside them, their forces solved with it (:meth:`held_force_trial`)."""
        m, tr = self.model, self.cache(h)
        held = self.held_pairs()
        start = m.touching(z[:, 0], held, self.tol, deep=True)
        # the start load: the ground's and the force laws' (the held pairs' own force at the start is the held step's)
        p0 = self.load(t) + self.fc_law if self.force_pairs.size else self.load(t)
        p1 = self.load(t + h)
        contact = HeldContact(float(self.tol), float(self.touch))
        z_in, A, B = np.ascontiguousarray(z), np.ascontiguousarray(tr.A), np.ascontiguousarray(tr.B)

        def held_step(extra=None):
            """The held step with the extra end load ``extra`` (n,) (None: none): (HeldStep, the springs' trial)."""
            args = (z_in, p0, p1 if extra is None else p1 + extra, A, B, float(h), m.modes, HeldSet(held, contact, start), m.geo)
            if self.springs is not None:  # their end remainders by the fixed point around the held step
                return self.springs.held_step(*args)
            return hold.held_step(*args), None

        st, sp = held_step()
        if not self.force_pairs.size:
            return Step(st.z0, st.z1, st.f0, st.f1, sp, arrival=float(st.arrival), arriving=int(st.apair))
        return self.held_force_trial(z, t, h, held_step, st, sp)

    def held_force_trial(self, z, t, h, held_step, st, sp) -> Step:
        """The held step ``st`` (its springs' trial ``sp``) with the force laws' points that press at its
        end: their forces solved with it. ``held_step(extra)`` is the held step with an extra end load.

        The held step is linear in its end load while its held points and their features stay: its
        compliance at the pressed points (the change of their gaps and rates per unit force, m x m)
        is found by stepping it once per point with that point's force, and the laws are solved on
        it (:func:`~pounding.framework.engine.contact_laws.solve_forces`, as with free buildings). The
        step is then taken with the forces; where its gaps differ from the linear model by more than
        rounding (a held point let go) the model is found again about those forces, up to
        :data:`HELD_FORCE_PASSES` times."""
        from pounding.framework.engine.contact_episodes import StepContacts
        from pounding.framework.engine.contact_laws import solve_forces

        near, near_gap, _, pressed = self.pressed(z, st.z1, t, h)
        n = self.model.n
        if pressed is None:
            return Step(st.z0, st.z1, st.f0 + self.fc_law, st.f1, sp, contacts=StepContacts.empty(near, near_gap, n),
                        arrival=float(st.arrival), arriving=int(st.apair))
        state, Wr, Q, N = pressed
        laws = self.pair_law[state.pair]
        m = len(state.gap)
        gap0, rate0 = state.gap.copy(), state.rate.copy()  # at the end of the held step without their forces
        q_free, v_free = Wr @ st.z1[:, 0], Wr @ st.z1[:, 1]
        lam, base, eye = np.zeros(m), st, np.eye(m)
        for _ in range(HELD_FORCE_PASSES):
            # the compliance about the current forces, a point's force at a time (each the size of the force
            # that would undo its penetration through the free buildings' compliance)
            qb, vb = Wr @ base.z1[:, 0], Wr @ base.z1[:, 1]
            S_q, S_v = np.empty((m, m)), np.empty((m, m))
            for j in range(m):
                size = max(-float(gap0[j]), float(self.tol)) / max(float(state.S_q[j, j]), 1e-300)
                probe, _ = held_step(Wr.T @ (lam + size * eye[j]))
                S_q[:, j] = (Wr @ probe.z1[:, 0] - qb) / size
                S_v[:, j] = (Wr @ probe.z1[:, 1] - vb) / size
            # the linear model through the current forces: gaps g + S_q lam, rates r + S_v lam
            trial = state._replace(gap=gap0 + (qb - q_free) - S_q @ lam, rate=rate0 + (vb - v_free) - S_v @ lam, S_q=S_q, S_v=S_v)
            lam = solve_forces(self.laws, laws, trial)
            end, sp = held_step(Wr.T @ lam)
            gap, rate = gap0 + Wr @ end.z1[:, 0] - q_free, rate0 + Wr @ end.z1[:, 1] - v_free
            # the step agrees with the model, gaps and rates, to 1e-9 of their size (the held points stayed): done
            reach = max(float(np.max(np.abs(gap))), float(self.eps))  # [m]
            if (np.max(np.abs(gap - (trial.gap + S_q @ lam))) <= 1e-9 * reach
                    and np.max(np.abs(rate - (trial.rate + S_v @ lam))) <= 1e-9 * max(float(np.max(np.abs(rate))), reach / h)):
                break
            base = end
        else:
            import warnings

            from pounding.errors import AnalysisWarning

            warnings.warn(f"t = {t + h:.6g} s: the force law's points pressed beside a held pair did not settle in "
                          f"{HELD_FORCE_PASSES} passes (held points letting go and coming back); the last pass is taken",
                          AnalysisWarning, stacklevel=2)
        f_law = Wr.T @ lam
        contacts = StepContacts(state.pair, lam, gap, Q, N, Wr, state.start, state.approach, near, near_gap, f_law, trial)
        return Step(end.z0, end.z1, end.f0 + self.fc_law, end.f1 + f_law, sp, contacts=contacts, arrival=float(end.arrival),
                    arriving=int(end.apair))

    def locate_arrival(self, t: float, h: float, st: Step) -> float | None:
        """Step length [s] from t to the instant at which a point of a held pair that is apart at t
        reaches contact, on the held trajectory (:meth:`held_trial`: the pairs' touching points held),
        or None where it does not; ``st`` is the trial step of h [s], in which one arrives.

        The one crossing search (:meth:`locate_crossing`) on the arrival gap: the smallest gap of
        the held pairs' points that were apart at t (``Step.arrival``), with the trial step's
        interpolant as its guide."""
        held = self.held_pairs()
        gap0 = self.model.touching(self.z[:, 0], held, self.tol, deep=True).gap
        apart = gap0[gap0 > self.touch]
        # a point beyond the features listed is more than the tolerance away: the search only needs a
        # positive gap where none is listed (at the start, or inside the step)
        far = float(self.tol)
        start = float(apart.min()) if apart.size else far

        def gap(hh):  # (the search keeps its last evaluations itself)
            if hh <= 0.0:
                return start
            g = self.trial(self.z, t, hh).arrival
            return g if g < np.inf else far

        herm = (np.ascontiguousarray(st.z0[:, 0]), np.ascontiguousarray(st.z0[:, 1]), np.ascontiguousarray(st.z1[:, 0]),
                np.ascontiguousarray(st.z1[:, 1]), float(h))
        plist = np.array([st.arriving], dtype=np.int64)
        if self.search_record is not None and not self.forces_act(st):  # the held step (with the links: its fixed
            # point) compiled inside the search; a force law's pressed points are solved by the trial steps instead
            return self.locate_compiled(t, herm, self.load(t), plist, self.held_search(arrival=True, far=far, g0=start))
        return self.locate_crossing(gap, h, herm, plist)

    def strike_arrival(self, t: float, p: int) -> bool:
        """Strike held pair p at t, where a point of it that was apart has reached contact: the law's
        impulses over every touching point of the pair, as at any impact (:meth:`contact_at`), the
        impact recorded and its loss booked. True if any impulse acted."""
        return self.contact_at(t, [p])

    def stop_closing(self, t: float) -> None:
        """Plastic impulses on the touching points of held pairs that still close
        (:func:`pounding.framework.engine.held.stop_closing`); the kinetic energy they remove is
        booked as contact work. With the crossing locator only points that touch
        (:func:`~pounding.framework.engine.held.touch_gap`) are stopped, as in
        :func:`~pounding.framework.engine.held.held_stretch`; the paper's rules stop every point within
        the tolerance."""
        held = self.held_pairs()
        start = self.model.touching(self.z[:, 0], held, self.tol, deep=True)
        W = hold.rows_where(np.ascontiguousarray(start.gap <= self.touch), np.ascontiguousarray(start.W))  # (touch = inf: every point)
        v_before = self.z[:, 1].copy()
        hold.stop_closing(self.z, W, self.v_min)
        hold.book_velocity_change(self.E, self.model.bidx, v_before, self.z[:, 1].copy())

    def release_sustained(self) -> None:
        if not self.sustained:
            return
        held = self.held_pairs()
        for p, g in zip(held, self.model.gaps(self.z[:, 0], held, self.tol)):
            if g > self.tol:
                self.sustained.discard(int(p))

    # ---------------------------------------------------------------- impact location
    def locate(self, t: float, h: float, culprits: list[int], st: Step | None = None) -> float | None:
        """Step length from t to the first contact of the culprit pairs (within the tolerance; with the
        crossing locator, where the gap is zero, or None when none touches: ``st`` is the trial step)."""
        plist = np.array(culprits, dtype=np.int64)
        p0 = self.load(t) + self.fc  # the load at the start, the same for every trial
        # a force law's points press in the step: its trajectory is theirs too, and each trial step solves them
        forces = self.forces_act(st)

        def gmin(hh):
            if hh <= 0.0:
                return float(self.model.gaps(self.z[:, 0], plist).min())
            if not self.sustained and self.springs is None and not forces:  # (culprits come only with impulses)
                # no contact force in the step: only its end displacements are needed
                tr = self.cache(hh)
                return float(pg.stepped_min_gap(np.ascontiguousarray(tr.A), np.ascontiguousarray(tr.B), self.z, p0,
                                                self.load(t + hh), plist, self.model.geo))
            return float(self.model.gaps(self.trial(self.z, t, hh).z1[:, 0], plist).min())

        if self.crossing:
            z0, z1 = (self.z, self.trial(self.z, t, h).z1) if st is None else (st.z0, st.z1)
            # the step's cubic Hermite interpolant (q, q' at both ends): a fourth-order guess of the
            # integrator's intra-step solution, with no transition to build (pounding.framework.engine.crossing)
            herm = (np.ascontiguousarray(z0[:, 0]), np.ascontiguousarray(z0[:, 1]), np.ascontiguousarray(z1[:, 0]),
                    np.ascontiguousarray(z1[:, 1]), float(h))
            if self.search_record is not None and (self.sustained or z0 is self.z) and not forces:
                # the ground, the held pairs and the links act in the step: the same search, compiled whole
                if not self.sustained:
                    if self.springs is not None:  # the links' start load, as spring_trial forms it
                        p0 = self.load(t) + (self.fc - self.springs.g)
                    return self.locate_compiled(t, herm, p0, plist, self.held_search(arrival=False, far=0.0, g0=0.0))
                g0 = float(self.model.gaps(self.z[:, 0], plist).min())
                return self.locate_compiled(t, herm, self.load(t), plist, self.held_search(arrival=False, far=0.0, g0=g0))
            return self.locate_crossing(gmin, h, herm, plist)
        if self.law.locate == "root" and gmin(0.0) > self.tol:
            from scipy.optimize import brentq

            root = brentq(gmin, 0.0, h, xtol=self.xtol, rtol=4 * np.finfo(float).eps)
            if abs(gmin(root)) <= self.tol:
                return root
        # halving: bisection on [lo, hi] from the saved state at t (the paper)
        lo, hi = 0.0, h
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            g = gmin(mid)
            if g < -self.tol:
                hi = mid
            elif g <= self.tol:
                return mid
            else:
                lo = mid
            if hi - lo < 1e-15 * self.dt:
                break
        return hi if gmin(hi) >= -self.tol else lo

    def locate_crossing(self, gmin, h: float, herm: tuple, plist: np.ndarray) -> float | None:
        """Step length to the first zero of the smallest gap gmin(hh) of the pairs ``plist`` on [0, h],
        to the geometry's rounding, or None when the gap stays above -eps (a graze that did not touch).

        :func:`pounding.framework.engine.event_search.crossing_search`, the one search, run with its
        body interpreted because its gap, the integrator's own intra-step solution ``gmin``, is a
        Python callable; ``herm`` = (q0, v0, q1, v1 (n,), h) is the step's cubic Hermite interpolant."""
        from pounding.framework.engine.event_search import crossing_search

        found, hs = crossing_search.py_func(lambda hh: gmin(float(hh)), None, herm, self.eps, self.xtol,
                                            plist, self.model.geo)
        return float(hs) if found else None

    def locate_compiled(self, t: float, herm: tuple, p0: np.ndarray, plist: np.ndarray, held) -> float | None:
        """:func:`pounding.framework.engine.event_search.locate` from the state at t [s] with start
        load p0 (n,), for the pairs ``plist``, on the step's interpolant ``herm``; ``held`` the held
        pairs' :class:`~pounding.framework.engine.bundles.HeldSearch` (none held: only the ground acts).
        The step length to the zero [s], or None."""
        from pounding.framework.engine.event_search import locate

        maps, params = self._search_maps
        springs = self.link_search()
        laws = None if springs is None else self.springs.updates
        found, hs = locate(float(t), self.z, herm, p0, plist, self.eps, self.xtol, self.step_search(), maps, params, held,
                           laws, springs)
        if springs is not None and springs.failed[0] >= 0:  # a trial's Newton or fixed point failed: as the trial step says
            raise self.springs.fixed_point_error() if self.sustained else self.springs._diverged(int(springs.failed[0]))
        return float(hs) if found else None

    def link_search(self):
        """The :class:`~pounding.framework.engine.bundles.LinkSearch` of this run's links with laws
        (built once: the committed links are updated in place), its failure flag reset; None where
        every building is elastic."""
        if self.springs is None:
            return None
        if self._link_search is None:
            from pounding.framework.engine.bundles import LinkSearch

            sp = self.springs
            self._link_search = LinkSearch(sp.links, sp.now, np.full(1, -1, dtype=np.int64))
        self._link_search.failed[0] = -1
        return self._link_search

    def no_held_search(self):
        """The :class:`~pounding.framework.engine.bundles.HeldSearch` with no pair held: the search's
        one bundle type where only the ground acts (built once)."""
        from pounding.framework.engine.bundles import Features, HeldSearch

        if self._no_held is None:
            m = self.model
            none = np.zeros(0, dtype=np.int64)
            nothing = Features(none, np.zeros(0), np.zeros((0, m.n)), np.zeros((0, 2)), np.zeros((0, 2)), none, none, none)
            self._no_held = HeldSearch(HeldSet(none, HeldContact(float(self.tol), float(self.touch)), nothing), m.modes, False, 0.0, 0.0)
        return self._no_held

    def held_search(self, *, arrival: bool, far: float, g0: float):
        """The :class:`~pounding.framework.engine.bundles.HeldSearch` of the held pairs at the current
        state: what :meth:`held_trial` steps with (their touching features at the start), and the gap
        sought (``arrival``: the held pairs' points apart at the start, ``far`` where none is; else
        the culprits' smallest gap), ``g0`` its value at the start [m]."""
        from pounding.framework.engine.bundles import HeldSearch

        m = self.model
        if not self.sustained:
            return self.no_held_search()
        held = self.held_pairs()
        start = m.touching(self.z[:, 0], held, self.tol, deep=True)
        return HeldSearch(HeldSet(held, HeldContact(float(self.tol), float(self.touch)), start), m.modes, bool(arrival), float(far),
                          float(g0))

    def step_search(self):
        """The :class:`~pounding.framework.engine.bundles.StepSearch` bundle of this run (built once)."""
        if self._step_search is None:
            from pounding.framework.engine.bundles import StepSearch

            tr, (rec_t, rec_acc) = self.cache(self.dt), self.search_record
            self._step_search = StepSearch(float(self.dt), np.ascontiguousarray(tr.A), np.ascontiguousarray(tr.B), self.cache.omega,
                                           self.cache.zeta, self.ag, rec_t, rec_acc, self.model.L, self.model.geo)
        return self._step_search

    # ---------------------------------------------------------------- impacts
    def contact_at(self, t: float, pairs=None) -> bool:
        """Apply impulses at time t to every touching, approaching pair among ``pairs`` (default:
        every pair not held; a held pair is given where a point of it arrives). True if any impulse acted.

        The kernel's one impulse step (:func:`~pounding.framework.engine.kernel.impulses_at`, which
        its compiled stretches call too) with this run's law (:meth:`_law_impulses_at`), logged to
        the same records. A pair whose rebound is too slow to open the tolerance within one step
        (Zeno) is held from then on.
        """
        if not self.law.at_events:
            return False
        if pairs is not None and len(pairs) == 0:  # nothing to strike (the crossing locator's step ends, mostly)
            self.drain_kernel_events()
            return False
        m = self.model
        candidates = np.zeros(len(m.pairs), dtype=np.bool_)
        candidates[self.free_pairs() if pairs is None else np.asarray(pairs, dtype=np.int64)] = True
        n_before = len(self.impacts)
        acted = self._law_impulses_at(t, candidates)
        self.drain_kernel_events()
        if self.crossing:  # chatter decided by the rest of the sequence, not the law's test on dt x speed
            struck = {imp.pair for imp in self.impacts[n_before:]}
            self.log.zeno[:] = [p in struck and self.chatters(p, t) for p in range(len(self.log.zeno))]
        self.sustained.update(int(p) for p in np.flatnonzero(self.log.zeno))
        self.log.zeno[:] = False
        return bool(acted)

    def chatters(self, p: int, t: float) -> bool:
        """Whether pair p, just struck at t, starts chatter the step cannot resolve (crossing locator):
        its impact sequence ends within a step (:func:`pounding.framework.engine.held.chatter_duration`,
        the restitution its pair's law's). Then the pair is held now (the sequence's limit; the
        error is bounded by the sequence's duration, below dt); otherwise the impacts are resolved
        one by one."""
        rem = self.springs.g if self.springs is not None else 0.0
        k = float(self.laws[self.pair_law[p]].restitution)  # (a wall's own)
        duration = hold.chatter_duration(self.z, np.ascontiguousarray(self.load(t) + self.fc - rem, dtype=float), int(p), k,
                                         float(self.tol), self.model.modes, self.model.geo)
        return bool(duration < self.dt)

    def _law_impulses_at(self, t: float, candidates: np.ndarray) -> bool:
        """The one impulse step (:func:`~pounding.framework.engine.kernel.impulses_at`) at time t
        [s] on the ``candidates`` (P,) bool, with this run's law: compiled with the Newton rule
        for a law that declares ``compiled_impulses``, else the same function with the compiler
        off around the law's own ``impulses(W, b)``. Its records go to the log (drained by the
        caller). True if an impulse acted."""
        from pounding.framework.engine.kernel import impulses_at

        m, law = self.model, self.law
        fc = self.fc - self.springs.g if self.springs is not None else self.fc  # the springs' remainders load too
        settings = self.settings._replace(after_eq=law.after_impact == "equilibrium")
        if self.own_restitutions:  # a wall's own restitution: each point its pair's
            step = impulses_at.py_func

            def rule(D, b, _settings, pairs):
                return np.asarray(self._group_impulses(D, b, self.pair_law[pairs]), dtype=float)
        elif law.compiled_impulses:
            step, rule = impulses_at, None
            settings = settings._replace(restitution=float(law.restitution))
        else:
            step = impulses_at.py_func

            def rule(D, b, _settings, _pairs):
                return np.asarray(law.impulses(D, b), dtype=float)
        acted, _ = step(rule, float(t), self.ag_at(t), self.z, np.ascontiguousarray(fc, dtype=float), m.modes, settings,
                        float(self.dt), self.log, m.geo, candidates)
        return bool(acted)

    def _group_impulses(self, W: np.ndarray, b: np.ndarray, which: np.ndarray) -> np.ndarray:
        """Impulses (m,) [N s] of one group's features, given their Delassus matrix W (m, m), closing speeds
        b (m,) and the index of each feature's law ``which`` (m,) (impulse laws that differ at most in
        restitution: :meth:`~pounding.contact.base.ContactLaw.own_law_problem`, a pair's or a wall's own).

        One restitution: the law's own impulses. Several (a building striking a wall and a neighbour at
        once): Newton's problem with every approaching point's own target (1 + k_j) b_j, solved as the law
        with the smallest k_0 on the closing speeds scaled by (1 + k_j) / (1 + k_0): its active points reach
        their own targets exactly, and an inactive point, not closing at the scaled speed, is not closing
        at its own (the scale is >= 1), so the answer satisfies every point's own conditions."""
        laws = [self.laws[int(j)] for j in which]
        k = np.array([law.restitution for law in laws], dtype=float)
        if np.all(k == k[0]):
            return laws[0].impulses(W, b)
        low = laws[int(np.argmin(k))]
        scale = np.where(b > 0.0, (1.0 + k) / (1.0 + low.restitution), 1.0)
        return low.impulses(W, b * scale)


def _record_arrays(gm, components: int):
    """(times (m,), accelerations (m, c)) of a record that ``samples`` interpolates with numpy's interp
    (strictly increasing times, ``components`` columns), else None."""
    record = gm.piecewise_linear() if hasattr(gm, "piecewise_linear") else None
    if record is None:
        return None
    t, acc = record
    t = np.ascontiguousarray(t, dtype=float)
    acc = np.ascontiguousarray(np.asarray(acc, dtype=float).reshape(t.shape[0], -1))
    if acc.shape[1] != components or not np.all(np.diff(t) > 0):
        return None
    return t, acc


def _no_pairs(geo: PairArrays) -> PairArrays:
    """``geo`` with no pair to watch (contact "none")."""
    return geo._replace(pa=geo.pa[:0].copy(), pb=geo.pb[:0].copy(), rest=geo.rest[:0].copy(), axis=geo.axis[:0].copy())
