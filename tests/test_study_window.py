"""Studies that do not mislead: the Arias intensity, the analysis window against each record, and the measure stated.

A study scales each record by an intensity measure of the whole record, then analyses only the window
``[0, duration]``. When the window ends before the record's strong motion (95 % of its Arias intensity) or its
peak, the run answers for shaking it never applied; `pounding sweep` and `pounding fragility` must say so by name
and mark the rows. The records here are SYNTHETIC (a two-cycle sine pulse early or late in 3 s of zeros), short,
and the runs serial, so the studies take a few seconds.
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.sparse.linalg import eigsh

from pounding.framework.model.assembly import assemble
from pounding.framework.model.units import G
from pounding.framework.post.intensity import arias_history, arias_time, strong_motion
from pounding.framework.studies.window import WindowWarning, check_window
from pounding.io.ground_motion import GroundMotion
from pounding.io.motion_pair import GroundMotionPair
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
EPS = np.finfo(float).eps
DT = 0.01  # [s], the synthetic records' sample interval
LENGTH = 3.0  # [s], the synthetic records' length
WINDOW = 1.5  # [s], the studies' --duration: holds the early pulse, not the late one
PULSE = (0.2, 1.8)  # [s], start of the early and of the late pulse (each lasts 1 s: two cycles of 0.5 s)


# --------------------------------------------------------------------------- the Arias intensity
def test_arias_of_a_ramp_is_its_closed_form():
    """a(t) = c t on [0, T] is linear between samples, so the history is exact to rounding:
    I_A(t) = pi c^2 t^3 / (6 g) and I_A reaches 95 % at t95 = 0.95^(1/3) T.

    Tolerance: the history is a cumulative sum of n = 1000 positive terms, each exact to a few roundings:
    relative error below n eps ~ 2e-13; t95 is found to 4 eps of t by Brent's method, then rounded.
    """
    c, T = 0.3, 10.0  # [m/s^3], [s]
    t = np.linspace(0.0, T, 1001)
    history = arias_history(t, c * t)
    assert history == pytest.approx(np.pi * c * c * t**3 / (6.0 * G), rel=t.size * EPS, abs=0.0)
    assert arias_time(t, c * t, 0.95) == pytest.approx(0.95 ** (1.0 / 3.0) * T, rel=16 * EPS)


def test_arias_of_a_sine_grows_linearly_and_reaches_95_percent_near_095_of_the_duration():
    """a(t) = A sin(w t): I_A(t) = pi A^2 / (2 g) (t / 2 - sin(2 w t) / (4 w)), linear growth on average, and on
    20 whole cycles the 95 % time t95 solves t - sin(2 w t) / (2 w) = 0.95 T, so |t95 - 0.95 T| <= 1 / (2 w).

    The samples are joined by straight lines, which differ from the sine by at most e = A (w h)^2 / 8; so
    |a_lin^2 - a^2| <= e (2 A + e) and the history is within pi / (2 g) e (2 A + e) t of the closed form at every
    sample (the bound checked, h = 0.01 s: w h = 0.063). The 95 % time is checked where that bound applies,
    in intensity: I_exact(t95) differs from 0.95 I_exact(T) by at most the bound at t95 plus 0.95 of it at T.
    """
    A, f, T, h = 2.0, 1.0, 20.0, 0.01
    w = 2.0 * np.pi * f
    t = np.linspace(0.0, T, int(round(T / h)) + 1)
    a = A * np.sin(w * t)

    def exact(s):
        return np.pi * A * A / (2.0 * G) * (s / 2.0 - np.sin(2.0 * w * s) / (4.0 * w))

    e = A * (w * h) ** 2 / 8.0
    bound = np.pi / (2.0 * G) * e * (2.0 * A + e)  # [m/s per s of record]
    assert np.all(np.abs(arias_history(t, a) - exact(t)) <= bound * t + 1e3 * EPS * exact(T))
    t95 = arias_time(t, a, 0.95)
    assert abs(exact(t95) - 0.95 * exact(T)) <= bound * (t95 + 0.95 * T)
    t95_exact = brentq(lambda s: exact(s) - 0.95 * exact(T), 0.9 * T, T)
    assert abs(t95_exact - 0.95 * T) <= 1.0 / (2.0 * w)  # the closed form's statement, for the record above


def test_arias_of_a_pair_is_the_sum_of_its_components_in_any_orientation():
    """The horizontal Arias intensity is the trace of the Arias tensor: a pair (a cos q, a sin q) has the
    intensity of a alone (cos^2 + sin^2 = 1 to 2 eps), and a pair (a, b) that of a plus that of b."""
    rng = np.random.default_rng(7)
    t = np.arange(500) * DT
    a, b = rng.standard_normal(t.size), rng.standard_normal(t.size)
    q = math.radians(35.0)
    alone = arias_history(t, a)
    assert arias_history(t, np.stack([a * math.cos(q), a * math.sin(q)], axis=1)) == pytest.approx(alone, rel=8 * EPS)
    assert arias_history(t, np.stack([a, b], axis=1)) == pytest.approx(alone + arias_history(t, b), rel=8 * EPS)


def test_the_peak_of_a_pair_is_its_larger_components():
    """A pair's peak time is where the larger component (what `pga =` scales) peaks, whichever it is."""
    t = np.arange(301) * DT
    small = GroundMotion(t, np.where(np.isclose(t, 0.5), 1.0, 0.0), name="small")
    large = GroundMotion(t, np.where(np.isclose(t, 2.5), -3.0, 0.0), name="large")
    assert strong_motion(GroundMotionPair(small, large)).peak_time == pytest.approx(2.5, abs=1e-12)


