"""Hard cases, one test each, and the numbers that reach the user.

Each hard case runs through :func:`tests.test_stress.run_and_check` (finishes, finite, bounded
events per step, no step ending overlapped beyond the tolerance, momentum at every impulse,
energy balance by integrator class) and then checks what is special about it. Bugs found by
these tests and by the random scenes of test_stress.py have their minimal reproductions here,
marked ``xfail(strict=True)`` with the reason, so the suite stays green until they are fixed.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from pounding.errors import AnalysisWarning, InputError
from pounding.framework.engine.driver import Driver
from pounding.framework.engine.stacked_model import Model
from pounding.framework.post.run import run
from pounding.framework.model.units import G
from pounding.io.ground_motion import load_record
from pounding.io.scene import load_scene, parse_scene

from tests import strategies as S
from tests.conftest import EXAMPLES
from tests.scenes_for_tests import box_building, frame, pointed_pair, pressed_position, side_by_side
from tests.test_stress import run_and_check, slab_momenta_ok
from pounding.framework.post.energy_account import energy_balance

PAPER = EXAMPLES / "paper" / "pair_gap_0.03.toml"


def quiet_run(sc, driver=Driver):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AnalysisWarning)
        d = driver(sc)
        return d, d.run()


def pulse_file(path, amplitude, duration, rise=0.1, dt=0.01):
    """A two-column record [s, m/s2]: ramp to ``amplitude`` in ``rise`` s, then constant to ``duration``."""
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    a = amplitude * np.clip(t / rise, 0.0, 1.0)
    np.savetxt(path, np.column_stack([t, a]), fmt="%.6f %.9e", header="time acc", comments="")
    return {"record": str(path), "units": "m/s2"}


def all_gaps(model, result) -> np.ndarray:
    """Signed gap of every pair at every output step, shape (nt, pairs)."""
    return np.array([[model.pair_gap(q, p) for p in range(len(result.pairs))] for q in result.q])


# ============================================================================ sustained contact
def pushed_pair(record: dict, k: float, integrator="newmark", tol=1e-4, damping=0.2, locate=None):
    """A stiff (left) and a soft (right) single-storey building touching at rest (gap 0); the ground
    accelerates along +x, so the inertia force pushes both to -x and the soft one leans on the stiff."""
    data = side_by_side(0.0, storeys=(1, 1), columns=(0.6, 0.35), columns_y=(0.6, 0.4), restitution=k, integrator=integrator,
                        dt=0.005, duration=3.0, damping={"type": "modal", "ratio": damping})
    data["ground_motion"] = record
    data["analysis"]["contact"] = {"name": "impulse", "tolerance": tol, "after_impact": "equilibrium"}
    if locate is not None:
        data["analysis"]["contact"]["locate"] = locate
    return data


@pytest.mark.parametrize("k", [0.0, 0.9])
def test_buildings_pushed_together_hold_in_sustained_contact(tmp_path, k):
    """A one-sided pulse (two-column file: ramp in 0.1 s to 2 m/s2, held for 3 s) presses a soft
    building onto a stiff one. Impacts accumulate (k = 0.9: a Zeno sequence of ever smaller
    rebounds) and the pair is held in sustained contact: a bounded number of impacts (<= steps/20),
    no overlap beyond the tolerance at any step, energy closing to 1e-8 (average acceleration), and
    at the end (20 % damping: the transient has decayed by exp(-0.2 omega t) < 1e-6) both slabs at
    the static position of the pressed pair, u = -(m_a + m_b) a_g / (k_a + k_b), to 1e-4.

    The paper's locator (named): it strikes the pair within the tolerance, so pressing from rest
    starts with impacts. With ``crossing`` (the next test) slabs that touch at rest with no
    approach are pressed without any impact."""
    amp = 2.0
    sc = parse_scene(pushed_pair(pulse_file(tmp_path / "pulse.txt", amp, 3.0), k, locate="halving"))
    d, r = run_and_check(sc)
    assert 1 <= r.n_impacts <= r.steps / 20
    assert 0 in d.ever_sustained and r.info["sustained_pairs_at_end"] == [0]
    u = pressed_position(d.model, amp)
    assert r.cm("left")[-1, 0, 0] == pytest.approx(u, rel=1e-4)
    assert r.cm("right")[-1, 0, 0] == pytest.approx(u, rel=1e-4)


@pytest.mark.parametrize("k", [0.0, 0.9])
def test_pressed_from_rest_holds_without_impacts(tmp_path, k):
    """The pushed pair with the default ``crossing`` locator: touching at rest with no approach, the
    slabs are held from the first step without any impact (nothing closes at a zero gap), stay
    within the tolerance, and end at the static pressed position (to 1e-4, as above)."""
    amp = 2.0
    sc = parse_scene(pushed_pair(pulse_file(tmp_path / "pulse.txt", amp, 3.0), k))
    d, r = run_and_check(sc)
    assert r.n_impacts == 0
    assert 0 in d.ever_sustained and r.info["sustained_pairs_at_end"] == [0]
    u = pressed_position(d.model, amp)
    assert r.cm("left")[-1, 0, 0] == pytest.approx(u, rel=1e-4)
    assert r.cm("right")[-1, 0, 0] == pytest.approx(u, rel=1e-4)


def test_central_difference_holds_a_sustained_contact(tmp_path):
    """The pushed pair above with central differences (omega dt = 0.07, far below the limit 2): the
    held pair stays within the tolerance at every step and the run passes every invariant.

    Found by the random scenes (fixed in e93d81b): the end displacement of central differences does
    not depend on the end load (B[:, 0, 1] = 0), so the rigid force was 0 and the slabs passed
    through each other (10 mm here, 75 mm in a random scene)."""
    sc = parse_scene(pushed_pair(pulse_file(tmp_path / "pulse.txt", 2.0, 3.0), 0.0, integrator="central_difference"))
    d, r = run_and_check(sc, check_energy=False)
    assert 0 in d.ever_sustained and r.info["sustained_pairs_at_end"] == [0]
    assert all_gaps(d.model, r).min() >= -d.tol * (1 + 1e-9)


def test_central_difference_sustained_contact_is_static_and_balanced(tmp_path):
    """Held at rest, the pair must sit at the static pressed position (1e-3; Newmark: 3e-8) and the
    energy balance must stay within the package's own tolerance (0.02; no AnalysisWarning)."""
    amp = 2.0
    sc = parse_scene(pushed_pair(pulse_file(tmp_path / "pulse.txt", amp, 3.0), 0.0, integrator="central_difference"))
    with warnings.catch_warnings():
        warnings.simplefilter("error", AnalysisWarning)
        d = Driver(sc)
        r = d.run()
    u = pressed_position(d.model, amp)
    assert r.cm("right")[-1, 0, 0] == pytest.approx(u, rel=1e-3)
    assert abs(energy_balance(r)["relative_error"]) < 0.02


