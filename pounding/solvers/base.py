"""The integrator plugin contract.

Why modal coordinates
---------------------
Every damping model a scene can ask for (Rayleigh, modal ratios, stiffness
proportional) is *classical*: the mass-normalised modes Phi of (K, M)
diagonalise M, C and K at once. Every built-in integrator combines M, C and K
linearly, so applying it to the coupled equations

    M x'' + C x' + K x = f(t)

gives, to rounding, the same numbers as applying it mode by mode to

    q_i'' + 2 zeta_i omega_i q_i' + omega_i**2 q_i = p_i(t),   x = Phi q,  p = Phi^T f.

An integrator therefore only has to step a batch of independent single-DOF
oscillators of unit mass. It is linear in its inputs, so one step is the
*transition*

    z1 = A z0 + B[:, 0] p0 + B[:, 1] p1,       z = (q, q', q'')

with per-mode ``A`` (n, 3, 3) and ``B`` (n, 3, 2) that depend on dt only. The
driver builds them once per distinct dt (:class:`TransitionCache`) and a
compiled kernel runs the no-contact stretches with them; the impact locator
asks for any other dt (dt/2, dt/4, or a root finder's trial) the same way.

Contract for an implementer
---------------------------
1. Subclass :class:`Integrator`; set the class attribute ``name`` to the
   registered name, and ``order`` to the order of accuracy.
2. Take parameters keyword-only in ``__init__`` and validate them there,
   raising :class:`pounding.errors.InputError` with ``field`` = the parameter.
3. Implement :meth:`step` vectorised over modes. It must be linear in
   ``(q, qd, qdd, p0, p1)`` and must not keep state between calls.
4. Explicit (conditionally stable) schemes override :meth:`check_dt`.
5. Optionally override :meth:`transition` with a closed form; the default
   probes :meth:`step` with unit inputs (exact, because the step is linear).
   Optionally set ``energy_nodes`` or override :meth:`work_maps` for the energy audit.
6. Optionally override :meth:`partial_transition` and :meth:`partial_work_maps`: the same maps
   for the crossing locator's one-off step lengths (its trials, the parts of a step split at an
   impact), cheaper and equal to rounding (not necessarily to the bit).
7. Optionally override :meth:`search_maps`: a compiled function giving :meth:`partial_transition`'s
   maps and its parameters, with which the impact search runs compiled whole (without it the
   search runs interpreted on :meth:`partial_transition`: the same instants, slower).
8. Register the class under the entry-point group ``pounding.integrators``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np


@dataclass(frozen=True)
class Transition:
    """Per-mode one-step map for a fixed dt.

    Attributes
    ----------
    A : ndarray, shape (n, 3, 3)
        ``z1 = A @ z0`` for the state z = (q [m·kg^0.5], q' , q'') of each mode.
    B : ndarray, shape (n, 3, 2)
        Response of z1 to the modal load at the start (column 0) and at the
        end (column 1) of the step, per unit load [N/kg^0.5].
    dt : float
        Step size [s].
    """

    A: np.ndarray
    B: np.ndarray
    dt: float


class Integrator(ABC):
    """A one-step method for uncoupled unit-mass modal oscillators.

    Subclasses provide :meth:`step`; see the module docstring for the contract.
    """

    name: ClassVar[str] = ""
    order: ClassVar[int] = 2
    explicit: ClassVar[bool] = False
    #: Gauss-Legendre points per step for the energy audit's work integrals, on the
    #: scheme's own intra-step trajectory; 0 = trapezoidal rule on step-end values,
    #: which is the exact discrete identity of average acceleration. A scheme that
    #: defines ``work_maps(omega, zeta, dt) -> (a1, a2, M)`` (closed-form work
    #: integrals of its intra-step trajectory, see :meth:`pounding.solvers.exact.Exact.work_maps`)
    #: is audited with those instead.
    energy_nodes: ClassVar[int] = 0
    #: True when the scheme's transition over any part of a step is the exact solution of the modal
    #: equations under the linear load (:class:`pounding.solvers.exact.Exact`): its intra-step
    #: trajectory then gives the true peaks. A subclass that changes :meth:`partial_transition`
    #: declares False.
    exact_within_step: ClassVar[bool] = False

    def work_maps(self, omega: np.ndarray, zeta: np.ndarray, dt: float):
        """Closed-form work integrals of the scheme's intra-step trajectory, or None (the default:
        the audit uses ``energy_nodes``). When given: (a1 (n, 4), a2 (n, 4), M (n, 4, 4)) with
        x = (q0, q'0, p0, p1): int q' = a1 x, int s q' = a2 x, int q'^2 = x M x over the step."""
        return None

    @abstractmethod
    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        """Advance every mode by one step.

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (n,) or (n, k)
            Modal displacement, velocity and acceleration at the start of the step.
            A trailing axis of probes may be present; broadcast over it.
        p0, p1 : ndarray, shape like q
            Modal load per unit modal mass at the start and the end of the step;
            the load varies linearly in between.
        omega : ndarray, shape (n,) or (n, 1)
            Circular frequencies [rad/s] (may be 0 for a rigid-body mode).
        zeta : ndarray, shape like omega
            Damping ratios [-].
        dt : float
            Step size [s].

        Returns
        -------
        (q1, qd1, qdd1) : tuple of ndarray
            The state at the end of the step.
        """

    def check_dt(self, omega: np.ndarray, zeta: np.ndarray, dt: float) -> None:
        """Raise ``InputError`` if ``dt`` is outside the method's stability range."""

    def transition(self, omega: np.ndarray, zeta: np.ndarray, dt: float) -> Transition:
        """Build the per-mode transition for this dt by probing :meth:`step`.

        Five probes (unit q, q', q'', p0, p1) recover the exact linear map.
        """
        omega = np.asarray(omega, dtype=float)
        zeta = np.asarray(zeta, dtype=float)
        self.check_dt(omega, zeta, dt)
        n = omega.shape[0]
        eye = np.eye(5)
        probes = [np.broadcast_to(eye[k], (n, 5)).copy() for k in range(5)]
        q1, qd1, qdd1 = self.step(*probes, omega[:, None], zeta[:, None], float(dt))
        out = np.stack([q1, qd1, qdd1], axis=1)  # (n, 3, 5)
        return Transition(A=np.ascontiguousarray(out[:, :, :3]), B=np.ascontiguousarray(out[:, :, 3:]), dt=float(dt))

    def partial_transition(self, omega: np.ndarray, zeta: np.ndarray, dt: float) -> Transition:
        """:meth:`transition` for a one-off step length of a contact event (crossing locator). The
        default is :meth:`transition` itself; an override must equal it to rounding."""
        return self.transition(omega, zeta, dt)

    def partial_work_maps(self, omega: np.ndarray, zeta: np.ndarray, dt: float):
        """:meth:`work_maps` for a one-off step length of a contact event (crossing locator); the
        default is :meth:`work_maps` itself; an override must equal it to rounding."""
        return self.work_maps(omega, zeta, dt)

    def search_maps(self):
        """The compiled maps of a one-off step length, for the impact search compiled whole
        (:func:`pounding.framework.engine.event_search.locate`): ``(maps, params)`` with ``maps`` a
        compiled function ``(omega (n,), zeta (n,), dt, params) -> (A (n, 3, 3), B (n, 3, 2))``
        giving :meth:`partial_transition`'s numbers (the same function it calls, so the same bits)
        and ``params`` its float64 parameters; or None (the default), where the search runs
        interpreted on :meth:`partial_transition`."""
        return None

    def describe(self) -> dict:
        """Name and parameters, as written to summary.json."""
        params = {k: v for k, v in vars(self).items() if not k.startswith("_")}
        return {"name": self.name, **params}


class TransitionCache:
    """Transitions of one integrator for one set of modes, built once per distinct dt.

    Step sizes are keyed by their float value: the driver only asks for dt,
    dt/2**k, and the remainders of a located step, so the set stays small.
    With ``partial`` (the crossing locator), every step length but ``grid_dt`` is built by
    :meth:`Integrator.partial_transition`.
    """

    def __init__(self, integrator: Integrator, omega: np.ndarray, zeta: np.ndarray, *, grid_dt: float | None = None,
                 partial: bool = False):
        self.integrator = integrator
        self.omega = np.ascontiguousarray(omega, dtype=float)
        # per mode, like omega (a scalar damping ratio is every mode's)
        self.zeta = np.array(np.broadcast_to(np.asarray(zeta, dtype=float), self.omega.shape))  # (a writable copy)
        self.grid_dt = grid_dt
        self.partial = partial
        self._cache: dict[float, Transition] = {}

    def __call__(self, dt: float) -> Transition:
        dt = float(dt)
        tr = self._cache.get(dt)
        if tr is None:
            if self.partial and dt != self.grid_dt:
                tr = self.integrator.partial_transition(self.omega, self.zeta, dt)
            else:
                tr = self.integrator.transition(self.omega, self.zeta, dt)
            if len(self._cache) > 256:  # a root finder's trials are used once; keep memory bounded
                self._cache.clear()
            self._cache[dt] = tr
        return tr
