"""A fluid viscous damper: F = c |v|^alpha sgn(v), as OpenSees' ``Viscous`` uniaxial material.

c [N (s/m)^alpha] is the damping coefficient and alpha in (0, 2] the velocity exponent: 1 is a
linear dashpot (c [N s/m]); fluid viscous dampers in buildings have alpha = 0.2-1, which caps the
force at high velocities. The damper has no stiffness: k0 = 0, so the modal model of the building
does not see it, and its whole force is the stepping's remainder.

Over a step the engine gives the law the mean rate v = (u - u_committed) / h
(:func:`pounding.framework.engine.links.law_update`), and the law returns the force at that rate,
its tangent dr/du = 0 and its damping tangent dr/dv = alpha c |v|^(alpha - 1). The damping tangent
is infinite at v = 0 for alpha < 1; it is taken at max(|v|, ``MIN_RATE``) (the force itself is
exact), a floor that only guards v = 0 exactly: any other rate the engine gives is a difference of
two floats over h, at least ulp(u) / h, and the tangent there is the true one, which the stepping's
Newton needs to tell how precisely a step ending near rest can be solved (the force differs by
c (ulp(u) / h)^alpha between neighbouring floats of u). That Newton converges for alpha down to
0.1 at the steps users take (10, 5, 2.5 ms; measured in tests/test_damper_laws.py): its line search
is on the convex potential whose gradient its residual is
(:func:`pounding.framework.engine.spring_core.solve_group`), which a tangent in error cannot defeat.

Energy: with the mean rate the damper moves by u - u0 = v h at the constant force F(v), so it
dissipates F(v) (u - u0) = c |v|^(1 + alpha) h in the step, exactly for this path, and stores
nothing. Under u = D sin(w t) a linear damper dissipates pi c w D^2 per cycle; with the mean rates
of N equal steps per cycle (N >= 3) the sum is that times [sin(w h/2) / (w h/2)]^2, exactly (the
mean rate of a sine over a step is its midpoint value times that factor; the squares of equally
spaced cosines sum to N/2): a relative error (w h)^2 / 12 + O(h^4). A nonlinear damper dissipates
lambda(alpha) c w^alpha D^(1 + alpha) per cycle, lambda = 2^(2 + alpha) Gamma(1 + alpha/2)^2 /
Gamma(2 + alpha) (lambda(1) = pi).

Note: the force at a step's end is the mean rate's, c v(t - h/2) + O(h^2) for a linear damper,
half a step behind the end rate; in a building this lag shifts the response by O(h) (an apparent
mass of c h / 2), so a run with dampers converges with the first power of the step (measured:
tests/test_damper_laws.py).
"""

from __future__ import annotations

import math

import numpy as np

from pounding.compiler import njit
from pounding.hysteresis._values import EXPONENT_SCHEMA, NoYieldLaw, check_exponent, positive

#: law-specific parameters: the coefficient c [N (s/m)^alpha] and the exponent alpha [-]
COEFFICIENT, EXPONENT = 3, 4
#: the rate [m/s] below which the damping tangent of alpha < 1 is taken at this rate: it only guards
#: v = 0 (OpenSees' minVel is 1e-11; a floor that high hid how steep the force is near rest)
MIN_RATE = 1e-100


@njit(borrowed=True)
def dashpot(c, alpha, v):
    """Force c |v|^alpha sgn(v) [N] and damping tangent alpha c max(|v|, MIN_RATE)^(alpha - 1) [N s/m]
    of a dashpot at the rate v [m/s]."""
    a = abs(v)
    if alpha == 1.0:  # the linear dashpot: no pow()
        return c * v, c
    force = c * a**alpha
    if v < 0.0:
        force = -force
    return force, alpha * c * max(a, MIN_RATE) ** (alpha - 1.0)


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Force [N], tangent 0 [N/m] and damping tangent [N s/m] of link s at deformation u [m] reached
    at the mean rate v [m/s] from its committed state ``state[s]`` = (u, r, dissipated);
    ``params[s]`` = (0, 0, 0, c, alpha). Writes ``new_state[s]``."""
    r, damping = dashpot(params[s, COEFFICIENT], params[s, EXPONENT], v)
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2] + r * (u - state[s, 0])  # c |v|^(1 + alpha) h >= 0
    return r, 0.0, damping


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: none."""
    return 0.0


def energy_per_cycle(c: float, alpha: float, amplitude: float, omega: float) -> float:
    """Energy [J] a damper F = c |v|^alpha sgn(v) dissipates in one cycle of u = D sin(w t):
    lambda(alpha) c w^alpha D^(1 + alpha), lambda = 2^(2 + alpha) Gamma(1 + alpha/2)^2 / Gamma(2 + alpha)."""
    lam = 2.0 ** (2.0 + alpha) * math.gamma(1.0 + alpha / 2.0) ** 2 / math.gamma(2.0 + alpha)
    return lam * c * omega**alpha * amplitude ** (1.0 + alpha)


class Viscous(NoYieldLaw):
    """A fluid viscous damper, F = c |v|^alpha sgn(v) (see the module docstring); no stiffness.

    Parameters
    ----------
    coefficient : float
        c [N (s/m)^alpha], > 0.
    exponent : float, default 1
        alpha [-], in (0, 2]: 1 a linear dashpot, below 1 a force that grows slower than the rate.
    """

    name = "viscous"
    n_params = 5
    n_state = 3
    schema = {
        "type": "object",
        "additionalProperties": False,
        "required": ["coefficient"],
        "properties": {
            "coefficient": {"type": "number", "units": "N (s/m)^alpha",
                            "description": "Damping coefficient c: F = c |v|^alpha sgn(v)."},
            "exponent": EXPONENT_SCHEMA,
        },
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, coefficient: float, exponent: float = 1.0):
        self.coefficient = positive("coefficient", coefficient, "the damping coefficient [N (s/m)^alpha]")
        self.exponent = check_exponent("exponent", exponent)

    def own_values(self) -> tuple[float, float, float]:
        """(0, 0, 0): a damper has no stiffness (the modal model does not see it) and no yield."""
        return 0.0, 0.0, 0.0


    def pack(self, stiffness: float, yield_force: float, hardening: float):
        return np.array([stiffness, yield_force, hardening, self.coefficient, self.exponent], dtype=float)

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``Viscous(c, alpha)``. See :meth:`HysteresisLaw.opensees_material`."""
        ops.uniaxialMaterial("Viscous", tag, self.coefficient, self.exponent)