@pytest.mark.parametrize("integrator", [
    {"name": "newmark"}, {"name": "exact"}, {"name": "hht", "alpha": -0.1},
    # linear acceleration amplifies a leftover normal velocity of held points by -2 per step (a
    # position constraint leaves it free): it chattered at up to 3e-7 m/s and booked 1.5e-7 of the
    # input here until held_step projected that velocity out; now 8e-11
    {"name": "newmark", "preset": "linear"},
    {"name": "generalized_alpha", "rho_inf": 0.0}, {"name": "central_difference"},
], ids=lambda i: i.get("preset", i["name"]))
def test_a_held_pair_at_rest_books_no_work(tmp_path, integrator):
    """The pushed pair (20 % damping) is at rest, pressed together, from well before 4 s (its kinetic
    energy is below 1e-12 of the input by then): between 4 s and 7 s the ground-motion input, the damping work and
    the contact-force work may change by rounding only (1e-9 of the input), and the balance error with
    them. Before the held constraint became a load carried through each scheme's own step, the free
    step pushed the slabs dt^2/2 a into each other every step and the correction pushed them back:
    from 3 s to 6 s at rest, Newmark booked +69 J of input and +94 J of damping, and every scheme
    but average acceleration and exact drifted (central differences 29 % -> 52 % of the input)."""
    rec = pulse_file(tmp_path / "pulse.txt", 2.0, 7.0)
    out = []
    for duration in (4.0, 7.0):
        data = pushed_pair(rec, 0.0, integrator=integrator)
        data["analysis"]["duration"] = duration
        _, r = quiet_run(parse_scene(data))
        out.append(r)
    r4, r7 = out
    assert 0.5 * np.sum(r4.qd[-1] ** 2) < 1e-12 * energy_balance(r4)["input"]
    assert r7.cm("right")[-1, 0, 0] == pytest.approx(r4.cm("right")[-1, 0, 0], rel=1e-9)
    e4, e7 = energy_balance(r4), energy_balance(r7)
    for key in ("input", "damping", "contact_force_work", "error"):
        assert abs(e7[key] - e4[key]) <= 1e-9 * e4["input"], (key, e4[key], e7[key])


