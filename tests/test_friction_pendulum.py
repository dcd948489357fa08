"""Friction pendulum isolators: the textbook parallelogram loop, the velocity-dependent friction, the
energy identity of a step, OpenSees' equivalent zero-length material, and a base-isolated slab run.

The law is driven on its own (a line of bearings under a prescribed deformation history), each trial
from the committed state and committed, as a converged step would be; then in a scene as a
``storey_springs`` line with ``storeys = 1``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.model.registry import HYSTERESIS
from pounding.hysteresis.friction_pendulum import FrictionPendulum, stored_energy

W, R, MU, UY = 2.0e6, 2.0, 0.06, 5.0e-4  # [N], [m], [-], [m]
EPS = np.finfo(float).eps


def _law(**kw):
    args = dict(weight=W, radius=R, friction=MU, yield_displacement=UY)
    args.update(kw)
    return FrictionPendulum(**args)


def drive(law, path, rates=None):
    """Forces (len(path),), tangents and states after each deformation of ``path`` [m], at the
    rates ``rates`` [m/s] (default 0: rate-independent use)."""
    cls = type(law)
    params = np.atleast_2d(law.pack(*law.own_values()))
    state, trial = np.zeros((1, cls.n_state)), np.zeros((1, cls.n_state))
    rates = np.zeros(len(path)) if rates is None else rates
    force, tangent, states = [], [], []
    for u, v in zip(path, rates):
        r, kt, _ = cls.update(float(u), float(v), state, params, trial, 0)
        state[:] = trial
        force.append(r)
        tangent.append(kt)
        states.append(state[0].copy())
    return np.array(force), np.array(tangent), np.array(states)


def cycle_path(amplitude, steps):
    """0 -> D, then D -> -D -> D (one full cycle), ``steps`` increments per quarter; index of the first D."""
    up = np.linspace(0.0, amplitude, steps + 1)
    down = np.linspace(amplitude, -amplitude, 2 * steps + 1)[1:]
    back = np.linspace(-amplitude, amplitude, 2 * steps + 1)[1:]
    return np.concatenate([up, down, back]), steps


def test_registered_and_sets_the_storey_values_from_its_own_parameters():
    """The law is found by name, and fixes the element's values as a bilinear isolator does:
    k0 = W/R + mu W/u_y, Fy = k0 u_y = W u_y / R + mu W (the force at which sliding starts),
    b = (W/R) / k0 (post-sliding over initial stiffness), to rounding."""
    assert HYSTERESIS.get("friction_pendulum") is FrictionPendulum
    k0, fy, b = _law().own_values()
    assert k0 == pytest.approx(W / R + MU * W / UY, rel=4 * EPS)
    assert fy == pytest.approx(W * UY / R + MU * W, rel=4 * EPS)
    assert b * k0 == pytest.approx(W / R, rel=4 * EPS)


def test_slow_cycle_is_the_textbook_parallelogram():
    """A slow cycle of amplitude D = 200 u_y (constant mu): the loop is the parallelogram of the
    textbook bilinear isolator (Zayas et al. 1990; Naeim & Kelly 1999, ch. 5):

    * off the elastic corners (2 u_y after each reversal) F = (W/R) u +- mu W: the slider's force
      is the friction bound exactly, so they agree to rounding (a few ulps of the largest force);
    * the dissipated energy per cycle is 4 mu W (D - u_y), the parallelogram's area: each sliding
      branch runs over 2 (D - u_y) at the force mu W; the law's dissipation is exact per step, so
      the sum equals it to the rounding of ~2000 additions (1e-12 relative);
    * the effective stiffness at D is F(D) / D = W/R + mu W / D (exactly, since F(D) = W D / R + mu W);
    * the effective damping E_D / (2 pi K_eff D^2) is the textbook 2 mu / (pi (mu + D/R)) times
      (1 - u_y / D), the elastic corners' share (u_y / D of it)."""
    law = _law()
    D = 200.0 * UY
    path, k_top = cycle_path(D, 500)
    r, kt, st = drive(law, path)
    fmax = W * D / R + MU * W
    # off the corners: the reversals are at indices k_top and 3 k_top (every step is D / 500 = 0.4 u_y)
    idx = np.arange(len(path))
    sliding = np.ones(len(path), bool)
    for rev in (k_top, 3 * k_top):
        sliding[(idx > rev) & (idx <= rev + 5)] = False  # 2 u_y = 5 steps of 0.4 u_y
    sliding[0:3] = False  # the first loading from rest: u_y = 2.5 steps
    direction = np.sign(np.diff(path, prepend=0.0))  # of the step arriving at each point
    expected = W * path / R + MU * W * direction
    assert np.max(np.abs(r - expected)[sliding]) <= 8 * EPS * fmax
    assert np.all(kt[sliding] == pytest.approx(W / R, rel=4 * EPS))
    dissipated = st[-1, 2] - st[k_top, 2]
    area = 4.0 * MU * W * (D - UY)
    assert dissipated == pytest.approx(area, rel=1e-12)
    k_eff = r[k_top] / D
    assert k_eff == pytest.approx(W / R + MU * W / D, rel=8 * EPS)
    beta_eff = dissipated / (2.0 * math.pi * k_eff * D * D)
    textbook = 2.0 * MU / (math.pi * (MU + D / R))
    assert beta_eff == pytest.approx(textbook * (1.0 - UY / D), rel=1e-12)  # = textbook - (u_y / D) textbook


