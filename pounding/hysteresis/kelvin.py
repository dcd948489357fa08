"""A Kelvin-Voigt link: a spring and a dashpot in parallel, F = k u + c |v|^alpha sgn(v).

Bilateral (it pulls as well as pushes: a damper with a stiff elastic brace beside it, a viscoelastic
damper, a bumper bonded to both faces), unlike the compression-only ``kelvin`` contact law. The
spring is the initial elastic part, k0 = k (in the modal model); the dashpot's force
(:func:`pounding.hysteresis.viscous.dashpot`, at the step's mean rate v) is the remainder, zero
exactly when the link does not move. OpenSees: ``Parallel`` of ``Elastic k`` and ``Viscous c alpha``.

Energy: stored k u^2 / 2; dissipated by the dashpot F_d(v) (u - u0) = c |v|^(1 + alpha) h per step,
exact for the step's path at the mean rate (see :mod:`pounding.hysteresis.viscous`).
"""

from __future__ import annotations


import numpy as np

from pounding.compiler import njit
from pounding.hysteresis._values import EXPONENT_SCHEMA, NoYieldLaw, check_exponent, positive
from pounding.hysteresis.viscous import COEFFICIENT, EXPONENT, dashpot


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Force [N], tangent k [N/m] and damping tangent [N s/m] of link s at deformation u [m] reached
    at the mean rate v [m/s]; ``params[s]`` = (k, 0, 0, c, alpha). Writes ``new_state[s]``."""
    k = params[s, 0]
    fd, damping = dashpot(params[s, COEFFICIENT], params[s, EXPONENT], v)
    r = k * u + fd
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2] + fd * (u - state[s, 0])
    return r, k, damping


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: the spring's k u^2 / 2."""
    return 0.5 * params[0] * state[0] * state[0]


class Kelvin(NoYieldLaw):
    """Spring and dashpot in parallel (see the module docstring); it sets the link's stiffness itself.

    Parameters
    ----------
    stiffness : float
        k [N/m], > 0.
    coefficient : float
        c [N (s/m)^alpha], > 0.
    exponent : float, default 1
        alpha [-], in (0, 2].
    """

    name = "kelvin"
    n_params = 5
    n_state = 3
    schema = {
        "type": "object",
        "additionalProperties": False,
        "required": ["stiffness", "coefficient"],
        "properties": {
            "stiffness": {"type": "number", "units": "N/m", "description": "Stiffness k of the parallel spring."},
            "coefficient": {"type": "number", "units": "N (s/m)^alpha",
                            "description": "Damping coefficient c of the parallel dashpot."},
            "exponent": EXPONENT_SCHEMA,
        },
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, stiffness: float, coefficient: float, exponent: float = 1.0):
        self.stiffness = positive("stiffness", stiffness, "the stiffness [N/m]")
        self.coefficient = positive("coefficient", coefficient, "the damping coefficient [N (s/m)^alpha]")
        self.exponent = check_exponent("exponent", exponent)

    def own_values(self) -> tuple[float, float, float]:
        """(k, 0, 0): the spring is the initial stiffness; no yield."""
        return self.stiffness, 0.0, 0.0


    def pack(self, stiffness: float, yield_force: float, hardening: float) -> np.ndarray:
        return np.array([stiffness, yield_force, hardening, self.coefficient, self.exponent], dtype=float)

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``Parallel`` of ``Elastic(k)`` and ``Viscous(c, alpha)``, the two parts tagged by
        ``tags()``. See :meth:`HysteresisLaw.opensees_material`."""
        spring, dashpot = tags(), tags()
        ops.uniaxialMaterial("Elastic", spring, self.stiffness)
        ops.uniaxialMaterial("Viscous", dashpot, self.coefficient, self.exponent)
        ops.uniaxialMaterial("Parallel", tag, spring, dashpot)
