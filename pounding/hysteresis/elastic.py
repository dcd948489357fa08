"""A linear elastic link: F = k u.

The whole force is the initial elastic part k0 u with k0 = k (kept in the modal model), so the
remainder r - k0 u is exactly zero: a link of this law never loads the stepping's Newton. Nothing is
dissipated; the stored energy is k u^2 / 2. OpenSees: ``uniaxialMaterial Elastic k``; as a contact
(the ``material`` contact law, pushing only) ``ElasticPPGap k -1e30 gap 0 noDamage``.
"""

from __future__ import annotations

from pounding.compiler import njit
from pounding.hysteresis._values import NoYieldLaw, positive


@njit(borrowed=True)
def update(u, v, state, params, new_state, s):
    """Force k u [N], tangent k [N/m], damping tangent 0 of link s at deformation u [m] (v unused);
    ``params[s]`` = (k, 0, 0). Writes ``new_state[s]`` = (u, k u, dissipated unchanged)."""
    k = params[s, 0]
    r = k * u
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2]
    return r, k, 0.0


@njit(borrowed=True)
def stored_energy(state, params):
    """Recoverable energy [J]: k u^2 / 2."""
    return 0.5 * params[0] * state[0] * state[0]


class Elastic(NoYieldLaw):
    """A linear spring, F = k u (see the module docstring); it sets the link's stiffness itself.

    Parameters
    ----------
    stiffness : float
        k [N/m], > 0.
    """

    name = "elastic"
    n_params = 3
    n_state = 3
    schema = {
        "type": "object",
        "additionalProperties": False,
        "required": ["stiffness"],
        "properties": {"stiffness": {"type": "number", "units": "N/m", "description": "Spring stiffness k: F = k u."}},
    }
    update = update
    stored_energy = stored_energy

    def __init__(self, *, stiffness: float):
        self.stiffness = positive("stiffness", stiffness, "the stiffness [N/m]")

    def own_values(self) -> tuple[float, float, float]:
        """(k, 0, 0): the stiffness is the law's; no yield force, no hardening."""
        return self.stiffness, 0.0, 0.0

    def opensees_material(self, ops, tag: int, k0: float, fy: float, b: float, *, tags, boucwen_tol: float) -> None:
        """OpenSees' ``Elastic(k)`` with the law's own k. See :meth:`HysteresisLaw.opensees_material`."""
        ops.uniaxialMaterial("Elastic", tag, self.stiffness)

    def opensees_gap_material(self, params, share: float, clear: float) -> tuple:
        """OpenSees' ``ElasticPPGap E -1e30 gap 0 noDamage`` with E = share k and gap = -clear: share k
        delta where the penetration delta > 0, none elsewhere, the law as a contact (a yield force no
        contact reaches keeps it elastic). See :meth:`HysteresisLaw.opensees_gap_material`."""
        return ("ElasticPPGap", share * float(params[0]), -1e30, -clear, 0.0, "noDamage")
