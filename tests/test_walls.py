"""Retaining walls fixed to the ground (``[[wall]]``): a slab striking a body that never moves.

The scene: one storey (a single rigid slab of mass M on springs of total stiffness K along x, split
on the two x lines so that nothing twists), no damping, a wall face ``GAP`` to the left of the slab.
From rest, a constant ground acceleration A0 along +x loads the slab by -M A0: undamped, it swings
towards the wall as u(t) = -(A0 / w^2) (1 - cos w t), w = sqrt(K / M), and meets the face (u = -GAP)
at t* = arccos(1 - GAP w^2 / A0) / w with speed b = (A0 / w) sin(w t*). The wall has infinite mass:
Newton's rule sends the slab back at e b (one impulse (1 + e) M b, shared by the face's two ends),
and the impact removes (1 - e^2) M b^2 / 2, all of it from the slab's building.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.engine.driver import Driver
from pounding.io.ground_motion import GroundMotion
from pounding.io.scene import load_scene, parse_scene

EPS = np.finfo(float).eps
M = 1.0e5  # [kg] the slab
K = 4.0e6  # [N/m] along x (w = sqrt(40) rad/s, T = 0.99 s)
A0 = 2.0  # [m/s^2] the ground's constant acceleration, along +x
GAP = 0.02  # [m] clear distance from the slab's left edge (x = 0) to the wall's face
W = np.sqrt(K / M)
T_HIT = np.arccos(1.0 - GAP * W**2 / A0) / W  # [s] the closed-form instant of the first impact
B_HIT = A0 / W * np.sin(W * T_HIT)  # [m/s] the closing speed then


def _springs(start, end, k) -> dict:
    return {"type": "storey_springs", "start": start, "end": end, "stiffness": k, "storeys": 1}


def _box(name: str = "box", x0: float = 0.0, storeys: int = 1) -> dict:
    x1 = x0 + 10.0
    return {"name": name, "storey_heights": [1.0] * storeys, "slab": [[x0, 0.0], [x1, 0.0], [x1, 8.0], [x0, 8.0]], "mass": M,
            "damping": {"type": "modal", "ratio": 0.0},
            "element": [_springs([x0, 0.0], [x1, 0.0], K / 2), _springs([x0, 8.0], [x1, 8.0], K / 2),
                        _springs([x0 + 5.0, 0.0], [x0 + 5.0, 8.0], K)]}


def _data(restitution: float = 0.5, wall_contact=None, duration: float = 0.6) -> dict:
    wall = {"name": "moat", "face": [[-GAP, -1.0], [-GAP, 9.0]], "top": 1.0}
    if wall_contact is not None:
        wall["contact"] = wall_contact
    return {"building": [_box()], "ground_motion": {"record": "elcentro"},
            "analysis": {"dt": 0.01, "duration": duration, "contact": {"name": "impulse", "restitution": restitution}},
            "wall": [wall]}


def _run(data: dict):
    step = GroundMotion(np.array([0.0, 10.0]), np.array([A0, A0]), name="step", source="test")
    scene = parse_scene(data).with_ground_motion(step)
    driver = Driver(scene)
    return driver, driver.run()


def _free(t0: float, u0: float, v0: float, t: np.ndarray):
    """(u, v) at times t [s] of the undamped slab under the load -M A0 from (u0 [m], v0 [m/s]) at t0."""
    tau, ust = t - t0, -A0 / W**2
    return (ust + (u0 - ust) * np.cos(W * tau) + v0 / W * np.sin(W * tau),
            -(u0 - ust) * W * np.sin(W * tau) + v0 * np.cos(W * tau))


# --------------------------------------------------------------------------- (a) the rigid-wall limit
@pytest.mark.parametrize("e, wall_contact", [(0.5, None), (0.8, {"restitution": 0.8})], ids=["scene's law", "wall's own restitution"])
def test_slab_rebounds_from_the_wall_at_minus_e_times_its_speed_at_the_closed_form_instant(e, wall_contact):
    """The first impact comes at t* with closing speed b (module docstring); after it the slab moves freely
    from (-GAP, +e b) at t*, so its displacement and velocity at every output time up to the next impact
    are the closed form's. The scene's impulse law has e = 0.5; the second case gives the wall its own
    restitution 0.8 (``contact = { restitution = 0.8 }``).

    Tolerances: the crossing locator puts the instant where the gap is zero to ``driver.eps`` (the
    geometry's zero), so t is within eps / b of t*; the exact integrator adds rounding of the
    amplitude (A0 / w^2) per step, 64 eps over the 30 steps compared. The state after carries the
    time error times the velocity jump (1 + e) b: eps (1 + e) in displacement, w times that in velocity.
    """
    driver, result = _run(_data(0.5, wall_contact))
    first = [i for i in result.impacts if i.time == result.impacts[0].time]
    assert {result.struck_building(i) for i in first} == {"moat"} and len(first) == 2  # the face's two ends
    t_i = first[0].time
    dt_tol = driver.eps / B_HIT + 64 * EPS * T_HIT
    assert abs(t_i - T_HIT) <= dt_tol
    assert all(abs(i.approach_velocity - B_HIT) <= W * A0 / W * dt_tol + 64 * EPS * B_HIT for i in first)
    # the impulse: (1 + e) M b, on the slab alone (the wall's mass is infinite)
    assert sum(i.impulse for i in first) == pytest.approx((1.0 + e) * M * B_HIT, rel=1e-9)
    later = [i.time for i in result.impacts if i.time > t_i]
    assert later, "the slab comes back to the wall"
    k = (result.t > t_i) & (result.t < later[0])
    u_cl, v_cl = _free(T_HIT, -GAP, e * B_HIT, result.t[k])
    cm = result.cm("box")[k, 0]
    vel = result.cm("box", velocity=True)[k, 0]
    amp = A0 / W**2 + GAP
    assert np.max(np.abs(cm[:, 0] - u_cl)) <= (1.0 + e) * driver.eps + 64 * EPS * amp
    assert np.max(np.abs(vel[:, 0] - v_cl)) <= W * ((1.0 + e) * driver.eps + 64 * EPS * amp)
    # nothing turns or moves across: the wall's normal is -x
    assert np.max(np.abs(cm[:, 1:])) <= 64 * EPS * amp


# --------------------------------------------------------------------------- (b) momentum and energy
def test_a_wall_impact_changes_the_buildings_momentum_by_the_impulse_and_books_its_loss_in_its_account():
    """Across the first impact the slab's momentum M u' jumps by the impulse along the wall's normal:
    M (v+ - v-) = sum I_j (n_j . x) with n from the slab to the wall (-x), so +sum I_j, v- the closed
    form's -b and v+ read from the run's state at the next output time carried back to the instant by
    the free motion (exact). The energy the impact removes, (1 - e^2) M b^2 / 2 [J], is the sum of the
    impacts' losses, and the building's own account books it as the work of the impulses on it
    (``impacts`` = -loss: the wall stores none), its balance closing to rounding.

    Tolerances: the instant to eps / b (test above); the carried-back velocity to 64 eps of w times the
    amplitude; the account closes to :func:`rounding_bound`-sized sums (1e-9 of the input here, a few
    hundred bookings of 1 mode).
    """
    from pounding.framework.post.energy_account import building_balances

    e = 0.5
    driver, result = _run(_data(e, duration=0.25))  # up to the first impact and a little after
    assert len({i.time for i in result.impacts}) == 1
    t_i = result.impacts[0].time
    k = int(np.argmax(result.t > t_i))
    u_k, v_k = result.cm("box")[k, 0, 0], result.cm("box", velocity=True)[k, 0, 0]
    _, v_after = _free(result.t[k], u_k, v_k, np.array([t_i]))
    impulse_x = sum(-i.impulse * i.normal[0] for i in result.impacts)
    tol = M * (W * A0 / W * (driver.eps / B_HIT) * (2.0 + e) + 64 * EPS * W * (A0 / W**2 + GAP))
    assert abs(M * (v_after[0] - (-B_HIT)) - impulse_x) <= tol
    loss = 0.5 * (1.0 - e**2) * M * B_HIT**2
    assert sum(i.energy_loss for i in result.impacts) == pytest.approx(loss, rel=1e-9)
    account = building_balances(result)["box"]
    assert account["impacts"] == pytest.approx(-loss, rel=1e-9)
    assert abs(account["error"]) <= 1e-9 * account["input"]


# --------------------------------------------------------------------------- the scene
def test_a_wall_in_the_gap_between_two_buildings_loads_and_each_strikes_its_own_side():
    """A wall standing in the gap between two one-storey buildings (its top at their slabs) does not
    overlap either: the scene loads, and each building's slab is paired with a fixed rectangle behind
    the face on the side away from it, its rest gap the distance to the face."""
    data = _data()
    data["building"] = [_box("left", -10.5), _box("right", 0.5)]
    data["wall"][0]["face"] = [[0.0, -1.0], [0.0, 9.0]]
    scene = parse_scene(data)
    from pounding.framework.engine.stacked_model import Model

    m = Model(scene)
    on_wall = {m.pairs[p][0]: m.pairs[p][4] for p in m.walls}
    assert on_wall == {0: pytest.approx(0.5, abs=1e-12), 1: pytest.approx(0.5, abs=1e-12)}


def test_scene_with_walls_is_written_and_read_back_equal(tmp_path):
    """write_scene then load_scene gives the same walls (name, face, top, law and parameters), the
    [[contact]] tables too."""
    from pounding.io.scene_writer import scene_differences, write_scene

    data = _data()
    data["analysis"]["contact"] = {"name": "penalty", "stiffness": 2e9}
    data["wall"][0]["contact"] = {"name": "kelvin", "stiffness": 1e9, "restitution": 0.5}
    data["wall"].append({"name": "kerb", "face": [[-1.0, 10.0], [11.0, 10.0]], "top": 0.5})
    scene = parse_scene(data)
    back = load_scene(write_scene(scene, tmp_path / "scene.toml"))
    assert scene_differences(scene, back) == []
    assert [w.name for w in back.walls] == ["moat", "kerb"]


# --------------------------------------------------------------------------- (d) bad input
BAD = [
    ("face cuts a storey", {"face": [[5.0, -1.0], [5.0, 9.0]]}, "wall[0].face", "cuts the space of storey 1 of 'box'"),
    ("top not positive", {"top": 0.0}, "wall[0].top", "expected a number > 0"),
    ("one point", {"face": [[-1.0, 0.0]]}, "wall[0].face", "at least 2 items"),
    ("zero-length segment", {"face": [[-1.0, 0.0], [-1.0, 0.0], [-1.0, 5.0]]}, "wall[0].face", "nonzero length"),
    ("law out of range", {"contact": {"name": "impulse", "restitution": 1.5}}, "wall[0].contact.restitution", "[0, 1]"),
    ("own restitution out of range", {"contact": {"restitution": -0.1}}, "wall[0].contact.restitution", "[0, 1]"),
    ("unknown law parameter", {"contact": {"name": "impulse", "stifness": 1e9}}, "wall[0].contact.stifness", "unknown"),
    ("name of a building", {"name": "box"}, "wall[0].name", "a building's name"),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_wall_is_one_message_naming_file_field_and_what_was_expected(tmp_path, case):
    """Each defect of a [[wall]] table: one InputError naming the scene file, the key path and what was expected."""
    from pounding.io.scene_writer import to_toml

    _, change, field, words = case
    data = _data()
    data["wall"][0].update(change)
    path = tmp_path / "scene.toml"
    path.write_text(to_toml(data))
    with pytest.raises(InputError) as exc:
        load_scene(path)
    text = str(exc.value)
    assert str(path) in text and field in text and words in text, text


def test_cli_refuses_a_wall_through_a_storey_in_one_line_exit_2_nothing_written(tmp_path):
    """``pounding run`` of a scene whose wall cuts a storey: one line on stderr, exit code 2, no output folder."""
    from pounding.io.scene_writer import to_toml

    data = _data()
    data["wall"][0]["face"] = [[5.0, -1.0], [5.0, 9.0]]
    path = tmp_path / "scene.toml"
    path.write_text(to_toml(data))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "wall[0].face" in proc.stderr
    assert not out.exists()


# --------------------------------------------------------------------------- (e) the gap study
def test_gap_study_reports_the_clearance_to_each_wall_the_peak_displacement_toward_it():
    """Without contact the undamped slab swings to u = -2 A0 / w^2 (at t = pi / w) and never moves toward
    +x: the clearance it needs to the wall on its left is 2 A0 / w^2, to a wall on its right 0, whatever
    their distances at rest (GAP and 0.3 m, reported as they are). The moat has a force law of its own,
    which the free run turns off with the scene's.

    Tolerance: the study takes the peak over the step ends (dt = 0.01 s); the nearest is within dt / 2
    of pi / w, where the closed form falls short by (A0 / w^2)(1 - cos(w dt / 2)) <= (A0 / w^2)(w dt)^2 / 8.
    """
    from pounding.framework.studies.wall_gap import wall_gaps

    data = _data(duration=0.8)
    data["analysis"]["contact"] = {"name": "penalty", "stiffness": 1e9}  # the moat's own law below: contact off in the free run too
    data["wall"][0]["contact"] = {"name": "kelvin", "stiffness": 1e9}
    data["wall"].append({"name": "east", "face": [[10.3, 9.0], [10.3, -1.0]], "top": 1.0})
    step = GroundMotion(np.array([0.0, 10.0]), np.array([A0, A0]), name="step", source="test")
    out = {c.wall: c for c in wall_gaps(parse_scene(data).with_ground_motion(step))}
    peak, dt = 2.0 * A0 / W**2, 0.01
    assert out["moat"].required <= peak + 64 * EPS * peak
    assert out["moat"].required >= peak - (A0 / W**2) * (W * dt) ** 2 / 8
    assert abs(out["moat"].time - np.pi / W) <= dt / 2 + 1e-12
    assert out["moat"].current == pytest.approx(GAP, abs=1e-12) and not out["moat"].ok  # 0.02 m < 0.2 m: it strikes
    assert out["east"].required == 0.0 and out["east"].current == pytest.approx(0.3, abs=1e-12) and out["east"].ok


def _row_between_walls() -> dict:
    """Two boxes in a row along x, 0.3 m apart, a wall 0.3 m beyond each end."""
    data = _data(duration=0.2)
    data["building"] = [_box("west"), _box("east", x0=10.3)]
    data["wall"] = [{"name": "w", "face": [[-0.3, -1.0], [-0.3, 9.0]], "top": 1.0},
                    {"name": "e", "face": [[20.6, 9.0], [20.6, -1.0]], "top": 1.0}]
    return data


def test_a_building_behind_its_neighbour_is_not_watched_against_the_wall_beyond_it():
    """Each wall of :func:`_row_between_walls` faces only the box beside it: the box behind would strike
    its neighbour before it could reach the wall (the path from its slab to the face passes through the
    neighbour's slab at the same level), so the engine watches each wall against the near box alone."""
    driver, _ = _run(_row_between_walls())
    watched = sorted((wall.name, driver.model.pairs[p][0]) for p, wall in driver.model.walls.items())
    assert watched == [("e", 1), ("w", 0)]


def test_a_law_that_switches_contact_off_under_a_name_of_its_own_builds_no_wall_pair():
    """The model asks the run's contact law whether it watches slab pairs
    (:meth:`~pounding.contact.base.ContactLaw.watches`), never its name: a law of a third party that
    declares neither impulses at events nor forces with the step, passed as a class, gets no wall
    slab and no slab pair at all, as the ``none`` law does."""
    from pounding.contact.base import ContactLaw

    class Off(ContactLaw):
        name = "switched_off"
        kind = "none"

    step = GroundMotion(np.array([0.0, 10.0]), np.array([A0, A0]), name="step", source="test")
    scene = parse_scene(_row_between_walls()).with_ground_motion(step).with_analysis(contact=Off, contact_params={})
    driver = Driver(scene)
    assert driver.model.walls == {} and driver.kgeo.pa.shape[0] == 0


def test_a_building_behind_its_neighbour_asks_no_clearance_of_the_wall_beyond_it():
    """The gap study of :func:`_row_between_walls` has one clearance per wall, the near box's (the box
    behind is screened by it), and its rest distance is the near box's 0.3 m."""
    from pounding.framework.studies.wall_gap import wall_gaps

    step = GroundMotion(np.array([0.0, 10.0]), np.array([A0, A0]), name="step", source="test")
    out = wall_gaps(parse_scene(_row_between_walls()).with_ground_motion(step))
    assert sorted((c.wall, c.building) for c in out) == [("e", "east"), ("w", "west")]
    assert all(c.current == pytest.approx(0.3, abs=1e-12) for c in out)


# --------------------------------------------------------------------------- (c) against OpenSees
def _isolated_beside_a_moat() -> dict:
    """A base-isolated building (storey 1: lead-rubber isolators, bilinear storey springs of 4e6 N/m
    per line yielding at 1e5 N, 10 % hardening; two storeys of elastic springs above, first_storey = 2),
    symmetric about its x axis, 5 % Rayleigh damping (modes 1, 3); a moat wall 0.05 m from its base slab
    (top 1.0 m, the base slab's level) with a Kelvin law of its own (1e9 N/m, e = 0.5, tension: OpenSees'
    ViscoelasticGap), [analysis] contact a penalty law (nothing else to strike). El Centro at 0.5 g along
    x for 3 s, Newmark average acceleration, dt = 0.002 s: the base slab strikes the wall once, at 2.79 s."""
    def springs(start, end, k, **kw):
        return {"type": "storey_springs", "start": start, "end": end, "stiffness": k, **kw}

    iso = {"storeys": 1, "yield_force": 1.0e5, "hardening": 0.1, "hysteresis": "bilinear"}
    building = {"name": "isolated", "storey_heights": [1.0, 3.2, 3.2], "slab": [[0, 0], [12, 0], [12, 8], [0, 8]],
                "mass": [150e3, 135e3, 120e3], "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
                "element": [springs([0, 0], [12, 0], 4e6, **iso), springs([0, 8], [12, 8], 4e6, **iso),
                            springs([0, 0], [0, 8], 4e6, **iso), springs([12, 0], [12, 8], 4e6, **iso),
                            springs([0, 0], [12, 0], 2e8, first_storey=2), springs([0, 8], [12, 8], 2e8, first_storey=2),
                            springs([6, 0], [6, 8], 4e8, first_storey=2)]}
    return {"building": [building], "ground_motion": {"record": "elcentro", "pga": 0.5},
            "analysis": {"integrator": "newmark", "dt": 0.002, "duration": 3.0, "contact": {"name": "penalty", "stiffness": 1e9}},
            "wall": [{"name": "moat", "face": [[-0.05, -1.0], [-0.05, 9.0]], "top": 1.0,
                      "contact": {"name": "kelvin", "stiffness": 1e9, "restitution": 0.5, "tension": True}}]}


def test_isolated_building_against_a_kelvin_moat_wall_matches_opensees(opensees):
    """OpenSees (:func:`pounding.peer.opensees_walls.run_wall_pounding`): the isolators as twoNodeLink
    Steel01 from the ground to the base slab, the storeys as Elastic links, the wall as two zeroLength
    ViscoelasticGap elements from fixed nodes to the base slab's edge ends (half the contact each, the
    clear distance as the negative gap). Both step the same discrete equations (Newmark average
    acceleration, the same dt, the isolators' and the contact's forces solved with each step), so they
    agree to their solvers' tolerance: every step stops within 1e-12 m of its solution (OpenSees'
    NormDispIncr; pounding's Newton to rounding), and a stable scheme carries such errors at most summed:
    n_steps x 1e-12 m on every floor's displacement, and that times the wall's stiffness on its force.
    Measured: 3e-12 m (3e-11 of the peak displacement), against 1.5e-9 m.
    """
    from pounding.peer.opensees_walls import run_wall_pounding

    scene = parse_scene(_isolated_beside_a_moat())
    result = Driver(scene).run()
    n = result.steps
    disp, forces, _ = run_wall_pounding(opensees, scene, result.dt, n)
    assert len(result.contacts) == 1 and result.second_body(result.contacts[0].pair) == ("moat", 0)
    assert forces.min() < 0.0  # the OpenSees wall is struck too
    tol = n * 1e-12
    assert np.max(np.abs(result.cm("isolated")[:, :, 0] - disp["isolated"][:, :, 0])) <= tol
    assert result.contacts[0].peak_force == pytest.approx(-forces.sum(axis=1).min(), abs=1e9 * tol)
    assert result.cm("isolated")[:, 0, 0].min() < -0.05  # the base slab went past the face (0.05 m away): contact


def test_points_of_one_instant_with_their_own_restitutions_each_leave_at_minus_k_times_their_speed():
    """A building striking a wall (k = 0.8, its own) and a neighbour (k = 0.5, the scene's) at one instant:
    one Newton problem whose points are coupled through the building (W = [[2, 1], [1, 3]] 1e-5 /kg,
    closing speeds b = (0.3, 0.2) m/s). Newton's rule for each point: it leaves at -k_j b_j, so the
    closing speeds after, b - W I, are (-0.24, -0.10) m/s, to the rounding of a 2 x 2 solve (8 eps).
    With equal restitutions the law's own impulses are used unchanged."""
    from types import SimpleNamespace

    from pounding.contact.impulse import Impulse

    laws = [Impulse(restitution=0.5), Impulse(restitution=0.8)]
    W, b = np.array([[2.0, 1.0], [1.0, 3.0]]) * 1e-5, np.array([0.3, 0.2])
    I = Driver._group_impulses(SimpleNamespace(laws=laws), W, b, np.array([1, 0]))
    assert np.all(I > 0.0)
    assert np.allclose(b - W @ I, [-0.8 * 0.3, -0.5 * 0.2], rtol=0.0, atol=8 * EPS * 0.3)
    same = Driver._group_impulses(SimpleNamespace(laws=laws), W, b, np.array([0, 0]))
    assert np.array_equal(same, laws[0].impulses(W, b))


def test_a_plastic_impact_leaves_the_slab_resting_on_the_wall_held_there_by_its_load():
    """With e = 0 the slab stops at the face (u = -GAP, u' = 0) and the load pressing it on (M A0 = 2e5 N
    against the springs' K GAP = 8e4 N) keeps it there: the pair is held in sustained contact (a rigid
    unilateral constraint against a body of infinite mass) to the end, the slab at the face to the
    geometry's zero (driver.eps) plus rounding, the building's account closing with the held contact
    doing no work (the slab does not move) and the impact's loss M b^2 / 2 booked as impact work."""
    from pounding.framework.post.energy_account import building_balances

    driver, result = _run(_data(0.0))
    t_i = result.impacts[0].time
    assert abs(t_i - T_HIT) <= driver.eps / B_HIT + 64 * EPS * T_HIT
    after = result.t > t_i
    u = result.cm("box")[after, 0, 0]
    v = result.cm("box", velocity=True)[after, 0, 0]
    assert np.max(np.abs(u + GAP)) <= 2 * driver.eps + 64 * EPS * GAP
    assert np.max(np.abs(v)) <= W * (2 * driver.eps + 64 * EPS * GAP)
    held = result.info["sustained_pairs_at_end"]
    assert held and set(held) <= set(driver.model.walls)
    account = building_balances(result)["box"]
    assert account["impacts"] == pytest.approx(-0.5 * M * B_HIT**2, rel=1e-9)
    assert abs(account["contact_forces"]) <= 1e-9 * account["input"]
    assert abs(account["error"]) <= 1e-9 * account["input"]


def test_impacts_on_a_wall_are_in_impacts_csv_contacts_csv_and_summary(tmp_path):
    """The run folder names the wall as the struck body: impacts.csv rows with struck_building "moat",
    storey 0, element "wall"; contacts.csv rows with building_b "moat", storey_b 0; summary.json's
    ``walls.moat`` totals the impulse (1 + e) M b of the first impact plus the later ones, and the
    energy its impacts dissipated, which is the loss the building's account books (its impact work)."""
    import csv
    import json

    from pounding.io.results import write_results

    _, result = _run(_data(0.5, duration=0.25))  # one impact instant (two face ends)
    out = write_results(result, tmp_path / "run")
    rows = list(csv.DictReader(open(out / "impacts.csv")))
    assert len(rows) == 2 and {(r["struck_building"], r["struck_storey"], r["struck_element"]) for r in rows} == {("moat", "0", "wall")}
    contacts = list(csv.DictReader(open(out / "contacts.csv")))
    assert {(r["building_b"], r["storey_b"]) for r in contacts} == {("moat", "0")}
    summary = json.loads((out / "summary.json").read_text())
    moat = summary["walls"]["moat"]
    assert moat["struck_by"] == ["box"] and moat["n_contacts"] == 2
    assert moat["impulse"] == pytest.approx(1.5 * M * B_HIT, rel=1e-9)
    loss = 0.5 * (1.0 - 0.5**2) * M * B_HIT**2
    assert moat["energy_dissipated"] == pytest.approx(loss, rel=1e-9)
    assert summary["buildings"]["box"]["energy"]["impacts"] == pytest.approx(-loss, rel=1e-9)


def test_a_wall_under_an_overhang_above_its_top_is_accepted():
    """A storey whose floor below is at or above the wall's top does not stand where the wall is: a face
    under the overhanging second floor of a two-storey building (storey 1 from 0 to 1.0 m over the
    12 m slab, storey 2 from 1.0 m up over a slab reaching 2 m further west) with its top at 1.0 m
    loads; the same face 0.5 m higher cuts storey 2's space and is refused."""
    data = _data()
    b = data["building"][0]
    b.update(storey_heights=[1.0, 3.2], mass=[M, M], slabs=[[[0, 0], [10, 0], [10, 8], [0, 8]], [[-2, 0], [10, 0], [10, 8], [-2, 8]]])
    b.pop("slab")
    for e in b["element"]:
        e.pop("storeys")  # both storeys
    data["wall"][0]["face"] = [[-1.0, -1.0], [-1.0, 9.0]]
    scene = parse_scene(data)
    assert scene.walls[0].top == 1.0
    data["wall"][0]["top"] = 1.5
    with pytest.raises(InputError, match="storey 2 of 'box'"):
        parse_scene(data)


def test_with_wall_checks_the_wall_as_the_loader_does():
    """``Scene.with_wall`` (the Python API) adds a wall that can stand and refuses, as the scene file does,
    one whose face cuts a storey's space, naming the call and the field."""
    scene = parse_scene(_data())
    kerb = scene.with_wall("kerb", [[-1.0, 10.0], [11.0, 10.0]], 0.5)
    assert [w.name for w in kerb.walls] == ["moat", "kerb"] and [w.name for w in scene.walls] == ["moat"]
    with pytest.raises(InputError, match=r"Scene.with_wall\('cut'\).face: the wall's face cuts the space of storey 1"):
        scene.with_wall("cut", [[5.0, -1.0], [5.0, 9.0]], 1.0)
