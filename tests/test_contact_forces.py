"""Force-law contact force histories rebuilt from the recorded states (:mod:`pounding.framework.post.contact_forces`).

The scene is :mod:`contact_pair`: two doubly symmetric 3-storey shear buildings pounding face to face
along x (nothing twists, so every contact point's gap is linear in the modal state and its row is
constant). There the law evaluated at a committed state's touching points is exactly the equation the
driver solved at that step's end (its penetrations and rates *with* the forces), so the rebuilt force
is the run's own to the end-of-step Newton tolerance (1e-12 of the force) plus rounding of the gap
(coordinates ~15 m against penetrations ~1e-3 m: ~15 eps / 1e-3 ~ 3e-12 relative, times the law's
exponent <= 1.5): 1e-9 of the peak is a wide margin. Each run takes < 1 s (900 steps of 1 ms).
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_pair import pair_scene
from pounding.framework.post.contact_forces import contact_force_history
from pounding.framework.post.run import run

H = 1e-3  # [s]
DURATION = 0.9  # [s]: the pulse and the first group of episodes (storeys 1-3)
#: the rebuilt force against the run's, relative (module docstring)
AGREEMENT = 1e-9

LAWS = [
    {"name": "kelvin", "restitution": 0.5},
    {"name": "hertz"},
    {"name": "hertzdamp", "restitution": 0.5},
    {"name": "jankowski", "restitution": 0.5},
]


def _run(contact: dict):
    result = run(pair_scene(contact, H, DURATION))
    return result, contact_force_history(result)


@pytest.mark.parametrize("contact", LAWS, ids=lambda c: c["name"])
def test_the_rebuilt_forces_give_each_episodes_peak_force_and_impulse(contact):
    """For every episode, the largest rebuilt force over its steps is the episode's peak force, and its
    trapezoidal integral over the step ends from the one at or before the start to the one at or after
    the end (where the force is zero) is the episode's impulse, the same rule the run uses."""
    result, forces = _run(contact)
    assert len(result.contacts) >= 3
    for e in result.contacts:
        i0 = int(np.floor(e.start / H + 1e-9))
        i1 = int(np.ceil(e.end / H - 1e-9))
        f = forces.pair_force[i0 : i1 + 1, e.pair]
        assert f.max() == pytest.approx(e.peak_force, rel=AGREEMENT)
        assert H * (f.sum() - 0.5 * (f[0] + f[-1])) == pytest.approx(e.impulse, rel=AGREEMENT)
    assert np.all(forces.pair_force >= 0.0)  # no law here pulls


@pytest.mark.parametrize("contact", LAWS[:2], ids=lambda c: c["name"])
def test_the_contact_accelerations_are_the_pair_forces_over_the_masses(contact):
    """Newton's second law floor by floor: the contact part of the floor accelerations, times the floor
    masses and summed along x, is the sum of the pair forces, -x on "low" and +x on "high" (the normal
    points from low to high), at every output time, to rounding of the mode sums (1e-12 of the peak)."""
    result, forces = _run(contact)
    total = forces.pair_force.sum(axis=1)
    for name, sign in (("low", -1.0), ("high", 1.0)):
        s = result.systems[result.names.index(name)]
        mass = np.array([slab.mass for slab in s.slabs])
        push = (forces.floor_acceleration(result, name)[:, :, 0] * mass).sum(axis=1)
        assert np.allclose(push, sign * total, rtol=0, atol=1e-12 * total.max())