@pytest.mark.parametrize("omega_dt", [1.0, 2.0])
def test_conditionally_stable_schemes_gain_no_energy_through_sustained_contact(omega_dt):
    """Within its stability limit (sqrt 12 = 3.46 for linear acceleration) a scheme must not gain energy
    through sustained contact: the balance error stays above -0.02 (the package's own warning level)
    and the stiffest modes stay within twice their size under average acceleration at the same dt.

    Measured: omega_max dt = 1: +0.009, 1.1x; 2: +0.013, 1.1x. When the held constraint was a
    correction after a free step, omega_max dt = 3 gave -0.79 and 4.8x. At omega_max dt = 3 it is
    now -0.050 and 2.6x, but that is linear acceleration's own error under velocity jumps, not
    sustained contact: the same pair 0.03 m apart, 6 impacts and no held pair, gives -0.040 (the
    physical energy is not this scheme's invariant; near its limit a stiff mode's physical energy
    swings by a factor 1 / (1 + (beta - 1/4) (omega dt)^2) within a period: 1.09, 1.5 and 4 at
    omega dt = 1, 2 and 3, checked in free vibration)."""
    data = twisting_pair(1, "newmark", 1e-4)
    data["analysis"]["integrator"] = {"name": "newmark", "preset": "linear"}
    om = float(Model(parse_scene(data)).omega.max())
    data["analysis"]["dt"] = omega_dt / om
    sc = parse_scene(data)
    d, r = quiet_run(sc, S.InstrumentedDriver)
    _, ra = quiet_run(sc.with_analysis(integrator="newmark", integrator_params={}))
    assert d.ever_sustained
    stiff = np.argsort(d.model.omega)[-2:]
    assert energy_balance(r)["relative_error"] >= -0.02
    assert np.abs(r.q[:, stiff]).max() <= 2 * np.abs(ra.q[:, stiff]).max()


def twisting_pair(n=1, integrator="newmark", tol=1e-4, pga=1.0):
    """Two box buildings touching face to face (gap 0); the left one's far x-frame is weaker, so it
    twists under x shaking and the facing edges meet at an angle, one end first."""
    data = side_by_side(0.0, storeys=(n, n), columns=(0.6, 0.35), columns_y=(0.6, 0.4), restitution=0.0, duration=3.0, dt=0.01,
                        pga=pga, integrator=integrator)
    data["building"][0] = box_building("left", 0.0, 10.0, 10.0, n, 0.6, 0.6, column_x_far=0.3)
    data["analysis"]["contact"] = {"name": "impulse", "tolerance": tol, "after_impact": "equilibrium"}
    return data


@pytest.mark.parametrize("n, integrator, tol", [(1, "newmark", 1e-4), (2, "exact", 1e-4), (1, "newmark", 1e-5)])
def test_sustained_contact_of_twisting_slabs_stays_within_the_tolerance(n, integrator, tol):
    """Face-to-face sustained contact of twisting slabs must still end every step within the tolerance.

    Found by the random scenes (fixed in e93d81b): the rigid force was solved once for the features
    penetrating in the free step; the rotation it caused closed the other end of the facing edges and
    nothing re-checked (1 storey, Newmark: 1.54e-4 m > tol 1e-4; 2 storeys, exact: 6.6e-4 m; a
    3-storey random scene: 2.6e-4 m > tol 1e-5)."""
    sc = parse_scene(twisting_pair(n, integrator, tol))
    d, r = run_and_check(sc, check_energy=integrator == "newmark")
    assert d.ever_sustained
    assert all_gaps(d.model, r).min() >= -d.tol * (1 + 1e-9)


