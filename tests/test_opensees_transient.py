"""Time-history cross-check against OpenSeesPy, and the energy balance of the integrators.

The issue asks that "the no-contact response of a non-symmetric building under
El Centro equals OpenSeesPy's (same model, Newmark average acceleration, same
dt, same Rayleigh damping) to 1e-6 relative on the peak displacements", and
that "for exact, the energy balance (ground-motion input = kinetic + strain +
damped) closes to 1e-6 of the input".

Set-up: the paper pair (``examples/paper/pair_gap_0.5.toml``: 3- and 5-storey
buildings, both non-symmetric, El Centro NS at 0.32 g along x) with
``contact = "none"``. pounding integrates in modal coordinates
(:func:`pounding.framework.post.run.run`); OpenSees integrates the full 3-D
model of :mod:`pounding.peer.opensees` (planar frames of elastic
beam-columns, rigid diaphragms, ``rayleigh`` damping per building through
``region``), which shares nothing with pounding but the scene. Both start from
rest with zero acceleration; the record starts at 0.0, so that is consistent.
dt = 0.01 s divides the record's 0.02 s, so OpenSees' ``Path`` interpolation
and pounding's linear load within a step are the same load.

What limits the agreement: the out-of-plane bending and torsional stiffness
(``out_of_plane`` x the in-plane inertia) OpenSees needs to keep the planar
frames stable, which the condensed model does not have. The deviation is
proportional to it (measured, whole record, dt 0.01: peak displacements
4e-10 to 1.2e-9 and whole histories 1.2e-9 to 2.2e-9 relative at
out_of_plane = 1e-9; exactly 1000x that at 1e-6; ~1e-12 at 1e-12), down to a
rounding floor of ~1e-12 on the histories reached at out_of_plane ~1e-14.
out_of_plane = 1e-9 leaves a factor of ~500 below the required 1e-6.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.framework.model.assembly import assemble, rayleigh_coefficients
from pounding.io.scene import load_scene
from pounding.framework.post.energy_account import energy_balance


PAIR = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.5.toml"
RTOL = 1e-6  # the requirement
DT = 0.01  # [s], divides the record's 0.02 s
OUT_OF_PLANE = 1e-9
HILBER_ALPHA = -0.05  # pounding's hht default; OpenSees' alpha is 1 + this
HHT_DURATION = 10.0  # [s], holds the strong motion and every peak (top of "low" at 2.3 s, of "high" at 5.9 s)


def _paper_scene():
    return load_scene(PAIR)


def _no_contact(scene, integrator: str, params: dict, dt: float, duration: float | None):
    return scene.with_analysis(integrator=integrator, integrator_params=params, contact="none", contact_params={}, dt=dt, duration=duration)


def _rayleigh(scene) -> list[tuple[float, float]]:
    """Each building's own (a0, a1) of C = a0 M + a1 K, the damping pounding uses (ratio 5 % at modes 1 and 3)."""
    out = []
    for b in scene.buildings:
        assert b.damping.kind == "rayleigh"
        out.append(tuple(float(c) for c in rayleigh_coefficients(b.damping, assemble(b).omega, b.name)))
    assert out[0] != out[1]  # two different pairs: the per-building ``region`` path of run_transient
    return out


def _pair(ops, integrator: str, params: dict, opensees_integrator, duration: float | None, out_of_plane: float = OUT_OF_PLANE):
    """(scene, pounding Result, OpenSees dict name -> (n+1, storeys, 3)) of one no-contact run."""
    from pounding.peer.opensees import run_transient

    scene = _paper_scene()
    scene = _no_contact(scene, integrator, params, DT, duration)
    result = run(scene)
    n = result.steps
    assert n == int(round((duration or scene.ground_motion.duration) / DT))
    peer = run_transient(ops, scene, scene.ground_motion, DT, n, integrator=opensees_integrator, rayleigh=_rayleigh(scene), out_of_plane=out_of_plane)
    return scene, result, peer


@pytest.fixture(scope="module")
def newmark_pair(opensees):
    """Newmark average acceleration over the whole El Centro record (31.18 s, 3118 steps)."""
    return _pair(opensees, "newmark", {}, ("Newmark", 0.5, 0.25), None)


