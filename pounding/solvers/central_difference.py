"""The central difference method in Newmark's (x, v, a) form."""

from __future__ import annotations

import math

import numpy as np

from pounding.errors import InputError
from pounding.solvers.base import Integrator


class CentralDifference(Integrator):
    """Explicit central differences: Newmark with ``beta = 0``, ``gamma = 1/2``.

    The displacement is advanced from the start state alone,

        q1 = q0 + dt q'0 + dt**2/2 q''0,

    and the end acceleration follows from equilibrium with
    ``q'1 = q'0 + dt/2 (q''0 + q''1)``:

        (1 + dt c/2) q''1 = p1 - c (q'0 + dt/2 q''0) - k q1.

    Physically this needs only a diagonal solve; in modal coordinates every
    scheme is a scalar solve, so the gain is the order of operations, and the
    cost is stability: ``omega dt <= 2`` for every mode (damping, entering
    through ``gamma = 1/2``, does not change the limit).
    """

    name = "central_difference"
    order = 2
    explicit = True

    def check_dt(self, omega, zeta, dt):
        omega_max = float(np.max(np.asarray(omega, dtype=float), initial=0.0))
        if omega_max == 0.0:
            return
        dt_max = 2.0 / omega_max
        if dt > dt_max * (1.0 + 1e-12):  # dt_max itself is accepted, up to rounding
            raise InputError(
                f"dt = {dt:.6g} s exceeds the central difference stability limit "
                f"dt_max = {dt_max:.6g} s = 2/omega_max (omega_max = {omega_max:.6g} rad/s, "
                f"T_min = {2 * math.pi / omega_max:.6g} s = pi dt_max)",
                field="dt",
            )

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        c = 2.0 * zeta * omega
        k = omega * omega
        q1 = q + dt * qd + 0.5 * dt * dt * qdd
        vp = qd + 0.5 * dt * qdd
        qdd1 = (p1 - c * vp - k * q1) / (1.0 + 0.5 * dt * c)
        return q1, vp + 0.5 * dt * qdd1, qdd1
