"""True peaks: extremes over the continuous trajectory (pounding.framework.engine.peaks), not over step ends."""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.engine import peaks
from pounding.solvers.exact import Exact


def free_segments(omega, dt, nsteps, phase=0.0):
    """Step ends (q, q') of q = cos(omega t + phase) (exact), as the pieces of a run of one mode."""
    t = np.arange(nsteps + 1) * dt
    q = np.cos(omega * t + phase)[:, None]
    v = (-omega * np.sin(omega * t + phase))[:, None]
    return peaks.Segments(t[:-1], np.diff(t), q[:-1], v[:-1], q[1:], v[1:])


def test_cubic_closed_form_matches_dense_sampling():
    """The closed-form extreme of a cubic Hermite (roots of the quadratic y') equals the maximum of
    |y| sampled densely on the same cubic, to the sampling resolution (1e-6 of the step: the value
    error is second order there, 1e-12 of the slopes' scale, far below the 1e-9 asked)."""
    rng = np.random.default_rng(3)
    y0, y1, m0, m1 = rng.normal(size=(4, 200))
    best, where = peaks.hermite_extremes(y0, y1, m0, m1)
    s = np.linspace(0.0, 1.0, 1_000_001)[:, None]
    dense = np.max(np.abs(peaks.hermite_value(y0, y1, m0, m1, s)), axis=0)
    assert np.allclose(best, dense, rtol=0.0, atol=1e-9)
    scalar = np.array([peaks.cubic_abs_max(*a) for a in zip(y0, y1, m0, m1)])
    assert np.array_equal(scalar, best)  # the compiled kernel's function: same formula, same numbers


def test_hermite_peak_of_free_vibration_is_fourth_order():
    """q = cos(omega t + phase), sampled exactly at step ends, with the true peak 1 falling mid-step.

    The step-end peak misses by 1 - cos(omega h / 2) ~ (omega h)^2 / 8 (second order). The cubic
    Hermite through (q, q') at the step ends interpolates with the remainder
    |q''''| h^4 / 384 = (omega h)^4 / 384, which bounds the error of its peak; halving h divides
    the error by 2^4 = 16 asymptotically (asserted > 12 at omega h = 0.4 -> 0.2).
    """
    omega, dt = 2.0 * np.pi, 0.4 / (2.0 * np.pi)
    errs = []
    for h in (dt, dt / 2):
        n = 2 * int(round(0.2 / h))  # under half a period: one extreme of |q| in the window
        phase = -omega * (n // 2 + 0.5) * h  # the peak (t = -phase / omega) mid-step
        seg = free_segments(omega, h, n, phase)
        ends = np.max(np.abs(seg.q1))
        got = peaks.abs_peaks(seg, np.array([[1.0]]))[0]
        assert 1.0 - ends == pytest.approx(1.0 - np.cos(omega * h / 2), rel=1e-9)
        err = abs(1.0 - got)
        assert err <= (omega * h) ** 4 / 384
        errs.append(err)
    assert errs[0] / errs[1] > 12.0


def test_exact_peak_is_the_closed_form_to_rounding():
    """Damped free vibration q0 = 1, q'0 = 0: q' = -(omega^2 / omega_d) e^(-zeta omega t) sin(omega_d t),
    so |q| peaks at t = pi / omega_d with |q| = exp(-zeta pi / sqrt(1 - zeta^2)). Steps from the exact
    integrator with the extreme mid-step (omega h = 0.9, where the Hermite cubic alone misses by
    ~1e-3); the exact intra-step solution with Newton on q' = 0 gives the closed form to rounding:
    the exact transition is accurate to ~1e-14 of each entry's scale (pounding.solvers.exact),
    a few of them combined -> 1e-13 relative."""
    omega, zeta = 3.0, 0.05
    wd = omega * np.sqrt(1 - zeta**2)
    t_peak = np.pi / wd
    h = 0.3
    t0 = t_peak - 0.5 * h - 2 * h  # grid shifted so that the peak is mid-step: start the run at -t0
    ex = Exact()
    n = 8
    tr0 = ex.transition(np.array([omega]), np.array([zeta]), t0)
    z = np.array([[1.0, 0.0, -omega**2]])
    z = np.einsum("nij,nj->ni", tr0.A, z)  # the state at t0 (no load)
    tr = ex.transition(np.array([omega]), np.array([zeta]), h)
    states = [z[0]]
    for _ in range(n):
        z = np.einsum("nij,nj->ni", tr.A, z)
        states.append(z[0])
    S = np.array(states)
    intra = peaks.ExactIntraStep(ex, [omega], [zeta], np.zeros((1, 1)), np.zeros((n + 1, 1)), h)
    seg = peaks.Segments(np.arange(n) * h, np.full(n, h), S[:-1, :1], S[:-1, 1:2], S[1:, :1], S[1:, 1:2], intra)
    closed = np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))
    hermite = peaks.abs_peaks(peaks.Segments(seg.t0, seg.h, seg.q0, seg.v0, seg.q1, seg.v1), np.array([[1.0]]))[0]
    got = peaks.abs_peaks(seg, np.array([[1.0]]))[0]
    assert abs(hermite - closed) > 1e-6  # the interpolant alone is not enough here
    assert got == pytest.approx(closed, rel=1e-13, abs=0.0)