# ============================================================================ grazing
def test_corner_grazing_along_an_edge():
    """The tip of a pentagon touches the left slab's face at rest (gap 0) and the ground shakes along
    the face (y): the corner slides along the edge. Every invariant holds; any impulse is small, along
    the face normal (+x), and no step ends with the tip through the face."""
    data = pointed_pair(restitution=0.5)
    data["ground_motion"] = {"record": "elcentro", "pga": 0.5, "angle": 90.0}
    data["analysis"].update(duration=3.0, dt=0.005, contact={"name": "impulse", "tolerance": 1e-5, "after_impact": "equilibrium"})
    d, r = run_and_check(parse_scene(data))
    for imp in r.impacts:
        assert abs(imp.normal[1]) < 1e-2 and imp.normal[0] > 0


def test_corner_grazing_a_corner():
    """Two squares, one rotated 45 degrees, touch corner to face at rest and the ground shakes at 30
    degrees: corners graze each other's edges. Every invariant holds."""
    diamond = [[12.0, 5.0], [17.0, 0.0], [22.0, 5.0], [17.0, 10.0]]  # tip (12, 5) on the face x = 12 of the box
    right = {
        "name": "right", "storey_heights": [3.2, 3.2], "slab": diamond, "mass_per_area": 900.0,
        "element": [frame([14.0, 3.0], [20.0, 3.0], 0.45), frame([14.0, 7.0], [20.0, 7.0], 0.4),
                    frame([15.0, 2.0], [15.0, 8.0], 0.45), frame([19.0, 2.0], [19.0, 8.0], 0.5)],
    }
    data = {
        "building": [box_building("left", 0.0, 12.0, 10.0, 2, 0.45, 0.5, column_x_far=0.35), right],
        "ground_motion": {"record": "elcentro", "pga": 0.6, "angle": 30.0},
        "analysis": {"integrator": "hht", "dt": 0.005, "duration": 3.0, "restitution": 0.5,
                     "contact": {"name": "impulse", "tolerance": 1e-5, "locate": "root"}},
    }
    sc = parse_scene(data)
    assert Model(sc).pairs[0][4] == pytest.approx(0.0, abs=1e-12)
    run_and_check(sc)


# ============================================================================ impacts at every storey
def test_simultaneous_impacts_at_every_storey():
    """Two 10-storey buildings touching at every floor (gap 0); every left slab moves at +0.2 m/s and
    every right slab at -0.1 m/s: one contact check gives face-to-face impulses at all ten storeys at
    once. Each pair: Newton's law at both ends (b' = -k b), linear and angular momentum conserved
    (1e-10 of the jumps), and the logged losses equal the kinetic-energy drop (1e-10)."""
    k = 0.5
    n = 10
    data = side_by_side(0.0, storeys=(n, n), restitution=k)
    data["analysis"]["contact"] = {"name": "impulse", "tolerance": 1e-4}
    d = S.InstrumentedDriver(parse_scene(data))
    m = d.model
    from tests.scenes_for_tests import modal_from_physical, physical

    v = {(0, f): np.array([0.2, 0.0, 0.0]) for f in range(n)} | {(1, f): np.array([-0.1, 0.0, 0.0]) for f in range(n)}
    d.z[:, 1] = modal_from_physical(m, v)
    assert d.contact_at(0.0)
    (ev,) = d.impulse_log
    assert sorted({i.pair for i in ev["impacts"]}) == list(range(n))
    assert all(i.vertex == -1 for i in ev["impacts"]) and len(ev["impacts"]) == 2 * n
    assert slab_momenta_ok(m, ev)
    after = physical(m, ev["after"])
    for f in range(n):
        closing = after[(0, f)][0] - after[(1, f)][0]
        assert closing == pytest.approx(-k * 0.3, rel=1e-10)
    ke = lambda x: sum(0.5 * sl.mass * float(x[(b, f)][:2] @ x[(b, f)][:2]) + 0.5 * sl.polar_inertia * x[(b, f)][2] ** 2
                       for b, s in enumerate(m.systems) for f, sl in enumerate(s.slabs))
    drop = ke(physical(m, ev["before"])) - ke(after)
    assert drop == pytest.approx(sum(i.energy_loss for i in ev["impacts"]), rel=1e-10)


