"""Response quantities of practice: drifts, storey shears, floor accelerations, impact forces.

Every check recomputes the quantity from the written files (response.npz) and
the elements' own stiffness, by hand, from first principles: nothing here calls
:mod:`pounding.framework.post.response`.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from pounding.framework.post.run import run
from tests.scenes_for_tests import scene as build_scene
from tests.scenes_for_tests import side_by_side


def _pounding_pair():
    """Two box buildings (3 and 5 storeys) 5 mm apart under El Centro at 30 degrees: they pound at
    several storeys, twist (the right one has a softer far frame), and one frame of each has a
    cracked-section stiffness modifier of 0.7."""
    data = side_by_side(0.005, storeys=(3, 5), duration=3.0, integrator="newmark")
    data["ground_motion"]["angle"] = 30.0
    data["building"][1]["element"][1]["column"]["b"] = 0.35
    data["building"][1]["element"][1]["column"]["h"] = 0.35
    for b in data["building"]:
        b["element"][0]["stiffness_modifier"] = 0.7
    return build_scene(data)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    import warnings

    from pounding.io.results import write_results

    scene = _pounding_pair()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the paper's "keep" rule is flagged; not what is tested here
        result = run(scene)
    out = tmp_path_factory.mktemp("resp") / "run"
    write_results(result, out)
    return scene, result, np.load(out / "response.npz"), json.loads((out / "summary.json").read_text())


def test_the_scene_pounds_at_several_storeys(written):
    """The fixture is a real test case: impacts at more than one storey, and twisting slabs."""
    _, result, npz, _ = written
    assert len({result.impact_storey(i) for i in result.impacts}) >= 2
    assert np.abs(npz["right_cm"][:, :, 2]).max() > 1e-5  # rad


def test_storey_shears_equal_the_elements_forces_summed_by_hand(written):
    """Storey shear (x, y) of storey s = sum over the elements of (modifier x k_e d_e) summed over
    the floors f >= s, with d_e[f] = n . (u_f, v_f) + phi_f ((p - c_f) x n) the element's floor
    displacement along its line n through its point p, from the centre-of-mass histories in
    response.npz. Both sides are sums of the same O(10) products of (large stiffness) x (small
    displacement) taken in different orders: they agree to rounding relative to the largest
    element floor force, so 1e-12 of the peak shear (measured ~1e-15)."""
    scene, _, npz, summ = written
    for b in scene.buildings:
        cm = npz[f"{b.name}_cm"]
        nt, n = cm.shape[:2]
        shear = np.zeros((nt, n, 2))
        for e, factor in zip(b.elements, b.element_modifiers()):
            nrm = np.asarray(e.direction)
            disp = np.zeros((nt, n))
            for f in e.floors:
                r = np.asarray(e.point) - b.slabs[f - 1].centre
                disp[:, f - 1] = nrm[0] * cm[:, f - 1, 0] + nrm[1] * cm[:, f - 1, 1] + cm[:, f - 1, 2] * (r[0] * nrm[1] - r[1] * nrm[0])
            idx = np.asarray(e.floors) - 1
            forces = disp[:, idx] @ (factor * e.lateral_stiffness())
            for s in range(n):
                above = forces[:, idx >= s].sum(axis=1)
                shear[:, s] += above[:, None] * nrm
        peak = np.abs(shear).max()
        assert np.abs(npz[f"{b.name}_storey_shear"] - shear).max() <= 1e-12 * peak
        mag = np.hypot(shear[..., 0], shear[..., 1]).max(axis=0)
        np.testing.assert_allclose(summ["buildings"][b.name]["peak_storey_shear"], mag, rtol=1e-12)
        assert summ["buildings"][b.name]["peak_base_shear"] == pytest.approx(mag[0], rel=1e-12)


def test_drift_ratios_from_the_vertex_histories(written):
    """Drift ratio at a corner of storey s = |(vertex displacement of slab s) - (that of slab s-1)|
    / h_s, read straight from B_vertices in response.npz (the box slabs have the same polygon at
    every storey, so vertex k of both floors is the same plan point; the ground does not move).
    At the centre of mass: the same from B_cm, moving the floor below to the point above by its
    rotation. Differences of O(1e-2) m displacements: rounding is 1e-16 m, so 1e-12 of the peak
    drift ratio. summary.json reports the peaks over the continuous trajectory (pounding.framework.engine.peaks:
    the same code on the same result gives the same numbers), which the step-end maxima bound from below
    (up to the rounding of the two ways of summing the modal rows, 1e-12 as above)."""
    from pounding.framework.engine.peaks import drift_peaks

    scene, result, npz, summ = written
    for b in scene.buildings:
        verts = npz[f"{b.name}_vertices"]
        h = np.asarray(b.storey_heights)
        below = np.concatenate([np.zeros_like(verts[:, :1]), verts[:, :-1]], axis=1)
        corner = (np.linalg.norm(verts - below, axis=-1) / h[None, :, None]).max(axis=2)
        peak = corner.max()
        assert np.abs(npz[f"{b.name}_drift_ratio_corner"] - corner).max() <= 1e-12 * peak
        cm = npz[f"{b.name}_cm"]
        c = np.array([s.centre for s in b.slabs])
        d = np.zeros(cm.shape[:2] + (2,))
        for s in range(b.n_storeys):
            d[:, s] = cm[:, s, :2]
            if s > 0:  # floor s-1 at the plan point c_s: its centre's motion plus its rotation about c_{s-1}
                r = c[s] - c[s - 1]
                d[:, s, 0] -= cm[:, s - 1, 0] - cm[:, s - 1, 2] * r[1]
                d[:, s, 1] -= cm[:, s - 1, 1] + cm[:, s - 1, 2] * r[0]
        at_cm = np.linalg.norm(d, axis=-1) / h
        assert np.abs(npz[f"{b.name}_drift_ratio_cm"] - at_cm).max() <= 1e-12 * peak
        cont_cm, cont_corner = drift_peaks(result, b.name)
        assert summ["buildings"][b.name]["peak_drift_ratio_corner"] == cont_corner.tolist()
        assert summ["buildings"][b.name]["peak_drift_ratio_cm"] == cont_cm.tolist()
        assert np.all(cont_corner >= corner.max(axis=0) - 1e-12 * peak)
        assert np.all(cont_cm >= at_cm.max(axis=0) - 1e-12 * peak)
        assert np.all(corner.max(axis=0) >= at_cm.max(axis=0) * (1 - 1e-12))  # a corner drifts at least as much


def test_overturning_moment_is_the_moment_of_the_storey_shears(written):
    """Overturning moment at the foot of storey s = sum over storeys j >= s of (storey shear of j) x
    h_j (the floor forces above, each at its lever arm; Abel summation), M = (-V_y, V_x) moment
    arms. Rounding of sums of O(10) terms: 1e-12 of the peak moment."""
    scene, _, npz, _ = written
    for b in scene.buildings:
        V = npz[f"{b.name}_storey_shear"]
        h = np.asarray(b.storey_heights)
        M = np.zeros_like(V)
        for s in range(b.n_storeys):
            sumVh = (V[:, s:] * h[s:, None]).sum(axis=1)
            M[:, s] = np.stack([-sumVh[:, 1], sumVh[:, 0]], axis=-1)
        assert np.abs(npz[f"{b.name}_overturning_moment"] - M).max() <= 1e-12 * np.abs(M).max()


def test_floor_acceleration_is_the_equation_of_motion(written):
    """Absolute floor acceleration (smooth part) = -M^-1 (K x + C v), with K and C of the assembled
    building and x, v from the physical histories (v from the modal velocities). Far from
    impacts this equals the second difference of the absolute displacement too; here the
    identity itself is checked, matrix against matrix, to 1e-9 of the peak (K x is a
    difference of terms ~ omega_max^2 |x|, conditioning ~1e4 times rounding)."""
    scene, result, npz, summ = written
    for s in result.systems:
        x = npz[f"{s.name}_cm"].reshape(len(result.t), -1)
        v = result.cm(s.name, velocity=True).reshape(len(result.t), -1)
        acc = -(x @ s.K + v @ s.C) / s.mass
        got = npz[f"{s.name}_floor_acceleration"].reshape(len(result.t), -1)
        peak = np.abs(acc).max()
        assert np.abs(got - acc).max() <= 1e-9 * peak
        a = acc.reshape(len(result.t), s.n_storeys, 3)
        np.testing.assert_allclose(summ["buildings"][s.name]["peak_floor_acceleration"], np.hypot(a[..., 0], a[..., 1]).max(axis=0), rtol=1e-9)


def test_floor_velocity_jumps_are_the_impulses_over_the_masses(written):
    """At every impact instant the floors' velocity jumps carry the impulses: the sum over both
    buildings of m_f dv_f (linear momentum) is zero, and for each building it equals the
    impulses it received, sum_j I_j (+-n_j) (n from the first building towards the second;
    the first building is pushed along -n). Momentum of O(1e5) kg x O(0.1) m/s: 1e-9 relative."""
    scene, result, npz, _ = written
    times = npz["left_impact_time"]
    assert len(times) == len({i.time for i in result.impacts}) > 0
    for k, t in enumerate(times):
        expected = {"left": np.zeros(2), "right": np.zeros(2)}
        for imp in result.impacts:
            if imp.time == t:
                expected["left"] -= imp.impulse * imp.normal
                expected["right"] += imp.impulse * imp.normal
        for name in ("left", "right"):
            m = np.array([s.mass for s in scene.building(name).slabs])
            p = (m[:, None] * npz[f"{name}_floor_velocity_jump"][k][:, :2]).sum(axis=0)
            assert np.abs(p - expected[name]).max() <= 1e-9 * np.abs(expected[name]).max()


def test_hertz_peak_force_and_duration_match_the_contact_ode(written):
    """Elastic Hertz impact of an effective mass m at approach speed b: m delta'' = -k_h delta^1.5,
    delta(0) = 0, delta'(0) = b. Integrated numerically (scipy solve_ivp, rtol 1e-10), its peak
    force k_h delta_max^1.5 and contact time (delta back to 0) must equal the closed forms used
    for impacts.csv (delta_max = (5 m b^2 / 4 k_h)^0.4, tau = (4/5) B(2/5, 1/2) delta_max / b).
    The ODE's own accuracy (rtol 1e-12, events located by root finding on the dense
    output) bounds both to 1e-7 relative. The effective
    mass of each impact is 1/(w . w) with its modal row, recomputed here as sum(1/m + h^2/J) of
    the two slabs for single-point impacts."""
    from scipy.integrate import solve_ivp

    from pounding.framework.post.response import impact_forces

    scene, result, _, _ = written
    force, tau = impact_forces(result)
    kh = 2.75e9
    checked = 0
    for j, imp in enumerate(result.impacts):
        same_instant = [i for i in result.impacts if i.time == imp.time]
        if len(same_instant) != 1 or imp.approach_velocity <= 0:
            continue
        a, fa, b, fb, _ = result.pairs[imp.pair]
        k = int(np.flatnonzero(result.event_t == imp.time)[0])
        inv_m = 0.0
        for bld, f in ((a, fa), (b, fb)):
            name = result.names[bld]
            slab = scene.building(name).slabs[f]
            i0 = result.mode_start[bld]
            s = result.systems[bld]
            dofs = s.modes[3 * f : 3 * f + 3] @ result.event_q[k, i0 : i0 + s.n_dof]
            r = imp.point - (slab.centre + dofs[:2])
            lever = r[0] * imp.normal[1] - r[1] * imp.normal[0]
            inv_m += 1.0 / slab.mass + lever**2 / slab.polar_inertia
        m, v = 1.0 / inv_m, imp.approach_velocity

        def rhs(t, y):
            return [y[1], -kh * max(y[0], 0.0) ** 1.5 / m]

        end = lambda t, y: y[0] if t > 0 else 1.0  # noqa: E731
        end.terminal, end.direction = True, -1
        turn = lambda t, y: y[1]  # noqa: E731  maximum compression: the relative velocity vanishes
        sol = solve_ivp(rhs, (0, 1.0), [0.0, v], rtol=1e-12, atol=1e-15, events=[end, turn], max_step=1e-4)
        dmax = sol.y_events[1][0][0]
        assert force[j] == pytest.approx(kh * dmax**1.5, rel=1e-7)
        assert tau[j] == pytest.approx(sol.t_events[0][0], rel=1e-7)
        checked += 1
    assert checked >= 3


def test_duration_model_is_a_half_sine_pulse():
    """model = "duration": a half-sine pulse F(t) = F sin(pi t / tau) carrying the impulse I has
    int F dt = 2 F tau / pi = I, so F = pi I / (2 tau). Checked on the pair's impacts, exact."""
    import warnings

    from pounding.framework.post.response import impact_forces

    scene = _pounding_pair().with_analysis(duration=1.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run(scene)
    F, tau = impact_forces(result, {"model": "duration", "duration": 0.01})
    assert len(F) == result.n_impacts > 0 and np.all(tau == 0.01)
    I = np.array([i.impulse for i in result.impacts])
    np.testing.assert_allclose(2 * F * tau / np.pi, I, rtol=1e-15)


def test_impacts_csv_header_has_units(written, tmp_path):
    """Every dimensional column of impacts.csv names its unit."""
    import csv

    from pounding.io.results import write_results

    _, result, _, _ = written
    write_results(result, tmp_path / "o")
    header = next(csv.reader(open(tmp_path / "o" / "impacts.csv")))
    for col in ("time [s]", "impulse [N s]", "approach_velocity [m/s]", "energy_loss [J]", "peak_force [N]", "contact_duration [s]"):
        assert col in header