def test_rest_and_small_motions_are_exactly_the_initial_stiffness():
    """Before the slider first slides the force is k0 u bit for bit (the stepping's exact elastic
    reduction needs it: base.py, item 7), with tangent k0, and nothing is dissipated."""
    law = _law()
    k0 = law.own_values()[0]
    path = np.linspace(-0.9 * UY, 0.9 * UY, 37)
    r, kt, st = drive(law, path)
    assert np.array_equal(r, k0 * path)
    assert np.all(kt == k0)
    assert np.all(st[:, 2] == 0.0)


def test_steady_sliding_force_follows_the_velocity_dependent_friction():
    """Sliding at a steady rate V with mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|) (OpenSees'
    VelDependent): once the rate of a committed step is V, the force is (W/R) u + mu(V) W, to
    rounding. The first step from rest slides at mu_slow (the rate at rest is 0). Three rates span
    the transition (a V = 0.2, 2, 20)."""
    slow, fast, a = 0.03, 0.09, 20.0
    law = _law(friction=fast, friction_slow=slow, rate=a)
    h = 1e-3
    for V in (0.01, 0.1, 1.0):
        n = 200
        path = V * h * np.arange(1, n + 1)
        r, _, _ = drive(law, path, np.full(n, V))
        mu_v = fast - (fast - slow) * math.exp(-a * V)
        later = path > 3 * UY  # past the elastic start (the slider's u_y at mu_slow is smaller)
        later[0] = False
        expected = W * path / R + mu_v * W
        assert np.max(np.abs(r - expected)[later]) <= 8 * EPS * np.max(np.abs(r))


def test_the_energy_of_every_step_is_the_work_done_on_it():
    """Passivity and exactness with velocity-dependent friction: over every step of a random path at
    random rates (the bound changes between steps, and falls below the committed force where the
    slider slows), the work done on the bearing, the integral of the force along the step's own
    path, equals the change of the stored energy plus the step's dissipation, which is never
    negative. The path integral is taken independently of the law's dissipation: the trial force at
    400 points between the step's ends (each a trial from the committed state), by the trapezoid
    rule, whose error is at most k0 (du / 400)^2 / 8 per kink of the piecewise-linear force (two at
    most: the relaxation at the start and the onset of sliding)."""
    law = _law(friction=0.1, friction_slow=0.04, rate=30.0)
    cls = type(law)
    params = np.atleast_2d(law.pack(*law.own_values()))
    k0 = params[0, 0]
    rng = np.random.default_rng(3)
    h = 0.005
    du = UY * rng.normal(0.0, 2.0, 150)
    state, trial = np.zeros((1, cls.n_state)), np.zeros((1, cls.n_state))
    relaxed = 0
    for step in du:
        u0 = state[0, 0]
        u1 = u0 + step
        m = 400
        us = np.linspace(u0, u1, m + 1)
        f = np.empty(m + 1)
        for j in range(m + 1):  # j = 0: the force once relaxed, at u0 (the relaxation does no work)
            f[j], _, _ = cls.update(float(us[j]), step / h, state, params, trial, 0)
        work = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(us)))
        cls.update(float(u1), step / h, state, params, trial, 0)
        bound = params[0, 3] * (params[0, 4] - (params[0, 4] - params[0, 5]) * math.exp(-params[0, 6] * abs(state[0, 4])))
        relaxed += abs(params[0, 8] * (state[0, 0] - state[0, 3])) > bound
        d_stored = stored_energy(trial[0], params[0]) - stored_energy(state[0], params[0])
        d_diss = trial[0, 2] - state[0, 2]
        assert d_diss >= 0.0
        quadrature = 2 * k0 * (step / m) ** 2 / 8
        assert abs(work - (d_stored + d_diss)) <= quadrature + 64 * EPS * (abs(work) + abs(d_stored) + d_diss)
        state[:] = trial
    assert relaxed > 0  # the path did make the bound fall below the committed force