@pytest.fixture(scope="module")
def hht_pair(opensees):
    """HHT with Hilber's alpha = -0.05 (OpenSees 0.95) over the first 10 s."""
    return _pair(opensees, "hht", {"alpha": HILBER_ALPHA}, ("HHT", 1.0 + HILBER_ALPHA), HHT_DURATION)


def _check_peaks(scene, result, peer) -> None:
    for b in scene.buildings:
        expected = result.cm(b.name)
        got = peer[b.name]
        assert got.shape == expected.shape == (result.steps + 1, b.n_storeys, 3)
        peaks = np.max(np.abs(expected), axis=0)  # (storeys, 3): |u|, |v|, |phi| per storey
        # non-symmetric: x shaking drives v and phi too, well above rounding (>= 1 mm, >= 0.5 mrad)
        assert np.all(peaks[:, :2] > 1e-3) and np.all(peaks[:, 2] > 5e-4), peaks
        np.testing.assert_allclose(np.max(np.abs(got), axis=0), peaks, rtol=RTOL, atol=0, err_msg=b.name)


def _check_history(scene, result, peer) -> None:
    for b in scene.buildings:
        expected = result.cm(b.name)
        scale = np.max(np.abs(expected), axis=(0, 1))  # per DOF kind: m, m, rad
        diff = np.max(np.abs(peer[b.name] - expected), axis=(0, 1))
        np.testing.assert_array_less(diff, RTOL * scale, err_msg=b.name)


@pytest.mark.opensees
def test_newmark_peaks_match_opensees(newmark_pair):
    """The issue's test: peak |u|, |v|, |phi| of every storey of both buildings to 1e-6 (measured <= 1.2e-9)."""
    _check_peaks(*newmark_pair)


@pytest.mark.opensees
def test_newmark_history_matches_opensees(newmark_pair):
    """Every sample of the whole history, max |difference| / peak per DOF kind, to 1e-6 (measured <= 2.2e-9)."""
    _check_history(*newmark_pair)


@pytest.mark.opensees
def test_hht_matches_opensees(hht_pair):
    """HHT: OpenSees' ``HHT 0.95`` (alpha on the new state, load at t_n + 0.95 dt) is pounding's hht alpha = -0.05.

    OpenSees applies the load at t_{n+alpha_OS} = t_{n+1} + alpha_H dt; with dt
    dividing the record's step that is (1 + alpha_H) p_{n+1} - alpha_H p_n,
    pounding's shifted equilibrium. Peaks and histories to 1e-6 (measured
    <= 1.2e-9 and <= 2.2e-9, the out-of-plane deviation as for Newmark).
    """
    _check_peaks(*hht_pair)
    _check_history(*hht_pair)


@pytest.mark.opensees
def test_hht_comparison_discriminates(hht_pair):
    """The HHT check is not vacuous: HHT and Newmark differ by ~1e-3 of the peaks here, 1000x the tolerance."""
    scene, result, peer = hht_pair
    newmark = run(_no_contact(_paper_scene(), "newmark", {}, DT, HHT_DURATION))
    for b in scene.buildings:
        scale = np.max(np.abs(result.cm(b.name)), axis=(0, 1))
        assert np.max(np.abs(newmark.cm(b.name) - peer[b.name]) / scale) > 1e3 * RTOL


@pytest.mark.opensees
def test_deviation_follows_out_of_plane_stiffness(opensees, newmark_pair):
    """The residual is the out-of-plane stiffness: 100x more of it (1e-7), 100x the history deviation.

    Only the first 5 s of OpenSees are recomputed (runtime); the same window of
    the 1e-9 run is the reference.
    """
    from pounding.peer.opensees import run_transient

    scene, result, peer = newmark_pair
    n = 500
    coarse = run_transient(opensees, scene, scene.ground_motion, DT, n, rayleigh=_rayleigh(scene), out_of_plane=100 * OUT_OF_PLANE)
    for b in scene.buildings:
        expected = result.cm(b.name)[: n + 1]
        scale = np.max(np.abs(expected), axis=(0, 1))
        d9 = np.max(np.abs(peer[b.name][: n + 1] - expected), axis=(0, 1)) / scale
        d7 = np.max(np.abs(coarse[b.name] - expected), axis=(0, 1)) / scale
        assert np.all(d9 < RTOL / 100) and np.all(d9 > 1e-11)  # the deviation is there, well above rounding
        np.testing.assert_allclose(d7 / d9, 100.0, rtol=0.05)


