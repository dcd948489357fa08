"""Pounding between buildings with yielding storey springs (the driver, :mod:`pounding.framework.engine.yielding`).

Two eccentric 3-storey buildings on storey springs side by side along x, the right one half as
strong and 0.6 times as stiff, shaken along x by El Centro at 0.32 g: both yield, unequally, and they collide.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.engine.driver import Driver

from pounding.framework.post.run import run
from pounding.framework.post.energy_account import building_balances
from pounding.framework.engine.inelastic import NEWTON_TOL
from pounding.framework.post.inelastic_run import run_inelastic
from pounding.io.scene import parse_scene

from inelastic_scenes import eccentric_building
from test_impacts import RecordingDriver, closing_speed, kinetic, lever_arms, momenta
from pounding.framework.post.energy_account import energy_balance

EPS = np.finfo(float).eps


def pair(gap: float, *, contact_params=None, **kw):
    """The pair, ``gap`` [m] apart (:func:`pair_data`), parsed; ``contact_params`` replace the law's."""
    scene = parse_scene(pair_data(gap, **kw))
    if contact_params is not None:
        scene = scene.with_analysis(contact_params=contact_params)
    return scene


def pair_data(gap: float, *, strength: float = 1.0, duration: float = 5.0, dt: float = 0.01, contact="impulse",
              yielding: bool = True) -> dict:
    """The pair's scene dict, ``gap`` [m] apart; ``strength`` scales both buildings' yield forces (the
    right one has half the left one's); ``yielding=False`` drops yield_force (elastic springs)."""
    left = eccentric_building("left", strength=strength)
    right = eccentric_building("right", x0=15.0 + gap, strength=0.5 * strength)
    for e in right["element"]:  # and 0.6 times as stiff, so that the pair moves out of phase
        e["stiffness"] = (0.6 * np.asarray(e["stiffness"], dtype=float)).tolist()
    if not yielding:
        for b in (left, right):
            for e in b["element"]:
                for key in ("yield_force", "hardening", "hysteresis"):
                    e.pop(key, None)
    return {
        "building": [left, right],
        "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": 0.0},
        "analysis": {"integrator": "newmark", "dt": dt, "duration": duration, "contact": contact},
    }


EQUILIBRIUM = {"restitution": 0.5, "after_impact": "equilibrium"}


@pytest.fixture(scope="module")
def pounding_run():
    d = RecordingDriver(pair(0.01, contact_params=EQUILIBRIUM))
    return d, d.run()


def test_a_gap_wider_than_any_approach_is_the_contact_free_inelastic_run():
    """With the buildings 1 m apart (they approach by centimetres) nothing touches, and the driver's
    run equals :func:`run_inelastic` (contact off) to rounding.

    Both solve the same step equations; each step's Newton stops within NEWTON_TOL u_y,min of the
    exact end deformations, and their arithmetic differs by rounding (numpy here, compiled loops
    there). Tolerance: each spring's deformation within 2 NEWTON_TOL u_y,min per step over every
    step, plus 1e3 eps of the peak for the sums' rounding (measured 1e-15 of the peak)."""
    scene = pair(1.0)
    r = run(scene)
    assert r.n_impacts == 0
    free = run_inelastic(scene.with_analysis(contact="none"))
    d = Driver(scene)
    for i, b in enumerate(free.buildings):
        q = r.q[:, r.mode_start[i]:r.mode_start[i] + b.q.shape[1]]
        u, u_free = q @ (b.springs.T @ b.system.modes).T, b.deformation  # spring deformations (nt, ns)
        assert np.max(b.ductility) > 2.0  # the springs do yield
        tol = 2 * NEWTON_TOL * b.springs.yield_deformation.min() * r.steps + 1e3 * EPS * np.abs(u_free).max()
        assert np.abs(u - u_free).max() <= tol
    assert d.springs is not None and d.use_kernel  # yielding scenes run compiled between contact events


