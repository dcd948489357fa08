"""How long a contact lasts in a run, so that the default step can resolve it.

A force law's contact between two slabs lasts a few milliseconds (a stiff spring on the
slabs' effective mass); a step chosen from the buildings' modes alone may take one or two steps
over it. Each law says how long one contact lasts for an effective mass m_eff and an approach
speed v0 (:meth:`pounding.contact.base.ContactLaw.contact_duration`; inf for an impulse law);
this module supplies the two numbers for every slab pair that can touch, both on the safe side
(a smaller m_eff and a larger v0 give a shorter contact, so a finer step). A pair whose slabs face
each other only through a third building at their level (the ends of a row:
:meth:`pounding.framework.engine.stacked_model.Model.faces`, the rule the gap study and the walls
take) strikes that building first, and its contact, which never comes, does not set the step.

m_eff, a lower bound
    A contact at point Q with unit normal n has the Delassus entry a = w.w of its modal row
    (:func:`pounding.framework.engine.pairs.pair_row`): 1 / a is the pair's effective mass there,
    m1 m2 / (m1 + m2) for two floors struck through their centres, less at a corner, where the
    slabs also turn. At a point, a(n) is a quadratic form in n whose largest value over unit n is
    the largest eigenvalue of the 2 x 2 Gram matrix of the rows along x and y. Q lies on the
    boundary of both slabs where one can reach the other: the candidates are points along either
    slab's edges (SAMPLES_PER_EDGE per edge, vertices included) within the rest gap plus the
    largest relative displacement of the run (the absolute sum of the modal peak displacements
    along the rows) of the other slab, and 1 / m_eff is the largest a over them. a is convex
    along an edge (the row is affine in Q), so between samples it exceeds the sampled values by
    at most its variation over 1/SAMPLES_PER_EDGE of the edge.
v0, an upper bound
    The closing speed at Q along n is w . q', over the same candidate points. Each mode's peak speed V_i over the record without
    contact is computed by the exact (piecewise-linear record) modal recurrence at the record's
    sample interval; then |w . q'| <= sum_i |w_i| V_i (the absolute sum of the modal peaks,
    larger than any combination in time), and over the normals |w_i| <= the norm of the x and y
    rows' i-th entries. Pounding redistributes momentum between the buildings but the closing
    speed it starts from is the buildings' own: measured on the paper's pair, the largest approach
    speed of any contact in converged runs of every force law is below this bound
    (docs/accuracy.md). The contact durations of the Hertz laws fall only as v0^(-1/5), so a
    generous v0 costs little.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pounding.compiler import njit
from pounding.framework.engine import pairs as pg
from pounding.framework.engine.ground_load import modal_loads
from pounding.framework.engine.modal_step import stepped


@dataclass(frozen=True)
class ContactTime:
    """The shortest contact of a run: how long it lasts and what it was computed from.

    Attributes
    ----------
    duration : float
        Shortest contact duration over the pairs that can touch [s] (inf: no law with a duration).
    pair : int
        The pair it belongs to (index into the run's pair list; -1 when none).
    law : str
        That pair's contact law.
    m_eff : float
        The pair's effective mass bound [kg].
    approach_speed : float
        The pair's approach speed bound [m/s].
    """

    duration: float = math.inf
    pair: int = -1
    law: str = ""
    m_eff: float = math.nan
    approach_speed: float = math.nan

    def report(self, dt: float) -> dict:
        """summary.json's ``contact_time`` for a run at step dt [s]: the fields above (null when no
        law has a duration), ``steps_per_contact`` = duration / dt, and ``resolving_dt`` [s], the
        largest step that resolves it (duration / STEPS_PER_CONTACT)."""
        from pounding.framework.engine.timestep import STEPS_PER_CONTACT

        if not math.isfinite(self.duration):
            return {k: None for k in ("duration", "steps_per_contact", "resolving_dt", "pair", "law", "m_eff", "approach_speed")}
        return {"duration": self.duration, "steps_per_contact": self.duration / dt, "resolving_dt": self.duration / STEPS_PER_CONTACT,
                "pair": self.pair, "law": self.law, "m_eff": self.m_eff, "approach_speed": self.approach_speed}


def _pair_rows(geo, n: int, p: int, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Modal rows (n,) of pair p at ``point`` (2,) [m] along x and along y, at rest."""
    q = np.zeros(n)
    wx = pg.pair_row(q, p, float(point[0]), float(point[1]), 1.0, 0.0, geo)
    wy = pg.pair_row(q, p, float(point[0]), float(point[1]), 0.0, 1.0, geo)
    return wx, wy