# --------------------------------------------------------------------------- energy balance


def _balance(integrator: str, params: dict, dt: float, duration: float | None = 10.0) -> dict:
    result = run(_no_contact(_paper_scene(), integrator, params, dt, duration))
    eb = energy_balance(result)
    assert eb["impact_loss"] == 0.0 and eb["contact_force_work"] == 0.0
    assert eb["input"] > 4e5  # J: the balance is measured against a real input
    return eb


def test_exact_energy_balance_closes():
    """The issue's test: for exact, input = kinetic + strain + damped to 1e-6 of the input.

    The work integrals are taken in closed form on the exact intra-step trajectory (the
    trapezoidal rule on step ends gave 2.8e-4 at dt 0.005, O(dt^2); 4 Gauss points ~1e-12);
    measured now: 7e-14 at dt 0.01 and 8e-15 at dt 0.005, so 1e-6 has wide margin.
    """
    for dt in (0.01, 0.005):
        eb = _balance("exact", {}, dt)
        assert abs(eb["relative_error"]) < 1e-6


@pytest.mark.parametrize("dt", [0.01, 0.005, 0.001])
def test_newmark_average_energy_balance_is_exact(dt):
    """Newmark average acceleration closes the balance to rounding (measured <= 5e-14 of the input).

    With v1 - v0 = dt (a0 + a1)/2, x1 - x0 = dt (v0 + v1)/2 and equilibrium
    a + c v + k x = p at both step ends, per mode
    (v1^2 - v0^2)/2 + k (x1^2 - x0^2)/2 + dt c vm^2 = dt vm pm  (vm, pm: step
    averages), exactly the trapezoidal increments the driver accumulates.
    """
    for duration in (10.0, None):
        eb = _balance("newmark", {}, dt, duration)
        assert abs(eb["relative_error"]) < 1e-10, eb


@pytest.mark.opensees
def test_two_components_match_opensees(opensees):
    """A non-symmetric pair under two horizontal components at once: El Centro NS along x and a
    SYNTHETIC second component along y (NS reversed in time, x0.7; not a recording), i.e. two
    ``UniformExcitation`` patterns in OpenSees, one per component, against pounding's modal load
    with L (n, 2). Newmark average acceleration, dt 0.01 s, first 10 s, contact off; the same
    1e-6 as the one-component tests (which measure <= 2.2e-9, set by the out-of-plane stiffness
    OpenSees needs; see the module docstring). Both components drive u, v and phi of every storey.
    """
    from pounding.io.ground_motion import GroundMotion
    from pounding.io.motion_pair import GroundMotionPair
    from pounding.peer.opensees import run_transient

    scene = _no_contact(_paper_scene(), "newmark", {}, DT, HHT_DURATION)
    ns = scene.ground_motion
    second = GroundMotion(ns.t, 0.7 * ns.acc[::-1], name="synthetic_reversed_x0.7", source="synthetic")
    pair = GroundMotionPair(ns, second, angle=0.0)
    scene = scene.with_ground_motion(pair)
    result = run(scene)
    n = result.steps
    peer = run_transient(opensees, scene, pair, DT, n, integrator=("Newmark", 0.5, 0.25), rayleigh=_rayleigh(scene),
                         out_of_plane=OUT_OF_PLANE)
    _check_peaks(scene, result, peer)
    _check_history(scene, result, peer)
    # the second component matters: without it the response differs by far more than the tolerance
    alone = run(scene.with_ground_motion(ns))
    for b in scene.buildings:
        assert np.max(np.abs(alone.cm(b.name) - result.cm(b.name))) > 1e3 * RTOL * np.max(np.abs(result.cm(b.name)))
