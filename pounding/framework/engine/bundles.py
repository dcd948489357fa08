"""The declared interface between the driver and the compiled core.

The compiled entry points (:func:`pounding.framework.engine.free_stretch.advance`,
:func:`pounding.framework.engine.kernel.impulses_at`,
:func:`pounding.framework.engine.held.held_stretch` and the pair queries of
:mod:`pounding.framework.engine.pairs`) take their arrays in named bundles, one per
concern, and unpack them on their first line; nothing is indexed by position.
They answer with a :class:`Status` and log impacts as records of
:data:`IMPACT_DTYPE`.

Every call site builds a bundle with the same field types (float64 arrays,
C-contiguous; int64 index arrays; Python floats and bools for scalars), so each
compiled function has one specialization per run. A bundle's arrays are filled in
place, never reshaped, re-typed or re-flagged: a bundle with other arrays is a new
bundle (the extension module built at install checks a bundle's types once,
:mod:`pounding.aot`).

Shapes: n stacked modes, c ground-motion components, S slabs, P slab pairs,
nmax the most modes of one building, kmax the most vertices of one slab.
"""

from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple

import numpy as np


class Status(IntEnum):
    """Why a compiled stretch stopped (returned with the grid index reached)."""

    #: the last grid step asked for was reached
    DONE = 0
    #: a pair touches within the tolerance and closes at the end of the step before the index
    #: returned: the driver applies the impulses (or, for force laws, steps in Python)
    CONTACT = 1
    #: a pair would overlap in the step starting at the index returned; the state is its start
    OVERLAP = 2
    #: every held pair was released at the end of the step before the index returned
    RELEASED = 3
    #: the kernel applied impulses and a pair's rebounds accumulate (Zeno): hold it
    HELD = 4
    #: the links' Newton iteration did not converge in the step starting at the index returned;
    #: the state is its start
    DIVERGED = 5


#: One impact: an impulse at one point of one slab pair (see :class:`pounding.framework.engine.results.Impact`).
IMPACT_DTYPE = np.dtype(
    [
        ("time", np.float64),  # [s]
        ("pair", np.int64),  # index in the run's pair list
        ("striker", np.int64),  # 0: a vertex of the pair's first slab hit, 1: the second's
        ("vertex", np.int64),  # striking vertex in its polygon, -1 face to face
        ("impulse", np.float64),  # [N s]
        ("nx", np.float64),  # unit normal from the first slab towards the second
        ("ny", np.float64),
        ("approach_velocity", np.float64),  # closing speed before the impact [m/s]
        ("energy_loss", np.float64),  # kinetic energy lost [J]
        ("px", np.float64),  # contact point in plan [m]
        ("py", np.float64),
    ]
)


class PairArrays(NamedTuple):
    """Every slab pair that shares a level, as flat arrays (see :mod:`pounding.framework.engine.pairs`)."""

    pa: np.ndarray  #: (P, 2) int64, (building, storey) of the pair's first slab
    pb: np.ndarray  #: (P, 2) int64, of its second slab
    rows: np.ndarray  #: (S, 3, nmax), Phi rows (u, v, phi) of every slab over its building's modes
    off: np.ndarray  #: (n_buildings,) int64, slab index of a building's first storey
    n_modes: np.ndarray  #: (n_buildings, 2) int64, first stacked mode and mode count of each building
    verts: np.ndarray  #: (S, kmax, 2) rest polygons [m]
    nvert: np.ndarray  #: (S,) int64 vertex counts
    centres: np.ndarray  #: (S, 2) centres of mass [m]
    radii: np.ndarray  #: (S,) largest distance of a vertex from the centre [m]
    rest: np.ndarray  #: (P,) signed gap at rest [m]
    axis: np.ndarray  #: (P, 2) unit direction a -> b of the closest points at rest (zeros: none)
    #: (S + V, 2) int64, the real slabs whose rows make up a slab's contact row (-1: none, the
    #: ground): (s, -1) for a real slab, the floors below and above for a facade slab
    floors: np.ndarray
    weights: np.ndarray  #: (S + V, 2) their weights: (1, 0), or the storey shape's (N1, N2)


