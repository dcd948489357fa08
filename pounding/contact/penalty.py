"""Kelvin-Voigt penalty contact: a spring and a dashpot at the contact point.

    lambda = max(0, k_p delta + c_p delta')       (delta = penetration)

with the dashpot from the restitution k by Anagnostopoulos (1988):

    c_p = 2 xi sqrt(k_p m_eff),   xi = -ln k / sqrt(pi^2 + ln^2 k)

where m_eff = 1/a is the effective mass of the two slabs at the contact point
(for two point masses, m1 m2 / (m1 + m2), the original form). The force is
solved implicitly with the step: the driver gives the end-of-step gaps and
rates without contact and their compliances, so stiff springs stay stable
with implicit integrators. As k_p grows the response tends to the impulse
law with the same k.

Reference: Anagnostopoulos, S. A. (1988), Earthquake Eng. Struct. Dyn. 16, 443-456.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pounding.contact.base import ContactLaw
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
    """

    name: ClassVar[str] = "penalty"
    kind: ClassVar[str] = "force"

    def __init__(self, *, stiffness: float = 1e9, restitution: float = 0.5, tolerance: float = 1e-4):
        super().__init__(restitution=restitution)
        if not (isinstance(stiffness, (int, float)) and math.isfinite(stiffness) and stiffness > 0):
            raise InputError(f"expected a positive contact stiffness [N/m], got {stiffness!r}", field="stiffness")
        if not (isinstance(tolerance, (int, float)) and 0 < tolerance < 1):
            raise InputError(f"expected a length tolerance in (0, 1) m, got {tolerance!r}", field="tolerance")
        self.stiffness = float(stiffness)
        self.tolerance = float(tolerance)

    @property
    def damping_ratio(self) -> float:
        k = self.restitution
        if k <= 0.0:
            return 1.0  # the limit of the formula as k -> 0
        ln = math.log(k)
        return -ln / math.sqrt(math.pi**2 + ln**2)

    def forces(self, gap, rate, S_q, S_v, W):
        m = len(gap)
        kp = self.stiffness
        cp = 2.0 * self.damping_ratio * np.sqrt(kp / np.diag(W))  # m_eff = 1 / a
        active = np.ones(m, dtype=bool)
        lam = np.zeros(m)
        for _ in range(m + 1):  # active set: drop points that would pull
            idx = np.flatnonzero(active)
            if idx.size == 0:
                break
            K = np.eye(idx.size) + kp * S_q[np.ix_(idx, idx)] + cp[idx, None] * S_v[np.ix_(idx, idx)]
            rhs = -kp * gap[idx] - cp[idx] * rate[idx]
            sol = np.linalg.solve(K, rhs)
            lam[:] = 0.0
            lam[idx] = sol
            if np.all(sol >= 0):
                break
            active[idx[sol < 0]] = False
        return np.maximum(lam, 0.0)