def test_a_step_split_into_substeps_dissipates_the_same():
    """Rate-independent use (constant mu): the update's dissipation is exact along its path, so a step
    split into 10 equal substeps, each committed, ends in the same state with the same dissipated
    energy (to the rounding of the sum: 1e-12 of it) on a path of random steps across the elastic range."""
    law = _law()
    rng = np.random.default_rng(5)
    coarse = np.cumsum(UY * rng.normal(0.0, 3.0, 200))
    fine = np.concatenate([[0.0], coarse])
    fine = np.concatenate([np.linspace(a, b, 11)[1:] for a, b in zip(fine[:-1], fine[1:])])
    r1, _, st1 = drive(law, coarse)
    r2, _, st2 = drive(law, fine)
    np.testing.assert_allclose(r2[9::10], r1, rtol=0, atol=1e-12 * np.max(np.abs(r1)))
    assert st2[-1, 2] == pytest.approx(st1[-1, 2], rel=1e-12)


def _opensees_material_path(ops, path):
    ops.wipe()
    ops.uniaxialMaterial("Elastic", 1, W / R)
    ops.uniaxialMaterial("ElasticPP", 2, MU * W / UY, UY)
    ops.uniaxialMaterial("Parallel", 3, 1, 2)
    ops.testUniaxialMaterial(3)
    force, tangent = [], []
    for u in path:
        ops.setStrain(float(u))
        force.append(ops.getStress())
        tangent.append(ops.getTangent())
    ops.wipe()
    return np.array(force), np.array(tangent)


@pytest.mark.opensees
def test_constant_friction_is_opensees_pendulum_beside_elastic_perfectly_plastic(opensees):
    """A random path (cycles growing to 60 u_y, random increments, reversals inside the elastic
    range) through OpenSees' zero-length equivalent of the bearing, Parallel(Elastic(W/R),
    ElasticPP(mu W / u_y, u_y)) (singleFPBearing's small-displacement force with Coulomb friction):
    both clip the same elastic trial of the slider, so the forces agree to rounding, and the tangents
    (W/R or k0) to rounding of the sum W/R + k_i.

    The forces' rounding: each code forms the trial k0 (u - u_p) from a slip deformation u_p set at the
    last slip, where u and u_p reach 60 u_y but differ by at most u_y; u_p carries the rounding of
    eps |u| it was set with and the difference another half ulp of u, so the slider's force is
    rounded to ~2 eps k0 max|u|, and adding W/R u rounds to eps of the force: 8 eps (k0 max|u| +
    max|F|) covers both codes (8.4e-14 of the peak force here, where k0 max|u| is 46 times it;
    measured 5.2e-15)."""
    law = _law()
    rng = np.random.default_rng(1)
    k = np.arange(401)
    path = UY * (60.0 * k / 400 * np.sin(2.0 * np.pi * k / 60.0) + np.concatenate([[0.0], rng.normal(0.0, 0.8, 400)]))
    r, kt, _ = drive(law, path)
    r_os, kt_os = _opensees_material_path(opensees, path)
    k0 = law.own_values()[0]
    assert np.max(np.abs(r - r_os)) <= 8 * EPS * (k0 * np.max(np.abs(path)) + np.max(np.abs(r)))
    np.testing.assert_allclose(kt, kt_os, rtol=4 * EPS)


@pytest.mark.parametrize("params, field, words", [
    ({"radius": 0.0}, "radius", "> 0"),
    ({"weight": -1.0}, "weight", "> 0"),
    ({"friction": 1.2}, "friction", "(0, 1]"),
    ({"friction": 0.0}, "friction", "elastic spring"),
    ({"yield_displacement": 0.0}, "yield_displacement", "> 0"),
    ({"friction_slow": 0.02}, "rate", "both"),
    ({"friction_slow": 0.08, "rate": 10.0}, "friction_slow", "(0, friction]"),
    ({"friction_slow": 0.02, "rate": -1.0}, "rate", "> 0"),
    ({"radius": float("nan")}, "radius", "finite"),
])
def test_parameters_out_of_range_are_rejected(params, field, words):
    """One InputError per bad parameter, naming it and the range expected."""
    with pytest.raises(InputError) as exc:
        _law(**params)
    assert exc.value.field == field
    assert words in str(exc.value)


