"""Floor response spectra: oscillators on the floors, checked against independent solutions.

The smooth floor acceleration is piecewise linear between output steps, so a linear
oscillator driven by it has an exact solution that scipy.signal.lsim (linear input
interpolation) also computes, by a different route (matrix exponential of the state
space). The impacts add Dirac spikes: each one starts a free vibration
-dv e^(-zeta w s) sin(w_d s) / w_d, added by superposition.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.framework.post.response import floor_acceleration, floor_velocity_jumps, impact_forces
from pounding.framework.post.spectra import floor_spectra
from pounding.io.scene import load_scene

PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"
PERIODS = np.array([0.05, 0.2, 0.6])
ZETA = 0.05


@pytest.fixture(scope="module")
def result():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run(load_scene(PAPER).with_analysis(duration=4.0))


def _lsim_peak(t, a, T):
    from scipy.signal import lsim

    w = 2 * np.pi / T
    A = [[0.0, 1.0], [-w * w, -2 * ZETA * w]]
    _, y, _ = lsim((A, [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]]), a, t)
    return y


def test_smooth_part_matches_lsim(result):
    """Without impulses: w^2 max|u| from the exact-integrator recursion equals lsim's on the same
    piecewise-linear input, at every floor and direction. Both exact for this input: they differ
    by rounding accumulated over 800 steps of a stable recursion, 1e-9 relative."""
    s = result.systems[result.names.index("low")]
    acc = floor_acceleration(s, result.modal("low"), result.modal("low", velocity=True))
    sa = floor_spectra(result, "low", PERIODS, ZETA, impulses=False)
    for k, T in enumerate(PERIODS):
        for f in range(s.n_storeys):
            for d in range(2):
                y = _lsim_peak(result.t, acc[:, f, d], T)
                assert sa[k, f, d] == pytest.approx((2 * np.pi / T) ** 2 * np.abs(y).max(), rel=1e-9)


def test_impacts_add_free_vibrations(result):
    """With impulses: the oscillator's response is the smooth part's plus, for every impact, the
    free vibration -dv e^(-zeta w s) sin(w_d s) / w_d from the output step at or after the instant
    (s = t - that step's time), by superposition; compared on the output grid, 1e-9 relative.
    The impacts hit the top floor of "low" in x, the only floor and direction with jumps."""
    assert result.n_impacts > 0
    s = result.systems[result.names.index("low")]
    acc = floor_acceleration(s, result.modal("low"), result.modal("low", velocity=True))
    _, tau = impact_forces(result)
    times, jumps, _ = floor_velocity_jumps(result, "low", tau)
    sa = floor_spectra(result, "low", PERIODS, ZETA)
    dt = result.t[1] - result.t[0]
    f = s.n_storeys - 1  # the top floor of "low" is the one struck
    for k, T in enumerate(PERIODS):
        w = 2 * np.pi / T
        wd = w * np.sqrt(1 - ZETA**2)
        y = _lsim_peak(result.t, acc[:, f, 0], T)
        for tk, dv in zip(times, jumps[:, f, 0]):
            t0 = result.t[np.searchsorted(result.t, tk - 1e-12 * dt)]
            sdt = np.clip(result.t - t0, 0.0, None)
            y = y - np.where(result.t >= t0, dv * np.exp(-ZETA * w * sdt) * np.sin(wd * sdt) / wd, 0.0)
        assert sa[k, f, 0] == pytest.approx(w * w * np.abs(y).max(), rel=1e-9)
    # a short-period oscillator feels the spikes most (here 4x); at longer periods an impulse may
    # as well lower the peak, by reversing the motion
    assert sa[0, f, 0] > 2 * floor_spectra(result, "low", PERIODS, ZETA, impulses=False)[0, f, 0]


def test_plot_spectra_writes_csv_with_units(tmp_path, result):
    """`pounding plot --spectra`: floor_spectra.csv has the period [s] and one column per floor and
    direction in m/s2, and the PNG."""
    import csv

    pytest.importorskip("matplotlib")
    from pounding.io.profile_plots import write_floor_spectra

    paths = write_floor_spectra(result, tmp_path, periods=PERIODS)
    rows = list(csv.reader(open(paths[0])))
    assert rows[0][0] == "period [s]" and rows[0][1] == "low storey 1 x [m/s2]"
    assert len(rows) == 1 + len(PERIODS) and len(rows[0]) == 1 + 2 * (3 + 5)
    assert paths[1].stat().st_size > 0
