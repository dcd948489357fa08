"""The contact law of every slab pair: ``[analysis] contact``, a ``[[contact]]`` table's, a bumper's or a wall's.

``[analysis] contact`` gives every pair its law; a ``[[contact]]`` table
(:class:`pounding.framework.model.scene.ContactRule`) gives the pairs between two named buildings
a law of their own (a retaining wall and a slab, a stiff and a soft facade), a bumper on such a rule
the pairs it stands in, and a ``[[wall]]`` its slabs. The engine solves each step's points with
these laws (:mod:`pounding.framework.engine.contact_laws`).
"""

from __future__ import annotations

import numpy as np

from pounding.contact.base import ContactLaw
from pounding.framework.model.bumpers import rule_pairs
from pounding.framework.model.registry import CONTACT_LAWS


def law_name(law: ContactLaw) -> str:
    """The name a law is reported by: its registered ``name``, else its class's (a law passed as a class)."""
    return law.name or type(law).__name__


def wall_law(scene, wall, default: ContactLaw) -> ContactLaw:
    """The contact law of the slabs against ``wall`` (a :class:`~pounding.framework.model.scene.Wall`).

    Its own law (``wall.law`` with ``wall.params``), or without one ``[analysis] contact`` with
    ``wall.params`` over its parameters (a restitution of its own). A force law may serve a wall
    beside any ``[analysis] contact`` (as for a ``[[contact]]`` table); an impulse law when it is
    ``[analysis] contact``'s class, which declares how a restitution of its own is applied, or beside
    a force law there the run's one impulse law (:meth:`~pounding.contact.base.ContactLaw.own_law_problem`,
    :func:`impulse_law_problem`). Raises ValueError naming what does not fit.
    """
    an = scene.analysis
    if wall.law is None:
        cls, params = CONTACT_LAWS.get(an.contact), {**an.contact_params, **wall.params}
    else:
        cls, params = CONTACT_LAWS.get(wall.law), dict(wall.params)
    law = cls(**params)
    problem = law.own_law_problem(default)
    if problem is not None:
        raise ValueError(f"wall {wall.name!r}: {problem}")
    return law


def bumper_law(rule, slabs: ContactLaw) -> ContactLaw:
    """The law of the pairs a rule's bumper stands in (:class:`~pounding.contact.bumper.BumperLaw`):
    the layer's law (``rule.bumper.law`` with its parameters) and ``slabs``, the rule's own law.
    Raises ValueError when either acts by impulses (a bumper needs a force law: a layer compresses)."""
    from pounding.contact.bumper import BumperLaw

    b = rule.bumper
    layer = CONTACT_LAWS.get(b.law)(**b.params)
    try:
        return BumperLaw(layer=layer, slabs=slabs, thickness=b.thickness, compressible=b.compressible)
    except ValueError as exc:
        raise ValueError(f"contact between {rule.between[0]!r} and {rule.between[1]!r}: {exc}") from None


