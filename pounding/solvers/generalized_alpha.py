"""The generalized-alpha method of Chung & Hulbert.

Reference: J. Chung & G. M. Hulbert (1993), A time integration algorithm for
structural dynamics with improved numerical dissipation: the generalized-alpha
method, J. Appl. Mech. 60, 371-375.
"""

from __future__ import annotations

from pounding.errors import InputError
from pounding.solvers.base import Integrator
from pounding.solvers.newmark import alpha_family_maps, alpha_family_transition, alpha_step, real_param


class GeneralizedAlpha(Integrator):
    """Generalized-alpha method parametrised by its high-frequency spectral radius.

    Newmark's updates closed by

        M a_{n+1-alpha_m} + C v_{n+1-alpha_f} + K x_{n+1-alpha_f} = p(t_{n+1-alpha_f}),

    ``y_{n+1-a} = (1 - a) y_{n+1} + a y_n``, with Chung & Hulbert's optimal

        alpha_m = (2 rho_inf - 1)/(rho_inf + 1),  alpha_f = rho_inf/(rho_inf + 1),
        gamma = 1/2 - alpha_m + alpha_f,         beta = (1 - alpha_m + alpha_f)**2 / 4.

    Parameters
    ----------
    rho_inf : float, default 0.8
        Spectral radius as ``omega dt -> inf``, in ``[0, 1]``. ``1`` is
        Newmark's average acceleration (no dissipation); ``0`` annihilates the
        highest modes in one step. Second-order accurate and unconditionally
        stable throughout.

    Notes
    -----
    As with HHT, a mode far above the step's resolution released with its
    equilibrium acceleration shows a first-step velocity spike proportional
    to ``omega dt``, which then decays at the rate ``rho_inf``.
    """

    name = "generalized_alpha"
    order = 2

    def __init__(self, *, rho_inf=0.8):
        rho_inf = real_param(rho_inf, "rho_inf")
        if not 0.0 <= rho_inf <= 1.0:
            raise InputError(f"rho_inf must be in [0, 1]; got {rho_inf}", field="rho_inf")
        self.rho_inf = rho_inf

    @property
    def alpha_m(self) -> float:
        return (2.0 * self.rho_inf - 1.0) / (self.rho_inf + 1.0)

    @property
    def alpha_f(self) -> float:
        return self.rho_inf / (self.rho_inf + 1.0)

    @property
    def gamma(self) -> float:
        return 0.5 - self.alpha_m + self.alpha_f

    @property
    def beta(self) -> float:
        return (1.0 - self.alpha_m + self.alpha_f) ** 2 / 4.0

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        return alpha_step(
            q, qd, qdd, p0, p1, omega, zeta, dt,
            beta=self.beta, gamma=self.gamma, alpha_m=self.alpha_m, alpha_f=self.alpha_f,
        )

    def transition(self, omega, zeta, dt):
        return alpha_family_transition(self, GeneralizedAlpha, omega, zeta, dt, beta=self.beta, gamma=self.gamma, alpha_m=self.alpha_m,
                                       alpha_f=self.alpha_f)

    def search_maps(self):
        return alpha_family_maps(self, GeneralizedAlpha, beta=self.beta, gamma=self.gamma, alpha_m=self.alpha_m, alpha_f=self.alpha_f)
