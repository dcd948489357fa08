"""Kelvin (linear viscoelastic) contact: a spring and a dashpot in parallel.

    F = k delta + c delta',    c = 2 xi sqrt(k m_eff),    xi = -ln e / sqrt(pi^2 + ln^2 e)

The damping ratio xi makes the free vibration of m_eff on the spring and dashpot lose, in the
half period of contact, the energy a collision of restitution e loses: with a dashpot that may
pull at the end of the contact (``tension = true``, Anagnostopoulos' original model) the two
bodies separate with exactly e times their approach speed, for any k and m_eff. Komodromos et
al. noted that the pull is unphysical and drop it (``tension = false``, the default: F >= 0);
the contact then ends where the force returns to zero, before the spring is back to its length,
and the rebound is larger than e (0.55 for e = 0.5; see docs/contact-laws.md).

Glossary: delta the penetration [m] (> 0 in contact), delta' its rate [m/s] (> 0 approaching),
m_eff the contact's effective mass [kg] (:mod:`pounding.contact.pointwise`), k [N/m], c [N s/m],
e the coefficient of restitution [-]. The face rule and the solve with the step are
:mod:`pounding.contact.pointwise`'s.

References
----------
Anagnostopoulos, S. A. (1988). Pounding of buildings in series during earthquakes. Earthquake
    Engineering and Structural Dynamics 16, 443-456.
Komodromos, P., Polycarpou, P. C., Papaloizou, L. and Phocas, M. C. (2007). Response of seismically
    isolated buildings considering poundings. Earthquake Engineering and Structural Dynamics 36,
    1605-1622.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pounding.compiler import njit
from pounding.contact.pointwise import PointwiseLaw, check_stiffness
from pounding.errors import InputError

#: default stiffness [N/m]: the package's penalty default (a stiff slab edge, no literature source:
#: choose it for the structure, e.g. the slab's axial stiffness over a bay)
DEFAULT_STIFFNESS = 1e9


def anagnostopoulos_damping_ratio(e: float) -> float:
    """Damping ratio xi [-] of a Kelvin contact that rebounds with restitution e when its dashpot
    may pull: -ln e / sqrt(pi^2 + ln^2 e) (1 at e = 0, the limit)."""
    if e <= 0.0:
        return 1.0
    ln = math.log(e)
    return -ln / math.sqrt(math.pi**2 + ln**2)


def kelvin_contact_duration(k: float, m_eff: float, xi: float, tension: bool) -> float:
    """Duration [s] of one Kelvin contact of stiffness k [N/m] and damping ratio xi [-] between
    bodies of effective mass m_eff [kg]; it does not depend on the approach speed.

    With omega = sqrt(k / m_eff) and, for xi < 1, omega_d = omega sqrt(1 - xi^2), the penetration is
    delta = (v0 / omega_d) exp(-xi omega t) sin(omega_d t). A dashpot that may pull keeps the slabs
    together until delta returns to zero: pi / omega_d. A compression-only contact ends where the
    force k delta + c delta' first returns to zero, tan(omega_d t) = -2 xi sqrt(1 - xi^2) / (1 - 2 xi^2),
    that is omega_d t = pi - 2 arcsin(xi): (pi - 2 arcsin xi) / omega_d, shorter; 2 / omega at
    critical damping, and for xi > 1 (roots s1,2 = omega (-xi +- sqrt(xi^2 - 1))) the force's zero
    t = ln((1 + 2 xi s2 / omega) / (1 + 2 xi s1 / omega)) / (s1 - s2). An overdamped dashpot that may
    pull never lets delta return to zero: its force's positive phase, the compression-only time, is
    returned as the bound.
    """
    omega = math.sqrt(k / m_eff)
    if xi < 1.0:
        phase = math.pi if tension else math.pi - 2.0 * math.asin(max(xi, 0.0))
        return phase / (omega * math.sqrt(1.0 - xi * xi))
    if xi == 1.0:
        return 2.0 / omega
    root = math.sqrt(xi * xi - 1.0)
    s1, s2 = -xi + root, -xi - root  # in units of omega
    return math.log((1.0 + 2.0 * xi * s2) / (1.0 + 2.0 * xi * s1)) / ((s1 - s2) * omega)


@njit(borrowed=True)
def kelvin_force(delta, rate, approach_rate, params):
    """Kelvin force of one contact: (F [N], dF/d delta [N/m], dF/d rate [N s/m]).

    params = (k [N/m], c [N s/m], tension (1.0: may pull, 0.0: never)); approach_rate unused.
    """
    k, c, tension = params[0], params[1], params[2]
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    f = k * delta + c * rate
    if f < 0.0 and tension == 0.0:
        return 0.0, 0.0, 0.0
    return f, k, c


class Kelvin(PointwiseLaw):
    """Linear spring and dashpot, damping from the restitution (Anagnostopoulos 1988).

    Parameters
    ----------
    stiffness : float
        Spring stiffness k [N/m] (default 1e9).
    restitution : float
        Coefficient of restitution e in [0, 1] giving the dashpot.
    tension : bool
        True: the dashpot may pull while the slabs overlap (Anagnostopoulos; rebound exactly e).
        False (default): the force never pulls (Komodromos et al. 2007).
    tolerance : float
        Contact length tolerance [m] (a pair within it is watched).
    """

    name: ClassVar[str] = "kelvin"
    law_force = staticmethod(kelvin_force)
    #: the spring's power of delta (linear)
    exponent: ClassVar[float] = 1.0

    def __init__(self, *, stiffness: float = DEFAULT_STIFFNESS, restitution: float = 0.5, tension: bool = False,
                 tolerance: float = 1e-4):
        super().__init__(restitution=restitution, tolerance=tolerance)
        self.stiffness = check_stiffness(stiffness, "N/m")
        if not isinstance(tension, bool):
            raise InputError(f"expected true or false, got {tension!r}", field="tension")
        self.tension = tension
        self.damping_ratio = anagnostopoulos_damping_ratio(self.restitution)

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """Duration [s] of one contact of effective mass ``m_eff`` [kg], whatever the approach speed
        (:func:`kelvin_contact_duration`)."""
        return kelvin_contact_duration(self.stiffness, m_eff, self.damping_ratio, self.tension)

    def params(self, m_eff: np.ndarray) -> np.ndarray:
        """(k, c = 2 xi sqrt(k m_eff), tension) at each of m points (m, 3)."""
        m_eff = np.asarray(m_eff, dtype=float)
        out = np.empty((m_eff.shape[0], 3))
        out[:, 0] = self.stiffness
        out[:, 1] = 2.0 * self.damping_ratio * np.sqrt(self.stiffness * m_eff)
        out[:, 2] = 1.0 if self.tension else 0.0
        return out

    def opensees_material(self, share: float, m_eff: float, clear: float) -> tuple:
        """OpenSees' ``ViscoelasticGap K C gap``: K delta + C delta' with the share of the law's k and
        c = 2 xi sqrt(k m_eff) at the point, which may pull (it is this law with ``tension = true``).
        See :meth:`ContactLaw.opensees_material`."""
        k, c, _ = self.params(np.array([m_eff]))[0]
        return ("ViscoelasticGap", share * float(k), share * float(c), -clear)

    def opensees_notes(self) -> list[str]:
        """Without tension the law never pulls, while ``ViscoelasticGap`` does."""
        if self.tension:
            return []
        return [f"contact law {self.name!r} with tension = false never pulls, but its OpenSees material ViscoelasticGap "
                f"does at the end of a contact ({self.name} with tension = true): the script's contacts rebound with e "
                "where pounding's rebound faster"]