# -- a base-isolated slab ----------------------------------------------------------------------------

G = 9.81
MASS = 4.0e5  # [kg]


def _line(start, end, **kw):
    table = {"name": "friction_pendulum", "weight": MASS * G / 2, "radius": R, "friction": MU}
    table.update(kw)
    return {"type": "storey_springs", "start": start, "end": end, "storeys": 1, "hysteresis": table}


def _isolated_slab(dt, duration=6.0, **kw):
    """A rigid 12 m x 10 m slab of 400 t on four lines of bearings, each line carrying half the weight
    (two lines per direction), shaken along x: the x lines slide, the y lines stay still."""
    lines = [_line([0, 0], [12, 0], **kw), _line([0, 10], [12, 10], **kw), _line([0, 0], [0, 10], **kw),
             _line([12, 0], [12, 10], **kw)]
    building = {"name": "iso", "storey_heights": [1.0], "slab": [[0, 0], [12, 0], [12, 10], [0, 10]], "mass": MASS,
                "damping": {"type": "rayleigh", "ratio": 0.0, "modes": [1, 2]}, "element": lines}
    return {"building": [building], "ground_motion": {"record": "elcentro", "pga": 0.5, "angle": 0.0},
            "analysis": {"integrator": "newmark", "dt": dt, "duration": duration, "contact": "none"}}


def _run(dt, **kw):
    from pounding.framework.post.inelastic_run import run_inelastic
    from pounding.io.scene import parse_scene

    return run_inelastic(parse_scene(_isolated_slab(dt, **kw))).buildings[0]


@pytest.mark.parametrize("friction", [{}, {"friction": 0.09, "friction_slow": 0.04, "rate": 20.0}],
                         ids=["constant", "velocity-dependent"])
def test_isolated_slab_energy_account_books_the_friction(friction):
    """A slab on friction pendulum lines under 6 s of El Centro at 0.5 g, average acceleration at
    dt = 5 ms:

    * input = kinetic + strain + damping + hysteretic closes to rounding (the integrator's exact
      identity: each of the 1200 steps adds its terms to a handful of running sums, each addition
      rounding by at most eps of the sums, which stay below the input: within 8 eps per step);
    * the law's own dissipation (exact along each step's path) is never decreasing, and differs from
      the audit's (the trapezoidal rule on step ends) only in the steps where sliding starts again
      (the force's kink): in such a step the trapezoid misses at most Q |du| (the slider's force
      changes by at most 2Q at the kink), summed over those steps;
    * passivity bounds the peak: the pendulum's stored energy (W/R) D^2 / 2 at the peak D never
      exceeds the work put in, so D <= sqrt(2 E_input / (W/R)) over the two sliding lines."""
    b = _run(0.005, **friction)
    e = b.energy
    assert abs(e["relative_error"]) <= 8 * EPS * (len(b.deformation) - 1)
    x_lines = [0, 1]
    diss = b.dissipated[:, x_lines]
    assert np.all(np.diff(diss, axis=0) >= 0.0)
    assert e["hysteretic_law"] > 0.5 * e["input"]  # sliding is where the input goes (no viscous damping)
    q_max = max(friction.get("friction", MU), MU) * MASS * G / 2
    inc = np.diff(diss, axis=0) > 0.0
    starts = inc[1:] & ~inc[:-1]  # steps where the slider starts sliding again
    du = np.abs(np.diff(b.deformation[:, x_lines], axis=0))[1:]
    assert abs(e["hysteretic"] - e["hysteretic_law"]) <= q_max * float(np.sum(du[starts])) + 1e-12 * e["input"]
    peak = float(np.max(np.abs(b.deformation[:, x_lines])))
    assert 0.0 < peak <= math.sqrt(2.0 * e["input"] / (2 * (MASS * G / 2) / R))