# --------------------------------------------------------------------------- the window
def pulse_at(start: float) -> np.ndarray:
    """A SYNTHETIC record [g]: zeros on [0, LENGTH] but two cycles of a 0.5 s sine, amplitude 0.3 g, from ``start``."""
    t = np.arange(int(round(LENGTH / DT)) + 1) * DT
    inside = (t >= start) & (t <= start + 1.0)
    return np.where(inside, 0.3 * np.sin(2.0 * np.pi * (t - start) / 0.5), 0.0)


def write_at2(path: Path, acc_g: np.ndarray) -> Path:
    lines = [path.stem, "SYNTHETIC sine pulse for the tests", "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {acc_g.size:6d}, DT= {DT:.4f} SEC"]
    lines += ["".join(f"{v:12.7f}" for v in acc_g[i:i + 8]) for i in range(0, acc_g.size, 8)]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="module")
def pulses(tmp_path_factory):
    """Two records: ``early`` (its pulse inside the window) and ``late`` (its pulse after the window's end)."""
    folder = tmp_path_factory.mktemp("pulses")
    write_at2(folder / "early.AT2", pulse_at(PULSE[0]))
    write_at2(folder / "late.AT2", pulse_at(PULSE[1]))
    return folder


def test_a_record_is_cut_exactly_when_its_strong_motion_ends_after_the_window(pulses):
    """The late pulse's 95 % Arias time lies inside its pulse, after the window: cut; the early one's before it:
    not cut; and no record is cut by a window as long as itself (both times lie within the record)."""
    from pounding.io.ground_motion import read_at2

    scene = load_scene(PAPER)
    for name, start, cut in (("early", PULSE[0], False), ("late", PULSE[1], True)):
        motion = read_at2(pulses / f"{name}.AT2")
        check = check_window(name, scene.with_ground_motion(motion).with_analysis(duration=WINDOW))
        assert start < check.arias95_time < start + 1.0 and start < check.peak_time < start + 1.0
        assert bool(check.cut) is cut and (not cut or "95 % Arias" in check.cut and "peak" in check.cut)
        assert check_window(name, scene.with_ground_motion(motion)).cut is None  # the record's own length


def taller_period(scene) -> tuple[str, float]:
    """(name, T1 [s]) of the building of largest total height, by ARPACK's shift-invert Lanczos on (K, M):
    an algorithm other than the assembly's dense eigh."""
    b = max(scene.buildings, key=lambda b: sum(b.storey_heights))
    s = assemble(b)
    lam = eigsh(s.K, k=1, M=s.M, sigma=0.0, which="LM", return_eigenvectors=False)[0]
    return b.name, 2.0 * np.pi / math.sqrt(lam)


def period_tolerance(scene) -> float:
    """Relative tolerance between two backward-stable symmetric eigensolvers on T1: 100 eps kappa, kappa =
    lambda_max / lambda_min of the taller building (the eigenvalue's condition relative to itself)."""
    b = max(scene.buildings, key=lambda b: sum(b.storey_heights))
    w = assemble(b).omega
    return 100.0 * EPS * (w[-1] / w[0]) ** 2


