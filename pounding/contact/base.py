"""The contact-law plugin contract.

Geometry (where slabs touch, the point Q and the normal n) is found by
:mod:`pounding.contact.geometry`; the driver turns each touching feature k
into a row w_k over the modal coordinates of both buildings such that

* the feature's gap changes as ``d gap_k = w_k . dq`` (so its closing speed is
  ``b_k = -w_k . q'``, the paper's b = v_n1 - v_n2 of eq. 12), and
* a pair of equal and opposite impulses I_k along n at Q (pushing the slabs
  apart) changes the modal velocities by ``w_k I_k``; a force lambda_k adds
  ``w_k lambda_k`` to the modal load.

With mass-normalised modes, ``W = w^T w`` (the Delassus matrix) has on its
diagonal the paper's ``a = sum_i (1/m_i + h_i^2 / J_i)``.

A contact law declares how it acts (``kind``):

``impulse`` laws are asked, at an instant of contact with approaching
    slabs, for the impulses ``I >= 0`` (shape (m,)) given W (m, m) and the
    approach speeds b (m,) [m/s]; the driver locates those instants.
``force`` laws are asked, once per step while slabs touch, for the contact
    forces at the end of the step, solved implicitly with it: given one
    :class:`ContactState` (the end-of-step gaps and gap rates that the step
    would end with without contact forces, their compliances ``S_q``, ``S_v``
    (m, m) to end-of-step forces, and the contact's history: when it began,
    its approach speed then, its pair), return ``lambda >= 0`` (m,) [N].

``none`` laws switch contact off: no slab pair is watched and no contact
    code is loaded.

What a law reports is the same for both kinds: contact *episodes*
(:class:`pounding.framework.engine.results.ContactEpisode`: start, end, pair,
point, peak force, peak penetration, impulse = integral of the force, energy
dissipated), one per impact of an impulse law and one per stretch of touching
of a force law, in ``contacts.csv``, ``summary.json`` and the impact timeline.
The engine measures them from the forces and impulses the law returned; a
law adds nothing to report them.

Contract for an implementer
---------------------------
Everything the driver reads from a law is declared on :class:`ContactLaw`, with
a default and its meaning:

1. ``name`` (the registered name) and ``kind`` (one of :data:`KINDS`), from which the base class
   sets what the engine reads: ``at_events`` (impulses at located instants) and ``with_step``
   (forces solved with the step); the engine never reads ``kind`` or the law's class.
2. Parameters keyword-only in ``__init__`` (``restitution`` always accepted),
   validated there with :class:`pounding.errors.InputError` naming the field.
3. ``tolerance`` [m]: a pair within it is in contact (impulse laws) or watched
   (force laws).
4. Impulse laws: :meth:`ContactLaw.impulses`; ``locate`` (how an impact instant is
   found inside an overlapping step) and ``after_impact`` (what happens to the
   accelerations). ``compiled_impulses``: True declares that ``impulses(W, b)`` is
   exactly :func:`newton_impulses` with ``restitution``, so the compiled core may apply
   them itself between Python steps; leave it False for any other rule (the driver
   then calls :meth:`~ContactLaw.impulses` at every impact).
5. Force laws: :meth:`ContactLaw.forces`, which takes one :class:`ContactState`
   (never more positional arguments: a field added to the bundle breaks no law). Optionally
   :meth:`ContactLaw.forces_solver`, the same solve as a compiled function of the end gaps and
   rates, which the engine then calls inside its compiled step with yielding links (the default
   calls :meth:`~ContactLaw.forces` from Python: correct, slower). Every call of ``forces`` is a
   trial; a law that declares ``keeps_state`` is given each point's identity
   (``ContactState.point``) and :meth:`ContactLaw.commit` is called once per accepted step with
   the state and forces accepted, so it may keep a state of its own point by point as an OpenSees
   material does (trial, commit, revert: a plastic set, tests/contact_plugins.py).
6. :meth:`ContactLaw.contact_duration`: how long one contact lasts for a given effective mass
   and approach speed (force laws; the default, inf, suits impulse laws). The default time step
   resolves it.
7. Force laws given point by point (:class:`pounding.contact.pointwise.PointwiseLaw`) say so with
   :meth:`ContactLaw.point_law` (the default, None: a law given only as :meth:`~ContactLaw.forces`);
   a law built on others (a bumper's layer and slabs, :mod:`pounding.contact.bumper`) sums them
   point by point when both do.
8. Optionally :meth:`ContactLaw.opensees_material`: the law's OpenSees counterpart, the
   ``uniaxialMaterial`` of the ``zeroLength`` contact elements the OpenSees peer of the tests
   and ``pounding export opensees`` place between facing slabs or a slab and a wall
   (:mod:`pounding.peer.opensees_contact`), and :meth:`ContactLaw.opensees_notes`, what that
   material computes differently from the law. None (the default): OpenSees has no material
   of this law, and the export leaves its contact out, saying so.
9. Register the class under the entry-point group ``pounding.contact``, or pass the
   class itself as the scene's contact law, or name it ``"module:Class"`` in a scene
   (``[analysis] contact`` or a ``[[contact]]`` table, which gives one pair of
   buildings its own law: :meth:`ContactLaw.override_problem` and :meth:`ContactLaw.own_law_problem`
   say which laws may). The
   registry checks the class when it is loaded (:meth:`ContactLaw.check_contract`), not in
   the middle of a run.
"""

