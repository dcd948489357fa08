"""Hertz contact: an elastic force growing as a power of the penetration.

    F = k_h delta^n,    n = 1.5 by default (two elastic spheres; Goldsmith 1960)

No energy is lost in the contact (the rebound is 1 for any restitution): the law is the
elastic limit of :mod:`pounding.contact.hertzdamp` and :mod:`pounding.contact.jankowski`.
For two free bodies of effective mass m_eff meeting at v0 the largest penetration is
(5 m_eff v0^2 / (4 k_h))^(2/5) and the contact lasts 2.943 delta_max / v0 (n = 1.5).

Glossary: delta the penetration [m] (> 0 in contact), k_h [N/m^n], n [-]. The face rule and the
solve with the step are :mod:`pounding.contact.pointwise`'s.

References
----------
Goldsmith, W. (1960). Impact: the theory and physical behaviour of colliding solids. Arnold, London.
Jankowski, R. (2005). Non-linear viscoelastic modelling of earthquake-induced structural pounding.
    Earthquake Engineering and Structural Dynamics 34, 595-611 (k_h = 2.75e9 N/m^1.5 for concrete).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pounding.compiler import njit
from pounding.contact.pointwise import CONCRETE_HERTZ_STIFFNESS, PointwiseLaw, check_exponent, check_stiffness


def hertz_contact_duration(k_h: float, n: float, m_eff: float, v0: float) -> float:
    """Duration [s] of one elastic Hertz contact F = k_h delta^n [N] between bodies of effective
    mass m_eff [kg] meeting at v0 [m/s] (inf when v0 <= 0).

    Energy gives the closing speed at penetration delta, v^2 = v0^2 - 2 k_h delta^(n+1) / ((n+1) m_eff),
    so the largest penetration is delta_max = ((n+1) m_eff v0^2 / (2 k_h))^(1/(n+1)) and the contact,
    symmetric in time, lasts 2 (delta_max / v0) integral_0^1 (1 - x^(n+1))^(-1/2) dx
    = 2 (delta_max / v0) sqrt(pi) Gamma(1 + 1/(n+1)) / Gamma(1/2 + 1/(n+1)): 2.943 delta_max / v0 with
    delta_max = (5 m_eff v0^2 / (4 k_h))^(2/5) for n = 1.5, and pi sqrt(m_eff / k_h) for n = 1.
    It falls as v0^(-(n-1)/(n+1)) (v0^(-1/5) for n = 1.5): a larger v0 gives a shorter contact.
    """
    if not v0 > 0.0:
        return math.inf
    p = n + 1.0
    delta_max = (p * m_eff * v0 * v0 / (2.0 * k_h)) ** (1.0 / p)
    shape = math.sqrt(math.pi) * math.gamma(1.0 + 1.0 / p) / math.gamma(0.5 + 1.0 / p)
    return 2.0 * delta_max / v0 * shape


@njit(borrowed=True)
def hertz_force(delta, rate, approach_rate, params):
    """Hertz force of one contact: (F [N], dF/d delta [N/m], dF/d rate = 0).

    params = (k_h [N/m^n], n); rate and approach_rate unused.
    """
    k, n = params[0], params[1]
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    f = k * delta**n
    return f, n * f / delta, 0.0


class Hertz(PointwiseLaw):
    """Elastic Hertz contact F = k_h delta^n.

    Parameters
    ----------
    stiffness : float
        k_h [N/m^n] (default 2.75e9 N/m^1.5, concrete: Jankowski 2005).
    exponent : float
        n in (0, 3] (default 1.5).
    restitution : float
        Accepted (as by every contact law) and unused: the law is elastic.
    tolerance : float
        Contact length tolerance [m] (a pair within it is watched).
    """

    name: ClassVar[str] = "hertz"
    law_force = staticmethod(hertz_force)

    def __init__(self, *, stiffness: float = CONCRETE_HERTZ_STIFFNESS, exponent: float = 1.5, restitution: float = 1.0,
                 tolerance: float = 1e-4):
        super().__init__(restitution=restitution, tolerance=tolerance)
        self.stiffness = check_stiffness(stiffness, "N/m^n")
        self.exponent = check_exponent(exponent)

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """Duration [s] of one contact of effective mass ``m_eff`` [kg] met at ``approach_speed`` [m/s]
        (:func:`hertz_contact_duration`)."""
        return hertz_contact_duration(self.stiffness, self.exponent, m_eff, approach_speed)

    def params(self, m_eff: np.ndarray) -> np.ndarray:
        """(k_h, n) at each of m points (m, 2)."""
        out = np.empty((np.asarray(m_eff).shape[0], 2))
        out[:, 0], out[:, 1] = self.stiffness, self.exponent
        return out

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple:
        """OpenSees' ``Hertzdamp Kh 0 gap n``: with no damping (xiNorm = 0) it is k_h delta^n exactly
        (OpenSees has no elastic Hertz material), Kh the share of the law's k_h. See
        :meth:`ContactLaw.opensees_material`."""
        k, n = self.params(np.array([m_eff]))[0]
        return ("Hertzdamp", share * float(k), 0.0, -clear, float(n))
