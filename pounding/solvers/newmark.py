"""Newmark's family of one-step methods, and the step shared by its alpha variants.

Newmark (1959) advances a unit-mass oscillator ``q'' + c q' + k q = p(t)``
(``c = 2 zeta omega``, ``k = omega**2``) with

    q1  = q0 + dt q'0 + dt**2 ((1/2 - beta) q''0 + beta q''1)
    q'1 = q'0 + dt ((1 - gamma) q''0 + gamma q''1)

and closes the step with an equilibrium equation. :func:`alpha_step`
evaluates that equation at a shifted instant, which covers Newmark
(``alpha_m = alpha_f = 0``), HHT (``alpha_m = 0``) and the generalized-alpha
method of Chung & Hulbert (1993) with one kernel.

Reference: N. M. Newmark (1959), A method of computation for structural
dynamics, J. Eng. Mech. Div. ASCE 85(EM3), 67-94.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from pounding.compiler import is_compiled, njit
from pounding.errors import InputError
from pounding.solvers.base import Integrator, Transition

PRESETS = {"average": (0.25, 0.5), "linear": (1.0 / 6.0, 0.5)}


class AlphaScheme(NamedTuple):
    """The parameters of one method of the family (:func:`alpha_step`), all dimensionless."""

    beta: float  #: weight of the end acceleration in the displacement update
    gamma: float  #: weight of the end acceleration in the velocity update
    alpha_m: float  #: shift of the inertia term towards the start (0: Newmark, HHT)
    alpha_f: float  #: shift of the damping, stiffness and load terms towards the start (0: Newmark)


def real_param(value, field: str) -> float:
    """``value`` as a finite float, or an ``InputError`` naming ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"expected a number, got {value!r}", field=field)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value!r}", field=field)
    return value


def alpha_step(q, qd, qdd, p0, p1, omega, zeta, dt, *, beta, gamma, alpha_m=0.0, alpha_f=0.0):
    """One step of the Newmark / HHT / generalized-alpha family (unit mass).

    Solves, for the end-of-step acceleration ``a1``,

        (1 - alpha_m) a1 + alpha_m a0
          + (1 - alpha_f) (c v1 + k x1) + alpha_f (c v0 + k x0)
          = (1 - alpha_f) p1 + alpha_f p0

    with Newmark's updates for ``x1`` and ``v1``. The load is linear in the
    step, so ``p(t_{n+1-alpha_f})`` is the same blend of ``p0`` and ``p1``.

    Parameters
    ----------
    q, qd, qdd : ndarray, shape (n,) or (n, k)
        Displacement, velocity [1/s x displacement] and acceleration at the start.
    p0, p1 : ndarray, shape like q
        Load per unit mass at the start and the end of the step.
    omega, zeta : ndarray, shape (n,) or (n, 1)
        Circular frequency [rad/s] (0 allowed) and damping ratio [-].
    dt : float
        Step size [s].
    beta, gamma, alpha_m, alpha_f : float
        Method parameters.

    Returns
    -------
    (q1, qd1, qdd1) : tuple of ndarray, broadcast shape of the inputs

    Each element is one mode's step (:func:`_alpha_scalar`, compiled): the acceleration form, exact
    for beta = 0, or where beta Omega^2 >> 1 (there q1 = qp + beta dt^2 a1 cancels and loses ~eps
    beta Omega^2 relative) the displacement form with the effective stiffness m_eff / (beta dt^2),
    accurate where the other is not. The transitions (:func:`alpha_transition`) are the same
    function on unit probes.
    """
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (q, qd, qdd, p0, p1, omega, zeta)))
    shape = arrays[0].shape
    out = np.empty((3, arrays[0].size))
    if out.shape[1]:
        _alpha_steps(*(np.ascontiguousarray(x).reshape(-1) for x in arrays), float(dt),
                     AlphaScheme(float(beta), float(gamma), float(alpha_m), float(alpha_f)), out)
    return out[0].reshape(shape), out[1].reshape(shape), out[2].reshape(shape)


@njit(borrowed=True)
def _alpha_steps(q, qd, qdd, p0, p1, omega, zeta, dt, scheme, out):
    """out (3, m) <- (q1, q'1, q''1) of :func:`alpha_step` for m elements (flat arrays (m,)), each by
    :func:`_alpha_scalar`; ``scheme`` the :class:`AlphaScheme`."""
    for i in range(q.shape[0]):
        _alpha_scalar(q[i], qd[i], qdd[i], p0[i], p1[i], 2.0 * zeta[i] * omega[i], omega[i] * omega[i], dt, scheme, out, i)