from __future__ import annotations

import math
from abc import ABC
from typing import ClassVar, NamedTuple

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError


#: the kinds of contact law the driver knows (see the module docstring)
KINDS = ("impulse", "force", "none")
#: the ways an impulse law's impact instant can be located: "crossing" (where the gap is zero, grazes
#: included: :mod:`pounding.framework.engine.crossing`), or the paper's overlap-then-search "halving" and "root"
LOCATORS = ("crossing", "halving", "root")
#: what an impulse law does to the accelerations after an impact
AFTER_IMPACT = ("keep", "equilibrium")


class ContactState(NamedTuple):
    """What a force law is given at the end of a trial step: the m points of slab pairs that touch.

    Every array has one entry per contact point (shape (m,), or (m, m) for the matrices);
    the history fields are the point's pair's *episode* (the stretch of time its slabs have
    touched without letting go), so all the points of one pair share them.

    Attributes
    ----------
    t : float
        Time at the end of the step [s] (the forces act there).
    dt : float
        Length of the step [s].
    gap : ndarray (m,)
        Signed gap at the end of the step without contact forces [m] (negative: the slabs
        overlap; the penetration is -gap).
    rate : ndarray (m,)
        Rate of the gap at the end of the step without contact forces [m/s] (negative:
        closing).
    S_q, S_v : ndarray (m, m)
        Compliances of the end-of-step gaps and gap rates to the end-of-step forces: a force
        vector lambda (m,) [N] changes them by ``S_q @ lambda`` [m] and ``S_v @ lambda`` [m/s].
        Zero where the forces are asked at a given state (the forces rebuilt after a run,
        :mod:`pounding.framework.post.contact_forces`): lambda is then the law at ``gap``, ``rate``.
    W : ndarray (m, m)
        Delassus matrix [1/kg]: its inverse is the pair's mass seen at the points (one point:
        W = 1/m_eff).
    pair : ndarray (m,) int
        Index of each point's slab pair in the run's pair list (``Result.pairs``).
    start : ndarray (m,)
        When the pair's episode began [s]: where the gap crossed zero, interpolated in the
        step it first closed (the step's start when it began overlapping).
    approach : ndarray (m,)
        The pair's closing speed at ``start`` [m/s] (>= 0 for an impact; the deepest point's).
    local_stiffness : ndarray (m,)
        Stiffness of the element each point strikes [N/m]: a neighbour's column or wall
        struck between its floors (:func:`pounding.framework.model.facade.local_stiffness`), inf at
        a slab.
    share : ndarray (m,) or None
        The share of one whole contact each point stands for, fixed by the slabs' rest geometry
        (:mod:`pounding.framework.engine.face_shares`): 1/2 at each end of a face (two slabs
        meeting face to face), so that a face pressed flat carries one contact's force, 1 at a
        corner. It does not change while the point stays in contact, so a law whose force is
        ``share * F(delta)`` is conservative. None (a state built without it): every point is
        a whole contact.
    point : ndarray (m, 3) int or None
        Each point's identity: (pair, striking slab (0: a vertex of the pair's first slab, 1: of its
        second), that slab's vertex), so a law with a state of its own keys it by point
        (:meth:`ContactLaw.commit`). It is the same at every step while the same vertex presses the
        same slab; where the two slabs' vertices stand at the same end of a face at rest (facades
        that end in line), the end is one point whichever of the two presses (the first slab's
        vertex names it). A point that is not a vertex (a midpoint of crossing edges, vertex -1)
        shares one identity per pair and striking slab. None where no law of the run keeps a state
        (:attr:`ContactLaw.keeps_state`: none asks it), or in a state built without it.
    """

    t: float
    dt: float
    gap: np.ndarray
    rate: np.ndarray
    S_q: np.ndarray
    S_v: np.ndarray
    W: np.ndarray
    pair: np.ndarray
    start: np.ndarray
    approach: np.ndarray
    local_stiffness: np.ndarray
    share: np.ndarray | None = None
    point: np.ndarray | None = None

    @property
    def penetration(self) -> np.ndarray:
        """-gap (m,) [m]: positive where the slabs overlap at the step's end without contact forces."""
        return -self.gap

    @classmethod
    def empty(cls, t: float = 0.0, dt: float = 0.0) -> "ContactState":
        """A state with no point (m = 0), at the end t [s] of a step of dt [s]."""
        z, zz = np.zeros(0), np.zeros((0, 0))
        return cls(float(t), float(dt), z, z, zz, zz, zz, np.zeros(0, dtype=np.int64), z, z, z, z, np.zeros((0, 3), dtype=np.int64))

    def take(self, idx: np.ndarray) -> "ContactState":
        """The state of the points ``idx`` (k,) only (matrices cut to (k, k))."""
        ix = np.ix_(idx, idx)
        return self._replace(gap=self.gap[idx], rate=self.rate[idx], S_q=self.S_q[ix], S_v=self.S_v[ix], W=self.W[ix],
                             pair=self.pair[idx], start=self.start[idx], approach=self.approach[idx],
                             local_stiffness=self.local_stiffness[idx],
                             share=None if self.share is None else self.share[idx],
                             point=None if self.point is None else self.point[idx])


