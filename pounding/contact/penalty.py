"""Kelvin-Voigt penalty contact: a spring and a dashpot at the contact point.

    lambda = max(0, k_p delta + c_p delta')       (delta = penetration)

with the dashpot from the restitution k by Anagnostopoulos (1988):

    c_p = 2 xi sqrt(k_p m_eff),   xi = -ln k / sqrt(pi^2 + ln^2 k)

where m_eff = 1/a is the effective mass of the two slabs at the contact point
(for two point masses, m1 m2 / (m1 + m2), the original form). Several points
pressed at once (two ends of a face) share one dashpot matrix that gives every
contact mode that ratio (:func:`dashpot_matrix`). That relation
assumes a dashpot that may pull; with the force clamped at zero the rebound of
a stiff contact is larger than k (0.551 for k = 0.5, 0.135 for k = 0). With
``dashpot = "no_tension"`` xi is instead calibrated so that the clamped
contact rebounds with exactly k, and the stiff limit is the impulse law. The force is
solved implicitly with the step: the driver gives the end-of-step gaps and
rates without contact and their compliances, so stiff springs stay stable
with implicit integrators. As k_p grows the response tends to the impulse
law with the same k.

Reference: Anagnostopoulos, S. A. (1988), Earthquake Eng. Struct. Dyn. 16, 443-456.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import ClassVar

import numpy as np

from pounding.compiler import njit
from pounding.contact.base import ContactLaw, ContactState, keep_pushing
from pounding.errors import InputError


class Penalty(ContactLaw):
    """Linear spring-dashpot contact.

    Parameters
    ----------
    stiffness : float
        Contact spring stiffness k_p [N/m].
    restitution : float
        Coefficient of restitution k giving the dashpot (Anagnostopoulos).
    tolerance : float
        Contact length tolerance [m] (used to start watching a pair).
    dashpot : {"anagnostopoulos", "no_tension"}
        How the damping ratio follows from k: Anagnostopoulos' relation (for a
        dashpot that may pull), or calibrated for the compression-only contact.
    """

    name: ClassVar[str] = "penalty"
    kind: ClassVar[str] = "force"

    def __init__(self, *, stiffness: float = 1e9, restitution: float = 0.5, tolerance: float = 1e-4, dashpot: str = "anagnostopoulos"):
        super().__init__(restitution=restitution)
        if dashpot not in ("anagnostopoulos", "no_tension"):
            raise InputError(f"expected 'anagnostopoulos' or 'no_tension', got {dashpot!r}", field="dashpot")
        if dashpot == "no_tension" and self.restitution < 0.05:
            # xi grows without bound as k -> 0 (xi = 500 at k = 1e-6): no step resolves such a dashpot
            raise InputError("the no_tension dashpot needs restitution >= 0.05; use the impulse law for plastic impact", field="dashpot")
        self.dashpot = dashpot
        if not (isinstance(stiffness, (int, float)) and math.isfinite(stiffness) and stiffness > 0):
            raise InputError(f"expected a positive contact stiffness [N/m], got {stiffness!r}", field="stiffness")
        if not (isinstance(tolerance, (int, float)) and 0 < tolerance < 1):
            raise InputError(f"expected a length tolerance in (0, 1) m, got {tolerance!r}", field="tolerance")
        self.stiffness = float(stiffness)
        self.tolerance = float(tolerance)

    @cached_property
    def damping_ratio(self) -> float:
        """Dashpot damping ratio xi [-] (computed once: the calibration solves a root)."""
        k = self.restitution
        if self.dashpot == "no_tension":
            return no_tension_damping_ratio(k)
        from pounding.contact.kelvin import anagnostopoulos_damping_ratio

        return anagnostopoulos_damping_ratio(k)

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """Duration [s] of one contact of effective mass ``m_eff`` [kg] on the spring k_p: the force
        never pulls, so it is the compression-only Kelvin contact's
        (:func:`pounding.contact.kelvin.kelvin_contact_duration`). A facade point's spring in series
        with the struck element is softer, its contact longer: k_p gives the lower bound."""
        from pounding.contact.kelvin import kelvin_contact_duration

        return kelvin_contact_duration(self.stiffness, m_eff, self.damping_ratio, False)

    def forces(self, contact: ContactState) -> np.ndarray:
        """End-of-step forces (see :meth:`ContactLaw.forces`): lambda = k delta + C delta' on the
        points that push, solved with the step (:func:`penalty_forces`, compiled)."""
        solve, args = self.forces_solver(contact)
        return solve(args, np.ascontiguousarray(contact.gap, dtype=float), np.ascontiguousarray(contact.rate, dtype=float))

    def forces_solver(self, contact: ContactState):
        """(:func:`penalty_solve`, (W, S_q, S_v, springs, xi)): the compiled solve of :meth:`forces`."""
        c = contact
        return penalty_solve, (np.ascontiguousarray(c.W, dtype=float), np.ascontiguousarray(c.S_q, dtype=float),
                               np.ascontiguousarray(c.S_v, dtype=float), self.point_springs(c), float(self.damping_ratio))

    def point_springs(self, contact: ContactState) -> np.ndarray:
        """Spring of every point (m,) [N/m]: k_p at each."""
        return np.full(len(contact.gap), self.stiffness)

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple | None:
        """OpenSees' ``ElasticPPGap k -1e30 gap 0 noDamage``: the spring k_p at every point whatever its
        share (this law puts a spring at each point, not a share of one), the huge negative yield force
        keeping it elastic; no dashpot (:meth:`opensees_notes`). See :meth:`ContactLaw.opensees_material`."""
        return ("ElasticPPGap", float(self.stiffness), -1e30, -clear, 0.0, "noDamage")

    def opensees_notes(self) -> list[str]:
        """The dashpot of a restitution below 1 has no counterpart in ``ElasticPPGap``."""
        if self.restitution >= 1.0:
            return []
        return [f"contact law {self.name!r}: its dashpot (restitution {self.restitution:g}) has no counterpart in "
                "ElasticPPGap: the script's contact springs are elastic and lose no energy in impacts"]


@njit
def dashpot_matrix(W, k, xi):
    """Dashpot matrix C (m, m) [N s/m] of m points pressed together, with Delassus matrix W (m, m)
    [1/kg] and springs k (m,) [N/m], that gives every contact mode the damping ratio xi.

    The points' mass is M = W^-1; C = 2 xi M^1/2 (M^-1/2 K M^-1/2)^1/2 M^1/2 gives every mode of
    (M, K = diag k) the ratio xi. With one spring k_p at every point it is 2 xi sqrt(k_p) W^-1/2:
    one point gets 2 xi sqrt(k_p m_eff), m_eff = 1/a (Anagnostopoulos), and two ends of a face
    pressed together rebound as one contact would. Directions of W with no compliance (rounding:
    eigenvalues below 1e-12 of the largest) get no dashpot: nothing moves along them.
    """
    m = W.shape[0]
    lam, V = np.linalg.eigh(0.5 * (W + W.T))
    top = max(np.max(lam), 0.0)
    root_w, inv_root_w = np.zeros(m), np.zeros(m)
    for i in range(m):
        if lam[i] > 1e-12 * top:
            root_w[i] = math.sqrt(lam[i])
            inv_root_w[i] = 1.0 / root_w[i]
    Mh = (V * inv_root_w) @ V.T  # M^1/2 = W^-1/2 on the compliant directions
    Wh = (V * root_w) @ V.T  # M^-1/2 = W^1/2
    A = Wh @ (np.expand_dims(k, 1) * Wh)
    a, U = np.linalg.eigh(0.5 * (A + A.T))
    root = (U * np.sqrt(np.maximum(a, 0.0))) @ U.T
    return 2.0 * xi * (Mh @ root @ Mh)


@njit
def penalty_forces(W, S_q, S_v, gap, rate, k, xi):
    """End-of-step forces lambda (m,) [N] of m points, each a spring k (m,) [N/m] with the dashpots
    of :func:`dashpot_matrix` (damping ratio xi), solved with the step:

        (I + diag(k) S_q + C S_v) lambda = -k gap - C rate

    over an active set (a point whose force would pull is let go, and the rest solved again); W,
    S_q, S_v (m, m) the points' Delassus matrix and compliances, gap [m] and rate [m/s] (m,) their
    end-of-step values without contact forces."""
    m = gap.shape[0]
    active = np.ones(m, dtype=np.bool_)
    lam = np.zeros(m)
    for _ in range(m + 1):  # active set: drop points that would pull
        idx = np.flatnonzero(active)
        n = idx.shape[0]
        if n == 0:
            break
        Wa, Sq, Sv = np.empty((n, n)), np.empty((n, n)), np.empty((n, n))
        ka, ga, ra = np.empty(n), np.empty(n), np.empty(n)
        for i in range(n):
            ka[i], ga[i], ra[i] = k[idx[i]], gap[idx[i]], rate[idx[i]]
            for j in range(n):
                Wa[i, j], Sq[i, j], Sv[i, j] = W[idx[i], idx[j]], S_q[idx[i], idx[j]], S_v[idx[i], idx[j]]
        C = dashpot_matrix(Wa, ka, xi)
        K = np.eye(n) + np.expand_dims(ka, 1) * Sq + C @ Sv
        if keep_pushing(idx, np.linalg.solve(K, -ka * ga - C @ ra), lam, active):
            break
    return np.maximum(lam, 0.0)


@njit
def penalty_solve(args, gap, rate):
    """:func:`penalty_forces` of the points ``args`` = (W, S_q, S_v, springs, xi) at the end gaps
    ``gap`` [m] and rates ``rate`` [m/s] (m,) without contact forces (:meth:`Penalty.forces_solver`)."""
    W, S_q, S_v, k, xi = args
    return penalty_forces(W, S_q, S_v, gap, rate, k, xi)


def no_tension_restitution(xi: float) -> float:
    """Rebound of a Kelvin-Voigt contact whose force may not pull, for damping ratio xi.

    Unit mass and frequency, closing speed 1: d'' + 2 xi d' + d = 0 from d = 0,
    d' = 1 until the force d + 2 xi d' first returns to zero; the restitution is
    -d' there. Exact state transition (2x2 exponential), Brent for the instant.
    """
    from scipy.linalg import expm
    from scipy.optimize import brentq

    F = np.array([[0.0, 1.0], [-1.0, -2.0 * xi]])

    def state(t):
        return expm(F * t) @ np.array([0.0, 1.0])

    def force(t):
        d, v = state(t)
        return d + 2.0 * xi * v

    # the force starts at 2 xi > 0; step out until it turns negative (bounded: it does within ~pi + 1/xi)
    hi = 0.1
    while force(hi) > 0.0:
        hi *= 1.5
        if hi > 1e4:
            return 0.0
    t = brentq(force, 1e-12, hi, xtol=1e-14)
    return float(-state(t)[1])


def no_tension_damping_ratio(k: float) -> float:
    """Damping ratio xi whose compression-only contact rebounds with restitution k."""
    from scipy.optimize import brentq

    if k >= 1.0:
        return 0.0
    return float(brentq(lambda x: no_tension_restitution(x) - k, 1e-9, 1e4, xtol=1e-13))


class FacadePenalty(Penalty):
    """:class:`Penalty` whose points on a neighbour's facade (a slab striking between floors,
    :mod:`pounding.framework.model.facade`) have the local stiffness of the struck column or wall in
    series with the slab-edge spring: 1/k = 1/k_p + 1/k_local. Slab-to-slab points keep k_p.

    A rigid impact (the impulse law) on a facade makes the struck column as stiff as a slab's
    edge; this law lets the column bend locally under the blow (a fixed-fixed member with a point
    load, :func:`~pounding.framework.model.facade.local_stiffness`), which lengthens the contact and
    lowers the peak force.

    Parameters
    ----------
    stiffness : float
        Contact spring stiffness k_p [N/m] of the slab edge (alone at slab-to-slab points).
    restitution : float
        Coefficient of restitution k giving the dashpot (Anagnostopoulos).
    tolerance : float
        Contact length tolerance [m] (used to start watching a pair).
    dashpot : {"anagnostopoulos", "no_tension"}
        How the damping ratio follows from k (as :class:`Penalty`).
    """

    name: ClassVar[str] = "facade_penalty"

    def opensees_material(self, share: float, m_eff: float, clear: float) -> None:
        """None: no OpenSees material is declared for the facade springs (the peer's contact elements
        join slab edges, where this law is :class:`Penalty`'s; export a scene with ``penalty`` to
        write that)."""
        return None

    def point_springs(self, contact: ContactState) -> np.ndarray:
        """Spring of every point (m,) [N/m]: k_p in series with the struck element's local stiffness."""
        return self.point_stiffness(contact.local_stiffness)

    def point_stiffness(self, local: np.ndarray) -> np.ndarray:
        """Springs (m,) [N/m] of points whose struck element has the local stiffness ``local`` (m,)
        [N/m] (nan or inf: a slab, or an element with none known): k_p in series with it."""
        local = np.asarray(local, dtype=float)
        out = np.full(local.shape, self.stiffness)
        finite = np.isfinite(local) & (local > 0)
        out[finite] = 1.0 / (1.0 / self.stiffness + 1.0 / local[finite])
        return out
