"""The face rule with shares fixed at rest: where two slabs meet face to face each end of the face
carries half of one contact's law, whichever ends press (:mod:`pounding.framework.engine.face_shares`).

The scenes are :mod:`contact_pair`'s two 3-storey shear buildings pounding face to face under a
half-sine pulse, and a twisting variant of it: the soft building's x springs on its facade line
(y = 0) are 2.5 times those on its far line (y = 10), so its centre of stiffness lies off its centre of mass
and it turns as it sways; its slabs then strike the stiff building's facade at one end first,
press along the whole face, and lift off at one end while the other still presses.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from contact_pair import GAP, _springs, pair_scene, pulse
from pounding.contact.base import ContactState
from pounding.contact.geometry import face_ends, rest_gap
from pounding.contact.hertz import Hertz
from pounding.contact.pointwise import solve_point_forces
from pounding.framework.engine.driver import Model
from pounding.framework.engine.face_shares import rest_face_ends, touching_with_shares
from pounding.framework.post.energy_account import energy_balance, rounding_bound
from pounding.framework.post.run import run
from pounding.io.scene import parse_scene

EPS = np.finfo(float).eps
DT = 1e-3  # [s] the twisting scene's step (the record's sampling)
DURATION = 1.0  # [s]: the pulse (0.6 s) and the contacts that follow it
TOL = 1e-4  # [m] every law's default contact tolerance


def _building(name: str, x0: float, width: float, k_facade, k_far, k_y: float, depth: float = 10.0) -> dict:
    """A 3-storey shear building (as :mod:`contact_pair`'s) with x springs ``k_facade`` on the line y = 0
    and ``k_far`` on y = ``depth``, one spring along y through the centre."""
    x1, xc = x0 + width, x0 + 0.5 * width
    return {"name": name, "storey_heights": [3.2] * 3, "slab": [[x0, 0.0], [x1, 0.0], [x1, depth], [x0, depth]],
            "mass_per_area": 900.0, "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
            "element": [_springs([x0, 0.0], [x1, 0.0], k_facade), _springs([x0, depth], [x1, depth], k_far),
                        _springs([xc, 0.0], [xc, depth], k_y)]}


def twisting_scene(contact, dt: float = DT, duration: float = DURATION):
    """The twisting pair (module docstring) with contact law ``contact`` (a name or a class)."""
    soft = [4.0e7, 3.5e7, 3.0e7]
    stiff = [2.0e8, 1.8e8, 1.5e8]
    data = {"building": [_building("low", 0.0, 15.0, soft, [k / 2.5 for k in soft], 1.2e8),
                         _building("high", 15.0 + GAP, 12.0, stiff, stiff, 4.0e8)],
            "ground_motion": {"record": "elcentro"},
            "analysis": {"integrator": "newmark", "dt": dt, "duration": duration, "contact": "none"}}
    return parse_scene(data).with_ground_motion(pulse(duration)).with_analysis(contact=contact, contact_params={})


def _run(scene):
    """The run and the AnalysisWarnings it gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = run(scene)
    return result, [str(w.message) for w in caught]


def _pressed_states(result):
    """Per output time, the pressed points of every pair: a list of (pair (m,), penetration (m,),
    penetration rate (m,), share (m,), W rows (m, n)) rebuilt from the recorded modal states."""
    ends = rest_face_ends(result.geo)
    plist = np.arange(len(result.pairs), dtype=np.int64)
    n = result.q.shape[1]
    out = []
    for k in range(len(result.t)):
        pair, gap, W, _, _, share = touching_with_shares(result.q[k], plist, TOL, n, result.geo, ends)
        keep = gap < 0
        W = W[keep]
        out.append((pair[keep], -gap[keep], -(W @ result.qd[k]), share[keep], W))
    return out


def _lift_offs(states) -> int:
    """How many times a pair goes from both ends of a face pressed to one end alone in one step."""
    count = 0
    for before, after in zip(states, states[1:]):
        b = np.bincount(before[0], minlength=64)
        a = np.bincount(after[0], minlength=64)
        count += int(np.sum((b == 2) & (a == 1)))
    return count


# ------------------------------------------------------------------------------ the rest faces
def test_the_facing_edges_of_two_rectangles_end_one_face():
    """Two rectangles 0.01 m apart along x: the edge x = 15 of the first (its vertices 1 and 2) faces the
    edge x = 15.01 of the second (its vertices 3 and 0) at the rest gap, so those four vertices end one
    face; the others end none. Turned by 0.1 rad the second has no edge parallel to the first's: no face."""
    A = np.array([[0.0, 0.0], [15.0, 0.0], [15.0, 10.0], [0.0, 10.0]])
    B = np.array([[15.01, 0.0], [27.01, 0.0], [27.01, 10.0], [15.01, 10.0]])
    ends_a, ends_b = face_ends(A, B, 0.01)
    assert ends_a.tolist() == [0, 1, 1, 0] and ends_b.tolist() == [1, 0, 0, 1]
    c, s = np.cos(0.1), np.sin(0.1)
    turned = (B - B.mean(axis=0)) @ np.array([[c, s], [-s, c]]) + B.mean(axis=0) + [1.0, 0.0]
    ends_a, ends_b = face_ends(A, turned, rest_gap(A, turned))
    assert not ends_a.any() and not ends_b.any()


def test_a_face_pressed_flat_carries_one_contacts_force():
    """The reason for the face rule: the soft building's slabs moved along x by the gap plus delta = 2 mm at
    0.1 m/s, the stiff one at rest, every storey's face presses flat at both ends (share 1/2 each, the
    same row). Their forces add up to the law's force of one contact of that penetration and rate,
    F(delta, delta'; m_eff = 1/W_ii), for every law, to rounding: the two ends' penetrations differ from
    delta by the geometry's rounding only (a few eps of the 27 m coordinates, 1e-14 m), which moves
    F ~ delta^n (n <= 1.5, the rate term linear) by n times that relative change, below 1e-10."""
    delta, rate = 2e-3, 0.1
    scene = pair_scene("hertz", DT, 0.1)
    model = Model(scene)
    n = model.n
    q, qd = np.zeros(n), np.zeros(n)
    low = model.systems[0]
    x = np.zeros(low.n_dof)
    x[0::3] = GAP + delta  # every slab of "low" along x, no turn
    sl = slice(int(model.mode_start[0]), int(model.mode_start[0]) + low.n_dof)
    q[sl] = np.linalg.solve(low.modes, x)
    qd[sl] = np.linalg.solve(low.modes, x / (GAP + delta) * rate)
    pair, gap, W, _, _, share = model.touching_shares(q, model.all_pairs, TOL)
    assert np.bincount(pair).tolist() == [2, 2, 2] and share.tolist() == [0.5] * 6
    assert np.allclose(-gap, delta, rtol=0, atol=64 * EPS * 30.0)
    m = len(pair)
    zero = np.zeros((m, m))
    for law in (Hertz(), *(cls(restitution=0.5) for cls in _dissipative_laws())):
        state = ContactState(0.0, DT, gap, W @ qd, zero, zero, W @ W.T, pair, np.zeros(m), np.full(m, rate),
                             np.full(m, np.inf), share)
        lam = law.forces(state)
        for p in range(3):
            one = law.point_force(delta, rate, rate, 1.0 / (W[2 * p] @ W[2 * p]))[0]
            assert lam[pair == p].sum() == pytest.approx(one, rel=1.5 * 64 * EPS * 30.0 / delta), law.name


def _dissipative_laws():
    from pounding.contact.hertzdamp import HertzDamp
    from pounding.contact.jankowski import Jankowski
    from pounding.contact.kelvin import Kelvin

    return Kelvin, HertzDamp, Jankowski