def pair_laws(scene, pairs: list, default: ContactLaw, walls: dict | None = None) -> tuple[list[ContactLaw], np.ndarray]:
    """The laws of a run and the index of each pair's law.

    Parameters
    ----------
    scene : Scene
        Its ``contacts`` rules override ``default`` for the pairs between their two buildings.
    pairs : list of (building a, storey a, building b, storey b, rest gap)
        The run's slab pairs (building indices in scene order).
    default : ContactLaw
        The law of ``[analysis] contact``: index 0.
    walls : dict or None
        {pair index: :class:`~pounding.framework.model.scene.Wall`} of the pairs where a slab meets a
        wall (``Model.walls``): they take the wall's law (:func:`wall_law`).

    Returns
    -------
    laws : list of ContactLaw
        ``default`` first, then one per rule, then one per rule with a bumper (:func:`bumper_law`,
        for the pairs :func:`~pounding.framework.model.bumpers.rule_pairs` finds), then one per
        wall of the scene.
    which : ndarray (P,) int64
        Index into ``laws`` of every pair's law.
    """
    names = [b.name for b in scene.buildings]
    laws, by_pair, by_bumper = [default], {}, {}
    for rule in getattr(scene, "contacts", ()):
        if not default.watches():  # contact off (a gap study's free run): nothing is watched, as for the walls below
            laws.append(default)
            by_pair[frozenset(rule.between)] = len(laws) - 1
            continue
        law = CONTACT_LAWS.get(rule.law)(**rule.params)
        problem = law.own_law_problem(default)
        if problem is not None:
            raise ValueError(f"contact between {rule.between[0]!r} and {rule.between[1]!r}: {problem}")
        laws.append(law)
        by_pair[frozenset(rule.between)] = len(laws) - 1
    for r, rule in enumerate(getattr(scene, "contacts", ())):
        if getattr(rule, "bumper", None) is not None and default.watches():
            laws.append(bumper_law(rule, laws[1 + r]))
            by_bumper.update({p: len(laws) - 1 for p in rule_pairs(scene.buildings, pairs, rule)})
    which = np.array([by_pair.get(frozenset((names[a], names[b])), 0) for a, _, b, _, _ in pairs], dtype=np.int64)
    for p, law in by_bumper.items():
        which[p] = law
    by_wall = {}
    for wall in getattr(scene, "walls", ()):
        # with contact off (a gap study's free run) nothing is watched: the walls take that law too
        laws.append(wall_law(scene, wall, default) if default.watches() else default)
        by_wall[wall.name] = len(laws) - 1
    for p, wall in (walls or {}).items():
        which[p] = by_wall[wall.name]
    own = [(f"contact between {r.between[0]!r} and {r.between[1]!r}", laws[1 + i]) for i, r in enumerate(getattr(scene, "contacts", ()))]
    walls_ = getattr(scene, "walls", ())
    own += [(f"wall {w.name!r}", laws[len(laws) - len(walls_) + i]) for i, w in enumerate(walls_)]
    problem = impulse_law_problem(default, own)
    if problem is not None:
        raise ValueError(f"{problem[0]}: {problem[1]}")
    return laws, which


def impulse_law_problem(default: ContactLaw, own: list[tuple]) -> tuple | None:
    """(where, why) the impulse laws of ``own`` cannot serve their pairs beside ``default``
    (``[analysis] contact``), or None when they can: ``own`` holds (where, law) of the
    ``[[contact]]`` tables' and ``[[wall]]`` tables' own laws, in scene order.

    One impulse law serves every pair that takes impulses (its Newton problem couples the pairs that
    share a building at an instant). Beside an impulse law ``default`` each is checked against it
    (:meth:`~pounding.contact.base.ContactLaw.own_law_problem`, as each is built); beside a force law
    ``default`` the first impulse law serves them and the others must be it, with at most a
    restitution of their own (:meth:`~pounding.contact.base.ContactLaw.impulse_law_problem`)."""
    if default.at_events:
        return None
    impulse = [(where, law) for where, law in own if law.at_events]
    for where, law in impulse[1:]:
        problem = law.impulse_law_problem(impulse[0][1], impulse[0][0])
        if problem is not None:
            return where, problem
    return None


def events_law(laws: list[ContactLaw]) -> ContactLaw:
    """The law of a run's events among ``laws`` (:func:`pair_laws`' list): ``[analysis] contact``'s
    (the first) when it acts at events, else the first impulse law a table or a wall gives its pairs
    (:func:`impulse_law_problem`: the others are it, but for a restitution), else ``[analysis]
    contact``'s (no pair takes impulses)."""
    return next((law for law in laws if law.at_events), laws[0])


def default_law(scene) -> ContactLaw:
    """The law of ``scene``'s ``[analysis] contact``, with its parameters."""
    an = scene.analysis
    return CONTACT_LAWS.get(an.contact)(**an.contact_params)


def scene_laws(scene, pairs: list, walls: dict | None = None) -> tuple[list[ContactLaw], np.ndarray]:
    """:func:`pair_laws` with the default of ``scene``'s ``[analysis] contact`` (:func:`default_law`,
    index 0): the laws of a run of ``scene`` on its ``pairs`` and ``walls`` as the driver, the
    export, ``pounding check``, the rebuilt contact forces and a run folder read back all resolve
    them."""
    return pair_laws(scene, pairs, default_law(scene), walls)