def test_impacts_at_several_storeys_in_one_instant_during_a_run():
    """A stiff and a soft 4-storey building touching at every floor under El Centro: some instants have
    impacts at several storeys at once (measured: 3 of 4; all four only arise from a constructed state,
    above, because the storeys of a real run never close in exactly the same step). Every invariant
    holds (tight energy: average acceleration, equilibrium after impact)."""
    data = side_by_side(0.0, storeys=(4, 4), columns=(0.7, 0.35), columns_y=(0.7, 0.4), restitution=0.5, dt=0.005, duration=3.0)
    data["analysis"]["contact"] = {"name": "impulse", "after_impact": "equilibrium"}
    d, r = run_and_check(parse_scene(data))
    per_instant = {}
    for i in r.impacts:
        per_instant.setdefault(i.time, set()).add(r.impact_storey(i))
    assert max(len(s) for s in per_instant.values()) >= 2


# ============================================================================ identical buildings
def copy_of_paper_low(dx: float) -> dict:
    """The paper's eccentric 3-storey "low" and a copy of it translated by dx along x."""
    import tomllib

    raw = tomllib.loads(PAPER.read_text())
    a = raw["building"][0]
    b = json.loads(json.dumps(a))
    b["name"] = "copy"
    b["slab"] = [[x + dx, y] for x, y in a["slab"]]
    for e in b["element"]:
        e["start"] = [e["start"][0] + dx, e["start"][1]]
    data = {**raw, "building": [a, b]}
    data["analysis"] = {**raw["analysis"], "duration": 8.0, "contact": {"name": "impulse", "after_impact": "equilibrium"}}
    return data


def test_identical_buildings_side_by_side_move_in_phase_without_impact():
    """Two copies of one eccentric building (the paper's 3-storey "low", 15 m wide), the second
    translated by 15.001 m: under the same ground motion they move identically - in phase, twist
    included (1e-12 of the response) - and never touch. They twist by phi about their own centres, so
    the facing edges, turned alike, stay parallel, slide past each other and stand
    (W + g0) cos(phi) - W = g0 cos(phi) - W (1 - cos(phi)) apart along their normal (W = 15 m the
    width): checked to 1e-12 m at every step."""
    d, r = run_and_check(parse_scene(copy_of_paper_low(15.001)))
    assert r.n_impacts == 0 and r.info["located_events"] == 0
    assert np.max(np.abs(r.cm("low") - r.cm("copy"))) <= 1e-12 * np.max(np.abs(r.cm("low")))
    phi = r.cm("low")[:, :, 2]
    assert np.max(np.abs(phi)) > 1e-3, "the buildings must twist for the test to mean something"
    g = all_gaps(d.model, r)
    assert np.max(np.abs(g - (0.001 * np.cos(phi) - 15.0 * (1.0 - np.cos(phi))))) <= 1e-12


def test_identical_buildings_touching_in_phase_never_impact():
    """Two identical symmetric box buildings touching at rest (gap 0), shaken along x and at 30
    degrees: their relative motion is zero up to rounding (1e-23 m), so no impulse may be applied.

    Found here (fixed in fd05b69): every closing speed b > 0 counted, rounding included (~1e-20 m/s),
    and 3-4 'impacts' of ~1e-16 N s were logged."""
    for angle in (0.0, 30.0):
        a = box_building("a", 0.0, 12.0, 10.0, 3, 0.5, 0.45)
        b = box_building("b", 12.0, 12.0, 10.0, 3, 0.5, 0.45)
        data = {"building": [a, b], "ground_motion": {"record": "elcentro", "pga": 0.5, "angle": angle},
                "analysis": {"integrator": "newmark", "dt": 0.005, "duration": 4.0,
                             "contact": {"name": "impulse", "after_impact": "equilibrium"}}}
        d, r = run_and_check(parse_scene(data))
        assert np.max(np.abs(r.cm("a") - r.cm("b"))) <= 1e-15
        assert r.n_impacts == 0, [(i.time, i.impulse, i.approach_velocity) for i in r.impacts[:4]]


