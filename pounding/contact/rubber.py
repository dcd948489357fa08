"""A rubber layer's contact law: Hertz-type spring with Hunt-Crossley damping.

    F = k_r delta^n (1 + xi delta' / delta'_0),    xi = 3 (1 - e) / 2      while positive

What this is, honestly: the issue asks for the nonlinear rubber law of Polycarpou, Komodromos and
Polycarpou (2013), which we could not read (the paper was not found among the sources at hand),
so this law is *not* theirs. It is the Hertz-type law with Hunt and Crossley's (1975) damping that
their family of rubber models builds on: a spring k_r delta^n whose damping grows with the
compression, so the force starts from zero at the first touch, and whose loss per impact depends
on e alone (not on k_r, m_eff or the speed). The layer's finite thickness (the stiffening of a
nearly fully compressed rubber) is not in this law: a bumper hands it to the slabs' law beyond
its ``compressible`` fraction (:class:`pounding.contact.bumper.BumperLaw`).

Calibration: xi = 3 (1 - e) / 2 is Hunt and Crossley's, derived for nearly elastic impact; the
rebound it gives (two free bodies, :mod:`pounding.contact.rebound`, docs/contact-laws.md) is
0.9524 at e = 0.95 but 0.6630 at e = 0.5 and 0.5813 at e = 0.3 (measured with
:func:`pounding.contact.rebound.rebound`, rtol 1e-12): it loses less than e says for a lossy rubber.
Calibrate e on the measured rebound, or take ``damping = "ye"`` (Ye, Li and Zhu 2009, as
``hertzdamp``), whose rebound is within 15 % of e from e = 0.3 to 0.95 (0.4704 at e = 0.5).

Glossary: delta the compression of the layer [m] (> 0 in contact), delta' its rate [m/s] (> 0
approaching), delta'_0 the closing speed when the contact began [m/s], k_r [N/m^n], n [-], e [-].
The kernel and the face rule are :mod:`pounding.contact.hertzdamp`'s and
:mod:`pounding.contact.pointwise`'s.

References
----------
Hunt, K. H. and Crossley, F. R. E. (1975). Coefficient of restitution interpreted as damping in
    vibroimpact. Journal of Applied Mechanics 42, 440-445.
Polycarpou, P. C., Komodromos, P. and Polycarpou, A. C. (2013). A nonlinear impact model for
    simulating the use of rubber shock absorbers for mitigating the effects of structural pounding
    during earthquakes. Earthquake Engineering and Structural Dynamics 42, 81-100 (the model the
    issue names; not reproduced here, see above).
"""

from __future__ import annotations

from typing import ClassVar

from pounding.contact.hertzdamp import HertzDamp, ye_damping
from pounding.errors import InputError


def hunt_crossley_damping(e: float) -> float:
    """xi = 3 (1 - e) / 2 [-] (Hunt and Crossley 1975), e in [0, 1]."""
    return 1.5 * (1.0 - e)


#: the calibrations of xi from e, by name
DAMPING_RULES = {"hunt_crossley": hunt_crossley_damping, "ye": ye_damping}


class Rubber(HertzDamp):
    """A rubber layer: Hertz-type spring with Hunt-Crossley damping (see the module docstring).

    Parameters
    ----------
    stiffness : float
        k_r [N/m^n], required: for a pad of Young's modulus E [Pa], area A [m^2] and thickness t [m]
        pressed flat, n = 1 and k_r = E A / t (docs/modelling.md).
    exponent : float
        n in (0, 3] (default 1.5, Hertz's).
    restitution : float
        Coefficient of restitution e in [0, 1] (in (0, 1] with ``damping = "ye"``).
    damping : {"hunt_crossley", "ye"}
        The calibration of xi from e: 3 (1 - e) / 2 (default) or 8 (1 - e) / (5 e).
    tolerance : float
        Contact length tolerance [m].
    """

    name: ClassVar[str] = "rubber"
    damping_rules: ClassVar[dict] = DAMPING_RULES

    def __init__(self, *, stiffness: float | None = None, exponent: float = 1.5, restitution: float = 0.5,
                 damping: str = "hunt_crossley", tolerance: float = 1e-4):
        if stiffness is None:
            raise InputError("a rubber layer needs its stiffness k_r [N/m^n] (E A / t for a pad pressed flat, n = 1)",
                             field="stiffness")
        # hertzdamp's spring, damping kernel, contact duration and parameters, with the rubber's calibrations
        super().__init__(stiffness=stiffness, exponent=exponent, restitution=restitution, damping=damping, tolerance=tolerance)

    def opensees_material(self, share: float, m_eff: float, clear: float) -> None:
        """None: the layer is not exported to OpenSees (its law is ``hertzdamp``'s kernel with another
        calibration of xi, which OpenSees' ``Hertzdamp`` has not been checked against here)."""
        return None