def test_driver_run_reports_true_peaks(tmp_path):
    """A run of the paper pair without contact, Newmark at dt = 0.02 s: the reported peaks are the
    Hermite extremes, never below the step-end ones, and the same whether every step is kept
    (from the histories) or the output is thinned (tracked by the compiled kernel during the run):
    the same cubic formula on the same step-end states, so equal to rounding of the modal
    combinations (1e-12 relative: n <= 30 modes summed, eps * n * cond ~ 1e-14)."""
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene

    from tests.conftest import EXAMPLES

    scene = load_scene(EXAMPLES / "paper" / "pair_gap_0.5.toml")
    scene = scene.with_analysis(dt=0.02, duration=6.0, output_every=1)
    full = run(scene)
    thin = run(scene.with_analysis(output_every=3))
    for name in full.names:
        ends = full.step_end_peaks(name)
        assert np.all(full.peaks(name) >= ends)
        assert np.max(full.peaks(name) / ends) > 1.0 + 1e-4  # something fell between steps
        np.testing.assert_allclose(thin.peaks(name), full.peaks(name), rtol=1e-12, atol=0.0)


def test_minimum_gap_of_oscillators_approaching_between_steps():
    """Two one-storey buildings side by side, no contact: the gap needed is the largest closing of
    their facing faces, max_t (u_a(t) - u_b(t)) (rotation-free: symmetric frames, motion along x).
    On the continuous trajectory (exact integrator, its intra-step solution) it is the maximum found
    by Newton on the exact solution, and it exceeds the step-end value at dt = 0.02 s."""
    from pounding.framework.studies.gap import gap_from_result, no_contact
    from pounding.framework.post.run import run
    from pounding.io.scene import parse_scene

    from tests.scenes_for_tests import side_by_side

    data = side_by_side(0.05, integrator="exact", dt=0.02, duration=4.0)
    scene = no_contact(parse_scene(data))
    res = run(scene)
    rep = gap_from_result(scene, res, "x")
    # reference: the relative displacement along x of the two slabs, a linear modal combination
    seg = peaks.segments(res)
    rows = []
    for i, s in enumerate(res.systems):
        r = np.zeros(sum(x.n_dof for x in res.systems))
        r[res.mode_start[i] : res.mode_start[i] + s.n_dof] = (1.0 if i == 0 else -1.0) * s.modes[0]
        rows.append(r)
    C = (rows[0] + rows[1])[None, :]
    # reference: the exact intra-step solution sampled densely (1000 points a step) in the steps around
    # the largest step-end closing; sampling misses the extreme by <= y'' (h/1000)^2 / 8, i.e.
    # (omega h)^2 / 8e6 < 1e-7 of the amplitude here (omega h < 0.9)
    y = (seg.q1 @ C.T)[:, 0]
    k = int(np.argmax(y))
    step_end = float(y[k])
    dense = max(float(C[0] @ peaks.state_at(seg, i, x)) for i in (k, k + 1) for x in np.linspace(0.0, 1.0, 1001))
    assert dense > step_end * (1 + 1e-6)  # the closing peaks between steps
    assert rep.min_gap == pytest.approx(dense, rel=1e-7)  # min_gap = g0 + max D, D = closing - g0