class Modes(NamedTuple):
    """The stacked modal model and its load."""

    L: np.ndarray  #: (n, c) modal load per unit ground acceleration: p_i = -sum_j L[i, j] ag_j
    c2: np.ndarray  #: (n,) 2 zeta omega [1/s]
    om2: np.ndarray  #: (n,) omega^2 [1/s^2]
    bidx: np.ndarray  #: (n,) int64, building of every mode
    slab_building: np.ndarray  #: (S,) int64, building of every slab


class Ground(NamedTuple):
    """The ground acceleration on the time grid."""

    dt: float  #: grid step [s]
    ag: np.ndarray  #: (nsteps + 1, c) ground acceleration [m/s^2]


class Transition(NamedTuple):
    """An integrator's per-mode step of the grid step and its energy rule (see ``_accumulate_forces``)."""

    A: np.ndarray  #: (n, 3, 3)
    B: np.ndarray  #: (n, 3, 2)
    GA: np.ndarray  #: (nq, n, 3, 3) transitions to the quadrature points c_j dt
    GB: np.ndarray  #: (nq, n, 3, 2)
    gc: np.ndarray  #: (nq,) quadrature points on [0, 1]
    gw: np.ndarray  #: (nq,) quadrature weights
    WA1: np.ndarray  #: (n, 4) closed-form work integrals (shape (0, 4) without them)
    WA2: np.ndarray  #: (n, 4)
    WM: np.ndarray  #: (n, 4, 4)


class StepSearch(NamedTuple):
    """What the compiled impact search needs to step the integrator to any instant inside a grid
    step, besides the integrator's maps (:func:`pounding.framework.engine.event_search.locate`)."""

    dt: float  #: grid step [s]
    A: np.ndarray  #: (n, 3, 3) the integrator's transition over the grid step
    B: np.ndarray  #: (n, 3, 2)
    omega: np.ndarray  #: (n,) modal circular frequencies [rad/s]
    zeta: np.ndarray  #: (n,) modal damping ratios
    ag: np.ndarray  #: (nsteps + 1, c) ground acceleration on the grid [m/s^2]
    rec_t: np.ndarray  #: (m,) the record's sample times [s]
    rec_acc: np.ndarray  #: (m, c) the record's accelerations [m/s^2] (interpolated linearly between samples)
    L: np.ndarray  #: (n, c) modal load per unit ground acceleration
    geo: PairArrays  #: the watched slab pairs


class StepSolution(NamedTuple):
    """The step whose gap the compiled impact search seeks the zero of
    (:func:`pounding.framework.engine.event_search.stepped_gap`): where it starts, the pairs it
    watches, and how it is stepped to any instant inside it."""

    t: float  #: the step's start [s]
    z: np.ndarray  #: (n, 3) the state there
    p0: np.ndarray  #: (n,) the modal load there (with the links' start load -g0 where only the ground acts)
    plist: np.ndarray  #: (k,) int64 the pairs whose smallest gap is sought
    search: StepSearch  #: the grid step's maps, the ground motion and the pairs
    maps: object  #: the integrator's compiled maps to any step length, or None (built-in maps ``builtin``)
    builtin: int  #: the number of the built-in maps (:data:`~pounding.framework.engine.event_search.BUILTIN_MAPS`), -1: ``maps``
    params: np.ndarray  #: the maps' parameters
    held: object  #: the held pairs (:class:`HeldSearch`), one with none held where only the ground acts
    laws: object  #: the links' law updates, or None (every building elastic)
    springs: object  #: the links (:class:`LinkSearch`), or None


class PairFeatures(NamedTuple):
    """The touching features of one slab pair, with their modal rows
    (:func:`pounding.framework.engine.pairs.pair_features`): rows of MAX_FEATURES
    (:data:`pounding.contact.geometry.MAX_FEATURES`), the first ``count`` valid."""

    count: int  #: number of valid rows (0..MAX_FEATURES)
    Q: np.ndarray  #: (MAX_FEATURES, 2) contact points [m]
    N: np.ndarray  #: (MAX_FEATURES, 2) unit normals from slab a towards slab b
    gap: np.ndarray  #: (MAX_FEATURES,) gap of every feature [m]
    who: np.ndarray  #: (MAX_FEATURES,) int64, the striking polygon (0: a vertex of a, 1: of b)
    idx: np.ndarray  #: (MAX_FEATURES,) int64, its vertex
    face: np.ndarray  #: (MAX_FEATURES,) int64, the partner edge of a face-to-face feature (-1: a point feature)
    #: (MAX_FEATURES, n) modal rows: d gap_k = W[k] . dq, and an impulse pair I_k pushing the slabs
    #: apart changes q' by W[k] I_k
    W: np.ndarray


