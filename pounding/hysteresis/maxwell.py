"""A Maxwell damper: a spring K in series with a nonlinear dashpot, as OpenSees' ``ViscousDamper``.

The spring (the brace and the damper's own axial flexibility) and the dashpot carry the same force F:

    F = K (u - w),    F = c |w'|^alpha sgn(w'),   so   F' = K (u' - g(F)),   g(F) = sgn(F) (|F| / c)^(1/alpha),

w [m] the dashpot's stroke. The link has no stiffness at rest (a slow motion goes through the
dashpot at no force): k0 = 0, the modal model does not see it. Linear (alpha = 1) it relaxes with
tau = c / K, and under u = D sin(w t) its steady force is D (E' sin(w t) + E'' cos(w t)) with the
storage and loss moduli E' = K (w tau)^2 / (1 + (w tau)^2), E'' = K w tau / (1 + (w tau)^2).

Update (chosen): the implicit midpoint rule on the series condition over the step from the committed
(u0, F0) to the trial u, the dashpot moving at the rate of the mean force Fm = (F0 + F1) / 2:

    F1 = F0 + K ((u - u0) - h g(Fm)),   i.e.   Fm - F0 - K (u - u0) / 2 + (K h / 2) g(Fm) = 0,

solved for Fm by Newton safeguarded by bisection (the left side increases with Fm, from -p at 0 to
(K h / 2) g(p) at p = F0 + K (u - u0) / 2: the root lies between 0 and p); alpha = 1 in closed form.
It is second order, and exact in energy: the trapezoid of the force over the step,
Fm (u - u0), is the spring's stored change (F1^2 - F0^2) / (2 K) plus the dashpot's dissipation
Fm h g(Fm) >= 0, which the law books (the stepping's energy rule for average acceleration is that
trapezoid, so its account closes with it). Linear, its steady loop is the exact one at the
frequency (2 / h) tan(w h / 2) (the rule's frequency warping): moduli within (w h)^2 / 12 relative.
It is not L-stable: with h longer than 2 tau the force's free response alternates in sign,
decaying by |1 - h / 2 tau| / (1 + h / 2 tau) per step; for a brace so stiff that tau << h the
``viscous`` law (K -> infinity) is the model. OpenSees' ``ViscousDamper`` integrates the same
equation in time by adaptive Dormand-Prince from the rates it is given (its velocity linear in the step).

The step h is not an argument of a law: it is h = (u - u0) / v from the mean rate v. A step that
does not move the link (u = u0) is taken as one of no length (the force is held): the law cannot
relax a force at rest (a step of exactly zero motion with a force on is not a case of a damper
in an earthquake, where the rate vanishes only at isolated instants).

The tangent returned is the step's dF1/du at fixed h, K / (1 + (K h / 2) g'(Fm)); the damping
tangent is zero (the rate's part is in it).
"""

from __future__ import annotations

import math

import numpy as np

from pounding.compiler import njit
from pounding.hysteresis._values import EXPONENT_SCHEMA, NoYieldLaw, check_exponent, positive

#: law-specific parameters: the spring K [N/m], the coefficient c [N (s/m)^alpha], the exponent alpha
SPRING, COEFFICIENT, EXPONENT = 3, 4, 5


@njit(borrowed=True)
def _rate(f, c, alpha):
    """The dashpot's rate g(F) = sgn(F) (|F| / c)^(1/alpha) [m/s] and g'(F) [m/(N s)] at the force f [N]."""
    if alpha == 1.0:
        return f / c, 1.0 / c
    a = abs(f) / c
    if a == 0.0:
        return 0.0, (math.inf if alpha > 1.0 else 0.0)
    p = a ** (1.0 / alpha - 1.0)
    g = p * a
    return (g if f > 0.0 else -g), p / (alpha * c)