def test_isolated_slab_peak_converges_with_the_step():
    """The peak isolator displacement D at 10 ms and 5 ms against a 0.5 ms reference. Away from the
    sliding onsets the stepping is average acceleration's, second order (its period error at the
    isolated period 2 pi sqrt(R/g) = 2.8 s, 280 steps of 10 ms, is 1e-5). A step where the slider
    starts sliding again straddles the force's kink and may misbook the work by Q |du| (see the
    energy test); an energy error dE before the peak moves it by about dE / F(D), F(D) = (W/R) D + Q
    the force there. So the relative error of D is within sum(Q |du|) / (F(D) D) over the onsets
    before the peak: a bound of first order in the step (measured 0.84 % within 2.5 % at 10 ms,
    0.007 % within 1.3 % at 5 ms)."""
    ref = float(np.max(np.abs(_run(0.0005).deformation[:, 0])))
    q = MU * MASS * G / 2
    for dt in (0.01, 0.005):
        b = _run(dt)
        u = b.deformation[:, 0]
        k = int(np.argmax(np.abs(u)))
        inc = np.diff(b.dissipated[:, 0]) > 0.0
        onsets = np.flatnonzero(inc[1:] & ~inc[:-1]) + 1  # step n (u[n] -> u[n+1]) starts sliding
        onsets = onsets[onsets < k]
        de = q * float(np.sum(np.abs(u[onsets + 1] - u[onsets])))
        peak = abs(u[k])
        force = MASS * G / 2 / R * peak + q
        assert abs(peak - ref) <= de / force


def _with_first_line(change):
    import copy

    from pounding.io.scene import parse_scene

    data = copy.deepcopy(_isolated_slab(0.01))
    change(data["building"][0]["element"][0])
    return parse_scene(data)


LINE = "building[0].element[0]"


@pytest.mark.parametrize("change, field, words", [
    (lambda e: e.update(stiffness=1.0e8), LINE + ".stiffness", "remove stiffness"),
    (lambda e: e.update(yield_force=1.0e5), LINE + ".yield_force", "remove yield_force"),
    (lambda e: e.update(hardening=0.1), LINE + ".hardening", "remove hardening"),
    (lambda e: e.update(hysteresis="friction_pendulum"), LINE + ".hysteresis", "needs weight, radius, friction"),
    (lambda e: e["hysteresis"].update(radius=-1.0), LINE + ".hysteresis.radius", "> 0"),
    (lambda e: e.pop("hysteresis"), LINE + ".stiffness", "missing the initial storey stiffness"),
], ids=["stiffness", "yield_force", "hardening", "no parameters", "radius", "no law, no stiffness"])
def test_the_element_takes_its_values_from_the_law_and_names_what_is_wrong(change, field, words):
    """storey_springs with the friction pendulum: the law sets k0, Fy and b (own_values), so the
    element's stiffness, yield_force and hardening would say it twice and are refused; without such
    a law the stiffness is required. One InputError naming the key path."""
    with pytest.raises(InputError) as exc:
        _with_first_line(change)
    assert field in str(exc.value) and words in str(exc.value)


def test_the_element_is_the_law_s_bilinear_isolator_and_round_trips(tmp_path):
    """A line of bearings is a storey spring of the law's k0, Fy, b (its lateral stiffness W/R +
    mu W/u_y in the initial modes), and writing the scene then loading it gives the same scene
    (the table keeps the law's parameters, not the element's values derived from them)."""
    from pounding.io.scene import load_scene
    from pounding.io.scene_writer import scene_differences, write_scene

    scene = _with_first_line(lambda e: e["hysteresis"].update(friction_slow=0.03, rate=20.0))
    line = scene.buildings[0].elements[0]
    k0, fy, b = line.law.own_values()
    assert line.stiffness == (k0,) and line.yield_force == (fy,) and line.hardening == b
    assert line.lateral_stiffness()[0, 0] == k0
    again = load_scene(write_scene(scene, tmp_path / "scene.toml"))
    assert scene_differences(scene, again) == []
    assert again.buildings[0].elements[0].law.describe() == line.law.describe()