class Features(NamedTuple):
    """The touching features of several slab pairs, stacked, m in all
    (:func:`pounding.framework.engine.pairs.struck_features`)."""

    pair: np.ndarray  #: (m,) int64, the pair of every feature
    gap: np.ndarray  #: (m,) gaps [m]
    W: np.ndarray  #: (m, n) modal rows (:func:`pounding.framework.engine.pairs.contact_row`)
    Q: np.ndarray  #: (m, 2) contact points [m]
    N: np.ndarray  #: (m, 2) unit normals from slab a towards slab b
    who: np.ndarray  #: (m,) int64, the striking slab (0: a vertex of slab a, 1: of slab b)
    idx: np.ndarray  #: (m,) int64, its vertex (-1: not a vertex)
    face: np.ndarray  #: (m,) int64, the face-to-face id within the pair (-1: a point feature)


class TouchingFeatures(NamedTuple):
    """The features of every candidate pair that touches, stacked in pair order, in arrays of a
    capacity ``cap`` of which the first ``count`` rows are valid
    (:func:`pounding.framework.engine.pairs.touching_features`)."""

    count: int  #: number of features
    pair: np.ndarray  #: (cap,) int64, the pair of every feature
    who: np.ndarray  #: (cap,) int64, the striking polygon (0: a vertex of a, 1: of b)
    vertex: np.ndarray  #: (cap,) int64, its vertex (-1: face to face)
    Q: np.ndarray  #: (cap, 2) contact points [m]
    N: np.ndarray  #: (cap, 2) unit normals from slab a towards slab b
    W: np.ndarray  #: (cap, n) modal rows (:func:`pounding.framework.engine.pairs.contact_row`)


class HeldSet(NamedTuple):
    """The pairs a step holds in rigid sustained contact (:func:`pounding.framework.engine.held.held_step`)."""

    pairs: np.ndarray  #: (k,) int64 the held pairs
    contact: HeldContact  #: the tolerance and the touching gap
    #: their touching features at the step's start (:func:`pounding.framework.engine.pairs.struck_features`
    #: with ``deep``), m of them
    start: Features


class StretchEnd(NamedTuple):
    """Where a compiled stretch of grid steps stopped (:func:`pounding.framework.engine.free_stretch.advance`,
    :func:`pounding.framework.engine.spring_core.stretch`, :func:`pounding.framework.engine.held.held_stretch`)."""

    k: int  #: the grid index reached (the start of the step that stopped it, or of the next one: see ``status``)
    status: int  #: a :class:`Status`: DONE, OVERLAP, CONTACT, HELD, RELEASED or DIVERGED
    pair: int  #: the pair that stopped it (-1: none)


class StepEnds(NamedTuple):
    """A step's start and end states and the modal contact forces at its ends, as the links' booking
    reads them (:func:`pounding.framework.engine.spring_core.book_links`; a :class:`HeldStep` serves too)."""

    z0: np.ndarray  #: (n, 3) the start state
    z1: np.ndarray  #: (n, 3) the end state
    f0: np.ndarray  #: (n,) modal contact force at the start [N/kg^0.5]
    f1: np.ndarray  #: (n,) at the end


class HeldStep(NamedTuple):
    """One step with held pairs in rigid sustained contact (:func:`pounding.framework.engine.held.held_step`)."""

    z0: np.ndarray  #: (n, 3) the start state, its acceleration consistent with f0
    z1: np.ndarray  #: (n, 3) the end state
    f0: np.ndarray  #: (n,) modal contact force at the start [N/kg^0.5]
    f1: np.ndarray  #: (n,) at the end
    #: the held pairs' touching features at the end state (pair, gap, W, Q are read): the next step's start
    end: Features
    arrival: float  #: the smallest end gap [m] of a point that was apart at the start (inf: none within the features)
    apair: int  #: its pair (-1: none)