def test_every_impulse_conserves_momentum_and_loses_the_newton_energy(pounding_run):
    """At every impulse of the yielding pair: linear and angular momentum of the slabs are conserved
    to 1e-12 of the size of the jumps (the impulses are internal; the springs act over time, not at
    the instant), and a single-point impact loses (1 - k^2) b^2 / (2 a) as for elastic buildings
    (a = sum 1/m + h^2/J, lever arms about the displaced centres), to 1e-10 of the loss (the
    kinetic energies differenced are ~100 times the loss)."""
    d, r = pounding_run
    assert len(d.events) >= 5
    k, single = 0.5, 0
    for ev in d.events:
        p0, L0, _, _ = momenta(d.model, ev["q"], ev["before"])
        _, _, ps, Ls = momenta(d.model, ev["q"], ev["after"] - ev["before"])
        p1, L1, _, _ = momenta(d.model, ev["q"], ev["after"])
        assert np.all(np.abs(p1 - p0) <= 1e-12 * ps), ev["t"]
        assert abs(L1 - L0) <= 1e-12 * Ls, ev["t"]
        if len(ev["impacts"]) == 1:
            (imp,) = ev["impacts"]
            b = closing_speed(d.model, imp.pair, ev["q"], ev["before"], imp.point, imp.normal)
            h_a, h_b, sa, sb = lever_arms(d.model, imp.pair, ev["q"], imp.point, imp.normal)
            a = 1 / sa.mass + h_a**2 / sa.polar_inertia + 1 / sb.mass + h_b**2 / sb.polar_inertia
            loss = (1 - k**2) * b**2 / (2 * a)
            drop = kinetic(d.model, ev["before"]) - kinetic(d.model, ev["after"])
            assert drop == pytest.approx(loss, rel=1e-10), ev["t"]
            single += 1
    assert single >= 1


def test_energy_audit_closes_to_rounding_with_average_acceleration_and_equilibrium(pounding_run):
    """input = kinetic + strain + damping + impact losses + hysteretic (+ contact-force work), per
    building, for Newmark average acceleration with accelerations in equilibrium after impulses: the
    trapezoidal rule is the scheme's exact work identity, so the audit closes to rounding: 1e3 eps
    of the input (~500 steps of sums)."""
    d, r = pounding_run
    assert r.n_impacts >= 5
    eb = energy_balance(r)
    assert eb["hysteretic"] > 0.3 * eb["input"]  # the springs dissipate much of the input
    assert abs(eb["relative_error"]) <= 1e3 * EPS
    for name, b in building_balances(r).items():
        assert abs(b["relative_error"]) <= 1e3 * EPS, name


def test_springs_that_cannot_yield_give_the_elastic_pounding_run():
    """Yield forces 1e12 times the real ones: no spring leaves its initial branch, every remainder
    is exactly 0, and the run (Python path) equals today's elastic pounding run of the same pair
    without yield_force (compiled core) with the same impacts, to rounding: the two paths apply the
    same impulses with different arithmetic (numpy, compiled), 1e-9 of the peak allows the
    rounding's growth over the ~28 impacts (measured: equal bit for bit)."""
    strong = run(pair(0.01, strength=1e12, contact_params=EQUILIBRIUM))
    elastic = run(pair(0.01, yielding=False, contact_params=EQUILIBRIUM))
    assert strong.n_impacts == elastic.n_impacts >= 5
    assert np.abs(strong.q - elastic.q).max() <= 1e-9 * np.abs(elastic.q).max()
    for a, b in zip(strong.impacts, elastic.impacts):
        assert a.time == pytest.approx(b.time, abs=1e-9)


def test_yielding_pounding_converges_to_the_rigid_impact_limit_as_dt_shrinks():
    """The rigid-impact (impulse) model's answer is the limit of the stepped runs as dt -> 0 with
    impacts located to a tight tolerance: the peak spring deformations of dt = 0.01, 0.005, 0.0025
    and 0.00125 s differ from the next finer run by less each time, and the last difference is
    below 1% of the peak (2 s, the first 5 impacts; measured differences 1.2e-4, 2.9e-5, 8.3e-6 m
    against a peak of 0.022 m: the integrator's second order)."""
    peaks = []
    for dt in (0.01, 0.005, 0.0025, 0.00125):
        d = Driver(pair(0.01, duration=2.0, dt=dt, contact_params={"restitution": 0.5, "locate": "root", "tolerance": 1e-7}))
        r = d.run()
        assert r.n_impacts >= 1
        peaks.append(d.springs.peak.copy())
    diffs = [np.abs(a - b).max() for a, b in zip(peaks, peaks[1:])]
    assert all(b < a for a, b in zip(diffs, diffs[1:])), diffs
    assert diffs[-1] <= 0.01 * np.abs(peaks[-1]).max(), diffs


