"""The graze screen's memories (pounding.framework.engine.crossing.suspect_step) change its cost, not its answers.

Along a stretch of steps the compiled kernel keeps, per pair, the last exact gap it computed (with the
slabs' displacements then) and the nearest feature's gap and rate at the last step's end. Two facts make
that safe, one per test:

* the gap bounded from a remembered state (``moved_bound``) is a lower bound on the signed gap: every
  point of a slab moves between two states by its centre's translation plus at most R times the
  change of rotation (the rest-state bound's proof with another reference state);
* with both memories, the screen answers every step of a stretch as the memoryless screen does.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.contact.geometry import ccw, displaced, radius, signed_gap
from pounding.framework.engine import crossing as cr
from pounding.framework.engine.stacked_model import Model
from scenes_for_tests import modal_from_physical, scene, side_by_side

# an L-shaped slab and a rectangle beside its re-entrant corner: the axis separation bound is far
# below their gap there, which is where the remembered gap decides
L_SLAB = ccw(np.array([[0.0, 0.0], [20.0, 0.0], [20.0, 8.0], [8.0, 8.0], [8.0, 20.0], [0.0, 20.0]]))
RECT = ccw(np.array([[9.0, 9.0], [19.0, 9.0], [19.0, 19.0], [9.0, 19.0]]))


def _centre(P):
    return np.mean(P, axis=0)


def test_the_gap_bounded_from_a_remembered_state_never_exceeds_the_gap():
    """Random pairs of states (translations up to 0.4 m, rotations up to 0.01 rad): the bound is at most
    the signed gap, to the rounding of the polygon distance (1e-12 m of coordinates of 20 m)."""
    rng = np.random.default_rng(7)
    ca, cb = _centre(L_SLAB), _centre(RECT)
    Ra, Rb = radius(L_SLAB, ca), radius(RECT, cb)
    decided = 0
    for _ in range(2000):
        ref_a, ref_b = rng.uniform(-1, 1, 3) * (0.4, 0.4, 0.01), rng.uniform(-1, 1, 3) * (0.4, 0.4, 0.01)
        g_ref = signed_gap(displaced(L_SLAB, ca, *ref_a), displaced(RECT, cb, *ref_b))
        if g_ref < 0.0:
            continue
        now_a = ref_a + rng.uniform(-1, 1, 3) * (0.2, 0.2, 0.005)
        now_b = ref_b + rng.uniform(-1, 1, 3) * (0.2, 0.2, 0.005)
        bound = cr.moved_bound(np.concatenate([[g_ref], ref_a, ref_b]), now_a, now_b, Ra, Rb)
        g = signed_gap(displaced(L_SLAB, ca, *now_a), displaced(RECT, cb, *now_b))
        assert bound <= g + 1e-12
        decided += bound > 0.0
    assert decided > 100  # the bound is informative, not vacuously below every gap


@pytest.fixture(scope="module")
def model():
    return Model(scene(side_by_side(0.05, storeys=(1, 1))))


def _stretch(model, steps=400, h=0.005):
    """States (q, q', q'') of a stretch where the right slab swings towards the left one and away:
    u = 0.06 sin(w t) - 0.02, phi = 4e-3 sin(1.7 w t), w = 2 pi / 0.8 s (the gap closes within the
    reach of some steps and opens again)."""
    w = 2.0 * np.pi / 0.8
    z = []
    for k in range(steps + 1):
        t = k * h
        u, ud, udd = 0.06 * np.sin(w * t) - 0.02, 0.06 * w * np.cos(w * t), -0.06 * w * w * np.sin(w * t)
        a = 1.7 * w
        p, pd, pdd = 4e-3 * np.sin(a * t), 4e-3 * a * np.cos(a * t), -4e-3 * a * a * np.sin(a * t)
        q = [modal_from_physical(model, {(1, 0): (-x, 0.0, r)}) for x, r in ((u, p), (ud, pd), (udd, pdd))]
        z.append(np.ascontiguousarray(np.stack(q, axis=1)))
    return z, h


def test_the_screen_with_memories_answers_every_step_as_without(model):
    """Step for step the same booleans; the memories were used (a remembered gap or rate was there
    to read at some steps), and some steps are suspected."""
    z, h = _stretch(model)
    eps, tol = 1e-6, 1e-4
    rates, gaps = np.full((1, 3), -1.0), np.full((1, 7), np.nan)
    plain, memo, remembered = [], [], 0
    for k in range(len(z) - 1):
        remembered += int(gaps[0, 0] >= 0.0 or rates[0, 0] == k)
        plain.append(bool(cr.suspect(z[k], z[k + 1], 0, h, eps, tol, model.geo)))
        memo.append(bool(cr.suspect_step(z[k], z[k + 1], 0, h, eps, tol, model.geo, k, rates, gaps)))
    assert memo == plain
    assert any(plain) and remembered > 10