class HeldFixedPoint(NamedTuple):
    """A held step of a model with links with laws, their end remainders by a fixed point around it
    (:func:`pounding.framework.engine.held.held_fixed_point`)."""

    #: Status.DONE, or Status.DIVERGED when the fixed point did not converge (``step`` is then the last pass's)
    status: Status
    step: HeldStep  #: the held step (the contact forces only in its f0, f1, not the links' loads)


class PressedPoints(NamedTuple):
    """The points a step presses, without contact forces at its end
    (:func:`pounding.framework.engine.spring_core.contact_fixed_point`), m of them."""

    W: np.ndarray  #: (m, n) their modal rows
    gap: np.ndarray  #: (m,) end gaps [m]
    rate: np.ndarray  #: (m,) end gap rates [m/s]


class ContactFixedPoint(NamedTuple):
    """The links' end remainders and a force law's contact forces of a step, solved together
    (:func:`pounding.framework.engine.spring_core.contact_fixed_point`)."""

    #: Status.DONE, or Status.DIVERGED when the fixed point did not converge (the rest is then the last pass's)
    status: Status
    lam: np.ndarray  #: (m,) the contact forces [N]
    gap: np.ndarray  #: (m,) the points' end gaps [m] without them, at the converged end load
    rate: np.ndarray  #: (m,) their end gap rates [m/s]


class Recorder(NamedTuple):
    """What a run records, written in place."""

    every: int  #: output rate: the state at grid index k is stored in Q[k // every] when k % every == 0
    Q: np.ndarray  #: (n_out, n) modal displacements
    V: np.ndarray  #: (n_out, n) modal velocities
    E: np.ndarray  #: (n_buildings, 3) ground-motion work, damping work, contact-force work [J]
    peak: np.ndarray  #: (S, 3) running peak |u|, |v|, |phi| of every slab (updated when every > 1)


class Settings(NamedTuple):
    """The contact decisions of a run."""

    tol: float  #: contact tolerance [m]: a step ending with a gap <= tol is contact
    overlap: float  #: gap [m] below which a step is rejected: -tol (impulse laws), 0 (force laws)
    v_min: float  #: closing speed [m/s] below which a touching point is not approaching (rounding)
    #: Newton restitution the kernel applies itself (a law declaring ``compiled_impulses``), -1: the driver does
    restitution: float
    after_eq: bool  #: after impulses, reset the accelerations to equilibrium
    #: the ``crossing`` locator: a step with a pair that ends below ``overlap`` (-eps, rounding) or may
    #: graze inside it (:func:`pounding.framework.engine.crossing.suspect`) goes to the driver; a pair within
    #: the tolerance at a step's end is not struck there
    instant: bool = False


class HeldContact(NamedTuple):
    """The settings of rigid sustained contact (:func:`pounding.framework.engine.held.held_step`)."""

    tol: float  #: contact tolerance [m]
    #: the gap [m] up to which a point touches (:func:`pounding.framework.engine.held.touch_gap`;
    #: inf: every point within the tolerance, the paper's rules)
    touch: float


class EventLog(NamedTuple):
    """Buffers the compiled code appends impacts and event states to; the driver drains them."""

    impacts: np.ndarray  #: (cap,) IMPACT_DTYPE
    n_impacts: np.ndarray  #: (1,) int64
    t: np.ndarray  #: (cape,) times of impact instants [s]
    q: np.ndarray  #: (cape, n) modal displacements just before the impulses
    v: np.ndarray  #: (cape, n) modal velocities just before the impulses
    n_events: np.ndarray  #: (1,) int64
    last_t: np.ndarray  #: (1,) time of the last event state recorded [s] (-inf: none)
    zeno: np.ndarray  #: (P,) bool, pairs whose rebound is too slow to open the tolerance in a step

    @classmethod
    def empty(cls, n: int, n_pairs: int, max_features: int, cap_events: int = 64) -> "EventLog":
        return cls(
            np.zeros(cap_events * max(n_pairs, 1) * max_features, dtype=IMPACT_DTYPE),
            np.zeros(1, dtype=np.int64),
            np.zeros(cap_events),
            np.zeros((cap_events, n)),
            np.zeros((cap_events, n)),
            np.zeros(1, dtype=np.int64),
            np.full(1, -np.inf),
            np.zeros(n_pairs, dtype=np.bool_),
        )


