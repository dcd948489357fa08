"""Contact force histories of force laws, rebuilt after a run from the recorded states.

A run records the modal state (q, q') at every output step and each force-law contact
*episode*'s figures (:class:`~pounding.framework.engine.results.ContactEpisode`: start, closing
speed, peak force, impulse), but not the force of every step. Those forces are a function of the
recorded state: at the end of every step the driver solves lambda = F(delta, delta') with the
step, where delta and delta' are the end-of-step penetrations and rates *with* the forces, i.e.
the committed state's. Evaluating the pair's own law (:meth:`ContactLaw.forces` with zero
compliances, the face rule included) at a recorded state's touching points therefore gives the
force the run applied at that step's end, to the end-of-step Newton tolerance and to the change
of the contact points' geometry between the state without forces (where the driver found the
points) and the committed one (a rotation of the order of the penetration over the slab size).
Where nothing twists the points' gaps are linear in the modal state and the two states give the
same points, so the rebuilt forces are the run's to the Newton tolerance: on a symmetric pair each
episode's peak force and impulse (the trapezoid over its step ends) come back to 1e-9 and below
(``tests/test_contact_forces.py``). On the paper's pair, whose slabs twist, they come back to
3.3e-5 (measured over its first 6 s with each force law at the default step).

Only the recorded steps are seen: with ``output_every > 1`` the history is thinned. A law with a
state of its own (:meth:`~pounding.contact.base.ContactLaw.commit`, a plastic set) is built afresh
and committed at every recorded step in turn, as the driver commits it: with ``output_every = 1`` it
follows the run's own sequence of accepted states; thinned, it skips the steps between them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ContactForces:
    """Contact forces of a run's force laws at the output times.

    Attributes
    ----------
    t : ndarray (nt,)
        Output times [s] (``Result.t``).
    pair_force : ndarray (nt, P)
        Total contact force of every slab pair (``Result.pairs`` order) at each output time [N],
        >= 0 pushing the slabs apart (0 where the pair does not touch).
    modal_force : ndarray (nt, n)
        The contact forces as a modal load (sum of w_k lambda_k over the points) [N / sqrt(kg)],
        mass-normalised modes: it adds to every mode's acceleration.
    """

    t: np.ndarray
    pair_force: np.ndarray
    modal_force: np.ndarray

    def floor_acceleration(self, result, name: str) -> np.ndarray:
        """The contact forces' part of building ``name``'s floor accelerations, (nt, N, 3)
        [m/s^2, m/s^2, rad/s^2]: Phi f_c over the building's modes (M^-1 of the floor forces)."""
        b = result.names.index(name)
        s = result.systems[b]
        i0 = int(result.mode_start[b])
        return (self.modal_force[:, i0 : i0 + s.n_dof] @ s.modes.T).reshape(len(self.t), s.n_storeys, 3)


def run_laws(result) -> tuple[list, np.ndarray]:
    """The laws of a run, as the driver builds them from its scene: (laws, index (P,) of each pair's law)."""
    from pounding.contact.rules import scene_laws

    scene = result.scene
    if scene is None:
        raise ValueError("the result carries no scene (Result.scene): the contact laws are unknown")
    return scene_laws(scene, result.pairs, getattr(result, "walls", {}))


def _episode_history(result, pair: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(start, approach) (m,) of the episode each point's pair is in at time t (the latest begun by then)."""
    start, approach = np.zeros(len(pair)), np.zeros(len(pair))
    for j, p in enumerate(pair.tolist()):
        begun = [e for e in result.contacts if e.pair == p and e.start <= t + 1e-12]
        if begun:
            e = max(begun, key=lambda e: e.start)
            start[j], approach[j] = e.start, e.approach_velocity
    return start, approach


def contact_force_history(result) -> ContactForces:
    """The force laws' contact forces at every output time of ``result`` (see the module docstring).

    Pairs under impulse laws carry none here (their impulses are ``Result.impacts``). Needs the
    run's pair geometry (``Result.geo``) and scene (``Result.scene``).
    """
    from pounding.contact.base import ContactState
    from pounding.framework.engine.contact_laws import commit_laws, solve_forces
    from pounding.framework.engine.face_shares import rest_face_ends, rest_point_names, touching_with_shares
    from pounding.framework.model.facade import struck_stiffness

    if result.geo is None:
        raise ValueError("the result carries no pair geometry (Result.geo)")
    laws, which = run_laws(result)
    forced = np.array([p for p in range(len(result.pairs)) if laws[which[p]].with_step], dtype=np.int64)
    tol = max(float(law.tolerance) for law in laws)
    nt, n = result.q.shape
    pair_force = np.zeros((nt, len(result.pairs)))
    modal = np.zeros((nt, n))
    if forced.size == 0:
        return ContactForces(result.t.copy(), pair_force, modal)
    ends = rest_face_ends(result.geo)
    names = rest_point_names(result.geo, ends) if any(law.keeps_state for law in laws) else None
    pressing: set = set()  # (a law with a state of its own is committed at the recorded steps, as the driver commits it)
    for k in range(nt):
        q = np.ascontiguousarray(result.q[k])
        step = float(result.t[k] - result.t[k - 1]) if k > 0 else float(result.dt)  # (a law's mean rate over the step)
        pts = touching_with_shares(q, forced, tol, n, result.geo, ends, names)
        keep = pts.gap < 0  # the pressed points, as the driver keeps them
        if not np.any(keep):
            if names is not None:
                pressing = commit_laws(laws, which, None, None, pressing, float(result.t[k]), step)
            continue
        pts = pts.take(keep)
        pair, gap, Wr, Q, N, share, point = pts.pair, pts.gap, pts.W, pts.Q, pts.N, pts.share, pts.point
        m = len(pair)
        start, approach = _episode_history(result, pair, float(result.t[k]))
        zero = np.zeros((m, m))
        state = ContactState(float(result.t[k]), step, gap, Wr @ result.qd[k], zero, zero, Wr @ Wr.T, pair, start, approach,
                             struck_stiffness(result.scene, result.systems, result.facades, pair, Q[:, :2], N[:, :2]), share, point)
        lam = solve_forces(laws, which[pair], state)
        if names is not None:
            pressing = commit_laws(laws, which, state, lam, pressing)
        np.add.at(pair_force[k], pair, lam)
        modal[k] = Wr.T @ lam
    return ContactForces(result.t.copy(), pair_force, modal)


def episode_window(result, episode, forces: ContactForces) -> tuple[np.ndarray, np.ndarray]:
    """(t, force) of one episode's pair over its episode, one recorded step either side [s], [N]."""
    t = forces.t
    sel = (t >= episode.start - 1.5 * result.dt) & (t <= episode.end + 1.5 * result.dt)
    return t[sel], forces.pair_force[sel, episode.pair]