@njit(borrowed=True)
def _alpha_scalar(q, qd, qdd, p0, p1, c, k, dt, scheme, out, r):
    """One mode's step of :func:`alpha_step` (c = 2 zeta omega, k = omega^2) by the method ``scheme``
    (:class:`AlphaScheme`): out[0..2, r] <- (q1, q'1, q''1)."""
    beta, gamma, alpha_m, alpha_f = scheme.beta, scheme.gamma, scheme.alpha_m, scheme.alpha_f
    dt2 = dt * dt
    qp = q + dt * qd + (0.5 - beta) * dt2 * qdd
    vp = qd + (1.0 - gamma) * dt * qdd
    rhs = (1.0 - alpha_f) * p1 + alpha_f * p0 - alpha_m * qdd - alpha_f * (c * qd + k * q)
    m_eff = (1.0 - alpha_m) + (1.0 - alpha_f) * (gamma * dt * c + beta * dt2 * k)
    a1 = (rhs - (1.0 - alpha_f) * (c * vp + k * qp)) / m_eff
    q1 = qp + beta * dt2 * a1
    if beta > 0.0 and (1.0 - alpha_f) * beta * dt2 * k > (1.0 - alpha_m):
        g = gamma / (beta * dt)
        k_hat = (1.0 - alpha_m) / (beta * dt2) + (1.0 - alpha_f) * (g * c + k)
        q1 = (rhs + (1.0 - alpha_m) / (beta * dt2) * qp - (1.0 - alpha_f) * c * (vp - g * qp)) / k_hat
        a1 = (q1 - qp) / (beta * dt2)
    out[0, r] = q1
    out[1, r] = vp + gamma * dt * a1
    out[2, r] = a1


@njit
def alpha_transition(omega, zeta, dt, beta, gamma, alpha_m, alpha_f):
    """Per-mode transition (A (n, 3, 3), B (n, 3, 2)) of :func:`alpha_step` for a step of dt [s]: the
    five unit probes of :meth:`Integrator.transition` (unit q, q', q'', p0, p1), mode by mode, compiled:
    the step's own function on them (:func:`_alpha_scalar`), so the probed transition to the bit
    (tests/test_transitions.py), at a few microseconds instead of ~65."""
    n = omega.shape[0]
    A = np.empty((n, 3, 3))
    B = np.empty((n, 3, 2))
    out = np.empty((3, 5))
    scheme = AlphaScheme(beta, gamma, alpha_m, alpha_f)
    for i in range(n):
        c = 2.0 * zeta[i] * omega[i]
        k = omega[i] * omega[i]
        for r in range(5):
            _alpha_scalar(1.0 if r == 0 else 0.0, 1.0 if r == 1 else 0.0, 1.0 if r == 2 else 0.0, 1.0 if r == 3 else 0.0,
                          1.0 if r == 4 else 0.0, c, k, dt, scheme, out, r)
        for a in range(3):
            for j in range(3):
                A[i, a, j] = out[a, j]
            B[i, a, 0] = out[a, 3]
            B[i, a, 1] = out[a, 4]
    return A, B


@njit
def alpha_maps(omega, zeta, dt, params):
    """:func:`alpha_transition` in the form the compiled impact search takes an integrator's maps,
    ``(omega, zeta, dt, params) -> (A, B)``, params = (beta, gamma, alpha_m, alpha_f)."""
    return alpha_transition(omega, zeta, dt, params[0], params[1], params[2], params[3])


def alpha_family_maps(integrator, owner, *, beta, gamma, alpha_m=0.0, alpha_f=0.0):
    """:meth:`Integrator.search_maps` of a scheme whose step is :func:`alpha_step` with these
    parameters (the class ``owner``'s ``step``): (:func:`alpha_maps`, its parameters), the same
    function :func:`alpha_family_transition` builds its transitions with; None for a subclass with
    a step of its own, or without the compiler."""
    if type(integrator).step is not owner.step or not is_compiled(alpha_maps):
        return None
    return alpha_maps, np.array([beta, gamma, alpha_m, alpha_f], dtype=float)


