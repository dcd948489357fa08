"""Bouc-Wen smooth hysteresis (Bouc 1967, Wen 1976), with the update of OpenSees' BoucWen.

Force and evolution of the dimensionless hysteretic variable z:

    r  = b k0 u + (1 - b) Fy z
    dz = (du / u_y) (A - |z|^n (gamma + beta sgn(du z))),    u_y = Fy / k0,  A = 1

so the initial tangent is k0 (the element's stiffness) and z tends to
z_u = (1 / (beta + gamma))^(1/n) under monotonic loading: with
beta + gamma = 1 the hysteretic force saturates at (1 - b) Fy and the
envelope tends to the bilinear law of the same k0, Fy, b as n -> infinity.
Monotonic loading from rest has closed forms: z = tanh(u / u_y) for n = 2 and
beta + gamma = 1; z = (1 - exp(-(beta + gamma) u / u_y)) / (beta + gamma) for n = 1.

Valid parameters (Ikhouane, Manosa & Rodellar 2007, Systems & Control Letters
56, 197-205: bounded, passive, with a stable loop): n >= 1, beta > 0,
-beta < gamma <= beta (so beta + gamma > 0 and beta - gamma >= 0). A is
fixed to 1: any other A is the same model with another k0 and u_y.

Update: backward Euler on z over the step, as ``BoucWenMaterial::setTrialStrain``
(OpenSees with deltaA = deltaNu = deltaEta = 0, ko = k0, alpha = b, Ao = 1,
beta_OS = beta / u_y^n, gamma_OS = gamma / u_y^n, whose z is u_y z here):

    z1 - z0 - (du / u_y) (1 - |z1|^n (gamma + beta sgn(du z1))) = 0,

solved by Newton safeguarded by bisection (the left side is increasing in z1
with slope >= 1, so the root is within |f(z0)| of z0). The tangent is the
consistent one, dz1/du from the same equation.

Energy: the hysteretic part is an elastic element of stiffness (1 - b) k0 and
deformation u_y z in series with a slider, so the stored energy is
b k0 u^2 / 2 + (1 - b) Fy u_y z^2 / 2 and the dissipation over a step the
trapezoid of the hysteretic force over the slider's motion,
(1 - b) Fy (z0 + z1) / 2 (du - u_y dz).
"""

from __future__ import annotations

import math

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError
from pounding.hysteresis.base import HysteresisLaw

#: law-specific state slot: the hysteretic variable z [-]
Z = 3


@njit(borrowed=True)
def _power(a, n):
    """a**n and a**(n - 1) for a >= 0, n >= 1, without pow() for the common n = 1, 2."""
    if n == 2.0:
        return a * a, a
    if n == 1.0:
        return a, 1.0
    if a == 0.0:
        return 0.0, 0.0
    p1 = a ** (n - 1.0)
    return p1 * a, p1


@njit(borrowed=True)
def _residual(z, z0, du_y, n, beta, gamma):
    s = 1.0 if du_y * z > 0.0 else -1.0  # OpenSees' signum: -1 at 0
    psi = gamma + beta * s
    az = abs(z)
    an, an1 = _power(az, n)
    f = z - z0 - du_y * (1.0 - an * psi)
    sz = 1.0 if z > 0.0 else -1.0
    d = 1.0 + du_y * n * an1 * sz * psi
    return f, d, psi