@njit(borrowed=True)
def mean_force(f0, du, h, k, c, alpha):
    """Fm of the midpoint step (module docstring) and g(Fm), g'(Fm), for the force f0 [N] at the start,
    the motion du [m] over h [s] > 0."""
    p = f0 + 0.5 * k * du
    q = 0.5 * k * h
    if alpha == 1.0:
        fm = p / (1.0 + q / c)
        return fm, fm / c, 1.0 / c
    lo, hi = min(0.0, p), max(0.0, p)
    fm = p / (1.0 + q / c)  # the linear dashpot's answer: a start inside the bracket
    for _ in range(200):
        g, dg = _rate(fm, c, alpha)
        res = fm - p + q * g
        if res == 0.0:
            break
        if res > 0.0:
            hi = fm
        else:
            lo = fm
        fn = fm - res / (1.0 + q * dg) if dg < math.inf else lo - 1.0
        if not (lo < fn < hi):  # Newton left the bracket (the dashpot's rate is stiff near F = 0): bisect
            fn = 0.5 * (lo + hi)
        if abs(fn - fm) <= 4e-16 * abs(fm) or hi - lo <= 4e-16 * max(abs(lo), abs(hi)):
            fm = fn
            break
        fm = fn
    g, dg = _rate(fm, c, alpha)
    return fm, g, dg


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Force [N], the step's tangent dF/du [N/m] and damping tangent 0 of link s at deformation u [m]
    reached at the mean rate v [m/s] from its committed state ``state[s]`` = (u, F, dissipated);
    ``params[s]`` = (0, 0, 0, K, c, alpha). Writes ``new_state[s]``."""
    k = params[s, SPRING]
    u0 = state[s, 0]
    f0 = state[s, 1]
    du = u - u0
    new_state[s, 0] = u
    if du == 0.0 or v == 0.0:  # a step of no length (or no motion): the spring alone
        r = f0 + k * du
        new_state[s, 1] = r
        new_state[s, 2] = state[s, 2]
        return r, k, 0.0
    h = du / v
    fm, g, dg = mean_force(f0, du, h, k, params[s, COEFFICIENT], params[s, EXPONENT])
    r = 2.0 * fm - f0
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2] + fm * (h * g)  # the dashpot's F w' h >= 0 (fm and g share a sign)
    tangent = 0.0 if dg == math.inf else k / (1.0 + 0.5 * k * h * dg)
    return r, tangent, 0.0


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: the spring's F^2 / (2 K)."""
    return 0.5 * state[1] * state[1] / params[SPRING]


class Maxwell(NoYieldLaw):
    """Spring and nonlinear dashpot in series, as OpenSees' ``ViscousDamper`` (see the module docstring).

    Parameters
    ----------
    stiffness : float
        K [N/m] of the spring in series (brace and damper body), > 0.
    coefficient : float
        c [N (s/m)^alpha] of the dashpot, > 0.
    exponent : float, default 1
        alpha [-], in (0, 2].
    """

    name = "maxwell"
    n_params = 6
    n_state = 3
    schema = {
        "type": "object",
        "additionalProperties": False,
        "required": ["stiffness", "coefficient"],
        "properties": {
            "stiffness": {"type": "number", "units": "N/m",
                          "description": "Stiffness K of the spring in series with the dashpot (brace and damper body)."},
            "coefficient": {"type": "number", "units": "N (s/m)^alpha",
                            "description": "Damping coefficient c of the dashpot: F = c |w'|^alpha sgn(w')."},
            "exponent": EXPONENT_SCHEMA,
        },
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, stiffness: float, coefficient: float, exponent: float = 1.0):
        self.stiffness = positive("stiffness", stiffness, "the stiffness of the spring in series [N/m]")
        self.coefficient = positive("coefficient", coefficient, "the damping coefficient [N (s/m)^alpha]")
        self.exponent = check_exponent("exponent", exponent)

    def own_values(self) -> tuple[float, float, float]:
        """(0, 0, 0): no stiffness at rest (the modal model does not see the damper), no yield."""
        return 0.0, 0.0, 0.0


    def pack(self, stiffness: float, yield_force: float, hardening: float) -> np.ndarray:
        return np.array([stiffness, yield_force, hardening, self.stiffness, self.coefficient, self.exponent], dtype=float)

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``ViscousDamper(K, c, alpha)``, its adaptive Dormand-Prince integration to 1e-10
        relative (1e-12 absolute, at most 20 halvings; its default is 1e-6). See
        :meth:`HysteresisLaw.opensees_material`."""
        ops.uniaxialMaterial("ViscousDamper", tag, self.stiffness, self.coefficient, self.exponent,
                             0.0, 1, 1e-10, 1e-12, 20)