#: boundary samples per slab edge where the bounds are evaluated (the Delassus entry and the closing
#: speed are convex along an edge, so the sampled maxima miss the true ones by the variation over
#: 1/SAMPLES_PER_EDGE of an edge at most)
SAMPLES_PER_EDGE = 32


def _boundary_samples(verts: np.ndarray) -> np.ndarray:
    """Points (k * SAMPLES_PER_EDGE, 2) [m] along the edges of a closed polygon (k, 2), its vertices included."""
    s = np.arange(SAMPLES_PER_EDGE)[:, None] / SAMPLES_PER_EDGE
    nxt = np.roll(verts, -1, axis=0)
    return np.concatenate([a + s * (b - a) for a, b in zip(verts, nxt)])


def _distance_to(points: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Distance (m,) [m] of every point (m, 2) to the boundary of the polygon (k, 2)."""
    a, b = verts, np.roll(verts, -1, axis=0)
    d = b - a
    t = np.clip(np.einsum("mkj,kj->mk", points[:, None, :] - a[None], d) / np.maximum(np.einsum("kj,kj->k", d, d), 1e-300), 0.0, 1.0)
    closest = a[None] + t[..., None] * d[None]
    return np.min(np.linalg.norm(points[:, None, :] - closest, axis=2), axis=1)


def pair_bounds(geo, n: int, peak_disp: np.ndarray, peak_speed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower bounds of every pair's effective mass [kg] and upper bounds of its approach speed
    [m/s], each (P,) (see the module docstring), from the modes' peak displacements and speeds
    without contact, ``peak_disp``, ``peak_speed`` (n,).

    The contact point lies on the boundary of both slabs, where one can reach the other: the
    candidates are the boundary samples of either slab within ``rest gap + reach`` of the other
    at rest, reach the largest relative displacement any sample can have (the absolute sum of the
    modal peaks along its rows)."""
    P = geo.pa.shape[0]
    m_eff, speed = np.empty(P), np.empty(P)
    q = np.zeros(n)
    for p in range(P):
        sa = int(geo.off[geo.pa[p, 0]] + geo.pa[p, 1])
        sb = int(geo.off[geo.pb[p, 0]] + geo.pb[p, 1])
        A, B = geo.verts[sa, : geo.nvert[sa]], geo.verts[sb, : geo.nvert[sb]]
        points = np.concatenate([_boundary_samples(A), _boundary_samples(B)])
        dist = np.concatenate([_distance_to(_boundary_samples(A), B), _distance_to(_boundary_samples(B), A)])
        rows = np.empty((len(points), 2, n))  # (m, 2, n): along x and along y
        _rows_at(q, p, np.ascontiguousarray(points), geo, rows)
        size = np.hypot(rows[:, 0], rows[:, 1])  # (m, n): a mode's largest share of the gap over the normals
        reach = float(np.max(size @ peak_disp))
        near = dist <= max(float(geo.rest[p]), 0.0) + reach
        gram = np.einsum("mrn,msn->mrs", rows[near], rows[near])
        a_max = float(np.max(np.linalg.eigvalsh(gram)[:, -1]))
        m_eff[p] = 1.0 / a_max if a_max > 0.0 else math.inf
        speed[p] = float(np.max(size[near] @ peak_speed))
    return m_eff, speed


def modal_peaks(integrator_cls, omega: np.ndarray, zeta: np.ndarray, L: np.ndarray, ag: np.ndarray, dt: float):
    """Peak |q_i| and |q_i'| ((n,) each) of every mode over a record without contact, at its samples.

    Parameters
    ----------
    integrator_cls : the ``exact`` integrator's class (its transition integrates a record linear
        between samples exactly)
    omega, zeta : ndarray (n,)
        Modal circular frequencies [rad/s] and damping ratios.
    L : ndarray (n, c)
        Modal load per unit ground acceleration of each component (p = -L ag).
    ag : ndarray (m, c)
        Ground acceleration samples [m/s^2] every ``dt`` [s].
    """
    tr = integrator_cls().transition(np.ascontiguousarray(omega, dtype=float), np.ascontiguousarray(zeta, dtype=float), float(dt))
    peak = np.zeros((len(omega), 2))
    _step_peaks(np.ascontiguousarray(tr.A), np.ascontiguousarray(tr.B), np.ascontiguousarray(L, dtype=float),
                np.ascontiguousarray(ag, dtype=float), peak)
    return peak[:, 0], peak[:, 1]


@njit
def _rows_at(q, p, points, geo, rows):
    """rows (m, 2, n) <- the modal rows of pair p at the points (m, 2) [m], along x and along y
    (:func:`~pounding.framework.engine.pairs.pair_row`, in one compiled loop: a call from Python
    per point cost about 40 ms a run)."""
    for j in range(points.shape[0]):
        rows[j, 0] = pg.pair_row(q, p, points[j, 0], points[j, 1], 1.0, 0.0, geo)
        rows[j, 1] = pg.pair_row(q, p, points[j, 0], points[j, 1], 0.0, 1.0, geo)


@njit
def _step_peaks(A, B, L, ag, peak):
    """peak (n, 2) <- the largest |q| and |q'| of every mode stepped from rest by the transition
    A (n, 3, 3), B (n, 3, 2) under the modal ground loads of L (n, c) and the ground acceleration
    samples ag (m, c) (a record of a few thousand samples: compiled, as a Python loop it cost about
    40 ms a run)."""
    n = L.shape[0]
    z, z0 = np.zeros((n, 3)), np.empty((n, 3))
    p0, p1 = np.empty(n), np.empty(n)
    modal_loads(L, ag[0], p1)
    for i in range(n):
        z[i, 2] = p1[i]  # at rest, the acceleration is the load's
    for k in range(ag.shape[0] - 1):
        p0[:] = p1
        modal_loads(L, ag[k + 1], p1)
        z0[:] = z
        for i in range(n):
            for r in range(3):
                z[i, r] = stepped(A, B, i, r, z0, p0[i], p1[i])
            peak[i, 0] = max(peak[i, 0], abs(z[i, 0]))
            peak[i, 1] = max(peak[i, 1], abs(z[i, 1]))


def shortest_contact(model, laws: list, pair_law: np.ndarray, peaks) -> ContactTime:
    """The shortest contact over the run's pairs (see the module docstring).

    Parameters
    ----------
    model : :class:`pounding.framework.engine.stacked_model.Model`
        The run's stacked modal model (its pair arrays ``geo`` and size ``n``).
    laws : list of ContactLaw
        The run's laws; ``pair_law`` (P,) the index of every pair's law.
    peaks : callable
        () -> the modes' peak displacements and speeds without contact ((n,) each,
        :func:`modal_peaks`), called only when a law has a duration: a law without one (inf at
        unit mass and speed) costs nothing.
    """
    P = len(pair_law)
    if P == 0 or all(math.isinf(law.contact_duration(1.0, 1.0)) for law in laws):
        return ContactTime()
    m_eff, v0 = pair_bounds(model.geo, model.n, *peaks())
    best = ContactTime()
    for p in range(P):
        if not model.faces(p):  # a third building stands between its slabs: they strike it first
            continue
        law = laws[int(pair_law[p])]
        d = float(law.contact_duration(float(m_eff[p]), float(v0[p])))
        if d < best.duration:
            best = ContactTime(d, p, law.name or type(law).__name__, float(m_eff[p]), float(v0[p]))
    return best


def record_peaks(model, scene) -> tuple[np.ndarray, np.ndarray]:
    """Peak displacements and speeds ((n,) each) of the run's modes without contact over the window
    the run covers (:func:`modal_peaks` at the record's sample interval, or the fallback step of
    :mod:`pounding.framework.engine.timestep` for a record without one)."""
    from pounding.framework.engine.timestep import FALLBACK_DT
    from pounding.framework.model.registry import INTEGRATORS

    gm = scene.ground_motion
    dt = float(gm.dt) if gm.dt else FALLBACK_DT
    end = float(scene.analysis.duration or gm.duration)
    t = np.arange(int(np.ceil(end / dt - 1e-9)) + 1) * dt
    ag = np.asarray(gm.samples(t), dtype=float).reshape(len(t), -1)
    return modal_peaks(INTEGRATORS.get("exact"), model.omega, model.zeta, model.L, ag, dt)


def run_dt(scene, model, laws: list, pair_law: np.ndarray, integrator: str) -> tuple[float, ContactTime]:
    """The run's step [s] and its shortest contact: ``[analysis] dt`` when given, else
    :func:`pounding.framework.engine.timestep.default_dt` with the shortest contact's duration
    (:func:`shortest_contact`). The driver, ``pounding check`` and the OpenSees export all call it."""
    from pounding.framework.engine.timestep import default_dt

    gm = scene.ground_motion
    contact = shortest_contact(model, laws, pair_law, lambda: record_peaks(model, scene))
    if scene.analysis.dt:
        return float(scene.analysis.dt), contact
    return float(default_dt(model.systems, model.directions, gm.dt, integrator, contact_duration=contact.duration)), contact