def _same_run(a, b, tol_q: float | None, tol_u: float) -> None:
    """The two runs' histories agree: modal displacements within tol_q of their peak (None: not
    compared), every spring's deformation and peak within tol_u [m], the same impacts."""
    assert a.n_impacts == b.n_impacts
    if tol_q is not None:
        assert np.abs(a.q - b.q).max() <= tol_q * np.abs(b.q).max()
    for name in b.springs:
        assert np.abs(a.springs[name]["deformation"] - b.springs[name]["deformation"]).max() <= tol_u, name
        assert np.abs(a.springs[name]["peak"] - b.springs[name]["peak"]).max() <= tol_u, name


def test_compiled_stretches_between_impacts_give_the_python_path():
    """A yielding pair pounding with impulses (equilibrium after impacts), run twice: with its
    stretches between contact events compiled (:func:`pounding.framework.engine.spring_core.stretch`) and
    every step in Python (``use_kernel=False``). The compiled stretch hands every step that ends
    with a pair within the tolerance back to the Python step, and takes the others with the same
    compiled functions in the same order (springs' Newton, end load, work rule), so the runs agree
    to rounding (measured: bit for bit). Tolerance: one rounding per operation of a step (~1e2 eps of
    the peak for the ~30 modes and springs of a row) accumulated over every step, which the
    contracting step does not amplify; the same impacts. Their instants: the event search of each
    run stops where the gap is within Driver.eps [m] of zero, so at the approach speed b two runs
    whose states differ by delta [m] of a vertex locate a strike within (2 eps + delta) / b of each
    other (bit for bit when the states are; measured: equal)."""
    scene = pair(0.01, contact_params=EQUILIBRIUM)
    compiled, python = Driver(scene), Driver(scene, use_kernel=False)
    a, b = compiled.run(), python.run()
    assert a.n_impacts >= 5 and max(max(sp["peak"] / sp["yield_deformation"]) for sp in b.springs.values()) > 2.0
    tol = 1e2 * EPS * a.steps
    _same_run(a, b, tol, tol * max(np.abs(sp["deformation"]).max() for sp in b.springs.values()))
    assert a.n_impacts == b.n_impacts
    delta = tol * max(np.nanmax(np.abs(b.vertices(n))) for n in b.names)
    for x, y in zip(a.impacts, b.impacts):
        assert x.pair == y.pair
        assert abs(x.time - y.time) <= (2.0 * compiled.eps + delta) / y.approach_velocity
    for name in a.energy:
        for key, value in b.energy[name].items():
            assert abs(a.energy[name][key] - value) <= tol * max(abs(v) for v in b.energy[name].values()), (name, key)


def test_compiled_stretches_with_penalty_contact_give_the_python_path():
    """The same pair with penalty contact: the Python step solves the springs by the fixed point around
    the penalty solve, stopped when the remainders change by less than NEWTON_TOL u_y,min k0, the
    compiled stretch by Newton to a residual below NEWTON_TOL u_y,min. Both are within
    NEWTON_TOL u_y,min of the step's exact end deformations; tolerance: twice that per step over
    every step (the step does not amplify differences), plus rounding (measured: 1e-14 m against a
    bound of 4e-13 m)."""
    scene = pair(0.01, contact="penalty", contact_params={"stiffness": 1e9, "restitution": 1.0})
    a, b = Driver(scene).run(), Driver(scene, use_kernel=False).run()
    uy = min(sp["yield_deformation"].min() for sp in b.springs.values())
    tol_u = 2 * NEWTON_TOL * uy * a.steps + 1e2 * EPS * a.steps * max(np.abs(sp["deformation"]).max() for sp in b.springs.values())
    assert any(e["contact_forces"] != 0.0 for e in b.energy.values())  # the penalty springs did act
    _same_run(a, b, None, tol_u)