def alpha_family_transition(integrator, owner, omega, zeta, dt, *, beta, gamma, alpha_m=0.0, alpha_f=0.0) -> Transition:
    """:meth:`Integrator.transition` of a scheme whose step is :func:`alpha_step` with these parameters
    (the class ``owner``'s ``step``), by :func:`alpha_transition` (compiled, the probes' numbers to the
    bit). A subclass with a step of its own is probed, as any integrator."""
    if type(integrator).step is not owner.step:  # a step of its own
        return Integrator.transition(integrator, omega, zeta, dt)
    omega = np.ascontiguousarray(omega, dtype=float).reshape(-1)
    if not (type(zeta) is np.ndarray and zeta.shape == omega.shape and zeta.dtype == np.float64 and zeta.flags.c_contiguous):
        # (per mode already, as the driver's transition cache holds it: a contact event's trial steps
        # build a transition each, and broadcast_to cost twice the compiled transition)
        zeta = np.ascontiguousarray(np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape))
    integrator.check_dt(omega, zeta, dt)
    A, B = alpha_transition(omega, zeta, float(dt), float(beta), float(gamma), float(alpha_m), float(alpha_f))
    return Transition(A=A, B=B, dt=float(dt))


class Newmark(Integrator):
    """Newmark's method with parameters ``beta`` and ``gamma``.

    Parameters
    ----------
    beta : float, default 1/4
        Weight of the end acceleration in the displacement update, ``>= 0``.
    gamma : float, default 1/2
        Weight of the end acceleration in the velocity update, ``>= 1/2``
        (below 1/2 the method adds energy). ``gamma = 1/2`` is second-order
        accurate and free of numerical damping.
    preset : {"average", "linear"}, optional
        Constant average acceleration (1/4, 1/2; unconditionally stable) or
        linear acceleration (1/6, 1/2; stable for ``omega dt <= sqrt(12)``).
        Exclusive with non-default ``beta``/``gamma``.

    Notes
    -----
    Unconditionally stable for ``2 beta >= gamma >= 1/2``. For
    ``beta < gamma/2`` the undamped oscillator is stable for
    ``omega dt <= Omega_crit = 1/sqrt(gamma/2 - beta)``; viscous damping does
    not lower that limit (it raises it when ``gamma > 1/2``), so
    :meth:`check_dt` applies the undamped limit to the highest mode.
    ``beta = 0`` is explicit.
    """

    name = "newmark"
    order = 2

    def __init__(self, *, beta=0.25, gamma=0.5, preset=None):
        beta = real_param(beta, "beta")
        gamma = real_param(gamma, "gamma")
        if preset is not None:
            if preset not in PRESETS:
                raise InputError(f"unknown preset {preset!r}; expected one of {sorted(PRESETS)}", field="preset")
            if (beta, gamma) != (0.25, 0.5) and (beta, gamma) != PRESETS[preset]:
                raise InputError(
                    f"give either preset={preset!r} or beta/gamma, not both (got beta={beta}, gamma={gamma})",
                    field="preset",
                )
            beta, gamma = PRESETS[preset]
        if gamma < 0.5:
            raise InputError(f"gamma must be >= 1/2 (smaller values add energy); got {gamma}", field="gamma")
        if beta < 0.0:
            raise InputError(f"beta must be >= 0; got {beta}", field="beta")
        self.beta = beta
        self.gamma = gamma

    @property
    def explicit(self) -> bool:
        """True when only conditionally stable (``beta < gamma/2``)."""
        return self.beta < self.gamma / 2.0

    @property
    def omega_crit(self) -> float:
        """Undamped stability limit of ``omega dt`` (``inf`` if unconditionally stable)."""
        margin = self.gamma / 2.0 - self.beta
        return math.inf if margin <= 0.0 else 1.0 / math.sqrt(margin)

    def check_dt(self, omega, zeta, dt):
        if math.isinf(self.omega_crit):  # unconditionally stable: every step length (each event's trial builds one)
            return
        omega_max = float(np.max(np.asarray(omega, dtype=float), initial=0.0))
        if omega_max == 0.0:
            return
        dt_max = self.omega_crit / omega_max
        if dt > dt_max * (1.0 + 1e-12):  # dt_max itself is accepted, up to rounding
            raise InputError(
                f"dt = {dt:.6g} s exceeds the stability limit of Newmark (beta={self.beta:.6g}, "
                f"gamma={self.gamma:.6g}): dt_max = {dt_max:.6g} s = Omega_crit/omega_max with "
                f"Omega_crit = 1/sqrt(gamma/2 - beta) = {self.omega_crit:.6g} (undamped), "
                f"omega_max = {omega_max:.6g} rad/s (T_min = {2 * math.pi / omega_max:.6g} s)",
                field="dt",
            )

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        return alpha_step(q, qd, qdd, p0, p1, omega, zeta, dt, beta=self.beta, gamma=self.gamma)

    def transition(self, omega, zeta, dt):
        return alpha_family_transition(self, Newmark, omega, zeta, dt, beta=self.beta, gamma=self.gamma)

    def search_maps(self):
        return alpha_family_maps(self, Newmark, beta=self.beta, gamma=self.gamma)