class Links(NamedTuple):
    """The links with laws of a run (yielding storey springs, and the ``[[link]]`` tables' links
    between slabs), as flat arrays over the Newton groups.

    A group is a run of consecutive buildings whose links are coupled (buildings joined by a link,
    :func:`pounding.framework.engine.link_table.link_groups`; a building on its own otherwise).
    Link s has deformation u_s = G[s] q over its group's modes; the links of group j are
    ``bounds[j]:bounds[j + 1]``, their rows over modes ``gmodes[j, 0] : gmodes[j, 0] + gmodes[j, 1]``
    of the stacked model (G is padded with zeros to the most modes of a group). Each link's law is
    ``laws[law[s]]`` of the tuple the stepping takes (:mod:`pounding.framework.engine.links`).
    """

    law: np.ndarray  #: (ns,) int64, index of every link's law in the run's law tuple
    G: np.ndarray  #: (ns, nmax) link rows over their building's modes
    bounds: np.ndarray  #: (n_groups + 1,) int64, first link of every group, then ns
    gmodes: np.ndarray  #: (n_groups, 2) int64, first stacked mode and mode count of every group
    k0: np.ndarray  #: (ns,) initial stiffness [N/m] (kept in the modes; the laws' remainder r - k0 u is a load)
    tol: np.ndarray  #: (n_groups,) Newton residual tolerance of every group [m]
    params: np.ndarray  #: (ns, n_params) law parameters, zero-padded to the widest law
    #: (ns,) 1.0 for a link between slabs (a ``[[link]]`` table: its work is booked to the buildings'
    #: ``links`` term), 0.0 for a storey spring (its work is its building's hysteretic term)
    joins: np.ndarray


class LinkTrial(NamedTuple):
    """The links at one instant: committed (the run's state) or a trial at a step's end."""

    f: np.ndarray  #: (ns,) remainders r - k0 u [N]
    state: np.ndarray  #: (ns, n_state) law states (slots 0, 1, 2: deformation [m], force [N], dissipated [J])
    g: np.ndarray  #: (n,) their modal load G^T f


class LinkRecord(NamedTuple):
    """What a run records of its links, written in place."""

    peak: np.ndarray  #: (ns,) running peak |deformation| [m]
    tangent: np.ndarray  #: (ns,) tangent [N/m] of the last committed step (the tangent-change count's memory)
    work: np.ndarray  #: (n_buildings,) work of the remainders' modal loads [J] (every link's, into the links)
    counts: np.ndarray  #: (n_groups, 3) int64, Newton iterations, steps that iterated, tangent changes (compiled steps)
    hist: np.ndarray  #: (3, n_out, ns) deformation [m], force [N], dissipated energy [J] at the output rows
    #: (n_buildings,) the part of ``work`` done by the links between slabs (``Links.joins``) [J]
    joined_work: np.ndarray


class NewtonWork(NamedTuple):
    """Work buffers of the links' Newton (:func:`pounding.framework.engine.spring_core.solve_group`),
    allocated once per stretch or step (:func:`pounding.framework.engine.spring_core.newton_work`);
    ns links, m of them in the largest group, n stacked modes."""

    qlin: np.ndarray  #: (n,) the linear step's end displacements
    dl: np.ndarray  #: (ns,) the linear step's end deformations [m]
    sf: np.ndarray  #: (ns,) S f, the start remainders' share of them [m] (kept until f changes)
    d: np.ndarray  #: (ns,) the end deformations being solved [m]
    kt: np.ndarray  #: (ns,) the step's tangents [N/m]
    J: np.ndarray  #: (m, m) the active links' Jacobian
    x: np.ndarray  #: (4 m,) residuals, the active rows' right-hand side, the step in the forces, the forces the iterate implies
    act: np.ndarray  #: (m,) int64, the active links (off their initial branch)
    d0: np.ndarray  #: (ns,) the last accepted iterate [m] (the backtracking's start)
    dd: np.ndarray  #: (ns,) the Newton step from it [m]


