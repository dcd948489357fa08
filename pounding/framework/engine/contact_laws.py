"""The forces of several force laws on one step's contact points, solved together.

Which law each slab pair takes is the model's (:mod:`pounding.contact.rules`); here
the engine solves a step's points with those laws: one law's own solve, or the sweeps of several
laws whose points share a building (:func:`solve_forces`).
"""

from __future__ import annotations

import numpy as np

from pounding.contact.base import ContactLaw, ContactState

#: block Gauss-Seidel between the laws of pairs that share a building: relative change at which it stops
COUPLING_RTOL = 1e-12
#: and the most sweeps it makes (a symmetric positive definite coupling converges; see solve_forces)
COUPLING_SWEEPS = 200


def forces_solver(laws: list[ContactLaw], which: np.ndarray, contact: ContactState):
    """:func:`solve_forces` as a solve the engine can repeat at other end gaps and rates (the
    contact-law contract's :meth:`~pounding.contact.base.ContactLaw.forces_solver`): the one law's
    own, or with several laws their sweeps, from Python (:func:`swept_forces`)."""
    if which.min() == which.max():
        return laws[int(which[0])].forces_solver(contact)
    return swept_forces, (laws, which, contact)


def swept_forces(args, gap, rate) -> np.ndarray:
    """:func:`solve_forces` of ``args`` = (laws, which, contact) at the end gaps ``gap`` [m] and rates
    ``rate`` [m/s] (m,)."""
    laws, which, contact = args
    return solve_forces(laws, which, contact._replace(gap=gap, rate=rate))


def solve_forces(laws: list[ContactLaw], which: np.ndarray, contact: ContactState) -> np.ndarray:
    """End-of-step forces lambda (m,) [N] of the m points in ``contact``, each by its pair's law
    (``which`` (m,): index into ``laws``).

    One law: its own :meth:`~pounding.contact.base.ContactLaw.forces`. Several: the points of
    one law see the others' forces as known loads (their gaps and rates moved by
    ``S_q @ lambda``, ``S_v @ lambda`` of the others), swept in turn until no force changes by
    more than :data:`COUPLING_RTOL` of the largest (block Gauss-Seidel; it converges for a
    linear spring law, whose system K^-1 + S_q is symmetric positive definite, and the points of
    pairs that share no building are not coupled: one sweep solves them).
    """
    if which.min() == which.max():  # one law (the common case)
        return np.asarray(laws[int(which[0])].forces(contact), dtype=float)
    groups = np.unique(which)
    lam = np.zeros(len(contact.gap))
    members = [(laws[int(g)], np.flatnonzero(which == g), np.flatnonzero(which != g)) for g in groups]
    for _ in range(COUPLING_SWEEPS):
        change = 0.0
        for law, idx, rest in members:
            new = np.asarray(law.forces(law_part(contact, idx, rest, lam)), dtype=float)
            change = max(change, float(np.max(np.abs(new - lam[idx]), initial=0.0)))
            lam[idx] = new
        if change <= COUPLING_RTOL * max(float(np.max(np.abs(lam))), 1e-300):
            return lam
    import warnings

    from pounding.errors import AnalysisWarning

    warnings.warn(f"the forces of {len(members)} contact laws on pairs that share a building did not settle in "
                  f"{COUPLING_SWEEPS} sweeps at t = {contact.t:.6g} s (last change {change:.3g} N)", AnalysisWarning, stacklevel=2)
    return lam


def law_part(contact: ContactState, idx: np.ndarray, rest: np.ndarray, lam: np.ndarray) -> ContactState:
    """The state of the points ``idx`` of ``contact`` as their law sees it when the other points ``rest``
    carry the forces lam[rest] [N]: their gaps and rates moved by those forces (``S_q``, ``S_v``)."""
    part = contact.take(idx)
    return part._replace(gap=part.gap + contact.S_q[np.ix_(idx, rest)] @ lam[rest],
                         rate=part.rate + contact.S_v[np.ix_(idx, rest)] @ lam[rest])


def commit_laws(laws: list[ContactLaw], pair_law: np.ndarray, contact: ContactState | None, forces: np.ndarray,
                pressed_before: set, t: float = 0.0, dt: float = 0.0) -> set:
    """Commit an accepted step to the laws (:meth:`~pounding.contact.base.ContactLaw.commit`): each law
    its own points of ``contact`` (None: none pressed) as it saw them when the forces (m,) [N] were
    solved (:func:`law_part`), and, with no point, each law in ``pressed_before`` (indices into
    ``laws`` whose points pressed at the last accepted step) whose points all let go, at the end t [s]
    of the step of dt [s]; ``pair_law`` (P,) is each pair's index into ``laws``. Returns the indices
    of the laws whose points press now."""
    now: set = set()
    if contact is not None and len(contact.gap):
        which = pair_law[contact.pair]
        if which.min() == which.max():  # one law (the common case)
            now.add(int(which[0]))
            laws[int(which[0])].commit(contact, forces)
        else:
            for g in np.unique(which):
                now.add(int(g))
                idx, rest = np.flatnonzero(which == g), np.flatnonzero(which != g)
                laws[int(g)].commit(law_part(contact, idx, rest, forces), forces[idx])
    for g in pressed_before - now:  # its last points let go in this step
        laws[g].commit(ContactState.empty(t, dt), np.zeros(0))
    return now