def _asks_no_law(default: type) -> str:
    """Why no pair may have a law of its own under ``[analysis] contact`` ``default`` (a law class that
    watches no pair, contact off)."""
    return (f"[analysis] contact {default.name or default.__name__!r} watches no pair, so no pair's law is asked; "
            "give [analysis] contact a law")


class ContactLaw(ABC):
    """Base class of every contact law (see the module docstring for the contract).

    Every attribute below is read by the driver; a subclass overrides what it needs.
    """

    #: registered name
    name: ClassVar[str] = ""
    #: "impulse", "force" or "none" (:data:`KINDS`)
    kind: ClassVar[str] = "impulse"
    #: True when :meth:`impulses` is exactly :func:`newton_impulses` with ``restitution``:
    #: the compiled core then applies the impulses itself (impulse laws only)
    compiled_impulses: ClassVar[bool] = False
    #: contact length tolerance [m]
    tolerance: float = 1e-4
    #: impact-instant location (impulse laws): "crossing", "halving" or "root" (:data:`LOCATORS`)
    locate: str = "crossing"
    #: accelerations after an impact (impulse laws): "equilibrium" or the paper's "keep"
    after_impact: str = "equilibrium"
    #: what the law needs from the engine, which is all the engine reads of ``kind``: impulses at
    #: located instants of contact (``at_events``), forces solved with every step while its pairs
    #: touch (``with_step``), or neither (contact off: no pair is watched). Set from ``kind`` for
    #: every subclass (:meth:`__init_subclass__`) unless the subclass sets them itself.
    at_events: ClassVar[bool] = True
    with_step: ClassVar[bool] = False
    #: True for a force law that keeps a state of its own point by point: the engine then names the
    #: points (``ContactState.point``) and commits the accepted steps to it (:meth:`commit`), and a law
    #: built on others (a bumper's) knows it cannot stand in for it
    keeps_state: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "at_events" not in cls.__dict__:
            cls.at_events = cls.kind == "impulse"
        if "with_step" not in cls.__dict__:
            cls.with_step = cls.kind == "force"

    @classmethod
    def watches(cls) -> bool:
        """Whether the engine watches the slab pairs for this law (False: contact is off)."""
        return bool(cls.at_events or cls.with_step)

    def __init__(self, *, restitution: float = 0.5):
        if not (isinstance(restitution, (int, float)) and 0.0 <= restitution <= 1.0):
            raise InputError(f"expected a coefficient of restitution in [0, 1], got {restitution!r}", field="restitution")
        self.restitution = float(restitution)

    @classmethod
    def check_contract(cls) -> None:
        """Raise :class:`TypeError` naming what a law class declares wrong (called on registration)."""
        if cls.kind not in KINDS:
            raise TypeError(f"contact law {cls.__name__} declares kind={cls.kind!r}; expected one of {KINDS}")
        if cls.kind == "impulse" and cls.impulses is ContactLaw.impulses:
            raise TypeError(f"contact law {cls.__name__} is an impulse law but does not implement impulses(W, b)")
        if cls.kind == "force" and cls.forces is ContactLaw.forces:
            raise TypeError(f"contact law {cls.__name__} is a force law but does not implement forces(...)")
        if cls.at_events and cls.with_step:
            raise TypeError(f"contact law {cls.__name__} declares both at_events and with_step; a law acts one way")
        if cls.compiled_impulses and cls.kind != "impulse":
            raise TypeError(f"contact law {cls.__name__} declares compiled_impulses but is not an impulse law")
        if cls.kind == "force":
            import inspect

            params = [p for p in inspect.signature(cls.forces).parameters.values()
                      if p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
            if len(params) > 2:  # self and the ContactState (a wrapper taking *args passes)
                raise TypeError(f"contact law {cls.__name__}: forces() takes one ContactState (forces(self, contact)), "
                                f"not ({', '.join(p.name for p in params)})")

    @classmethod
    def override_problem(cls, default: type) -> str | None:
        """Why this law cannot serve one pair of buildings in a run whose other pairs take the law
        class ``default`` (a ``[[contact]]`` table), or None when it can.

        A force law may serve any pair: each solves its own points with the step, beside the
        impulses of a run whose ``[analysis] contact`` acts at events (which then locates its
        impacts by ``crossing``: :meth:`mixing_problem`). An impulse law may serve pairs beside a
        force law's (it locates by ``crossing`` too). An impulse law's Newton problem couples every
        pair that shares a building at an instant, so one impulse law serves every pair that takes
        impulses: ``[analysis] contact``'s when it acts at events, whose restitution a pair may
        change, else the first table's (:meth:`impulse_law_problem` checks the others against it).
        With contact off nothing is watched."""
        if not cls.watches():
            return (f"{cls.name or cls.__name__!r} watches no pair: a pair's own law acts (a force law, or an impulse law); "
                    "leave the table out for the pair to take [analysis] contact's")
        if not cls.with_step:
            if cls.at_events and default.with_step:
                return None
            if default.at_events and cls is default:
                return None
            if default.at_events:
                return (f"{cls.name or cls.__name__!r} acts by impulses at events, and one impulse law serves every pair of a run "
                        f"(its Newton problem couples the pairs that share a building); a pair's own law must act by forces")
            return (f"{cls.name or cls.__name__!r} acts by impulses at events: one impulse law serves the pairs that take "
                    "impulses, and it is [analysis] contact's (make it [analysis] contact and give the other pairs their "
                    "force law here)")
        if not default.watches():
            return _asks_no_law(default)
        return None

    def mixing_problem(self) -> str | None:
        """Why force laws cannot serve some pairs of a run whose impulse law is this one, or None when
        they can: an impulse law mixes with force laws when it locates its impacts where the gap is
        zero (``locate = "crossing"``, the default), as the pairs that press by forces run through
        every step of their contact; the paper's locators strike every pair within the tolerance,
        force pairs included."""
        if self.at_events and getattr(self, "locate", "crossing") != "crossing":
            return (f"the impulse law locates impacts by {self.locate!r}, which strikes every pair within the tolerance; "
                    "a run with pairs under force laws beside impulses takes locate = \"crossing\" (the default)")
        return None

    def own_law_problem(self, default: "ContactLaw") -> str | None:
        """Why this law cannot serve some pairs of its own (a ``[[contact]]`` table's pairs of two
        buildings, or the slabs against a ``[[wall]]``) in a run whose other pairs take ``default``
        (``[analysis] contact``), or None when it can.

        A force law may (:meth:`override_problem`, :meth:`mixing_problem`), and so may an impulse law
        beside a force law ``default`` (it serves every pair that takes impulses: the run's other
        impulse laws are checked against it, :meth:`impulse_law_problem`). Beside an impulse law
        ``default``, an impulse law may when it is ``default``'s with, at most, a restitution of its
        own (:meth:`impulse_law_problem`)."""
        if not default.watches():
            return _asks_no_law(type(default))
        if self.with_step or default.with_step:
            return (type(self).override_problem(type(default))
                    or (default.mixing_problem() if self.with_step else self.mixing_problem()))
        return self.impulse_law_problem(default, "[analysis] contact")

    def impulse_law_problem(self, other: "ContactLaw", whose: str) -> str | None:
        """Why this impulse law cannot serve its pairs beside ``other``, the impulse law of the run's
        other pairs that take impulses (``whose``: where ``other`` is given), or None when it can: it
        must be ``other``'s law with, at most, a restitution of its own. The run's events (tolerance,
        locator, accelerations after an impact) are one for all pairs, and a restitution of its own is
        applied inside the Newton problem of an instant only to a law whose impulses are Newton's with
        its restitution (``compiled_impulses``)."""
        if type(self) is not type(other):
            return (f"the impulse law {self.name or type(self).__name__!r} differs from {other.name or type(other).__name__!r}, "
                    f"the impulse law {whose} gives: one impulse law serves every pair of a run that takes impulses "
                    "(a pair or a wall may take its own restitution)")
        mine = {k: v for k, v in self.describe().items() if k != "restitution"}
        theirs = {k: v for k, v in other.describe().items() if k != "restitution"}
        if mine != theirs:
            differ = ", ".join(sorted(k for k in mine if mine.get(k) != theirs.get(k)))
            return f"{differ} must be as {whose} gives it (the run's events are one for every pair); only the restitution may differ"
        if self.restitution != other.restitution and not self.compiled_impulses:
            return (f"{self.name or type(self).__name__!r} does not declare its impulses Newton's with its restitution "
                    "(compiled_impulses), so a pair or a wall cannot take a restitution of its own with it")
        return None

    def impulses(self, W: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Impulses I >= 0 [N s] (m,) at the touching features of one slab pair (impulse laws),
        given the Delassus matrix W (m, m) [1/kg] and the closing speeds b (m,) [m/s]."""
        raise NotImplementedError

    def forces(self, contact: ContactState) -> np.ndarray:
        """End-of-step contact forces lambda >= 0 [N] (m,) (force laws), solved with the step:
        the gaps at the step's end are ``contact.gap + contact.S_q @ lambda`` (see
        :class:`ContactState` for the state and history of the m points)."""
        raise NotImplementedError

    def commit(self, contact: ContactState, forces: np.ndarray) -> None:
        """Accept a step (force laws that declare :attr:`keeps_state`): ``forces`` (m,) [N] are the
        forces of the m points of ``contact`` at the end of a step the engine has accepted, solved
        from that state (the points' end gaps are ``contact.gap + contact.S_q @ forces``). Called,
        for a law that declares :attr:`keeps_state`, once per accepted step in which the law's points press, after every call of :meth:`forces` for that step, and once more,
        with no point (m = 0), at the first accepted step after its last points let go; every call
        of :meth:`forces` is a trial (a located impact, a fixed-point pass, a rejected step) that
        must not change what the law keeps. A law with a state of its own (a plastic set, a damage
        variable) declares :attr:`keeps_state`, updates its committed state here, point by point
        (``contact.point``), and reads it in :meth:`forces`: OpenSees' ``commitState``; a step that
        is not committed is reverted. A point absent from a commit has no force in that step (it is
        apart). The default keeps nothing (a law whose force is a function of the state and the
        contact's history)."""

    def forces_solver(self, contact: ContactState):
        """:meth:`forces` as a solve the engine can repeat with other end gaps and rates: ``(solve,
        args)`` with ``solve(args, gap, rate)`` the forces (m,) [N] of ``contact`` whose end gaps and
        rates without contact forces are ``gap`` [m] and ``rate`` [m/s] (m,), every other field as in
        ``contact``. With yielding links the engine solves the links and the contact forces of a step
        together by a fixed point that asks this solve at each pass
        (:func:`pounding.framework.engine.spring_core.contact_fixed_point`): where ``solve`` is a
        compiled function (:func:`pounding.compiler.njit`) and ``args`` a tuple of arrays, floats and
        compiled kernels, that whole step runs compiled. The default asks :meth:`forces` from Python;
        a law with a compiled solve returns it, and gives :meth:`forces` as that solve at the
        contact's own gaps and rates (one copy)."""
        return python_forces, (self, contact)

    def point_law(self, m_eff: np.ndarray):
        """The law point by point, for a law built on this one (a bumper's layer and slabs,
        :class:`pounding.contact.bumper.BumperLaw`): ``(law_force, params)``, the compiled kernel
        ``(delta, rate, approach_rate, params[i]) -> (force, d force / d delta, d force / d rate)``
        and its parameters (m, p) at m points of effective masses ``m_eff`` (m,) [kg]; or None (the
        default) for a law that is only given as :meth:`forces` of a whole contact state."""
        return None

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """How long one contact of this law lasts [s]: two free bodies of effective mass ``m_eff``
        [kg] meeting at ``approach_speed`` [m/s] stay in contact this long.

        The default step resolves it (:mod:`pounding.framework.engine.contact_step`), so a law
        that cannot give it exactly gives a lower bound (a shorter duration asks for a finer
        step). inf (the default): the law acts at instants (impulses) or not at all, and puts
        no bound on the step."""
        return math.inf

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple | None:
        """The law's OpenSees counterpart: the ``uniaxialMaterial`` arguments after its tag (the
        material's name first) of a ``zeroLength`` contact element along the contact's normal, or
        None (the default) when OpenSees has no material of this law, whatever the arguments.

        The element carries ``share`` [-] of one contact (1/2 at each end of a face: the face rule,
        :class:`ContactState`'s ``share``) at a point of effective mass ``m_eff`` [kg], the slabs
        (or slab and wall) ``clear`` [m] apart at rest. Its deformation is the separation's change
        [m], negative as the gap closes, so a gap material takes ``-clear`` as the deformation at
        which contact begins and returns a negative (compressive) force [N]; ``zeroLength`` passes
        it the deformation rate, and no Rayleigh damping: the material is the whole contact, as
        the law is.
        """
        return None

    def opensees_notes(self) -> list[str]:
        """What :meth:`opensees_material` computes differently from the law, one sentence each (the
        export writes them at the top of its script); empty (the default) when nothing."""
        return []

    def describe(self) -> dict:
        """Name and parameters, for summary.json."""
        return {"name": self.name, **{k: v for k, v in vars(self).items() if not k.startswith("_")}}


def newton_impulses(W: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Impulses that give every approaching point the Newton rebound -k b.

    Solves the small linear complementarity problem: I >= 0, and for each
    point either I_j > 0 with post-impact closing speed ``b_j - (W I)_j = -k b_j``
    (or 0 for a point that was not approaching but would be pushed into the other
    slab), or I_j = 0 with ``b_j - (W I)_j <= 0`` (not approaching). The active sets
    are enumerated, largest first (m <= MAX_FEATURES = 8 points per slab pair).

    Parameters
    ----------
    W : ndarray (m, m)
        Delassus matrix [1/kg].
    b : ndarray (m,)
        Closing speeds before impact [m/s].
    k : float
        Coefficient of restitution.
    """
    return newton_lcp(np.ascontiguousarray(W, dtype=float), np.ascontiguousarray(b, dtype=float), float(k))


@njit
def principal_solve(W, target, idx):
    """Impulses (size,) of the active points idx (size,): the principal system
    W[idx, idx] I = target[idx] of the Newton problem, by :func:`solve_small`."""
    size = idx.shape[0]
    sub = np.empty((size, size))
    rhs = np.empty(size)
    for r in range(size):
        rhs[r] = target[idx[r]]
        for s in range(size):
            sub[r, s] = W[idx[r], idx[s]]
    return solve_small(sub, rhs)


@njit
def newton_lcp(W, b, k):
    """Compiled core of :func:`newton_impulses` (same arguments, float64 arrays).

    Every subset of points is a candidate active set, largest first: an active point ends
    with the Newton rebound -k b if it approached (b > 0), or just stops closing (0) if the
    other impulses would drag it into the other slab; the inactive ones must not close.
    W is positive definite for distinct features, so the solution is unique.
    """
    m = b.shape[0]
    target = np.empty(m)
    for j in range(m):
        target[j] = (1.0 + k) * b[j] if b[j] > 0 else b[j]
    scale = 1.0
    for j in range(m):
        scale = max(scale, abs(b[j]))
    if not np.any(b > 0):
        return np.zeros(m)
    for size in range(m, 0, -1):
        for mask in range(1 << m):
            count = 0
            for j in range(m):
                if mask >> j & 1:
                    count += 1
            if count != size:
                continue
            idx = np.empty(size, dtype=np.int64)
            c = 0
            for j in range(m):
                if mask >> j & 1:
                    idx[c] = j
                    c += 1
            I_act = principal_solve(W, target, idx)
            if np.any(I_act < -1e-12 * np.abs(I_act).max()):
                continue
            I = np.zeros(m)
            for r in range(size):
                I[idx[r]] = max(I_act[r], 0.0)
            after = b - W @ I
            good = True
            for j in range(m):
                if not (mask >> j & 1) and after[j] > 1e-12 * scale:
                    good = False
            if good:
                return I
    return np.zeros(m)


@njit
def solve_small(S, rhs):
    """x with S x = rhs for a small symmetric positive semi-definite S (a Delassus or compliance
    matrix), as the minimum-norm least-squares solution: directions whose eigenvalue is below
    1e-12 of the largest (features that repeat one another, to rounding) get nothing, instead
    of the huge values an LU solve would give them."""
    if S.shape[0] == 1:  # one point: the common case, without LAPACK
        return rhs / S[0, 0] if S[0, 0] > 0.0 else np.zeros(1)
    lam, V = np.linalg.eigh(0.5 * (S + S.T))
    top = 0.0
    for j in range(lam.shape[0]):
        top = max(top, abs(lam[j]))
    c = V.T @ rhs
    for j in range(lam.shape[0]):
        c[j] = c[j] / lam[j] if lam[j] > 1e-12 * top else 0.0
    return V @ c



@njit(borrowed=True)
def keep_pushing(idx, sol, lam, active):
    """One pass of a unilateral active-set solve: lam (m,) <- the solution ``sol`` (na,) on the
    active points ``idx`` (na,) and 0 elsewhere; the points whose force would pull (sol < 0) leave
    ``active`` (m,). Returns True when none pulls (the pass solved the contact)."""
    lam[:] = 0.0
    ok = True
    for r in range(idx.shape[0]):
        lam[idx[r]] = sol[r]
        if sol[r] < 0.0:
            active[idx[r]] = False
            ok = False
    return ok

#: the most simultaneous features whose active sets :func:`newton_group` enumerates (as
#: :func:`newton_lcp`, 2^m candidate sets); beyond it, principal pivoting (:func:`newton_pivot`)
ENUMERATE_MAX = 8


@njit
def newton_group(W, b, k):
    """Newton impulses I >= 0 [N s] (m,) of a group of simultaneous features of any size.

    The Newton impulse problem over every touching, approaching feature of every slab pair
    that shares a building at an instant (a building struck from both sides at once, several
    storeys of one pair): W (m, m) the Delassus matrix of the stacked modal rows [1/kg], b (m,)
    the closing speeds [m/s], k the restitution. Up to :data:`ENUMERATE_MAX` features the
    active sets are enumerated (:func:`newton_lcp`, the solver of one slab pair, so a lone pair
    gets the same impulses to the bit); beyond, :func:`newton_pivot` solves the standard Newton
    LCP, whose solution is the enumerated one whenever every approaching point gets an impulse
    (the first set both try).
    """
    if b.shape[0] <= ENUMERATE_MAX:
        return newton_lcp(W, b, k)
    return newton_pivot(W, b, k)


@njit
def newton_pivot(W, b, k):
    """Newton impulses by Murty's least-index principal pivoting, for many features at once.

    The standard Newton LCP (Moreau; Glocker): with target t_j = (1 + k) b_j for an approaching
    point (b_j > 0) and b_j otherwise, find I >= 0 with w = W I - t >= 0 and I_j w_j = 0: an
    active point ends with the Newton rebound -k b_j (or stops closing), an inactive one
    separates at least that fast. Murty's rule (flip the first index that violates its
    condition) ends in finitely many pivots for a positive definite W (a P-matrix); features
    that repeat one another (W singular) are solved by minimum norm (:func:`solve_small`).
    Starts from the approaching points active, which is the answer in the common case.

    Reference: Murty, K. G. (1974), Note on a Bard-type scheme for solving the complementarity
    problem, Opsearch 11, 123-130.
    """
    m = b.shape[0]
    target = np.empty(m)
    scale = 1.0
    for j in range(m):
        target[j] = (1.0 + k) * b[j] if b[j] > 0 else b[j]
        scale = max(scale, abs(target[j]))
    if not np.any(b > 0):
        return np.zeros(m)
    active = b > 0
    I = np.zeros(m)
    for _ in range(50 * m + 100):
        size = 0
        for j in range(m):
            if active[j]:
                size += 1
        idx = np.empty(size, dtype=np.int64)
        c = 0
        for j in range(m):
            if active[j]:
                idx[c] = j
                c += 1
        I[:] = 0.0
        if size > 0:
            I_act = principal_solve(W, target, idx)
            for r in range(size):
                I[idx[r]] = I_act[r]
        top = 0.0
        for j in range(m):
            top = max(top, abs(I[j]))
        w = W @ I - target
        flip = -1
        for j in range(m):
            if active[j] and I[j] < -1e-12 * top:
                flip = j
                break
            if not active[j] and w[j] < -1e-12 * scale:
                flip = j
                break
        if flip < 0:
            return np.maximum(I, 0.0)
        active[flip] = not active[flip]
    return np.maximum(I, 0.0)  # not reached for a positive definite W


def python_forces(args, gap, rate) -> np.ndarray:
    """The forces (m,) [N] of the law and contact state ``args`` = (law, contact) at the end gaps
    ``gap`` [m] and rates ``rate`` [m/s] (m,): its :meth:`ContactLaw.forces` (the default
    :meth:`ContactLaw.forces_solver`)."""
    law, contact = args
    return np.asarray(law.forces(contact._replace(gap=gap, rate=rate)), dtype=float)