# ============================================================================ touching at t = 0
@pytest.mark.parametrize("integrator", ["newmark", "hht", "exact"])
def test_touching_at_rest_from_the_first_step(integrator):
    """A soft and a stiff 2-storey building touching at rest (gap 0) under El Centro: the driver
    steps in Python from step 0 (the pair is within the tolerance), impacts start within the first
    second, and every invariant holds."""
    data = side_by_side(0.0, storeys=(2, 2), columns=(0.6, 0.35), restitution=0.5, integrator=integrator, dt=0.005, duration=2.0)
    data["analysis"]["contact"] = {"name": "impulse", "after_impact": "equilibrium", "locate": "root"}
    d, r = run_and_check(parse_scene(data))
    assert d.step_log and d.step_log[0][0] == 0
    assert r.n_impacts > 0 and r.impacts[0].time < 1.0


# ============================================================================ stiff walls, dt >> T_min
def wall_building(name, x0, width=10.0, depth=10.0, storeys=3):
    """Soft frames along x (T1 ~ 0.6 s) and two thick shear walls along y (T_min ~ 3 ms)."""
    x1 = x0 + width
    return {
        "name": name, "storey_heights": [3.2] * storeys, "slab": [[x0, 0.0], [x1, 0.0], [x1, depth], [x0, depth]],
        "mass_per_area": 500.0,
        "element": [
            frame([x0, 0.0], [x1, 0.0], 0.4), frame([x0, depth], [x1, depth], 0.35),
            {"type": "shear_wall", "start": [x0, 0.0], "end": [x0, depth], "thickness": 0.8, "E": 30e9, "nu": 0.2},
            {"type": "shear_wall", "start": [x1, 0.0], "end": [x1, depth], "thickness": 0.8, "E": 30e9, "nu": 0.2},
        ],
    }


@pytest.mark.parametrize("integrator", [{"name": "newmark"}, {"name": "hht", "alpha": -0.1}, {"name": "generalized_alpha", "rho_inf": 0.5}])
def test_stiff_shear_walls_far_below_dt_stay_bounded_and_accurate_in_the_low_modes(integrator):
    """Shear walls give periods far shorter than dt = 0.02 s (the record's step; omega_max dt > 30).
    Implicit schemes stay bounded and follow the exact integrator at the same dt in the low modes: the
    modal coordinates of the modes with omega dt <= 0.3 match exact to 6 % of their peak over 4 s
    (second order: period error ~ (omega dt)^2 / 12 per cycle, plus the algorithmic damping of HHT and
    generalized-alpha; measured 0.9-1.3 % for Newmark, 3.4 % HHT -0.1, 4.0 % rho_inf 0.5), and the
    stiff modes stay within their quasi-static size (peak |q| <= 2 x exact's). Central differences are
    refused (dt >> 2/omega_max)."""
    data = {
        "building": [wall_building("a", 0.0), wall_building("b", 10.3, width=12.0, storeys=5)],
        "ground_motion": {"record": "elcentro", "pga": 0.4, "angle": 20.0},
        "analysis": {"integrator": integrator, "dt": 0.02, "duration": 4.0, "contact": "none"},
    }
    sc = parse_scene(data)
    m = Model(sc)
    assert np.max(m.omega) * 0.02 > 30, "the walls must be far too stiff for the step (T_min < dt / 5)"
    d, r = run_and_check(sc, check_energy=integrator["name"] == "newmark")
    ex = run(sc.with_analysis(integrator="exact", integrator_params={}))
    low = m.omega * 0.02 <= 0.3
    assert low.sum() >= 2
    peak = np.max(np.abs(ex.q[:, low]), axis=0)
    assert np.all(np.max(np.abs(r.q[:, low] - ex.q[:, low]), axis=0) <= 0.06 * peak)
    high = m.omega * 0.02 > 10
    assert np.all(np.max(np.abs(r.q[:, high]), axis=0) <= 2 * np.max(np.abs(ex.q[:, high]), axis=0) + 1e-12)
    with pytest.raises(InputError, match="central difference"):
        run(sc.with_analysis(integrator="central_difference", integrator_params={}))