class LinkStepping(NamedTuple):
    """The links of a compiled stretch (:func:`pounding.framework.engine.spring_core.stretch`)."""

    links: Links  #: the links and their laws' parameters
    S: np.ndarray  #: (ns, ns) the grid step's compliance [m/N] (block diagonal by group)
    now: LinkTrial  #: the committed links, updated in place
    record: LinkRecord  #: what the run records of them, updated in place


class HeldSearch(NamedTuple):
    """What the compiled impact search needs to step with held pairs in rigid sustained contact
    (:func:`pounding.framework.engine.held.held_step`) to any instant inside a grid step, and which
    gap it seeks the zero of (:func:`pounding.framework.engine.event_search.locate`)."""

    held: HeldSet  #: the held pairs, the tolerance and the touching gap, their touching features at the start
    modes: Modes  #: the stacked modal model
    arrival: bool  #: seek the arrival gap (held pairs' points apart at the start), else the pairs' smallest gap
    far: float  #: the arrival gap where no point is apart [m] (a positive stand-in)
    g0: float  #: the gap sought at the step's start [m]


class GrazeSearch(NamedTuple):
    """What the compiled stretch needs to search a suspected step as the driver's Python step does
    (:func:`pounding.framework.engine.event_search.step_touches`): the crossing locator's search on
    the integrator's built-in maps, where only the ground acts (no pair held, no link, no force law)."""

    search: StepSearch  #: the grid step's maps, the ground motion and the pairs
    held: "HeldSearch"  #: one with no pair held (the type the driver's search takes)
    builtin: int  #: the number of the integrator's built-in maps (:data:`~pounding.framework.engine.event_search.BUILTIN_MAPS`)
    params: np.ndarray  #: their parameters
    plist: np.ndarray  #: (k,) int64 the pairs struck by impulses (every pair: no force law in the run)
    eps: float  #: the geometry's zero [m]: a gap within it touches
    tol: float  #: the contact tolerance [m] (the screen's)
    xtol: float  #: the search's bracket width where the gap is not smooth [s]
    #: (2,) the start [s] of the last step in which the search found a zero, and the step length to
    #: it [s] (written by the stretch, read by the driver's Python step of it, which takes it rather
    #: than searching the same step again); a start of -1: none
    found: np.ndarray
    #: (k,) bool: which of ``plist`` the screen suspected in that step (the pairs the search ran on);
    #: written with ``found`` and read only with it
    culprits: np.ndarray


class LinkPass(NamedTuple):
    """The links of a step: committed and trial (:func:`pounding.framework.engine.spring_core._step_with_links`),
    or, where the step's contact forces depend on its end, solved by a fixed point on their end remainders
    around the contact solve (:func:`pounding.framework.engine.held.held_fixed_point`)."""

    links: Links  #: the links and their laws' parameters
    now: LinkTrial  #: the committed links (read)
    #: the trial the passes write: end remainders, trial states (slots a law does not write hold the
    #: committed values), their modal load
    out: LinkTrial


class HeldPairs(NamedTuple):
    """The pairs held in sustained contact and their contact force, updated in place by a held stretch."""

    fc: np.ndarray  #: (n,) modal contact force at the current instant [N/kg^0.5]
    mask: np.ndarray  #: (P,) bool, the held pairs


class LinkSearch(NamedTuple):
    """The links with laws of a run, for the compiled impact search's trial steps
    (:func:`pounding.framework.engine.event_search.locate`, which takes the laws' compiled updates
    beside it: arrays only here, which numba's dispatcher types without Python, as every bundle): each
    trial is the links' own step (:func:`pounding.framework.engine.spring_core.spring_step`, or with
    held pairs :func:`pounding.framework.engine.held.held_fixed_point`) from the committed links,
    whose trial is discarded."""

    links: Links  #: the links and their laws' parameters
    now: LinkTrial  #: the committed links (read)
    #: (1,) int64, set by the search: -1, or where a trial's links did not converge, the Newton group
    #: that diverged (0 for a held step's fixed point): the driver then raises what its trial step raises
    failed: np.ndarray
