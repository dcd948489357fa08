"""A point of a held pair that arrives is an impact: located at its instant and struck with the law.

A pair held in sustained contact is held only at the points that touch (within
:func:`pounding.framework.engine.held.touch_gap` with the ``crossing`` locator). Another point of
the pair that is apart moves freely; where its gap reaches zero inside a step, the driver locates
that instant on the held trajectory with its crossing search, steps there and strikes the pair with
the contact law's impulses over every touching point of the pair (the Newton problem of any
impact), records the impact and books its loss, then finishes the step.

The scene: two single-storey boxes 10 m deep face to face at gap 0 (``exact``, no ground motion),
held. The right slab is turned by 5e-6 rad about its corner A = (10, 0), which touches, so that its
corner B = (10, 10) is 5e-5 m away and closes at about 0.5 m/s (the slab turning back about A),
while A opens slowly (1e-4 m/s, against a closing acceleration of 0.7 m/s^2 from the damping of
the turning slab): until B arrives A stays within the touch gap and keeps opening, so no contact
force acts and the held trajectory is the free motion.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from pounding.framework.engine.bundles import Status
from pounding.framework.engine.driver import Driver
from pounding.framework.post.energy_account import energy_balance, rounding_bound
from pounding.io.ground_motion import GroundMotion
from pounding.io.scene import load_scene

from rounding import dot_abs, solve_rel
from scenes_for_tests import modal_from_physical, scene, side_by_side

STILL = GroundMotion(np.array([0.0, 10.0]), np.zeros(2), name="still", source="test")
PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"

TURN = -5e-6  # [rad] the right slab turned clockwise about A: B = (10, 10) is 10 |TURN| = 5e-5 m away
CLOSING = 0.5  # [m/s] B's closing speed from the slab turning back about A
OPENING = 1e-4  # [m/s] A's opening speed (a translation of the right slab)


def held_pair_with_an_arriving_corner(use_kernel: bool = False, locate: str = "crossing", turn: float = TURN,
                                      closing: float = CLOSING) -> Driver:
    """The module docstring's scene, as a driver at t = 0 with pair 0 held (restitution 0.5); B is
    10 |turn| [m] away and closes at about ``closing`` [m/s]."""
    data = side_by_side(0.0, integrator="exact", contact={"name": "impulse", "locate": locate})
    d = Driver(scene(data).with_ground_motion(STILL), use_kernel=use_kernel)
    w, arm = closing / 10.0, 6.0  # the right slab's turning rate [rad/s]; A to its centre (6, 5) along x
    d.z = np.zeros((d.model.n, 3))
    d.z[:, 0] = modal_from_physical(d.model, {(1, 0): np.array([-turn * 5.0, turn * arm, turn])})
    d.z[:, 1] = modal_from_physical(d.model, {(1, 0): np.array([-w * 5.0 + OPENING, w * arm, w])})
    d.sustained = {0}
    return d


def corner(d: Driver, q: np.ndarray, top: bool):
    """Feature of pair 0 at corner B (``top``: y = 10) or A (y = 0) at modal displacements q: (gap [m], row w (n,))."""
    feats = [f for f in d.model.features(q, 0, 1e-3) if (f.point[1] > 5.0) == top]
    f = min(feats, key=lambda f: f.gap)
    return f.gap, f.w


def free_motion(d: Driver, z0: np.ndarray, t: float) -> np.ndarray:
    """Modal displacements (n,) at t [s] of the unloaded damped modes from state z0 (n, 3), in closed form:
    q(t) = exp(-zeta omega t) (q0 cos(omega_d t) + (v0 + zeta omega q0) / omega_d sin(omega_d t))."""
    om, ze = d.model.omega, d.model.zeta
    od = om * np.sqrt(1.0 - ze**2)
    q0, v0 = z0[:, 0], z0[:, 1]
    return np.exp(-ze * om * t) * (q0 * np.cos(od * t) + (v0 + ze * om * q0) / od * np.sin(od * t))


def strikes(d: Driver) -> list:
    """Watch the driver's strikes of arriving points: a list that fills with (t, v before, v after)."""
    seen = []
    strike = d.strike_arrival

    def watched(t, p):
        before = d.z[:, 1].copy()
        acted = strike(t, p)
        seen.append((t, before, d.z[:, 1].copy()))
        return acted

    d.strike_arrival = watched
    return seen