def test_fragility_names_the_cut_record_marks_its_runs_and_states_the_period(pulses, tmp_path):
    """`pounding fragility --im sa --duration 1.5`: the warning names ``late`` and not ``early``; runs.csv marks
    late's rows in window_cut and not early's; the command prints the measure and its period, and study.json
    gives the period of the taller building's first mode (checked by another eigensolver), whose it is, and
    the oscillator's damping (5 %)."""
    out = tmp_path / "frag"
    proc = subprocess.run([sys.executable, "-m", "pounding", "fragility", str(PAPER), "--records", str(pulses), "--im", "sa",
                           "--levels", "0.2", "--duration", str(WINDOW), "--serial", "--quiet", "--no-plots", "--out", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    warning = [line for line in proc.stderr.splitlines() if line.startswith("pounding: warning: the analysis window")]
    assert len(warning) == 1 and "late (" in warning[0] and "early" not in warning[0], proc.stderr
    with open(out / "runs.csv", newline="") as fh:
        rows = {r["record"]: r for r in csv.DictReader(fh)}
    assert rows["late"]["window_cut"] and not rows["early"]["window_cut"]
    assert float(rows["late"]["arias95_s"]) > WINDOW >= float(rows["early"]["arias95_s"])
    study = json.loads((out / "study.json").read_text())
    im = study["intensity_measure"]
    scene = load_scene(PAPER)
    name, T1 = taller_period(scene)
    assert im["name"] == "sa" and im["damping"] == 0.05 and repr(name) in im["period_of"]
    assert im["period_s"] == pytest.approx(T1, rel=period_tolerance(scene))
    assert f"T = {im['period_s']:.4g} s" in proc.stdout and repr(name) in proc.stdout
    assert [w["record"] for w in study["window"] if w["cut"]] == ["late"]


def test_sweep_names_the_cut_record_marks_its_rows_and_states_the_scaling(pulses, tmp_path):
    """`run_sweep` over the two records: a WindowWarning naming ``late`` only, before any run; late's rows marked
    in sweep.csv's window_cut; sweep.json says the records were scaled to the scene's PGA (0.32 g) and lists the
    check of each record."""
    from pounding.framework.studies.sweep import read_table, run_sweep

    said_before = []  # at each finished run: had the warning been given?
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = run_sweep(PAPER, tmp_path / "sweep", gaps=[0.05], records=pulses, overrides={"duration": WINDOW},
                        serial=True, plots=False,
                        progress=lambda *_: said_before.append(any(w.category is WindowWarning for w in caught)))
    mine = [str(w.message) for w in caught if issubclass(w.category, WindowWarning)]
    assert len(mine) == 1 and "late (" in mine[0] and "early" not in mine[0] and said_before == [True, True]
    rows = {r["record"]: r for r in read_table(res.csv)}
    assert rows["late"]["window_cut"] and rows["early"]["window_cut"] is None and not res.failed
    description = json.loads((tmp_path / "sweep" / "sweep.json").read_text())
    assert description["intensity"]["name"] == "pga" and description["intensity"]["target_g"] == 0.32
    assert {w["record"]: bool(w["cut"]) for w in description["window"]} == {"early": False, "late": True}


def test_a_spectral_target_in_the_scene_is_stated_with_its_period(tmp_path):
    """A scene scaled by ``intensity = "sa"`` without a period: the sweep states T1 of the taller building (checked by
    another eigensolver), whose it is, and the 5 % damping; with ``period = 1.2`` it states 1.2 s, given; with
    ``scale = 1.5``, the factor."""
    from pounding.framework.studies.sweep import prepare

    text = PAPER.read_text().replace("pga = 0.32          # g", 'intensity = "sa"\ntarget = 0.5')
    path = tmp_path / "sa.toml"
    path.write_text(text)
    spec, _, _ = prepare(path)
    scene = load_scene(path)
    name, T1 = taller_period(scene)
    about = spec["intensity"]
    assert about["name"] == "sa" and about["target_g"] == 0.5 and about["damping"] == 0.05 and repr(name) in about["period_of"]
    assert about["period_s"] == pytest.approx(T1, rel=period_tolerance(scene))
    path.write_text(text.replace("target = 0.5", "target = 0.5\nperiod = 1.2"))
    about = prepare(path)[0]["intensity"]
    assert (about["period_s"], about["period_of"]) == (1.2, "given")
    path.write_text(text.replace('intensity = "sa"\ntarget = 0.5', "scale = 1.5"))
    assert prepare(path)[0]["intensity"] | {"definition": None} == {"name": "scale", "label": "factor", "unit": "-",
                                                                     "factor": 1.5, "definition": None}
