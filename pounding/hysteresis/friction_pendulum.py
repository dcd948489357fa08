"""Friction pendulum isolators: a line of single concave sliding bearings, as OpenSees' ``singleFPBearing``.

A slider on a concave dish of effective radius R carrying the weight W rises as it moves, so the
weight pulls it back with the pendulum stiffness k_R = W / R, and the sliding surface resists it
with the friction force mu W:

    r = k_R u + q,    k_R = W / R,    |q| <= Q = mu W.

Formulation (chosen): the friction force q is elastic-perfectly-plastic, as in OpenSees'
``singleFPBearing`` (Coulomb friction; its ``kInit`` is k0 below): before it slides the slider
deforms elastically with k_i = mu_fast W / u_y, u_y the yield (pre-sliding) displacement,

    q = k_i (u - u_s),    u_s the slip [m],    |q| <= Q,

so the whole law is bilinear with k0 = W / R + mu W / u_y, Fy = k0 u_y and b = (W / R) / k0
(the element's stiffness, yield force and hardening, worked out here: :meth:`FrictionPendulum.own_values`).
Constantinou's smooth sign z (u_y dz/dt = v - beta |v| z |z|^(n-1) - gamma v |z|^n) with a
constant mu is exactly the ``bouc_wen`` law with these k0, Fy, b; the elastic-plastic sign was
chosen here because it keeps the law passive with a velocity-dependent friction (below), its
dissipation is exact over a step, and it is OpenSees' isolator element but for the normal force:
``singleFPBearing`` takes N = W + F u / R (the horizontal force's component along the dish's
normal), this law N = W (small displacements: the forces differ by F (u/R)(u/R +- mu)); scaled
by W / N, its force is this law's to rounding (tests/test_friction_pendulum.py).

Velocity-dependent friction (optional, OpenSees' ``frictionModel VelDependent``):

    mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|),

v [m/s] the sliding rate. The law takes mu at the rate of the last committed step (stored in its
state), not at the trial's: the bound Q is then fixed within a step, the force is a nondecreasing
function of the trial deformation (tangent k0 or k_R, never negative, as the stepping's Newton
needs), and the rate dependence lags one step (first order in the step, converging with it).
A bound evaluated at the trial rate would make the force fall as the slider reverses faster
(a negative tangent of order W mu' / h). A bound that dropped below the committed force (the
slider slowed down) first relaxes q to it at the committed deformation, dissipating the released
elastic energy (q0^2 - Q^2) / (2 k_i), then the step proceeds from there.

Energy: the stored energy is k_R u^2 / 2 + q^2 / (2 k_i) (the pendulum's potential energy of the
raised weight and the slider's elastic deformation) and the dissipation over a step that
relaxation plus Q |du_s| (the slider moves one way, at the force Q, within a step): exact for the
update, and never negative: a passive isolator. A symmetric stabilised loop between -D and D
(D > u_y, constant mu) dissipates 4 mu W (D - u_y), the parallelogram's area.

References: M. Constantinou, A. Mokha, A. Reinhorn (1990), Teflon bearings in base isolation II:
modeling, J. Struct. Eng. 116(2); V. Zayas, S. Low, S. Mahin (1990), A simple pendulum technique
for achieving seismic isolation, Earthquake Spectra 6(2); OpenSees ``singleFPBearing`` and
``frictionModel VelDependent`` (A. Schellenberg).
"""

from __future__ import annotations

import math

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError
from pounding.hysteresis._values import number
from pounding.hysteresis.base import HysteresisLaw

#: law-specific state slots: the slip u_s [m], the rate of the committed step [m/s]
SLIP, RATE = 3, 4
#: law-specific parameters: weight W [N], mu_fast, mu_slow [-], rate a [s/m], k_R = W/R and k_i [N/m]
WEIGHT, MU_FAST, MU_SLOW, TRANSITION, K_PENDULUM, K_SLIDER = 3, 4, 5, 6, 7, 8

#: default yield (pre-sliding) displacement [m]: a fraction of a millimetre, the order of the
#: elastic deformation of a PTFE-type slider before it slides in fitted friction models
DEFAULT_YIELD_DISPLACEMENT = 2.5e-4


