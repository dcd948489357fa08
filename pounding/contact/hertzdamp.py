"""Hertz contact with non-linear damping (Muthukumar and DesRoches 2006).

    F = k_h delta^n (1 + xi delta' / delta'_0)    while positive (the force never pulls)

The damping force grows with the penetration as the spring's does, so the force starts from
zero at the first touch (unlike Kelvin's and Jankowski's) and the loss per impact does not
depend on k_h, m_eff or the impact speed. The normalised damping xi [-] follows from the
restitution e by one of two calibrations (``damping``):

``"ye"`` (default)
    xi = 8 (1 - e) / (5 e), Ye, Li and Zhu (2009), derived for this very law: close to e for
    every e (see docs/contact-laws.md).
``"lankarani_nikravesh"``
    xi = 3 (1 - e^2) / 4, Lankarani and Nikravesh (1990), derived for e near 1 (low loss).

Glossary: delta the penetration [m] (> 0 in contact), delta' its rate [m/s] (> 0 approaching),
delta'_0 the closing speed when the contact began [m/s], k_h [N/m^n], n [-], e [-]. A contact
that begins without closing speed (delta'_0 <= 0: slabs that come to rest against each other)
has no damping. The face rule and the solve with the step are
:mod:`pounding.contact.pointwise`'s.

OpenSees' ``Hertzdamp`` material writes the same law as (k_h + xi k_h / v_i delta') delta^n
with v_i the closing rate of the first trial state in contact (not the rate at the first
touch), and lets the force pull when the bracket turns negative.

References
----------
Muthukumar, S. and DesRoches, R. (2006). A Hertz contact model with non-linear damping for
    pounding simulation. Earthquake Engineering and Structural Dynamics 35, 811-828.
Ye, K., Li, L. and Zhu, H. (2009). A note on the Hertz contact model with nonlinear damping for
    pounding simulation. Earthquake Engineering and Structural Dynamics 38, 1135-1142.
Lankarani, H. M. and Nikravesh, P. E. (1990). A contact force model with hysteresis damping for
    impact analysis of multibody systems. Journal of Mechanical Design 112, 369-376.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from pounding.compiler import njit
from pounding.contact.pointwise import (CONCRETE_HERTZ_STIFFNESS, PointwiseLaw, check_exponent,
                                        check_positive_restitution, check_stiffness)
from pounding.errors import InputError


def ye_damping(e: float) -> float:
    """xi = 8 (1 - e) / (5 e) [-] (Ye, Li and Zhu 2009), e in (0, 1]."""
    return 8.0 * (1.0 - e) / (5.0 * e)


def lankarani_nikravesh_damping(e: float) -> float:
    """xi = 3 (1 - e^2) / 4 [-] (Lankarani and Nikravesh 1990), e in [0, 1]."""
    return 0.75 * (1.0 - e * e)


#: the calibrations of xi from e, by name
DAMPING_RULES = {"ye": ye_damping, "lankarani_nikravesh": lankarani_nikravesh_damping}


@njit(borrowed=True)
def hertzdamp_force(delta, rate, approach_rate, params):
    """Hertzdamp force of one contact: (F [N], dF/d delta [N/m], dF/d rate [N s/m]).

    params = (k_h [N/m^n], n, xi); approach_rate delta'_0 [m/s] (<= 0: no damping).
    """
    k, n, xi = params[0], params[1], params[2]
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    g = xi / approach_rate if approach_rate > 0.0 else 0.0  # d factor / d rate [s/m]
    factor = 1.0 + g * rate
    if factor <= 0.0:  # the damping would pull: the slabs part without force
        return 0.0, 0.0, 0.0
    spring = k * delta**n
    return spring * factor, n * spring / delta * factor, spring * g


class HertzDamp(PointwiseLaw):
    """Hertz contact with damping proportional to the spring force (Muthukumar and DesRoches 2006).

    Parameters
    ----------
    stiffness : float
        k_h [N/m^n] (default 2.75e9 N/m^1.5, concrete: Jankowski 2005).
    exponent : float
        n in (0, 3] (default 1.5).
    restitution : float
        Coefficient of restitution e: in (0, 1] for ``"ye"`` (which divides by it), [0, 1] otherwise.
    damping : {"ye", "lankarani_nikravesh"}
        The calibration of xi from e: "ye", 8 (1 - e) / (5 e) (Ye, Li and Zhu 2009), or
        "lankarani_nikravesh", 3 (1 - e^2) / 4, for nearly elastic impact (docs/contact-laws.md).
    tolerance : float
        Contact length tolerance [m] (a pair within it is watched).
    """

    name: ClassVar[str] = "hertzdamp"
    law_force = staticmethod(hertzdamp_force)
    #: the calibrations of xi from e this law takes, by name
    damping_rules: ClassVar[dict] = DAMPING_RULES

    def __init__(self, *, stiffness: float = CONCRETE_HERTZ_STIFFNESS, exponent: float = 1.5, restitution: float = 0.5,
                 damping: str = "ye", tolerance: float = 1e-4):
        super().__init__(restitution=restitution, tolerance=tolerance)
        self.stiffness = check_stiffness(stiffness, "N/m^n")
        self.exponent = check_exponent(exponent)
        rules = self.damping_rules
        if damping not in rules:
            raise InputError(f"expected one of {', '.join(repr(x) for x in rules)}, got {damping!r}", field="damping")
        if damping == "ye":
            check_positive_restitution(self.restitution)
        self.damping = damping
        self.damping_ratio = rules[damping](self.restitution)

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """The elastic Hertz contact's duration [s] with the same spring, for effective mass ``m_eff``
        [kg] and approach speed ``approach_speed`` [m/s]
        (:func:`pounding.contact.hertz.hertz_contact_duration`): a lower bound of this law's
        (measured below; half of it is a strict bound).

        Why: while the slabs approach, the damping adds to the spring's force, so the penetration
        never exceeds the elastic one at the same speed; while they part, the force is below
        the spring's, so the rebound from that shallower depth is no faster than the elastic one
        (an elastic Hertz half-contact from rest at depth A lasts in proportion to A^(-(n-1)/(2(n+1))),
        A^(-1/4) for n = 1.5). The restitution phase alone therefore lasts at least half the elastic
        contact: a strict bound. Measured on two free masses meeting at 0.5 m/s (solve_ivp, rtol
        1e-10), the whole contact lasts 1.005 (e = 0.95) to 1.35 (e = 0.3) times the elastic one with the
        "ye" damping, and 1.005 to 1.06 (e = 0.95 to 0.05) with "lankarani_nikravesh": the approach
        phase shortens less than the restitution phase lengthens.
        """
        from pounding.contact.hertz import hertz_contact_duration

        return hertz_contact_duration(self.stiffness, self.exponent, m_eff, approach_speed)

    def params(self, m_eff: np.ndarray) -> np.ndarray:
        """(k_h, n, xi) at each of m points (m, 3): the law does not depend on the mass."""
        out = np.empty((np.asarray(m_eff).shape[0], 3))
        out[:, 0], out[:, 1], out[:, 2] = self.stiffness, self.exponent, self.damping_ratio
        return out

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple | None:
        """OpenSees' ``Hertzdamp Kh xiNorm gap n``, Kh the share of the law's k_h, xiNorm its xi. See
        :meth:`ContactLaw.opensees_material` and :meth:`opensees_notes`."""
        k, n, xi = self.params(np.array([m_eff]))[0]
        return ("Hertzdamp", share * float(k), float(xi), -clear, float(n))

    def opensees_notes(self) -> list[str]:
        """``Hertzdamp`` reads the impact velocity elsewhere, and may pull."""
        return [f"contact law {self.name!r}: OpenSees' Hertzdamp reads the impact velocity at the end of the first step "
                "in contact (pounding: where the gap closed), which agrees as dt shrinks, and pulls where "
                "1 + xi delta'/v_i < 0 (pounding gives no force there)"]
