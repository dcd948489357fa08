"""A third-party hysteresis law, as a plugin author writes one: one module, one class.

A *linear* law whose force is k0 u, so a building of such springs must step exactly as the
elastic one. Registered by passing the class (entry points work the
same way for an installed package: ``[project.entry-points."pounding.hysteresis"]``).
"""

from __future__ import annotations

from pounding.compiler import njit
from pounding.hysteresis.base import HysteresisLaw


@njit
def update(u, v, state, params, new_state, s):
    k0 = params[s, 0]
    r = k0 * (u - 0.0)
    new_state[s, 0] = u
    new_state[s, 1] = r
    new_state[s, 2] = state[s, 2]
    return r, k0, 0.0


@njit
def stored_energy(state, params):
    return 0.5 * state[1] * state[1] / params[0]


class Linear(HysteresisLaw):
    """Force k0 u: never yields (the plugin contract's simplest member)."""

    name = "linear"
    n_params = 3
    n_state = 3
    update = update
    stored_energy = stored_energy

    def __init__(self):
        pass
