"""The Hilber-Hughes-Taylor (HHT, "alpha") method.

Reference: H. M. Hilber, T. J. R. Hughes & R. L. Taylor (1977), Improved
numerical dissipation for time integration algorithms in structural dynamics,
Earthquake Eng. Struct. Dyn. 5, 283-292.
"""

from __future__ import annotations

from pounding.errors import InputError
from pounding.solvers.base import Integrator
from pounding.solvers.newmark import alpha_family_maps, alpha_family_transition, alpha_step, real_param


class HHT(Integrator):
    """HHT method in Hilber's convention, with numerical damping of the high modes.

    Not the default: a scene that names no integrator gets ``exact`` or ``newmark``
    (:mod:`pounding.framework.engine.integrator_choice`); the paper's example names ``hht``.

    Newmark's updates with ``beta = (1 - alpha)**2 / 4`` and
    ``gamma = (1 - 2 alpha) / 2``, closed by the shifted equilibrium

        M a_{n+1} + (1 + alpha)(C v_{n+1} + K x_{n+1}) - alpha (C v_n + K x_n)
            = (1 + alpha) p_{n+1} - alpha p_n.

    Parameters
    ----------
    alpha : float, default -0.05
        Hilber's alpha, in ``[-1/3, 0]``. ``0`` is Newmark's average
        acceleration; more negative values damp the high modes more (spectral
        radius at ``omega dt -> inf`` is ``(1 + alpha)/(1 - alpha)``: 0.905 for
        -0.05, 0.5 for -1/3) while staying second-order accurate and
        unconditionally stable. The default -0.05 removes the spurious
        high-frequency content of stiff storeys and of contact with little
        effect on the modes that matter (period elongation ~0.1 % at
        ``omega dt = 0.1``).

    Notes
    -----
    Like generalized-alpha, the method overshoots in velocity on modes far
    above the step's resolution: a mode released from ``q0`` with its
    equilibrium acceleration gets ``q'1 ~ -alpha**2 Omega/(4 beta) omega q0``
    (``Omega = omega dt``) in the first step, which then decays at the rate
    of the spectral radius (Hilber & Hughes, 1978, Earthquake Eng. Struct.
    Dyn. 6, 99-117). Newmark's average acceleration has no such spike.

    OpenSees (``integrator HHT alpha``) weights the *new* state instead: its
    alpha is ``1 + alpha_Hilber``, in ``[2/3, 1]`` (Hilber's -0.05 is
    OpenSees' 0.95).
    """

    name = "hht"
    order = 2

    def __init__(self, *, alpha=-0.05):
        alpha = real_param(alpha, "alpha")
        if not -1.0 / 3.0 <= alpha <= 0.0:
            raise InputError(
                f"alpha must be in [-1/3, 0] (Hilber's convention; OpenSees' alpha is 1 + this); got {alpha}",
                field="alpha",
            )
        self.alpha = alpha

    @property
    def beta(self) -> float:
        return (1.0 - self.alpha) ** 2 / 4.0

    @property
    def gamma(self) -> float:
        return (1.0 - 2.0 * self.alpha) / 2.0

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        return alpha_step(
            q, qd, qdd, p0, p1, omega, zeta, dt, beta=self.beta, gamma=self.gamma, alpha_m=0.0, alpha_f=-self.alpha
        )

    def transition(self, omega, zeta, dt):
        return alpha_family_transition(self, HHT, omega, zeta, dt, beta=self.beta, gamma=self.gamma, alpha_m=0.0, alpha_f=-self.alpha)

    def search_maps(self):
        return alpha_family_maps(self, HHT, beta=self.beta, gamma=self.gamma, alpha_m=0.0, alpha_f=-self.alpha)
