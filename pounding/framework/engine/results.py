"""Results of a run: arrays at the output rate, the impact log, energies, timings.

A :class:`Result` holds modal histories and turns them into physical ones on
demand (one matrix product per building), so a run stores O(n) numbers per
output step however many storeys there are.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Impact:
    """One impact: an impulse at one point of one slab pair.

    Attributes
    ----------
    time : float
        [s].
    pair : int
        Index of the slab pair in the run's pair list.
    striker : int
        0 if a vertex of the pair's first slab hit, 1 if the second's.
    vertex : int
        Index of the striking vertex in its slab polygon (scene order), -1 face to face.
    impulse : float
        [N s].
    normal : ndarray (2,)
        Unit normal from the first slab towards the second.
    approach_velocity : float
        Closing speed b before the impact [m/s].
    energy_loss : float
        Kinetic energy lost [J].
    point : ndarray (2,)
        Contact point in plan [m].
    """

    time: float
    pair: int
    striker: int
    vertex: int
    impulse: float
    normal: np.ndarray
    approach_velocity: float
    energy_loss: float
    point: np.ndarray

    @classmethod
    def from_record(cls, r) -> "Impact":
        """From a record of :data:`~pounding.framework.engine.bundles.IMPACT_DTYPE`."""
        return cls(float(r["time"]), int(r["pair"]), int(r["striker"]), int(r["vertex"]), float(r["impulse"]),
                   np.array([r["nx"], r["ny"]]), float(r["approach_velocity"]), float(r["energy_loss"]), np.array([r["px"], r["py"]]))


@dataclass(frozen=True)
class ContactEpisode:
    """One contact episode of a slab pair: what every contact law reports, impulse or force.

    For a force law, the stretch of time the pair's slabs press on each other (from the step
    their gap first closed to the step it opened again); for an impulse law, one impact (an
    instant: ``end == start``, no penetration, its peak force the equivalent one of
    ``[analysis.impact_force]``, filled in by the writers).

    Attributes
    ----------
    start, end : float
        When the gap closed and opened again [s] (interpolated inside the steps where it crossed zero).
    pair : int
        Index of the slab pair in the run's pair list (``Result.pairs``).
    point : ndarray (2,)
        Contact point in plan at the peak force [m] (force-weighted over the pair's points).
    normal : ndarray (2,)
        Unit normal from the pair's first slab towards the second, at the peak force.
    approach_velocity : float
        Closing speed when the gap closed [m/s].
    peak_force : float
        Largest total contact force of the pair at a step's end [N] (nan for an impulse: see above).
    peak_penetration : float
        Largest overlap of the pair's slabs at a step's end [m] (0 for an impulse).
    impulse : float
        Integral of the pair's total contact force over the episode [N s] (the trapezoidal rule on
        the step ends, exact for the forces linear in each step that the driver applies).
    energy_dissipated : float
        Energy the contact took out of the buildings [J]: minus the work of its forces over the
        episode (each step's mean force times its displacement:
        :meth:`pounding.framework.engine.contact_episodes.Episodes.commit`), or the kinetic energy an
        impulse removed.
    strikes : int
        How many impacts or stretches of touching it holds: 1, or more for the merged episodes of
        :meth:`Result.contact_episodes` (a chatter).
    """

    start: float
    end: float
    pair: int
    point: np.ndarray
    normal: np.ndarray
    approach_velocity: float
    peak_force: float
    peak_penetration: float
    impulse: float
    energy_dissipated: float
    strikes: int = 1

    @property
    def time(self) -> float:
        """Start [s] (an impact's ``time``)."""
        return self.start

    @property
    def duration(self) -> float:
        """end - start [s]."""
        return self.end - self.start

    @classmethod
    def of_impact(cls, imp: "Impact") -> "ContactEpisode":
        """An impulse law's impact as an episode of no duration."""
        return cls(imp.time, imp.time, imp.pair, imp.point, imp.normal, imp.approach_velocity, float("nan"), 0.0,
                   imp.impulse, imp.energy_loss)


@dataclass
class Result:
    """Histories and logs of a run (physical arrays via :meth:`cm` and :meth:`vertices`).

    Attributes
    ----------
    t : ndarray (nt,)
        Output times [s].
    names : list of str
        Building names, scene order.
    q, qd : ndarray (nt, n)
        Stacked modal displacements and velocities.
    systems : list of System
    mode_start : ndarray (n_buildings,)
    pairs : list of (building a, storey a, building b, storey b, rest gap)
        0-based indices; storey numbers in files are 1-based.
    impacts : list of Impact
        The impulses of impulse laws (and of held contact's arrivals).
    contacts : list of ContactEpisode
        The contact episodes of force laws (:meth:`episodes` adds the impacts).
    energy : dict
        Per building: ground-motion input, damping, contact-force work, kinetic, strain [J]; with
        yielding storey springs also hysteretic [J] (strain is then what the springs store); with
        links between slabs also ``links``, the work they did on the building [J].
    """

    t: np.ndarray
    names: list[str]
    q: np.ndarray
    qd: np.ndarray
    systems: list
    mode_start: np.ndarray
    pairs: list
    impacts: list[Impact]
    energy: dict
    runtime_s: float
    dt: float
    steps: int
    integrator: dict
    contact: dict
    ground_motion: dict
    info: dict = field(default_factory=dict)
    energy_tolerance: float = 0.02
    #: the driver's own states at impact instants: times (ne,), q and q' just before the impulses (ne, n)
    event_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    event_q: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    event_qd: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    #: peak |u|, |v|, |phi| of every slab over the continuous trajectory [m, m, rad], shape (slabs, 3),
    #: slabs numbered building by building (:mod:`pounding.framework.engine.peaks`): tracked during the run when
    #: the output is thinned, else from the histories, split at the impacts
    slab_peaks: np.ndarray | None = None
    #: wall times [s]: loading and compiling the compiled core (``load_and_compile_s``, of which
    #: ``compile_s`` compiling), and the solve (``solve_s`` = ``runtime_s``)
    timings: dict = field(default_factory=dict)
    #: per building with yielding storey springs: :func:`pounding.framework.engine.yielding.spring_record`
    springs: dict = field(default_factory=dict)
    #: per link between slabs (by name): :func:`pounding.framework.engine.yielding.link_record`
    links: dict = field(default_factory=dict)
    #: the links between slabs' own account [J] (``dissipated``, ``stored``), None without links
    link_energy: dict | None = None
    #: the integrator's own solution inside a step (:class:`pounding.framework.engine.peaks.ExactIntraStep`) for
    #: the true peaks, or None (the cubic Hermite through the step ends); not written to files
    intra_step: object = field(default=None, repr=False)
    #: the pair geometry of the run (:class:`~pounding.framework.engine.bundles.PairArrays`): the modal
    #: contact rows of impacts (:func:`pounding.framework.engine.event_record.contact_row`) come from it
    geo: object = None
    #: {pair index: :class:`~pounding.framework.model.facade.Facade`} of the pairs where a slab strikes a
    #: neighbour between its floors
    facades: dict = field(default_factory=dict)
    #: {pair index: :class:`~pounding.framework.model.scene.Wall`} of the pairs where a slab meets a fixed wall
    walls: dict = field(default_factory=dict)
    #: the name of every slab pair's contact law (``pairs`` order), as the run resolved it
    #: (:func:`pounding.contact.rules.pair_laws`: ``[analysis] contact``, a pair's ``[[contact]]``, a
    #: wall's own law, a bumper)
    pair_law_names: list = field(default_factory=list)
    #: the scene's buildings (elements with their plan lines and sections), for the struck element
    buildings: tuple = ()
    #: the Scene that was run (None when unknown): :func:`pounding.io.results.write_results` writes it
    #: back as the run folder's scene.toml, so a folder written from Python can be plotted
    scene: object = field(default=None, repr=False)
    #: the contact episodes of force laws (:class:`ContactEpisode`), in the order they ended
    contacts: list = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.slab_peaks is None:
            from pounding.framework.engine.peaks import slab_peaks

            cont = slab_peaks(self) if len(self.t) else None
            self.slab_peaks = cont if cont is not None else self._step_end_slab_peaks()

    def _step_end_slab_peaks(self) -> np.ndarray:
        return np.vstack([np.max(np.abs(self.cm(name)), axis=0) for name in self.names]) if len(self.t) else np.zeros((0, 3))

    # ------------------------------------------------------------- physical histories
    def _index(self, name: str) -> int:
        return self.names.index(name)

    def modal(self, name: str, velocity: bool = False) -> np.ndarray:
        i = self._index(name)
        sl = slice(self.mode_start[i], self.mode_start[i] + self.systems[i].n_dof)
        return (self.qd if velocity else self.q)[:, sl]

    def cm(self, name: str, velocity: bool = False) -> np.ndarray:
        """(u, v, phi) of every slab's centre of mass [m, m, rad], shape (nt, storeys, 3)."""
        s = self.systems[self._index(name)]
        return (self.modal(name, velocity) @ s.modes.T).reshape(len(self.t), s.n_storeys, 3)

    def vertices(self, name: str, velocity: bool = False) -> np.ndarray:
        """x, y displacement of every slab vertex, shape (nt, storeys, kmax, 2); NaN pads shorter polygons.

        The structural model's small-rotation motion, (u - phi r_y, v + phi r_x) with r the vertex's
        offset from the slab's centre, as the drifts and the VTK files take it (the contact geometry
        turns slabs exactly: :func:`contact_offsets`, differing by phi^2 |r| / 2)."""
        s = self.systems[self._index(name)]
        x = self.cm(name, velocity)
        kmax = max(len(sl.vertices) for sl in s.slabs)
        out = np.full((len(self.t), s.n_storeys, kmax, 2), np.nan)
        for f, slab in enumerate(s.slabs):
            r = slab.vertices - slab.centre  # (k, 2)
            u, v, phi = x[:, f, 0:1], x[:, f, 1:2], x[:, f, 2:3]
            out[:, f, : len(r), 0] = u - phi * r[:, 1]
            out[:, f, : len(r), 1] = v + phi * r[:, 0]
        return out

    def contact_offsets(self, name: str, storey: int) -> np.ndarray:
        """Displacements (nt, k, 2) [m] of the vertices of slab ``storey`` (0-based) of building ``name``
        as the contact geometry moves them (:func:`pounding.contact.geometry.displaced`: the turn
        exact), for the studies that must find what the engine's contact finds (the gap studies)."""
        from pounding.contact.geometry import turned

        s = self.systems[self._index(name)]
        slab = s.slabs[storey]
        x = self.cm(name)[:, storey]
        return x[:, None, 0:2] + turned(np.asarray(slab.vertices, float) - slab.centre, x[:, 2:3])

    def peaks(self, name: str) -> np.ndarray:
        """Peak |u|, |v|, |phi| per storey over the continuous trajectory (inside the steps too), shape (storeys, 3)."""
        i = self._index(name)
        start = sum(s.n_storeys for s in self.systems[:i])
        return self.slab_peaks[start : start + self.systems[i].n_storeys].copy()

    def step_end_peaks(self, name: str) -> np.ndarray:
        """Peak |u|, |v|, |phi| per storey over the output steps' ends only, shape (storeys, 3): what a
        peer that reports step ends (OpenSees) reports, to compare like with like."""
        return np.max(np.abs(self.cm(name)), axis=0)

    @property
    def n_impacts(self) -> int:
        """Number of contact episodes: impacts of impulse laws and episodes of force laws."""
        return len(self.impacts) + len(self.contacts)

    def episodes(self) -> list[ContactEpisode]:
        """Every contact episode of the run, by start time: force laws' episodes and impulse laws'
        impacts (:meth:`ContactEpisode.of_impact`), one table for both kinds of law."""
        out = [ContactEpisode.of_impact(i) for i in self.impacts] + list(self.contacts)
        return sorted(out, key=lambda e: (e.start, e.pair))

    def contact_episodes(self) -> list[ContactEpisode]:
        """The run's contact episodes as they converge with the step: :meth:`episodes` with each
        pair's chatter merged into one (:func:`pounding.framework.engine.chatter.merge_chatter`; a
        maximal stretch with the pair in contact or chattering), by start time."""
        from pounding.framework.engine.chatter import merge_chatter, merge_intervals

        return merge_chatter(self.episodes(), merge_intervals(self.systems, self.pairs))

    def second_body(self, pair: int) -> tuple[str, int]:
        """(name, 1-based storey) of pair ``pair``'s second body: a building's slab, or a fixed wall's
        name with storey 0 (the ground it stands on)."""
        _, _, b, fb, _ = self.pairs[pair]
        wall = self.walls.get(pair)
        return (wall.name, 0) if wall is not None else (self.names[b], fb + 1)

    def impact_storey(self, imp: Impact) -> int:
        """1-based storey of an impact (the first slab's storey)."""
        return self.pairs[imp.pair][1] + 1

    def striking_building(self, imp: Impact) -> str:
        a, _, b, _, _ = self.pairs[imp.pair]  # (a wall pair's b is its slab's own building)
        return self.names[a if imp.striker == 0 else b]

    def struck_building(self, imp: Impact) -> str:
        """The building struck: the pair's other building (for a facade pair, the one whose
        columns and walls were hit, whichever polygon's vertex touched first)."""
        a, _, b, _, _ = self.pairs[imp.pair]
        if imp.pair in self.walls:  # a fixed wall: it is struck whichever polygon's vertex touched
            return self.walls[imp.pair].name
        if imp.pair in self.facades:
            return self.names[b]
        return self.names[b if imp.striker == 0 else a]

