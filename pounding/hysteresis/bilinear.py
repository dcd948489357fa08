"""Bilinear kinematic hardening: OpenSees' Steel01 without isotropic hardening.

The force stays between two bounds parallel to the post-yield branch,

    b k0 u - (1 - b) Fy  <=  r  <=  b k0 u + (1 - b) Fy,

and moves with the initial stiffness k0 in between. The trial force is the
elastic trial from the committed state clipped to the bounds, exactly
``Steel01::determineTrialState`` with a1 = a3 = 0 (no shift of the bounds),
written through the plastic deformation u_p = u - r / k0 so that a spring that
never yielded has u_p = 0 exactly and r = k0 u bit for bit.

Energy: with the back force H u_p, H = b k0 / (1 - b), the yield surface is
|r - H u_p| = Fy, the stored energy r^2 / (2 k0) + H u_p^2 / 2, and the
dissipation Fy |d u_p|: exact over a step, in which u_p moves one way only.
A symmetric stabilised loop between -u_max and u_max (u_max > u_y = Fy/k0)
dissipates 4 Fy (1 - b) (u_max - u_y).

As a contact (the ``material`` contact law: the law acting on the penetration, pushing only) the
law loads elastically from its plastic set u_p to the upper bound, unloads elastically and parts at
u_p, which it keeps for the next touch: OpenSees' ``ElasticPPGap`` with ``damage``, whose backbone
is the same line and whose gap grows by the same set (:meth:`Bilinear.opensees_gap_material`). The
two part ways only where the lower bound is reached while the contact still pushes, b k0 u_p >
(1 - b) Fy: a penetration beyond (1 + 1/b) Fy / k0 (:meth:`Bilinear.opensees_gap_notes`).

References: F. Filippou, E. Popov, V. Bertero (1983), UCB/EERC-83/19 (the
Steel01 bounds); OpenSees ``SRC/material/uniaxial/Steel01.cpp``.
"""

from __future__ import annotations

from pounding.compiler import njit
from pounding.hysteresis.base import HysteresisLaw

#: law-specific state slot: the plastic deformation u_p [m]
PLASTIC = 3


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Trial force [N], tangent [N/m] and damping tangent [N s/m] (zero: rate-independent) of link s
    at deformation u [m] and rate v [m/s] from its committed state ``state[s]`` = (u, r, dissipated,
    u_p); ``params[s]`` = (k0, Fy, b). Writes ``new_state[s]``."""
    k0 = params[s, 0]
    fy = params[s, 1]
    b = params[s, 2]
    up0 = state[s, PLASTIC]
    trial = k0 * (u - up0)
    reach = (1.0 - b) * fy
    upper = b * k0 * u + reach
    lower = b * k0 * u - reach
    if trial > upper:
        r = upper
        tangent = b * k0
        up = u - r / k0
    elif trial < lower:
        r = lower
        tangent = b * k0
        up = u - r / k0
    else:
        r = trial
        tangent = k0
        up = up0
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2] + fy * abs(up - up0)
    new_state[s, PLASTIC] = up
    return r, tangent, 0.0


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: elastic r^2/(2 k0) plus hardening H u_p^2 / 2, H = b k0 / (1 - b)."""
    k0 = params[0]
    b = params[2]
    h = b * k0 / (1.0 - b)
    return 0.5 * state[1] * state[1] / k0 + 0.5 * h * state[PLASTIC] * state[PLASTIC]


class Bilinear(HysteresisLaw):
    """Bilinear kinematic hardening (Steel01 without isotropic hardening); no parameters of its own.

    The scene gives k0 (``stiffness``), Fy (``yield_force``) and b (``hardening``, in [0, 1)).
    """

    name = "bilinear"
    n_params = 3
    n_state = 4
    update = update
    stored_energy = stored_energy

    def __init__(self):
        pass

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``Steel01(Fy, k0, b)``: the same kinematic hardening (its isotropic hardening a1..a4
        left at 0). See :meth:`HysteresisLaw.opensees_material`."""
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)

    def opensees_gap_material(self, params, share: float, clear: float) -> tuple:
        """OpenSees' ``ElasticPPGap E Fy gap eta damage`` with E = share k0 and its Fy = -share Fy
        (negative: compression; the law is homogeneous in (k0, Fy): s r(u; k0, Fy, b) = r(u; s k0, s Fy, b)),
        gap = -clear, eta = b and ``damage``: it loads elastically from its gap to the line
        Fy + b k0 (delta - Fy / k0) (the upper bound from a virgin state: the line is fixed in both),
        and on commit past it moves its gap to the deformation where the force unloads elastically to
        zero, the plastic set, which ``damage`` keeps while the contact is open (``noDamage`` would
        move the gap back as the surfaces part). See :meth:`HysteresisLaw.opensees_gap_material` and
        :meth:`opensees_gap_notes`."""
        k0, fy, b = (float(x) for x in params[:3])
        return ("ElasticPPGap", share * k0, -share * fy, -clear, b, "damage")

    def opensees_gap_notes(self, params) -> list[str]:
        """With hardening, the lower bound that ``ElasticPPGap`` does not have (module docstring)."""
        k0, fy, b = (float(x) for x in params[:3])
        if b <= 0.0:
            return []
        return [f"its bilinear material (kinematic hardening, b = {b:g}) reaches its lower bound while it still pushes "
                f"after a penetration beyond (1 + 1/b) Fy / k0 = {(1.0 + 1.0 / b) * fy / k0:.3g} m, and then unloads "
                "along b k0 to a smaller plastic set, where ElasticPPGap unloads elastically to its set: the two agree "
                "at smaller penetrations"]