# ============================================================================ a long record
def test_a_record_ten_times_el_centro(tmp_path):
    """El Centro tiled ten times (312 s, 15 600 samples) as a two-column file, the paper pair at 30 mm
    with pounding: the run finishes at the end of the record, every number is finite, and the result
    stores O(n) numbers per output step: q and qd are (nt, n) and nothing else grows with nt x
    storeys (the physical histories are computed on demand)."""
    gm = load_record({"record": "elcentro"})
    dt = gm.dt
    n0 = len(gm.t)
    t = np.arange(10 * n0) * dt
    a = np.tile(gm.acc, 10)
    path = tmp_path / "elcentro_x10.txt"
    np.savetxt(path, np.column_stack([t, a / G]), fmt="%.4f %.8e")
    import tomllib

    raw = tomllib.loads(PAPER.read_text())
    raw["ground_motion"] = {"record": str(path), "pga": 0.32}
    raw["analysis"] = {**raw["analysis"], "dt": 0.01}
    sc = parse_scene(raw)
    assert sc.ground_motion.duration == pytest.approx(t[-1])
    d, r = run_and_check(sc, check_energy=False)
    nt, n = len(r.t), d.model.n
    assert r.t[-1] == pytest.approx(t[-1]) and nt == r.steps + 1 == round(t[-1] / 0.01) + 1
    assert r.q.shape == r.qd.shape == (nt, n)
    arrays = {k: v for k, v in vars(r).items() if isinstance(v, np.ndarray)}
    grows_with_nt = {k for k, v in arrays.items() if v.ndim and v.shape[0] == nt}
    assert grows_with_nt == {"t", "q", "qd"}, {k: arrays[k].shape for k in arrays}
    assert r.q.nbytes == r.qd.nbytes == nt * n * 8
    # impulse states (if kept) grow with the impacts, not with nt
    for k, v in arrays.items():
        if k not in grows_with_nt:
            assert v.size <= max(r.n_impacts, 1) * n + 10 * n, (k, v.shape)
    assert r.n_impacts > 50
    assert abs(energy_balance(r)["relative_error"]) < 0.02


# ============================================================================ restitution 0 and 1
@pytest.mark.parametrize("k", [0.0, 1.0])
def test_restitution_exactly_zero_and_one(k):
    """The paper pair, 4 s, Newmark with equilibrium after impact: k = 0 - every impulse leaves its
    points not approaching and at least one point of each hit at zero closing speed (plastic); k = 1 -
    no impact loses energy (|loss| <= 1e-12 of the kinetic energy of the slabs); both close the
    energy balance to 1e-8 and satisfy every other invariant."""
    sc = load_scene(PAPER).with_analysis(duration=4.0, integrator="newmark", integrator_params={},
                                         contact_params={"restitution": k, "after_impact": "equilibrium"})
    d, r = run_and_check(sc)
    assert r.n_impacts > 5
    m = d.model
    for ev in d.impulse_log:
        ke = 0.5 * float(ev["before"] @ ev["before"])
        for imp in ev["impacts"]:
            a, fa, b, fb, _ = m.pairs[imp.pair]
            w = m.row(ev["q"], imp.pair, imp.point, imp.normal)
            b_after = -float(w @ ev["after"])
            assert b_after <= 1e-9 * imp.approach_velocity + 1e-15
            if k == 1.0:
                assert abs(imp.energy_loss) <= 1e-12 * ke
        if k == 0.0:
            by_pair = {}
            for imp in ev["impacts"]:
                w = m.row(ev["q"], imp.pair, imp.point, imp.normal)
                by_pair.setdefault(imp.pair, []).append(abs(float(w @ ev["after"])) / imp.approach_velocity)
            assert all(min(v) <= 1e-9 for v in by_pair.values())
    if k == 1.0:
        assert abs(energy_balance(r)["impact_loss"]) <= 1e-10 * energy_balance(r)["input"]


