"""Jankowski's non-linear viscoelastic contact (Jankowski 2005, 2006).

    F = k_h delta^1.5 + c delta'    while the slabs approach (delta' > 0)
    F = k_h delta^1.5               while they separate (delta' <= 0)

    c = 2 xi sqrt(k_h sqrt(delta) m_eff),
    xi = 9 sqrt(5) / 2 * (1 - e^2) / (e (e (9 pi - 16) + 16))

The damping acts only in the approach, as the energy of a concrete impact is lost in crushing
rather than in rebound; its coefficient follows the Hertz spring's tangent, c ~ sqrt(k_h sqrt(delta)),
so c = 0 at the first touch and the force starts from zero. The damping switches off where the
approach turns to separation, at delta' = 0, where it is zero: the force is continuous there, its
slope is not. xi from e is Jankowski's (2006) closed form, derived by expanding the approach and
restitution phases: approximate, within 1.1 % of e for e >= 0.5 and 2.8 % at e = 0.3 (see
docs/contact-laws.md).

Glossary: delta the penetration [m] (> 0 in contact), delta' its rate [m/s] (> 0 approaching),
m_eff the contact's effective mass [kg], k_h [N/m^1.5], c [N s/m], xi [-], e [-]. The face rule
and the solve with the step are :mod:`pounding.contact.pointwise`'s. OpenSees' material
``JankowskiImpact`` (Kh, xi, mEff, gap, n) is this law with xi and m_eff given by the user.

References
----------
Jankowski, R. (2005). Non-linear viscoelastic modelling of earthquake-induced structural pounding.
    Earthquake Engineering and Structural Dynamics 34, 595-611.
Jankowski, R. (2006). Analytical expression between the impact damping ratio and the coefficient
    of restitution in the non-linear viscoelastic modelling of structural pounding. Earthquake
    Engineering and Structural Dynamics 35, 517-524.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pounding.compiler import njit
from pounding.contact.pointwise import CONCRETE_HERTZ_STIFFNESS, PointwiseLaw, check_positive_restitution, check_stiffness


def jankowski_damping_ratio(e: float) -> float:
    """xi [-] from the restitution e in (0, 1] (Jankowski 2006, eq. 19)."""
    return 9.0 * math.sqrt(5.0) / 2.0 * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0) + 16.0))


@njit(borrowed=True)
def jankowski_force(delta, rate, approach_rate, params):
    """Jankowski force of one contact: (F [N], dF/d delta [N/m], dF/d rate [N s/m]).

    params = (k_h [N/m^1.5], xi, m_eff [kg]); approach_rate unused.
    """
    k, xi, m = params[0], params[1], params[2]
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    root = np.sqrt(delta)
    spring = k * delta * root
    if rate <= 0.0:
        return spring, 1.5 * k * root, 0.0
    c = 2.0 * xi * np.sqrt(k * root * m)
    # c grows as delta^(1/4): d(c rate)/d delta = c rate / (4 delta)
    return spring + c * rate, 1.5 * k * root + 0.25 * c * rate / delta, c


class Jankowski(PointwiseLaw):
    """Non-linear viscoelastic contact damped in the approach only (Jankowski 2005).

    Parameters
    ----------
    stiffness : float
        k_h [N/m^1.5] (default 2.75e9 N/m^1.5, concrete: Jankowski 2005).
    restitution : float
        Coefficient of restitution e in (0, 1] (the damping ratio divides by it).
    tolerance : float
        Contact length tolerance [m] (a pair within it is watched).
    """

    name: ClassVar[str] = "jankowski"
    law_force = staticmethod(jankowski_force)
    #: the spring's power of delta (Hertz's, fixed: the damping ratio's calibration assumes it)
    exponent: ClassVar[float] = 1.5

    def __init__(self, *, stiffness: float = CONCRETE_HERTZ_STIFFNESS, restitution: float = 0.5, tolerance: float = 1e-4):
        super().__init__(restitution=restitution, tolerance=tolerance)
        self.stiffness = check_stiffness(stiffness, "N/m^1.5")
        self.damping_ratio = jankowski_damping_ratio(check_positive_restitution(self.restitution))

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """The elastic Hertz contact's duration [s] with the same spring, for effective mass ``m_eff``
        [kg] and approach speed ``approach_speed`` [m/s]
        (:func:`pounding.contact.hertz.hertz_contact_duration`): an estimate of this law's, within 2 %.

        Why: while the slabs approach, the damping adds to the spring's force, so the penetration
        never exceeds the elastic one at the same speed; while they part, the force is exactly
        the spring's, so the rebound from that shallower depth is no faster than the elastic one
        (an elastic Hertz half-contact from rest at depth A lasts in proportion to A^(-(n-1)/(2(n+1))),
        A^(-1/4) for n = 1.5). The restitution phase alone therefore lasts at least half the elastic
        contact: a strict bound. Measured on two free masses meeting at 0.5 m/s (solve_ivp, rtol
        1e-10), the whole contact lasts 0.982 (e = 0.3 to 0.4) to 1.08 (e = 0.05) times the elastic one:
        the approach phase shortens about as much as the restitution phase lengthens, and the
        default step's margin (:data:`pounding.framework.engine.timestep.STEPS_PER_CONTACT`) covers the 2 %.
        """
        from pounding.contact.hertz import hertz_contact_duration

        return hertz_contact_duration(self.stiffness, self.exponent, m_eff, approach_speed)

    def params(self, m_eff: np.ndarray) -> np.ndarray:
        """(k_h, xi, m_eff) at each of m points (m, 3)."""
        m_eff = np.asarray(m_eff, dtype=float)
        out = np.empty((m_eff.shape[0], 3))
        out[:, 0], out[:, 1], out[:, 2] = self.stiffness, self.damping_ratio, m_eff
        return out

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple:
        """OpenSees' ``JankowskiImpact Kh xi mEff gap 1.5``, Kh and mEff the share of the law's k_h and
        of the point's effective mass (the share scales both: s F(delta; k_h, m) is the law with
        s k_h and s m). See :meth:`ContactLaw.opensees_material`."""
        k, xi, m = self.params(np.array([m_eff]))[0]
        return ("JankowskiImpact", share * float(k), float(xi), share * float(m), -clear, 1.5)