@njit(borrowed=True)
def solve_z(z0, du_y, n, beta, gamma):
    """z1 of the backward-Euler step for the increment du / u_y = du_y, and df/dz1 and psi there."""
    f, d, psi = _residual(z0, z0, du_y, n, beta, gamma)
    if f == 0.0:
        return z0, d, psi
    lo = z0 - abs(f)
    hi = z0 + abs(f)
    z = z0
    for _ in range(200):
        f, d, psi = _residual(z, z0, du_y, n, beta, gamma)
        if f == 0.0:
            break
        if f > 0.0:
            hi = z
        else:
            lo = z
        zn = z - f / d
        tol = 4e-16 * max(1.0, abs(z))
        if abs(zn - z) <= tol:  # converged: Newton's last correction is rounding
            z = zn
            break
        if not (lo <= zn <= hi):  # Newton left the bracket (near the kink of psi at z = 0): bisect
            zn = 0.5 * (lo + hi)
        z = zn
        if hi - lo <= tol:
            break
    f, d, psi = _residual(z, z0, du_y, n, beta, gamma)
    return z, d, psi


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Trial force [N], tangent [N/m] and damping tangent [N s/m] (zero: rate-independent) of link s
    at deformation u [m] and rate v [m/s] from its committed state ``state[s]`` = (u, r, dissipated,
    z); ``params[s]`` = (k0, Fy, b, n, beta, gamma). Writes ``new_state[s]``."""
    k0 = params[s, 0]
    fy = params[s, 1]
    b = params[s, 2]
    n = params[s, 3]
    beta = params[s, 4]
    gamma = params[s, 5]
    uy = fy / k0
    u0 = state[s, 0]
    z0 = state[s, Z]
    du_y = (u - u0) / uy
    z, d, psi = solve_z(z0, du_y, n, beta, gamma)
    r = b * k0 * u + (1.0 - b) * fy * z
    an, _ = _power(abs(z), n)
    dzdu = (1.0 - an * psi) / (uy * d)
    tangent = b * k0 + (1.0 - b) * fy * dzdu
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2] + (1.0 - b) * fy * 0.5 * (z0 + z) * ((u - u0) - uy * (z - z0))
    new_state[s, Z] = z
    return r, tangent, 0.0


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: b k0 u^2 / 2 + (1 - b) Fy u_y z^2 / 2."""
    k0 = params[0]
    fy = params[1]
    b = params[2]
    u = state[0]
    z = state[Z]
    return 0.5 * b * k0 * u * u + 0.5 * (1.0 - b) * fy * (fy / k0) * z * z


class BoucWen(HysteresisLaw):
    """Bouc-Wen smooth hysteresis (see the module docstring).

    Parameters
    ----------
    n : float, default 2
        Sharpness of the transition to yield, >= 1 (n -> infinity: bilinear).
    beta : float, default 0.5
        Weight of the sign-dependent term, > 0.
    gamma : float, default 0.5
        Weight of the sign-independent term, -beta < gamma <= beta.
    """

    name = "bouc_wen"
    n_params = 6
    n_state = 4
    schema = {
        "type": "object",
        "additionalProperties": False,
        "properties": {"n": {"type": "number"}, "beta": {"type": "number"}, "gamma": {"type": "number"}},
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, n: float = 2.0, beta: float = 0.5, gamma: float = 0.5):
        for key, value in (("n", n), ("beta", beta), ("gamma", gamma)):
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
                raise InputError(f"expected a finite number, got {value!r}", field=key)
        n, beta, gamma = float(n), float(beta), float(gamma)
        if n < 1.0:
            raise InputError(f"Bouc-Wen n must be >= 1 (the sharpness of yield), got {n:g}", field="n")
        if beta <= 0.0:
            raise InputError(f"Bouc-Wen beta must be > 0 (a bounded, passive loop), got {beta:g}", field="beta")
        if not -beta < gamma <= beta:
            raise InputError(
                f"Bouc-Wen gamma must satisfy -beta < gamma <= beta (= {beta:g}) for a bounded, passive loop, got {gamma:g}",
                field="gamma",
            )
        self.n = n
        self.beta = beta
        self.gamma = gamma

    def pack(self, stiffness: float, yield_force: float, hardening: float) -> np.ndarray:
        return np.array([stiffness, yield_force, hardening, self.n, self.beta, self.gamma], dtype=float)

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``BoucWen(b, k0, n, gamma / u_y^n, beta / u_y^n, 1, 0, 0, 0)``, u_y = Fy / k0 [m]:
        OpenSees' z is a displacement, u_y times this law's, so its gamma and beta [1/m^n] are this
        law's over u_y^n; no degradation; Newton on z to ``boucwen_tol * u_y`` [m] in at most 200
        iterations. See :meth:`HysteresisLaw.opensees_material`."""
        uy = fy / k0
        n, beta, gamma = self.n, self.beta, self.gamma
        ops.uniaxialMaterial("BoucWen", tag, b, k0, n, gamma / uy**n, beta / uy**n, 1.0, 0.0, 0.0, 0.0, float(boucwen_tol * uy), 200)