def test_a_point_that_is_apart_gets_no_force_and_its_arrival_is_reported():
    """B (5e-5 m away, closing at 0.5 m/s) reaches contact 2/3 into a held step of h = 1.5e-4 s. The
    step neither stops it at its start nor pushes it back: its start velocities are the state's, no
    contact force acts (A opens over the whole step: its free end gap is +7e-9 m), and it reports
    B's end gap with the pair: gap0 - b h to within the step's second-order term, |a_B| h^2 / 2 =
    2.6e-8 m with B's relative acceleration a_B = 2.3 m/s^2 (mostly the damping of the turning
    slab), 1e-3 of b h - gap0: bound 1e-2 relative."""
    d = held_pair_with_an_arriving_corner()
    gap0, w = corner(d, d.z[:, 0], top=True)
    b = -(w @ d.z[:, 1])
    assert gap0 == pytest.approx(5e-5, rel=1e-3) and b == pytest.approx(CLOSING, rel=1e-3)
    assert gap0 > d.touch
    h = 1.5 * gap0 / b
    st = d.held_trial(d.z, 0.0, h)
    assert np.array_equal(st.z0[:, 1], d.z[:, 1])
    assert not np.any(st.f0) and not np.any(st.f1)
    assert st.arriving == 0
    assert st.arrival == pytest.approx(gap0 - b * h, rel=1e-2)


@pytest.mark.parametrize("use_kernel", [False, True])
def test_an_arriving_corner_is_struck_where_it_touches_with_the_laws_restitution(use_kernel):
    """B is struck at the instant its gap is zero, not at the step's start: the instant is the root
    of B's gap on the free motion in closed form (A opens, so the held trajectory is the free one
    until the strike), to the locator's resolution: the search stops where |gap| <= eps, the
    geometry's zero, which the closed form's gap also carries, so within 2 eps / b + xtol [s].
    The compiled held stretch hands the step to the driver (OVERLAP at step 0, state and energy
    account as they were). At the strike A takes part as a unilateral constraint (B's impulse
    alone would turn the slab into A): Newton's rule gives B the rebound -k b and stops A (closing
    speed 0), with impulses >= 0 at both; the law's loss is recorded with the impact.
    Rounding: the 2 x 2 Newton problem is a solve with the Delassus matrix D = [w_A; w_B] [w_A; w_B]^T
    (SAFETY n eps cond(D) of its right-hand side, (1 + k) b), and each normal speed a dot product
    over the modes (dot_abs), before and after."""
    d = held_pair_with_an_arriving_corner(use_kernel)
    z_start, E_start = d.z.copy(), d.E.copy()
    if use_kernel:
        d.prepare()
        end = d.advance_held(0, 1)
        assert (end.k, Status(end.status), end.pair) == (0, Status.OVERLAP, 0)
        assert np.array_equal(d.z, z_start) and np.array_equal(d.E, E_start)
    seen = strikes(d)
    d.python_step(0)

    def gap_b(t):
        return corner(d, free_motion(d, z_start, t), top=True)[0]

    guess = 5e-5 / CLOSING
    t_root = brentq(gap_b, 0.5 * guess, 1.5 * guess, xtol=1e-16, rtol=4 * np.finfo(float).eps)
    assert len(seen) == 1
    t, v0, v1 = seen[0]
    q = d.event_states[0][1]
    assert d.event_states[0][0] == t
    _, wb = corner(d, q, top=True)
    _, wa = corner(d, q, top=False)
    b = -(wb @ v0)
    xtol = 1e-14 * max(d.dt, 1.0)
    assert abs(t - t_root) <= 2.0 * d.eps / b + xtol
    assert t > 0.5 * guess  # not at the step's start
    k = d.law.restitution
    Wab = np.stack([wa, wb])
    bound = solve_rel(Wab @ Wab.T) * (1.0 + k) * b + dot_abs(wb, v0) + dot_abs(wb, v1) + dot_abs(wa, v1)
    assert abs((wb @ v1) + k * (wb @ v0)) <= bound
    assert abs(wa @ v1) <= bound
    imps = [imp for imp in d.impacts if imp.time == t]
    assert len(imps) == 2 and all(imp.impulse > 0.0 and imp.pair == 0 for imp in imps)
    top = max(imps, key=lambda imp: imp.point[1])
    assert abs(top.approach_velocity - b) <= 2.0 * dot_abs(wb, v0)  # the driver's dot product and this one
    assert sum(imp.energy_loss for imp in imps) > 0.0
    assert d.sustained == {0}  # still held: the pair is let go only when it opens beyond the tolerance