@njit(borrowed=True)
def friction_force(params, s, rate):
    """Friction bound Q = mu(rate) W [N] of link s at the sliding rate ``rate`` [m/s]."""
    mu_fast = params[s, MU_FAST]
    mu_slow = params[s, MU_SLOW]
    if mu_slow == mu_fast:  # constant friction: Q = mu W exactly, whatever the rate
        return mu_fast * params[s, WEIGHT]
    mu = mu_fast - (mu_fast - mu_slow) * math.exp(-params[s, TRANSITION] * abs(rate))
    return mu * params[s, WEIGHT]


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Trial force [N], tangent [N/m] and damping tangent [N s/m] (zero: the friction is taken at
    the committed step's rate) of link s at deformation u [m] and rate v [m/s] from its committed
    state ``state[s]`` = (u, r, dissipated, u_s, rate); ``params[s]`` = (k0, Fy, b, W, mu_fast,
    mu_slow, a, k_R, k_i). Writes ``new_state[s]``."""
    k0 = params[s, 0]
    ki = params[s, K_SLIDER]
    kr = params[s, K_PENDULUM]
    u0 = state[s, 0]
    us0 = state[s, SLIP]
    bound = friction_force(params, s, state[s, RATE])
    dissipated = state[s, 2]
    # a bound that fell below the committed friction force relaxes it at u0 (released energy dissipated)
    q0 = ki * (u0 - us0)
    if q0 > bound:
        us0 = u0 - bound / ki
        dissipated += 0.5 * (q0 * q0 - bound * bound) / ki
    elif q0 < -bound:
        us0 = u0 + bound / ki
        dissipated += 0.5 * (q0 * q0 - bound * bound) / ki
    trial = ki * (u - us0)
    if trial > bound:
        us = u - bound / ki
        r = kr * u + bound
        tangent = kr
    elif trial < -bound:
        us = u + bound / ki
        r = kr * u - bound
        tangent = kr
    else:
        us = us0
        r = k0 * u - ki * us  # = k_R u + k_i (u - u_s), and k0 u bit for bit before any slip
        tangent = k0
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = dissipated + bound * abs(us - us0)
    new_state[s, SLIP] = us
    # a step of no length (an impact at a step's start: v = 0) keeps the committed rate
    new_state[s, RATE] = v if u != u0 else state[s, RATE]
    return r, tangent, 0.0


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: the pendulum's k_R u^2 / 2 plus the slider's q^2 / (2 k_i), q = k_i (u - u_s)."""
    u = state[0]
    ki = params[K_SLIDER]
    q = ki * (u - state[SLIP])
    return 0.5 * params[K_PENDULUM] * u * u + 0.5 * q * q / ki


class FrictionPendulum(HysteresisLaw):
    """A line of single friction pendulum bearings (see the module docstring).

    The law sets the storey's stiffness, yield force and hardening from its own parameters
    (:meth:`own_values`): the element gives none of them.

    Parameters
    ----------
    weight : float
        Weight W [N] the bearings of the line carry (> 0): the vertical load on them.
    radius : float
        Effective radius of curvature R [m] of the sliding surface (> 0); the isolated period is
        2 pi sqrt(R / g).
    friction : float
        Sliding friction coefficient mu [-], in (0, 1]; with ``friction_slow``, the coefficient at
        high sliding speed (mu_fast).
    friction_slow : float, optional
        Coefficient at low sliding speed mu_slow, in (0, friction]: makes the friction velocity
        dependent, mu(v) = mu_fast - (mu_fast - mu_slow) exp(-rate |v|).
    rate : float, optional
        Transition rate a [s/m] (> 0) of the velocity-dependent friction; required with
        ``friction_slow``.
    yield_displacement : float, default 2.5e-4
        Displacement u_y [m] at which the slider starts sliding at the friction ``friction``
        (> 0, below R): the slider's initial stiffness is k_i = mu W / u_y.
    """

    name = "friction_pendulum"
    n_params = 9
    n_state = 5
    schema = {
        "type": "object",
        "additionalProperties": False,
        "required": ["weight", "radius", "friction"],
        "properties": {
            "weight": {"type": "number", "units": "N", "description": "Weight the bearings of the line carry."},
            "radius": {"type": "number", "units": "m", "description": "Effective radius of curvature of the sliding surface."},
            "friction": {"type": "number", "units": "-", "description": "Sliding friction coefficient (at high speed, with friction_slow)."},
            "friction_slow": {"type": "number", "units": "-", "description": "Friction coefficient at low sliding speed."},
            "rate": {"type": "number", "units": "s/m", "description": "Transition rate of the velocity-dependent friction."},
            "yield_displacement": {"type": "number", "units": "m", "default": DEFAULT_YIELD_DISPLACEMENT,
                                   "description": "Displacement at which the slider starts to slide."},
        },
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, weight: float, radius: float, friction: float, friction_slow: float | None = None,
                 rate: float | None = None, yield_displacement: float = DEFAULT_YIELD_DISPLACEMENT):
        weight, radius, friction = number("weight", weight), number("radius", radius), number("friction", friction)
        uy = number("yield_displacement", yield_displacement)
        if weight <= 0.0:
            raise InputError(f"the weight the bearings carry must be > 0 [N], got {weight:g}", field="weight")
        if radius <= 0.0:
            raise InputError(f"the radius of curvature must be > 0 [m], got {radius:g}", field="radius")
        if not 0.0 < friction <= 1.0:
            raise InputError(f"the friction coefficient must be in (0, 1], got {friction:g} (a frictionless pendulum "
                             "is an elastic spring of stiffness W / R: storey_springs without yield_force)", field="friction")
        if not 0.0 < uy < radius:
            raise InputError(f"the yield displacement must be > 0 and below the radius [m], got {uy:g}", field="yield_displacement")
        if (friction_slow is None) != (rate is None):
            key = "rate" if rate is None else "friction_slow"
            raise InputError("velocity-dependent friction takes both friction_slow and rate", field=key)
        if friction_slow is not None:
            friction_slow, rate = number("friction_slow", friction_slow), number("rate", rate)
            if not 0.0 < friction_slow <= friction:
                raise InputError(f"friction_slow must be in (0, friction] = (0, {friction:g}], got {friction_slow:g}",
                                 field="friction_slow")
            if rate <= 0.0:
                raise InputError(f"the transition rate must be > 0 [s/m], got {rate:g}", field="rate")
        self.weight = weight
        self.radius = radius
        self.friction = friction
        self.friction_slow = friction_slow
        self.rate = rate
        self.yield_displacement = uy

    @property
    def pendulum_stiffness(self) -> float:
        """k_R = W / R [N/m]."""
        return self.weight / self.radius

    @property
    def slider_stiffness(self) -> float:
        """k_i = mu W / u_y [N/m] (mu = friction, the fast coefficient)."""
        return self.friction * self.weight / self.yield_displacement

    def own_values(self) -> tuple[float, float, float]:
        """(k0, Fy, b): k0 = W/R + mu W/u_y [N/m], Fy = k0 u_y [N], b = (W/R) / k0 [-]."""
        k0 = self.pendulum_stiffness + self.slider_stiffness
        return k0, k0 * self.yield_displacement, self.pendulum_stiffness / k0

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """With constant friction, OpenSees' ``Steel01(Fy, k0, b)``: the pendulum's W/R beside the
        elastic-perfectly-plastic slider (mu W / u_y, yield mu W) is kinematic hardening with the law's
        k0, Fy and b (``singleFPBearing`` would also add F u / R to the normal force, which the law
        leaves out). With velocity-dependent friction OpenSees has no uniaxial material of this law:
        NotImplementedError. See :meth:`HysteresisLaw.opensees_material`."""
        if self.friction_slow is not None:
            raise NotImplementedError(f"no OpenSees material for hysteresis law {self.name!r} with velocity-dependent friction")
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)

    def pack(self, stiffness: float, yield_force: float, hardening: float) -> np.ndarray:
        slow = self.friction if self.friction_slow is None else self.friction_slow
        rate = 0.0 if self.rate is None else self.rate
        return np.array([stiffness, yield_force, hardening, self.weight, self.friction, slow, rate,
                         self.pendulum_stiffness, self.slider_stiffness], dtype=float)

    def describe(self) -> dict:
        out = {"name": self.name, "weight": self.weight, "radius": self.radius, "friction": self.friction,
               "yield_displacement": self.yield_displacement}
        if self.friction_slow is not None:
            out.update(friction_slow=self.friction_slow, rate=self.rate)
        return out