def _single_fp_bearing_cycle(ops, path, k_init):
    """OpenSees' 2-D singleFPBearing (Coulomb friction mu, radius R, initial stiffness k_init) under
    the vertical load W and the horizontal displacements ``path`` (static, displacement control):
    its horizontal force at each point."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.node(2, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.fix(2, 0, 0, 1)
    ops.frictionModel("Coulomb", 1, MU)
    ops.uniaxialMaterial("Elastic", 2, 1e13)  # axial: stiff
    ops.uniaxialMaterial("Elastic", 3, 1e13)  # moment
    # local x (the bearing's axis) vertical; its iteration on the normal force to 1e-6 N (1e-11 of the forces)
    ops.element("singleFPBearing", 1, 1, 2, 1, R, k_init, "-P", 2, "-Mz", 3, "-orient", 0.0, 1.0, 0.0, -1.0, 0.0, 0.0,
                "-iter", 100, 1e-6)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -W, 0.0)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-14, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    assert ops.analyze(1) == 0
    ops.loadConst("-time", 0.0)
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    ops.load(2, 1.0, 0.0, 0.0)
    force = []
    for a, b in zip(path[:-1], path[1:]):
        ops.integrator("DisplacementControl", 2, 1, float(b - a))
        assert ops.analyze(1) == 0
        ops.reactions()
        force.append(-ops.nodeReaction(1, 1))
    ops.wipe()
    return np.array(force)


@pytest.mark.opensees
def test_single_fp_bearing_is_the_law_with_its_normal_force(opensees):
    """OpenSees' singleFPBearing (kInit = the law's k0) on a slow cycle to D = R / 20: its normal force
    includes the horizontal force's component along the dish's normal, N = W + F u / R (its
    equilibrium on the displaced slider, in its source), where the law keeps N = W. On the sliding branches both
    are N (u / R +- mu), so OpenSees' force times W / N is the law's, to its iteration tolerance
    (1e-10 of the force); unscaled they differ by F (u / R)(u / R +- mu), 0.55 % at D = R / 20, mu = 0.06
    (second order in u / R: the law's small-displacement form)."""
    law = _law()
    D = R / 20.0
    path, k_top = cycle_path(D, 250)
    r, _, _ = drive(law, path)
    f_os = _single_fp_bearing_cycle(opensees, path, law.own_values()[0])
    r = r[1:]
    u = path[1:]
    idx = np.arange(1, len(path))
    sliding = np.ones(len(u), bool)
    for rev in (k_top, 3 * k_top):  # the elastic corners: 2 u_y after each reversal, 3 steps of D / 250 = 0.8 u_y
        sliding[(idx > rev) & (idx <= rev + 3)] = False
    sliding[idx <= 2] = False  # the first u_y from rest
    n_os = W + f_os * u / R  # its normal force (SingleFPSimple2d::update; the axial force stays W)
    scaled = f_os * W / n_os
    assert np.max(np.abs(r - scaled)[sliding]) <= 1e-10 * np.max(np.abs(r))
    gap = np.abs(f_os - r)[sliding]
    assert np.all(gap <= np.abs(f_os[sliding]) * np.abs(u[sliding]) / R * (np.abs(u[sliding]) / R + MU) * (1 + 1e-9) + 1e-10 * W)


@pytest.mark.opensees
def test_isolated_slab_matches_opensees(opensees):
    """The isolated slab (constant friction) against OpenSees: each line a twoNodeLink with Steel01 of
    the law's k0, Fy, b (W/R beside the elastic-perfectly-plastic slider is kinematic hardening),
    the same Newmark average acceleration at dt = 5 ms, Newton on the full equations. The slab's u,
    displacement and every line's force within 1e-5 of the peak, the requirement of the other
    yielding buildings (tests/test_opensees_inelastic.py; measured 2.8e-13 and 1.0e-11: the two
    Newton tolerances and rounding)."""
    from pounding.framework.post.inelastic_run import run_inelastic
    from pounding.io.scene import parse_scene
    from pounding.peer.opensees_springs import run_springs_transient

    scene = parse_scene(_isolated_slab(0.005))
    result = run_inelastic(scene)
    b = result.buildings[0]
    disp, forces, _ = run_springs_transient(opensees, scene.buildings, scene.ground_motion, result.dt, result.steps)
    ours, peer = b.cm(), disp["iso"]
    peak = np.abs(peer[:, :, 0]).max()
    assert peak > 50 * UY  # it slides, far beyond the elastic corners
    assert np.abs(ours[:, :, 0] - peer[:, :, 0]).max() <= 1e-5 * peak
    # shaken along x, the symmetric slab neither moves in y nor twists (twist times the 12 m plan size), in either code
    for c, scale in ((1, 1.0), (2, 12.0)):
        assert max(np.abs(ours[:, :, c]).max(), np.abs(peer[:, :, c]).max()) * scale <= 1e-12 * peak
    assert np.abs(b.force - forces["iso"]).max() <= 1e-5 * np.abs(forces["iso"]).max()