# ============================================================================ energy audit of the exact integrator
def test_exact_integrator_balance_closes_at_the_records_own_step():
    """The exact integrator at the record's own dt (0.02 s) with stiffness-proportional damping and
    impacts exciting the highest modes (omega dt up to 6, zeta omega dt up to 0.3): the audit uses the
    closed-form work integrals of the exact trajectory, so the balance closes to rounding (1e-8).
    With 4 Gauss points per step it missed by 8.9e-5 of the input."""
    import tomllib

    raw = tomllib.loads(PAPER.read_text())
    for b in raw["building"]:
        b["damping"] = {"type": "stiffness", "ratio": 0.05}
    raw["analysis"] = {"integrator": "exact", "dt": 0.02, "duration": 8.0, "restitution": 0.5,
                       "contact": {"name": "impulse", "after_impact": "equilibrium"}}
    d, r = quiet_run(parse_scene(raw))
    assert r.n_impacts > 10
    assert abs(energy_balance(r)["relative_error"]) < 1e-8


# ============================================================================ numbers that reach the user
def test_periods_reported_by_info_are_the_models():
    """``pounding info --json`` prints, for every building, finite positive periods in descending
    order equal (bit for bit) to 2 pi / omega of the assembled model, and the damping ratios asked."""
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "pounding", "info", str(PAPER), "--json"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    info = json.loads(proc.stdout)
    sc = load_scene(PAPER)
    m = Model(sc)
    blds = info["buildings"] if "buildings" in info else info
    for s in m.systems:
        entry = blds[s.name] if isinstance(blds, dict) else next(b for b in blds if b.get("name") == s.name)
        periods = np.asarray(entry["periods"])
        assert np.all(np.isfinite(periods)) and np.all(periods > 0) and np.all(np.diff(periods) <= 0)
        assert np.array_equal(periods, s.periods[: len(periods)])
        zeta = np.asarray(entry["damping_ratios"])
        for mode in (1, 3):
            assert zeta[mode - 1] == pytest.approx(0.05, rel=1e-12)


def test_ground_motion_is_scaled_exactly_not_clipped():
    """pga = 0.32 g gives a record whose peak |a| is 0.32 g to rounding (not clipped, not a rounded
    factor), with the shape of the original kept (every sample scaled by one factor)."""
    raw = load_record({"record": "elcentro"})
    gm = load_record({"record": "elcentro", "pga": 0.32})
    assert gm.pga == pytest.approx(0.32 * G, rel=1e-15)
    ratio = gm.acc[raw.acc != 0] / raw.acc[raw.acc != 0]
    assert np.ptp(ratio) <= 1e-15 * ratio[0]


@pytest.mark.parametrize("value", [-0.1, 1.2])
def test_restitution_outside_0_1_is_rejected_not_clipped(value):
    data = side_by_side(0.01, restitution=value)
    with pytest.raises(InputError, match="restitution"):
        parse_scene(data)


def test_the_run_covers_the_requested_duration():
    """duration = 1.0 s with dt = 0.4 s: the run reaches at least 1.0 s, without a warning.

    Found here (fixed in fd05b69): nsteps = round(duration / dt) ended at 0.8 s (20 % short), silently."""
    data = side_by_side(0.5, duration=1.0, dt=0.4, integrator="newmark")
    with warnings.catch_warnings():
        warnings.simplefilter("error", AnalysisWarning)
        r = run(parse_scene(data))
    assert r.t[-1] >= 1.0 - 1e-12


def test_reported_peaks_do_not_depend_on_output_every(tmp_path):
    """peak_u in summary.json is the peak over every step, whatever output_every thins the histories to.

    Found here (fixed in fd05b69): the peaks were taken from the thinned output (output_every = 7:
    0.01405 m reported, 0.01534 m true, -8 %)."""
    from pounding.io.results import summary

    data = side_by_side(0.5, duration=3.0, dt=0.005, integrator="newmark")
    sc = parse_scene(data)
    every = summary(run(sc.with_analysis(output_every=7)))
    full = summary(run(sc.with_analysis(output_every=1)))
    for name in ("left", "right"):
        assert every["buildings"][name]["peak_u"] == pytest.approx(full["buildings"][name]["peak_u"], rel=1e-12)
