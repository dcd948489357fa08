"""Two horizontal components of ground motion: superposition, the one-component form, the time base.

The records. Only El Centro 1940 NS exists on this machine (in three AT2 layouts). The second
horizontal component used here is SYNTHETIC, built honestly from it and labelled so: the NS
samples in reverse time order, times 0.7 (:func:`synthetic_second`). It has the same sample
interval, a different waveform and a different peak, so the pair is non-symmetric in time and
amplitude; it is not a recorded motion and no result here claims to be about a real pair.

The paper pair (``examples/paper``: 3- and 5-storey non-symmetric buildings) is the structure.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pounding.framework.engine.driver import Driver
from pounding.framework.engine.stacked_model import Model

from pounding.framework.model.units import G
from pounding.io.ground_motion import GroundMotion, load_record
from pounding.io.motion_pair import GroundMotionPair, common_time_base
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER_POUNDING = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
PAPER_APART = ROOT / "examples" / "paper" / "pair_gap_0.5.toml"


def synthetic_second(first: GroundMotion) -> GroundMotion:
    """SYNTHETIC second component: ``first`` reversed in time and scaled by 0.7 (not a recording)."""
    return GroundMotion(first.t, 0.7 * first.acc[::-1], name="synthetic_reversed_x0.7", source="synthetic")


def _elcentro(pga_g: float = 0.32) -> GroundMotion:
    return load_record({"record": "elcentro", "pga": pga_g})


def _cm(result, scene) -> np.ndarray:
    return np.concatenate([result.cm(b.name).reshape(result.t.size, -1) for b in scene.buildings], axis=1)


# --------------------------------------------------------------------------- superposition
@pytest.mark.parametrize("integrator,params,use_kernel", [
    ("hht", {"alpha": -0.05}, True),
    ("exact", {}, True),
    ("newmark", {}, False),
])
def test_pair_is_the_sum_of_its_components_without_contact(integrator, params, use_kernel):
    """Linearity. Without contact the equations are linear in the ground acceleration, so the
    response to the pair (NS at 30 deg, synthetic at 120 deg) is the sum of the responses to
    each component alone at its own angle. Required: 1e-9 of the peak (the issue). What is
    computed differs only in the order of the rounding (the pair's modal load sums two products
    per step), so the difference is rounding grown over ~6000 steps: measured ~1e-15 of the peak.
    """
    ns = _elcentro()
    second = synthetic_second(ns)
    base = load_scene(PAPER_APART).with_analysis(contact="none", contact_params={}, integrator=integrator,
                                                 integrator_params=params, dt=0.005)
    pair = GroundMotionPair(ns, second, angle=30.0)
    r_pair = Driver(base.with_ground_motion(pair), use_kernel=use_kernel).run()
    r_a = Driver(base.with_ground_motion(ns.with_angle(30.0)), use_kernel=use_kernel).run()
    r_b = Driver(base.with_ground_motion(second.with_angle(120.0)), use_kernel=use_kernel).run()
    both, a, b = _cm(r_pair, base), _cm(r_a, base), _cm(r_b, base)
    peak = np.max(np.abs(both), axis=0)
    assert np.all(peak > 0)
    # each component alone moves the buildings by a comparable amount: the sum is not one term
    assert np.max(np.abs(b)) > 0.2 * np.max(np.abs(a))
    err = np.max(np.abs(both - (a + b)), axis=0) / peak
    assert np.max(err) < 1e-9, np.max(err)


# --------------------------------------------------------------------------- one component as before
def test_model_load_has_one_column_per_component():
    """Model.L is (n, c), C-contiguous float64: one component gives one column equal to the
    participation factors Gamma = Phi^T M b of its direction (bit for bit, the values used before
    two components existed); a pair at 30 deg gives the columns of directions 30 and 120 deg."""
    scene = load_scene(PAPER_POUNDING)
    m = Model(scene)
    expected = np.concatenate([s.participation(s.influence(scene.ground_motion.direction())) for s in m.systems])
    assert m.L.shape == (m.n, 1) and m.L.flags.c_contiguous and m.L.dtype == np.float64
    assert np.array_equal(m.L[:, 0], expected)
    pair = GroundMotionPair(scene.ground_motion, synthetic_second(scene.ground_motion), angle=30.0)
    m2 = Model(scene.with_ground_motion(pair))
    assert m2.L.shape == (m.n, 2) and m2.L.flags.c_contiguous
    for j, deg in enumerate((30.0, 120.0)):
        d = np.array([np.cos(np.radians(deg)), np.sin(np.radians(deg))])
        np.testing.assert_allclose(m2.L[:, j], np.concatenate([s.participation(s.influence(d)) for s in m.systems]),
                                   rtol=0, atol=1e-12 * np.max(np.abs(m2.L)))


@pytest.mark.parametrize("integrator,params", [("hht", {"alpha": -0.05}), ("exact", {}), ("newmark", {})])
@pytest.mark.parametrize("use_kernel", [True, False])
def test_one_component_equals_a_pair_with_a_silent_second_bit_for_bit(integrator, params, use_kernel):
    """With pounding (the paper pair at 0.03 m, impulses, held contact), a pair whose second
    component is all zeros gives exactly the one-component run: its extra modal load terms are
    L[i, 1] * 0.0, which add nothing in IEEE arithmetic, and the common time base copies equal
    grids sample by sample. Equality is asserted bit for bit (np.array_equal), including every impact.

    (Against the code before two components existed, the same bit-for-bit identity was checked on
    40 run configurations when the change was made: benchmarks/check_identity.py.)
    """
    scene = load_scene(PAPER_POUNDING).with_analysis(integrator=integrator, integrator_params=params, duration=12.0)
    gm = scene.ground_motion
    silent = GroundMotion(gm.t, np.zeros_like(gm.acc), name="zeros", source="synthetic")
    d1 = Driver(scene, use_kernel=use_kernel)
    d1.run()
    d2 = Driver(scene.with_ground_motion(GroundMotionPair(gm, silent, angle=gm.angle)), use_kernel=use_kernel)
    d2.run()
    assert len(d1.impacts) > 10
    assert np.array_equal(d1.Q, d2.Q) and np.array_equal(d1.V, d2.V) and np.array_equal(d1.E, d2.E)
    assert [(i.time, i.impulse) for i in d1.impacts] == [(i.time, i.impulse) for i in d2.impacts]


# --------------------------------------------------------------------------- one time base
def test_common_time_base_takes_the_finer_dt_and_pads_the_shorter_with_zeros():
    """A 0.02 s record of 1.0 s and a 0.01 s record of 0.5 s: the base is 0.01 s up to 1.0 s; the
    coarse record is linear between its samples (exact at them, the average at midpoints), the
    short one is copied sample by sample and zero after its end."""
    coarse = GroundMotion(np.arange(51) * 0.02, np.sin(np.arange(51.0)), name="coarse")
    short = GroundMotion(np.arange(51) * 0.01, np.cos(np.arange(51.0)) + 2.0, name="short")
    t, acc = common_time_base((coarse, short))
    assert t.size == 101 and t[1] == 0.01 and np.isclose(t[-1], 1.0)
    np.testing.assert_array_equal(acc[::2, 0], coarse.acc)
    # the midpoints' times are k 0.01 against the samples' j 0.02, each rounded to ~1e-16 s: the
    # interpolation weight is 1/2 to ~1e-16 / 0.01 = 1e-14, times a jump of at most 2 in the values
    np.testing.assert_allclose(acc[1::2, 0], 0.5 * (coarse.acc[1:] + coarse.acc[:-1]), rtol=0, atol=1e-13)
    np.testing.assert_array_equal(acc[:51, 1], short.acc)
    assert np.all(acc[51:, 1] == 0.0)
    pair = GroundMotionPair(coarse, short, angle=90.0)
    assert pair.dt == 0.01 and pair.duration == pytest.approx(1.0)
    assert np.array_equal(pair.directions(), [[0.0, 1.0], [-1.0, 0.0]])  # exact at multiples of 90 deg
    np.testing.assert_array_equal(pair.samples(np.array([0.0, 0.02, 2.0])), [[coarse.acc[0], short.acc[0]],
                                                                             [coarse.acc[1], short.acc[2]], [0.0, 0.0]])


def test_pair_scaling_uses_the_larger_component_peak():
    """pga = 0.4 scales both components by one factor so that the larger peak is 0.4 g."""
    ns = _elcentro(1.0)
    pair = GroundMotionPair(ns, synthetic_second(ns)).scaled_to_pga(0.4)
    assert pair.pga / G == pytest.approx(0.4, rel=1e-14)
    np.testing.assert_allclose(np.max(np.abs(pair.acc), axis=0) / G, [0.4, 0.28], rtol=1e-13)


# --------------------------------------------------------------------------- scene files
def _write_pair_scene(tmp_path: Path, gm_table: str) -> Path:
    text = PAPER_POUNDING.read_text()
    start = text.index("[ground_motion]")
    end = text.index("[analysis]")
    path = tmp_path / "pair.toml"
    path.write_text(text[:start] + gm_table + "\n" + text[end:])
    return path


def _column_files(tmp_path: Path) -> tuple[Path, Path, GroundMotion]:
    """The NS record as a two-column file in cm/s^2 and the synthetic second as one column in m/s^2."""
    ns = load_record({"record": "elcentro"})
    two = tmp_path / "ns_cm.txt"
    two.write_text("time acc(cm/s2)\n" + "\n".join(f"{float(t)!r} {float(100.0 * a)!r}" for t, a in zip(ns.t, ns.acc)))
    one = tmp_path / "synthetic_ms2.txt"
    one.write_text("\n".join(repr(float(a)) for a in synthetic_second(ns).acc))
    return two, one, ns


def test_scene_with_two_components_each_in_its_own_format_and_units(tmp_path):
    """components = [two columns in cm/s^2, single column in m/s^2 with dt]: the scene's pair holds
    the two records in m/s^2 (the cm factor 0.01 is not exact in binary: 1e-15 relative), at the
    scene's angle and the second at angle + 90, scaled by one factor."""
    two, one, ns = _column_files(tmp_path)
    path = _write_pair_scene(tmp_path, f'''[ground_motion]
components = [{{record = "{two.name}", units = "cm/s^2"}}, {{record = "{one.name}", dt = 0.02, units = "m/s^2"}}]
angle = 25.0
scale = 2.0
''')
    gm = load_scene(path).ground_motion
    assert isinstance(gm, GroundMotionPair) and gm.angle == 25.0
    np.testing.assert_allclose(gm.acc[:, 0], 2.0 * ns.acc, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(gm.acc[:, 1], 2.0 * synthetic_second(ns).acc, rtol=1e-14)
    assert [c.angle for c in gm.components] == [25.0, 115.0]


def test_baseline_correction_only_when_asked(tmp_path):
    """A record plus a linear drift c0 + c1 t: baseline = "linear" removes the least-squares line
    (so the corrected record is the residual of the fit, orthogonal to 1 and t); without the key
    the samples are read as they are, bit for bit."""
    ns = load_record({"record": "elcentro"})
    drifted = ns.acc + 0.05 + 0.01 * ns.t
    f = tmp_path / "drift.txt"
    f.write_text("\n".join(f"{float(t)!r} {float(a)!r}" for t, a in zip(ns.t, drifted)))
    raw = load_scene(_write_pair_scene(tmp_path, f'[ground_motion]\nrecord = "{f.name}"\nunits = "m/s^2"\n')).ground_motion
    assert np.array_equal(raw.acc, drifted)
    fixed = load_scene(_write_pair_scene(tmp_path, f'[ground_motion]\nrecord = "{f.name}"\nunits = "m/s^2"\nbaseline = "linear"\n')).ground_motion
    scale = np.max(np.abs(fixed.acc))
    assert abs(np.sum(fixed.acc)) < 1e-10 * scale * ns.t.size
    assert abs(np.sum(fixed.acc * ns.t)) < 1e-10 * scale * ns.t.size * ns.duration
    # the drift is gone: what is left differs from the NS record only by ITS own least-squares line
    coef = np.polynomial.polynomial.polyfit(ns.t / ns.duration, ns.acc, 1)
    np.testing.assert_allclose(fixed.acc, ns.acc - np.polynomial.polynomial.polyval(ns.t / ns.duration, coef),
                               rtol=0, atol=1e-12 * scale)
