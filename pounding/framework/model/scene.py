"""The scene: an immutable, validated description of what to analyse (SI units).

Nothing downstream writes into these objects; derived quantities (matrices,
modes, results) live in their own objects. ``with_*`` methods return copies.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # the model holds elements; it never needs their classes to run
    from pounding.elements.base import PlanarElement
from pounding.errors import InputError


class KeywordError(InputError, TypeError):
    """A misspelt or unknown keyword argument of the Python API (a TypeError, as Python raises for one,
    with the command line's "did you mean")."""


def check_keywords(given, accepted, where: str) -> None:
    """Raise :class:`KeywordError` for the first keyword of ``given`` not in ``accepted``, naming the closest
    accepted one (``unknown keyword 'dtt' (did you mean 'dt'?)``) or listing them."""
    import difflib

    for key in given:
        if key not in accepted:
            close = difflib.get_close_matches(str(key), list(accepted), n=1, cutoff=0.6)
            hint = f"did you mean {close[0]!r}?" if close else f"accepted: {', '.join(sorted(accepted))}"
            raise KeywordError(f"unknown keyword {key!r} ({hint})", field=where)


@dataclass(frozen=True, eq=False)
class Slab:
    """One rigid floor slab.

    Attributes
    ----------
    vertices : ndarray (k, 2)
        Plan polygon in global coordinates, counter-clockwise [m].
    mass : float
        [kg].
    centre : ndarray (2,)
        Centre of mass [m].
    polar_inertia : float
        Mass moment of inertia about the vertical axis through ``centre`` [kg m^2].
    elevation : float
        Height of the floor above the ground [m].
    """

    vertices: np.ndarray
    mass: float
    centre: np.ndarray
    polar_inertia: float
    elevation: float

    @property
    def radius(self) -> float:
        """Largest distance from the centre of mass to a vertex [m]."""
        return float(np.max(np.hypot(*(self.vertices - self.centre).T)))


@dataclass(frozen=True)
class Damping:
    """Classical damping model of one building.

    kind : "rayleigh" (ratio at two modes or two periods), "modal" (ratio per
    mode) or "stiffness" (stiffness proportional, ratio at one mode).
    """

    kind: str = "rayleigh"
    ratio: float | tuple[float, ...] = 0.05
    modes: tuple[int, ...] = (1, 3)
    periods: tuple[float, ...] | None = None


@dataclass(frozen=True)
class PDelta:
    """P-Delta from gravity loads: a linear storey geometric stiffness (``[building.p_delta]``).

    load_factor : float
        Gravity load of each floor = load_factor x g x its slab mass [-] (used when ``loads`` is None).
    loads : tuple of float or None
        Gravity load of each floor [N], bottom first, acting over the slab like its mass.
    """

    load_factor: float = 1.0
    loads: tuple[float, ...] | None = None


@dataclass(frozen=True, eq=False)
class Building:
    """One shear building: rigid slabs joined by planar elements."""

    name: str
    storey_heights: tuple[float, ...]
    slabs: tuple[Slab, ...]
    elements: tuple[PlanarElement, ...]
    damping: Damping = field(default_factory=Damping)
    #: stiffness modifier of every element, scene order (None: all 1); see :meth:`element_modifiers`
    modifiers: tuple[float, ...] | None = None
    #: P-Delta from gravity loads (None: off); see :mod:`pounding.framework.model.pdelta`
    p_delta: "PDelta | None" = None

    def element_modifiers(self) -> tuple[float, ...]:
        """Factor on each element's condensed lateral stiffness [-] (cracked sections), scene order."""
        return self.modifiers if self.modifiers is not None else (1.0,) * len(self.elements)

    @property
    def n_storeys(self) -> int:
        return len(self.storey_heights)

    @property
    def elevations(self) -> np.ndarray:
        """Floor heights above ground [m], shape (n_storeys,)."""
        return np.cumsum(self.storey_heights)


def _positive_number(value) -> bool:
    """Whether ``value`` is a finite number > 0 (not a bool)."""
    return (isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
            and bool(np.isfinite(value)) and value > 0)


@dataclass(frozen=True)
class Analysis:
    """Time-history options ([analysis] table)."""

    #: registered integrator name; None: chosen for the scene (:mod:`pounding.framework.engine.integrator_choice`)
    integrator: str | None = None
    integrator_params: dict[str, Any] = field(default_factory=dict)
    dt: float | None = None
    duration: float | None = None
    contact: str = "impulse"
    contact_params: dict[str, Any] = field(default_factory=dict)
    output_every: int = 1
    #: relative energy-balance error above which a run warns; HHT-type schemes dissipate
    #: ~1e-3 numerically and the paper's "keep accelerations" rule costs ~1e-2 with pounding
    energy_tolerance: float = 0.02
    #: contact-duration model for the equivalent peak force of impacts ([analysis.impact_force]);
    #: post-processing only, see :mod:`pounding.framework.post.response`
    impact_force: dict[str, Any] = field(default_factory=dict)
    #: names of the plausibility checks not to warn about (:mod:`pounding.framework.post.plausibility`)
    silence: tuple[str, ...] = ()

    def __post_init__(self):
        # what the scene file's schema checks, checked again for options set from Python (Scene.with_analysis):
        # a zero duration would otherwise run the whole record, a negative dt fail deep in an integrator
        for key in ("dt", "duration"):
            value = getattr(self, key)
            if value is not None and not _positive_number(value):
                raise InputError(f"expected a positive number of seconds (or None: chosen for the scene), got {value!r}",
                                 field=f"analysis.{key}")
        if isinstance(self.output_every, bool) or not isinstance(self.output_every, (int, np.integer)) or self.output_every < 1:
            raise InputError(f"expected a positive whole number of steps, got {self.output_every!r}", field="analysis.output_every")
        if not _positive_number(self.energy_tolerance):
            raise InputError(f"expected a positive relative error, got {self.energy_tolerance!r}", field="analysis.energy_tolerance")


@dataclass(frozen=True)
class Bumper:
    """A rubber layer on one building's face at chosen storeys (``bumper`` of a ``[[contact]]`` table):
    :mod:`pounding.framework.model.bumpers`.

    on : str
        The building whose slabs carry the layer (one of the rule's two).
    storeys : tuple of int
        The storeys (1-based) of ``on`` whose slab carries it; each has a slab of the other building
        at its level.
    thickness : float
        The layer's thickness t [m], less than every rest gap it stands in.
    compressible : float
        The fraction of t the layer compresses before the slabs' law acts too, in (0, 1] [-].
    law : str or type
        The layer's own contact law (a force law: ``rubber`` or any other).
    params : dict
        Its parameters.
    """

    on: str
    storeys: tuple[int, ...]
    thickness: float
    compressible: float
    law: Any
    params: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class ContactRule:
    """The contact law of the slab pairs between two buildings (a ``[[contact]]`` table), instead
    of ``[analysis] contact``.

    between : (str, str)
        The two buildings' names (either order).
    law : str or type
        A registered contact law's name, ``"module:Class"``, or the class itself.
    params : dict
        The law's parameters.
    bumper : Bumper or None
        A rubber layer at some storeys of one of the two (:class:`Bumper`); ``law`` then acts once
        the layer is compressed to its ``compressible`` fraction.
    """

    between: tuple[str, str]
    law: Any
    params: dict[str, Any] = field(default_factory=dict)
    bumper: Bumper | None = None


@dataclass(frozen=True, eq=False)
class Link:
    """A link between two slabs (a ``[[link]]`` table): a law acting between a point of one slab and
    a point of another (two buildings, or two floors of one), along the line between the points at
    rest, as OpenSees' zeroLength element with a uniaxial material.

    name : str
        The link's name (summary.json, response.npz).
    between : (str, str)
        The two buildings' names (a building may be named twice: two of its floors).
    storeys : (int, int)
        The slab of each building, 1-based.
    points : ndarray (2, 2)
        The attachment points in plan [m], each on its slab; they differ.
    law : HysteresisLaw
        The link's law (an instance of a ``pounding.hysteresis`` class).
    params : ndarray (n_params,)
        The law's parameter vector (:meth:`HysteresisLaw.pack`: k0 [N/m], Fy [N], b [-], its own).
    """

    name: str
    between: tuple[str, str]
    storeys: tuple[int, int]
    points: np.ndarray
    law: Any
    params: np.ndarray

    @property
    def direction(self) -> np.ndarray:
        """Unit vector (2,) from the first point to the second at rest: the line the link acts along."""
        d = self.points[1] - self.points[0]
        return d / float(np.hypot(*d))

@dataclass(frozen=True, eq=False)
class Wall:
    """A retaining wall fixed to the ground (a ``[[wall]]`` table): every slab at or below its top
    can strike its face (:mod:`pounding.framework.model.walls`).

    name : str
        Its name (the struck body in impacts.csv).
    face : ndarray (k, 2)
        Plan polyline of the wall's face [m], k >= 2; a building stands on the side of it where it is at rest.
    top : float
        Height of the wall's top above the ground [m], > 0.
    law : str, type or None
        Its contact law (a registered name, ``"module:Class"`` or the class); None: ``[analysis] contact``.
    params : dict
        The law's parameters (with ``law`` None: a ``restitution`` of its own for ``[analysis] contact``).
    """

    name: str
    face: np.ndarray
    top: float
    law: Any = None
    params: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything a run needs: the buildings, the ground motion and the options."""

    buildings: tuple[Building, ...]
    ground_motion: Any  # GroundMotion or GroundMotionPair (pounding.io; kept loose to avoid an import cycle)
    analysis: Analysis = field(default_factory=Analysis)
    source: Path | None = None
    #: per pair of buildings, a contact law instead of ``analysis.contact`` (:class:`ContactRule`)
    contacts: tuple[ContactRule, ...] = ()
    #: links between slabs (:class:`Link`, the ``[[link]]`` tables)
    links: tuple[Link, ...] = ()
    #: retaining walls fixed to the ground (:class:`Wall`)
    walls: tuple[Wall, ...] = ()

    def building(self, name: str) -> Building:
        for b in self.buildings:
            if b.name == name:
                return b
        raise KeyError(name)

    def with_analysis(self, **changes: Any) -> "Scene":
        """A copy with these :class:`Analysis` options changed (``dt=0.005``, ``contact="penalty"``,
        ``contact_params={...}``, ``integrator="newmark"``, ``duration=10.0``...).

        Raises :class:`KeywordError` (a TypeError) naming the closest option for a misspelt one.
        """
        check_keywords(changes, [f.name for f in fields(Analysis)], "Scene.with_analysis")
        return replace(self, analysis=replace(self.analysis, **changes))

    def with_contact(self, between: tuple[str, str], law: Any, **params: Any) -> "Scene":
        """A copy where the slab pairs between the buildings ``between`` take ``law`` (a name,
        ``"module:Class"`` or a class) with ``params`` (replacing an earlier rule for that pair)."""
        keep = tuple(r for r in self.contacts if frozenset(r.between) != frozenset(between))
        return replace(self, contacts=keep + (ContactRule(tuple(between), law, dict(params)),))

    def with_wall(self, name: str, face: Any, top: float, law: Any = None, **params: Any) -> "Scene":
        """A copy with a retaining wall ``name`` (replacing one of that name): its face a plan polyline
        (k, 2) [m], its top [m] above the ground, its contact law (None: ``[analysis] contact``, whose
        parameters ``params`` then override, e.g. ``restitution``). Raises :class:`~pounding.errors.InputError`
        for a wall that cannot stand here (:func:`pounding.framework.model.walls.check_wall`); its law is
        checked when a run builds it."""
        from pounding.framework.model.walls import check_wall

        wall = Wall(name, np.asarray(face, dtype=float), float(top), law, dict(params))
        try:
            check_wall(wall, self.buildings)
        except InputError as exc:
            raise exc.located(field_prefix=f"Scene.with_wall({name!r})") from None
        keep = tuple(w for w in self.walls if w.name != name)
        return replace(self, walls=keep + (wall,))

    def with_ground_motion(self, ground_motion: Any) -> "Scene":
        """A copy shaken by ``ground_motion`` (a :class:`~pounding.io.ground_motion.GroundMotion` or a
        :class:`~pounding.io.motion_pair.GroundMotionPair`, e.g. ``scene.ground_motion.scaled_to_pga(0.4)``)."""
        return replace(self, ground_motion=ground_motion)

    def with_gap(self, gap: float, direction: Any = None) -> "Scene":
        """A copy with the second building moved along ``direction`` so that the clear distance at rest is ``gap`` [m].

        ``direction``: ``None`` (the normal of the facing slab edges), ``"x"``, ``"y"``, an angle [degrees from x]
        or a plan vector (dx, dy); the clear distance is the smallest over the places where the buildings can
        meet (slabs at a common level, and a slab against the neighbour's facade between its floors,
        :func:`pounding.framework.model.placement.pair_sites`), measured along it (:func:`pounding.framework.model.placement.with_gap`, used by ``pounding gap`` and ``pounding sweep``).
        """
        from pounding.framework.model.placement import with_gap

        return with_gap(self, gap, direction)

    def with_building_shifted(self, name: str, offset: np.ndarray) -> "Scene":
        """A copy where building ``name`` (slabs and elements) is translated in plan by ``offset`` [m].
        Raises :class:`~pounding.errors.InputError` naming the scene's buildings when none is called ``name``."""
        names = [b.name for b in self.buildings]
        if name not in names:
            raise InputError(f"no building {name!r}; expected one of {', '.join(repr(n) for n in names)}",
                             field="Scene.with_building_shifted")
        offset = np.asarray(offset, dtype=float)
        out = []
        for b in self.buildings:
            if b.name == name:
                slabs = tuple(replace(s, vertices=s.vertices + offset, centre=s.centre + offset) for s in b.slabs)
                elements = tuple(e.replaced(point=e.point + offset) for e in b.elements)
                b = replace(b, slabs=slabs, elements=elements)
            out.append(b)
        # a link's point on the moved building moves with it
        links = tuple(replace(k, points=k.points + np.array([offset if nm == name else 0.0 * offset for nm in k.between]))
                      for k in self.links)
        return replace(self, buildings=tuple(out), links=links)