def test_a_touching_point_that_falls_back_within_the_step_is_projected_taking_energy_out():
    """With B 1e-4 m away closing at 0.05 m/s, A (touching, opening at 1e-4 m/s) would fall back
    below its start within a 5 ms step (the slab's turning reverses its normal acceleration): a
    rebound too short for the step, whose limit is rest. The held step projects A's normal velocity
    out at the start instead of pushing on it while it opens: A's normal speed becomes 0 and the
    kinetic energy falls by the projection's closed form (w_A . v)^2 / (2 w_A . w_A) (mass-normalised
    modes: kinetic energy |v|^2 / 2), no more. Rounding: a few dot products over the modes (dot_abs)."""
    d = held_pair_with_an_arriving_corner(turn=-1e-5, closing=0.05)
    _, wa = corner(d, d.z[:, 0], top=False)
    v = d.z[:, 1].copy()
    st = d.held_trial(d.z, 0.0, d.dt)
    assert wa @ v > 0.0  # A opens at the start
    v0 = st.z0[:, 1]
    assert abs(wa @ v0) <= dot_abs(wa, v0) + dot_abs(wa, v)
    drop = 0.5 * (v @ v) - 0.5 * (v0 @ v0)
    expected = 0.5 * (wa @ v) ** 2 / (wa @ wa)
    assert drop > 0.0
    assert abs(drop - expected) <= dot_abs(v, v) + dot_abs(v0, v0)


def test_the_papers_rules_hold_every_point_within_the_tolerance():
    """With the paper's locator (``halving``) every point of a held pair within the tolerance is held
    (touch = inf): B is not an arrival, the step reports none."""
    d = held_pair_with_an_arriving_corner(locate="halving")
    st = d.held_trial(d.z, 0.0, d.dt)
    assert st.arrival == np.inf and st.arriving == -1


def test_the_paper_pair_strikes_its_arrivals_and_takes_energy_out():
    """The paper pair at 0.03 m with every default (exact, crossing, equilibrium, dt 0.01 s, 15 s of El
    Centro at 0.32 g, k = 0.5): points of held pairs arrive and are struck, and the contact, passive,
    does no positive work over the run (<= the account's rounding bound), so the account is ok."""
    sc = load_scene(PAPER).with_analysis(integrator=None, integrator_params={}, dt=None, contact_params={"restitution": 0.5})
    d = Driver(sc)
    seen = strikes(d)
    result = d.run()
    assert result.dt == 0.01 and result.integrator["name"] == "exact" and result.contact["locate"] == "crossing"
    assert len(seen) > 0
    eb = energy_balance(result)
    assert eb["contact_force_work"] <= rounding_bound(result)
    assert eb["ok"] is True


def test_a_point_is_the_same_contact_where_one_touched_within_how_far_the_slabs_moved():
    """An end feature is a point that touched at the start when a touching start feature of the same
    pair lies within the reach (how far the slabs moved, plus the tolerance): a contact point moves
    with its slabs. A start feature that was apart, one of another pair at the same place in plan
    (another storey), or a point farther than the reach (another corner) is not."""
    from pounding.framework.engine.held import same_contact

    pair0 = np.array([0, 0, 1], dtype=np.int64)
    Q0 = np.array([[10.0, 0.0], [10.0, 10.0], [10.0, 5.0]])
    touching0 = np.array([True, False, True])
    pair1 = np.array([0, 0, 0, 1], dtype=np.int64)
    Q1 = np.array([[10.0, 0.004], [10.0, 9.999], [10.0, 5.0], [10.0, 5.002]])
    kept = same_contact(pair1, Q1, pair0, Q0, touching0, 0.005)
    assert kept.tolist() == [True, False, False, True]
