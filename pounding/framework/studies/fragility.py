"""Pounding fragility: the probability that two buildings pound, against the gap and the intensity, over a record set.

Method
------
Before their first impact two buildings move exactly as if contact were off.
So they pound at a clear distance g (at rest, along the direction of the gap)
if and only if the *required gap* of the contact-free run, r (the smallest
distance at which no slab pair ever touches, :mod:`pounding.framework.studies.gap`),
is at least g. One contact-free run per record and intensity level therefore
answers "pounding or not" for every gap at once: the gap grid costs nothing.

For each record i and level x_j, the record is scaled by ``x_j / IM_i`` (IM_i
its unscaled intensity measure) and run without contact; its required gap
r_ij, the governing storey, instant and corner and the code estimates (ABS,
SRSS, DDC at the governing storey) go to one row of ``runs.csv``. Then, for
every gap g of the grid and level j,

    P(pounding | g, x_j) = #{i : r_ij >= g} / n_j ,

and per gap a lognormal fragility in the intensity, fitted by maximum
likelihood over the levels (:mod:`pounding.framework.post.lognormal`). Per level,
the gap for a target probability p is the smallest gap above which at most
floor(p n_j) runs pound (an order statistic of r_.j), beside a lognormal fit of
r_.j and the mean over the records of the code estimates.

``required_gap_m`` is the maximum over the continuous trajectory (the gap
search's, :func:`pounding.framework.studies.gap.gap_from_result`, on the integrator's
own interpolant: :mod:`pounding.framework.engine.peaks`; it adds ~1e-4 of the gap at
dt = 0.005 s). ``required_gap_grid_m`` is the maximum over the steps, the
distance below which a run with contact (which checks for overlap after each
step) finds an impact.

A record is scaled by its whole record's measure but shakes the scene only
for the analysis window (``--duration``). A record whose strong motion (95 % of
its Arias intensity) or peak comes after the window's end is named in a
warning before the runs start and marked in ``runs.csv`` (``window_cut``, with
``window_s``, ``arias95_s``, ``peak_time_s`` and the Arias intensity of the
record as scaled, ``arias_m_s``): :mod:`pounding.framework.studies.window`.
``study.json`` states the measure (for a spectral one: the period, which
building's it is, and the damping) and every record's check.

Runs with contact (``consequences``) at chosen gaps give what pounding does:
the peak inter-storey drift of each building against the contact-free run's.

Each run is plain data in, one row of plain numbers out, so a study on any
number of Dask workers gives the same rows as a serial one. Rows are appended
to the CSV files (flushed) as runs finish; a rerun with the same folder reads
them back and runs only what is missing (runs that failed are run again).
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import os
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pounding.errors import InputError
from pounding.framework.post.lognormal import pounding_probability
from pounding.framework.studies.sweep import format_cell

RUNS_CSV = "runs.csv"
CONSEQUENCES_CSV = "consequences.csv"
FRAGILITY_CSV = "fragility.csv"
TARGET_CSV = "target_gap.csv"
CONSEQUENCES_SUMMARY_CSV = "consequences_summary.csv"
STUDY_JSON = "study.json"
#: 2: runs.csv has the window columns (window_s ... window_cut) and study.json the measure's definition
STUDY_VERSION = 2

__all__ = [
    "FragilityResult",
    "Study",
    "consequence_run",
    "contact_free_run",
    "default_gaps",
    "gap_for_probability",
    "pounding_probability",
    "prepare_study",
    "run_fragility",
    "summarise",
]


# =============================================================================
# One run (executes on a worker)
# =============================================================================


def run_columns(names: list[str]) -> list[str]:
    """Columns of ``runs.csv`` for buildings ``names``."""
    cols = ["record", "level", "im", "record_im", "scale", "window_cut", "window_s", "arias95_s", "peak_time_s", "arias_m_s",
            "status", "error", "required_gap_m", "required_gap_grid_m", "storey", "storey_b", "time_s", "striking", "vertex", "struck", "edge", "abs_m", "srss_m", "ddc_m"]
    return cols + [f"{n}_peak_drift_ratio_cm" for n in names] + [f"{n}_peak_ductility" for n in names] + ["warnings", "runtime_s"]


def consequence_columns(names: list[str]) -> list[str]:
    """Columns of ``consequences.csv`` for buildings ``names``."""
    return ["record", "level", "gap_m", "scale", "status", "error", "n_impacts"] + [f"{n}_peak_drift_ratio_cm" for n in names] + \
        [f"{n}_peak_ductility" for n in names] + ["max_impulse", "energy_loss", "warnings", "runtime_s"]


def peak_ductility(result, name: str) -> float | None:
    """Largest ductility demand (peak |deformation| / yield deformation) of a building's yielding storey
    springs over the run, or None for a building without springs that yield."""
    sp = getattr(result, "springs", {}).get(name)
    if not sp:
        return None
    yd = np.asarray(sp["yield_deformation"])
    finite = np.isfinite(yd)  # links with no yield deformation (dampers, linear springs) have no ductility
    return float(np.max(np.asarray(sp["peak"])[finite] / yd[finite])) if finite.any() else None


_RESPONSE = ("_peak_drift_ratio_cm", "_peak_ductility")


def _drifts(result, scene) -> dict:
    from pounding.framework.studies.sweep import _measures

    m = _measures(result, scene, [])
    return {k: v for k, v in m.items() if k.endswith("_peak_drift_ratio_cm")} | {
        f"{b.name}_peak_ductility": peak_ductility(result, b.name) for b in scene.buildings} | {
        "n_impacts": m["n_impacts"], "max_impulse": m["max_impulse"], "energy_loss": m["energy_loss"]}


def _caught(caught) -> str | None:
    return "; ".join(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught)) or None


def contact_free_run(scene, motion, scale: float, direction, row: dict) -> dict:
    """One contact-free run of ``scene`` under ``motion.scaled(scale)``: its required gap and where it governs.

    Parameters
    ----------
    scene : Scene
        Two buildings; its ground motion is replaced by the scaled ``motion``.
    motion : ground motion (see :mod:`pounding.framework.studies.fragility_inputs`)
    scale : float
        Factor on the motion (> 0).
    direction : None or (2,) unit vector
        Direction of the gap, oriented from the first building to the second.
    row : dict
        The run's identity (record, level, im, record_im), copied into the result.

    Returns
    -------
    dict
        One row of ``runs.csv`` (lengths in m, time in s), with the record as
        scaled against the analysis window (:func:`pounding.framework.studies.window.window_columns`).
        Never raises: a failure is a row with ``status = "error"`` and the message.
    """
    from pounding.framework.post.run import run
    from pounding.framework.studies.gap import gap_from_result, no_contact
    from pounding.framework.studies.window import check_window, window_columns

    t0 = time.perf_counter()
    row = dict(row, scale=scale)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            s = scene.with_ground_motion(motion.scaled(scale))
            row.update(window_columns(check_window(row["record"], s)))
            result = run(no_contact(s))
            rep = gap_from_result(s, result, direction, full=False)
        # min_gap: over the continuous trajectory (pounding.framework.engine.peaks); min_gap_grid: over the steps
        row.update(status="ok", error=None, required_gap_m=float(rep.min_gap), required_gap_grid_m=float(rep.min_gap_grid),
                   storey=rep.storey, storey_b=rep.storey_b, time_s=rep.time, striking=rep.striking, vertex=rep.vertex,
                   struck=rep.struck, edge=rep.edge, abs_m=rep.abs, srss_m=rep.srss, ddc_m=rep.ddc,
                   warnings=_caught(caught))
        row.update({k: v for k, v in _drifts(result, s).items() if k.endswith(_RESPONSE)})
    except Exception as exc:  # noqa: BLE001 - a failed run is reported in its row
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    row["runtime_s"] = time.perf_counter() - t0
    return row


def consequence_run(scene, motion, scale: float, gap: float, direction, row: dict) -> dict:
    """One run with contact at clear distance ``gap`` [m]: impacts and peak drifts (a row of ``consequences.csv``).

    The scene's contact law is used, the impulse law if the scene has none.
    Never raises.
    """
    from pounding.framework.post.run import run
    from pounding.framework.model.placement import with_gap
    from pounding.framework.model.registry import watches_contact

    t0 = time.perf_counter()
    row = dict(row, gap_m=gap, scale=scale)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            s = scene.with_ground_motion(motion.scaled(scale))
            if not watches_contact(s.analysis):
                s = s.with_analysis(contact="impulse", contact_params={})
            s = with_gap(s, gap, direction)
            result = run(s)
        row.update(status="ok", error=None, warnings=_caught(caught))
        row.update(_drifts(result, s))
    except Exception as exc:  # noqa: BLE001
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    row["runtime_s"] = time.perf_counter() - t0
    return row


# =============================================================================
# Statistics on the rows
# =============================================================================


def gap_for_probability(required, p: float) -> float:
    """Smallest gap [m] above which at most ``floor(p n)`` of the n runs pound (the infimum: it is the (k+1)-th largest required gap).

    0 if every run may pound; NaN without runs.
    """
    r = np.sort(np.asarray(required, dtype=float))[::-1]
    if r.size == 0:
        return math.nan
    k = int(math.floor(p * r.size + 1e-12))
    return 0.0 if k >= r.size else float(max(r[k], 0.0))


def lognormal_gap(required, p: float) -> float:
    """The gap exceeded with probability p by a lognormal fitted to the required gaps (mean and sample standard deviation of ln r); NaN for fewer than 2 positive values."""
    from scipy.special import ndtri

    r = np.asarray(required, dtype=float)
    r = r[r > 0]
    if r.size < 2:
        return math.nan
    lr = np.log(r)
    return float(math.exp(lr.mean() + lr.std(ddof=1) * ndtri(1.0 - p)))


def _nice_step(span: float, max_points: int) -> float:
    if not (span > 0 and math.isfinite(span)):
        return 0.001
    raw = span / max_points
    e = math.floor(math.log10(raw))
    for m in (1, 2, 5, 10):
        if m * 10**e >= raw:
            return m * 10.0**e
    return 10.0 ** (e + 1)


def default_gaps(required, max_points: int = 200) -> list[float]:
    """A grid of gaps from 0 to just above the largest required gap, with a round step (1, 2 or 5 x 10^k m)."""
    r = np.asarray([v for v in required if v is not None and math.isfinite(v)], dtype=float)
    top = max(float(r.max()) if r.size else 0.0, 0.0)
    step = _nice_step(1.05 * top, max_points)
    n = int(math.ceil(1.05 * top / step)) if top > 0 else 10
    return [float(f"{i * step:.12g}") for i in range(n + 1)]


def summarise(rows: list[dict], levels: list[float], gaps: list[float], targets: list[float], *, confidence: float = 0.95):
    """The tables of a study from the ``runs.csv`` rows.

    Returns
    -------
    fragility : list of dict
        One row per gap and level: ``gap_m, level, n_runs, n_pounding,
        p_pounding`` and the lognormal fit of that gap over the levels
        (``median, beta, median_lo, median_hi, beta_lo, beta_hi, fit``).
    target : list of dict
        One row per level and target probability: the gap for it
        (``gap_m``: order statistic; ``gap_lognormal_m``), the mean code
        estimates and the fraction of runs that pound at each of them.
    """
    from pounding.framework.post.lognormal import fit_lognormal

    ok = [r for r in rows if r.get("status") == "ok" and r.get("required_gap_m") is not None]
    by_level = {lv: np.array([r["required_gap_m"] for r in ok if r["level"] == lv], dtype=float) for lv in levels}
    present = [lv for lv in levels if by_level[lv].size]
    fragility = []
    P = {lv: pounding_probability(by_level[lv], gaps) for lv in present}
    for gi, g in enumerate(gaps):
        x = np.array(present, dtype=float)
        n = np.array([by_level[lv].size for lv in present], dtype=float)
        z = np.array([round(P[lv][gi] * by_level[lv].size) for lv in present], dtype=float)
        fit = fit_lognormal(x, n, z, level=confidence) if len(present) else None
        for j, lv in enumerate(present):
            fragility.append({
                "gap_m": g, "level": lv, "n_runs": int(n[j]), "n_pounding": int(z[j]), "p_pounding": float(P[lv][gi]),
                "median": fit.median, "beta": fit.beta, "median_lo": fit.median_lo, "median_hi": fit.median_hi,
                "beta_lo": fit.beta_lo, "beta_hi": fit.beta_hi, "fit": fit.status,
            })
    target = []
    for lv in present:
        r = by_level[lv]
        mine = [x for x in ok if x["level"] == lv]
        codes = {k: float(np.mean([x[f"{k}_m"] for x in mine])) for k in ("abs", "srss", "ddc")}
        for p in targets:
            row = {"level": lv, "p_target": p, "n_runs": int(r.size), "gap_m": gap_for_probability(r, p),
                   "gap_lognormal_m": lognormal_gap(r, p)}
            for k, v in codes.items():
                row[f"{k}_mean_m"] = v
            for k, v in codes.items():
                row[f"p_at_{k}"] = float(pounding_probability(r, [v])[0])
            target.append(row)
    return fragility, target


FRAGILITY_COLUMNS = ["gap_m", "level", "n_runs", "n_pounding", "p_pounding", "median", "beta", "median_lo", "median_hi",
                     "beta_lo", "beta_hi", "fit"]
TARGET_COLUMNS = ["level", "p_target", "n_runs", "gap_m", "gap_lognormal_m", "abs_mean_m", "srss_mean_m", "ddc_mean_m",
                  "p_at_abs", "p_at_srss", "p_at_ddc"]
CONSEQUENCE_SUMMARY_COLUMNS = ["gap_m", "level", "building", "n_runs", "n_pounding", "median_amplification",
                               "p84_amplification", "median_drift", "p84_drift", "median_drift_free", "p84_drift_free",
                               "median_ductility_amplification", "p84_ductility_amplification", "median_ductility",
                               "p84_ductility", "median_ductility_free", "p84_ductility_free"]


def summarise_consequences(free_rows: list[dict], rows: list[dict], names: list[str], levels: list[float], gaps: list[float]) -> list[dict]:
    """Per gap, level and building: the drift amplification (peak drift with contact / without) and, for a building
    with yielding storey springs, the ductility amplification (peak ductility demand with contact / without), each
    as median and 84th percentile (None for the ductility of an elastic building).

    Percentiles are empirical (:func:`numpy.quantile`, linear interpolation) over the records with both runs ok.
    """
    free = {(r["record"], r["level"]): r for r in free_rows if r.get("status") == "ok"}
    out = []
    for g in gaps:
        for lv in levels:
            pairs = [(r, free[(r["record"], lv)]) for r in rows
                     if r.get("status") == "ok" and r["gap_m"] == g and r["level"] == lv and (r["record"], lv) in free]
            if not pairs:
                continue
            for n in names:
                key = f"{n}_peak_drift_ratio_cm"
                d = np.array([a[key] for a, _ in pairs], dtype=float)
                d0 = np.array([b[key] for _, b in pairs], dtype=float)
                amp = np.divide(d, d0, out=np.full_like(d, np.nan), where=d0 > 0)
                q = (lambda v, p: float(np.quantile(v, p)) if v.size else math.nan)
                row = {"gap_m": g, "level": lv, "building": n, "n_runs": len(pairs),
                       "n_pounding": sum(1 for a, _ in pairs if a["n_impacts"] > 0),
                       "median_amplification": q(amp[np.isfinite(amp)], 0.5), "p84_amplification": q(amp[np.isfinite(amp)], 0.84),
                       "median_drift": q(d, 0.5), "p84_drift": q(d, 0.84), "median_drift_free": q(d0, 0.5), "p84_drift_free": q(d0, 0.84)}
                key = f"{n}_peak_ductility"
                if all(a.get(key) is not None and b.get(key) is not None for a, b in pairs):
                    mu = np.array([a[key] for a, _ in pairs], dtype=float)
                    mu0 = np.array([b[key] for _, b in pairs], dtype=float)
                    ratio = np.divide(mu, mu0, out=np.full_like(mu, np.nan), where=mu0 > 0)
                    row.update(median_ductility_amplification=q(ratio[np.isfinite(ratio)], 0.5),
                               p84_ductility_amplification=q(ratio[np.isfinite(ratio)], 0.84),
                               median_ductility=q(mu, 0.5), p84_ductility=q(mu, 0.84),
                               median_ductility_free=q(mu0, 0.5), p84_ductility_free=q(mu0, 0.84))
                out.append(row)
    return out


# =============================================================================
# Tables on disk: appended row by row, read back on resume
# =============================================================================

_TEXT = {"record", "im", "window_cut", "status", "error", "striking", "struck", "warnings", "fit", "building"}


def _parse(key: str, v: str):
    if v == "":
        return None
    if key in _TEXT:
        return v
    try:
        return int(v)
    except ValueError:
        return float(v)


def read_rows(path: Path, cols: list[str]) -> list[dict]:
    """Rows of a table written by this module; a row cut short by an interruption (wrong field count or unparsable) is dropped."""
    out = []
    if not path.exists():
        return out
    with open(path, newline="") as fh:
        reader = csv.reader(fh)
        header = next(reader, None)
        if header != cols:
            raise InputError(f"the columns differ from this study's ({len(header or [])} vs {len(cols)}): not written by this study",
                             file=str(path))
        for rec in reader:
            if len(rec) != len(cols):
                continue
            try:
                out.append({k: _parse(k, v) for k, v in zip(cols, rec)})
            except ValueError:
                continue
    return out


def write_rows(path: Path, cols: list[str], rows: list[dict]) -> Path:
    """Write a table atomically (a temporary file beside ``path``, then renamed)."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            w.writerow([format_cell(r.get(c)) for c in cols])
    os.replace(tmp, path)
    return path


class _Appender:
    """A CSV table appended and flushed row by row."""

    def __init__(self, path: Path, cols: list[str]):
        self.cols = cols
        self.fh = open(path, "a", newline="")
        self.writer = csv.writer(self.fh)

    def append(self, row: dict) -> None:
        self.writer.writerow([format_cell(row.get(c)) for c in self.cols])
        self.fh.flush()

    def close(self) -> None:
        self.fh.close()


# =============================================================================
# The study (client side)
# =============================================================================


@dataclass
class Study:
    """A checked study: the scene, the records and their intensities, what to run."""

    scene: object
    scene_path: Path
    records: list[tuple[str, object]]
    record_im: dict[str, float]
    im: str
    im_unit: str
    levels: list[float]
    direction: np.ndarray
    names: list[str]
    identity: dict
    consequence_gaps: list[float] = field(default_factory=list)
    #: the measure's definition (:class:`pounding.framework.studies.fragility_inputs.Measure` ``about``)
    measure: dict = field(default_factory=dict)
    #: every record against the analysis window (unscaled: the times do not depend on the scale)
    window: list = field(default_factory=list)

    def window_warning(self) -> str | None:
        """The warning naming the records whose strong motion or peak the window cuts (None if none)."""
        from pounding.framework.studies.window import window_warning

        return window_warning(self.window, f"their whole-record {self.im}", RUNS_CSV)


def _motion_hash(motion) -> str:
    h = hashlib.sha256()
    for name in ("t", "acc"):
        a = getattr(motion, name, None)
        if a is not None:
            h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    h.update(repr(getattr(motion, "angle", None)).encode())
    return h.hexdigest()[:16]


def prepare_study(scene_path, *, records=None, im: str = "pga", levels, direction=None, overrides=None,
                  consequence_gaps=None) -> Study:
    """Check every input and describe the study; raises InputError before anything is written.

    Parameters
    ----------
    scene_path : path of the scene file (TOML), two buildings
    records : None (the scene's own record) or a records folder (see :mod:`pounding.framework.studies.fragility_inputs`)
    im : intensity measure name
    levels : list of intensity levels (> 0) in the measure's unit
    direction : direction of the gap (see :func:`pounding.framework.model.placement.direction_vector`)
    overrides : {"dt": s, "duration": s}, optional
    consequence_gaps : gaps [m] for runs with contact, optional
    """
    from pounding.framework.studies.fragility_inputs import intensity_measure, record_set
    from pounding.framework.model.placement import direction_vector, rest_gap
    from pounding.framework.studies.window import check_window
    from pounding.io.scene import load_scene

    scene_path = Path(scene_path)
    scene = load_scene(scene_path)
    overrides = dict(overrides or {})
    for key, val in overrides.items():
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise InputError(f"expected a positive number, got {val!r}", field=f"--{key}")
    if overrides:
        scene = scene.with_analysis(**overrides)
    _, d = rest_gap(scene, direction_vector(direction))  # two buildings facing each other, or a clear message
    levels = [float(v) for v in levels]
    if not levels or any(not (math.isfinite(v) and v > 0) for v in levels):
        raise InputError(f"expected intensity levels > 0, got {levels}", field="--levels")
    if len(set(levels)) != len(levels):
        raise InputError(f"levels repeat: {levels}", field="--levels")
    cg = [float(g) for g in (consequence_gaps or [])]
    if any(not (math.isfinite(g) and g >= 0) for g in cg):
        raise InputError(f"expected gaps >= 0 m, got {cg}", field="--consequences")
    label, unit, fn, about = intensity_measure(im, scene)
    recs = record_set(records, scene)
    record_im = {}
    for name, motion in recs:
        value = float(fn(motion))
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"record {name!r} has {label} = {value!r}: it cannot be scaled to a level", field="--records")
        record_im[name] = value
    identity = {
        "version": STUDY_VERSION,
        "scene_sha256": hashlib.sha256(scene_path.read_bytes()).hexdigest(),
        "im": label,
        "im_unit": unit,
        "direction": [float(d[0]), float(d[1])],
        "overrides": overrides,
        "records": {name: _motion_hash(m) for name, m in recs},
        "intensity_measure": about,
    }
    window = [check_window(name, scene.with_ground_motion(m)) for name, m in recs]
    return Study(scene, scene_path, recs, record_im, label, unit, levels, d, [b.name for b in scene.buildings], identity, cg,
                 about, window)


def _check_folder(out: Path, identity: dict) -> None:
    """Refuse a folder that holds another study (or anything else); accept a new, empty or same-study folder."""
    sj = out / STUDY_JSON
    if not out.exists():
        return
    if not out.is_dir():
        raise InputError("exists and is not a folder", file=str(out), field="--out")
    if not sj.exists():
        if any(out.iterdir()):
            raise InputError("the folder is not empty and holds no study.json: not a fragility study folder", file=str(out), field="--out")
        return
    try:
        old = json.loads(sj.read_text())
    except (OSError, ValueError) as exc:
        raise InputError(f"unreadable: {exc}", file=str(sj)) from None
    for key in ("version", "scene_sha256", "im", "im_unit", "direction", "overrides"):
        if old.get(key) != identity[key]:
            raise InputError(f"this folder holds a study with another {key} ({old.get(key)!r}, now {identity[key]!r}); "
                             "use another --out", file=str(sj), field=key)
    for name, h in identity["records"].items():
        if name in old.get("records", {}) and old["records"][name] != h:
            raise InputError(f"record {name!r} differs from the one this folder's study ran; use another --out", file=str(sj),
                             field=f"records.{name}")


@dataclass
class FragilityResult:
    """What a study wrote: the rows and the tables, and how it ran."""

    runs: list[dict]
    fragility: list[dict]
    target: list[dict]
    consequences: list[dict]
    consequence_summary: list[dict]
    files: dict[str, Path]
    plots: list[Path]
    n_run: int  # runs executed now (the others were read back)
    n_resumed: int
    runtime_s: float
    workers: int
    #: the intensity measure's definition (study.json's ``intensity_measure``)
    measure: dict = field(default_factory=dict)
    #: every record against the analysis window (:class:`pounding.framework.studies.window.WindowCheck`)
    window: list = field(default_factory=list)

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.runs + self.consequences if r.get("status") != "ok"]


def _key(record: str, level: float, gap: float | None = None):
    return (record, float(level)) if gap is None else (record, float(level), float(gap))


def run_fragility(scene_path, out, *, records=None, im: str = "pga", levels, gaps=None, direction=None, overrides=None,
                  targets=(0.1,), plot_gaps=None, consequence_gaps=None, serial: bool = False, workers: int | None = None,
                  scheduler: str | None = None, plots: bool = True, progress=None, confidence: float = 0.95) -> FragilityResult:
    """Run a pounding-fragility study and write its tables and plots into ``out``.

    Parameters
    ----------
    scene_path : path of the scene file (TOML) with two buildings
    out : output folder (created; a folder of the same study is resumed)
    records, im, levels, direction, overrides, consequence_gaps : see :func:`prepare_study`
    gaps : list of gaps [m] for ``fragility.csv``, default :func:`default_gaps`
    targets : target probabilities of pounding for ``target_gap.csv``
    plot_gaps : gaps [m] whose fragility curves are drawn (default: three from the data)
    serial, workers, scheduler : see :func:`pounding.framework.studies.cluster.run_jobs`
    plots : draw the PNG plots (matplotlib)
    progress : callable(done, total, row), optional
    confidence : two-sided level of the fit's bounds

    Returns
    -------
    FragilityResult
    """
    from pounding.framework.studies.cluster import Shared, run_jobs

    t0 = time.perf_counter()
    out = Path(out)
    study = prepare_study(scene_path, records=records, im=im, levels=levels, direction=direction, overrides=overrides,
                          consequence_gaps=consequence_gaps)
    for p in targets:
        if not (0.0 < p < 1.0):
            raise InputError(f"expected target probabilities in (0, 1), got {list(targets)}", field="--target")
    if gaps is not None and any(not (math.isfinite(g) and g >= 0) for g in gaps):
        raise InputError(f"expected gaps >= 0 m, got {list(gaps)}", field="--gaps")
    _check_folder(out, study.identity)
    message = study.window_warning()
    if message:  # said before the runs start: a long study can be stopped and rerun with a longer duration
        from pounding.framework.studies.window import WindowWarning

        warnings.warn(message, WindowWarning, stacklevel=2)
    fresh = not out.exists() or not any(out.iterdir())
    out.mkdir(parents=True, exist_ok=True)
    sj = out / STUDY_JSON
    identity = dict(study.identity)
    if sj.exists():  # keep the hashes of records run before and not in this call
        identity["records"] = {**json.loads(sj.read_text()).get("records", {}), **identity["records"]}
    identity["window"] = [c.as_dict() for c in study.window]
    tmp = sj.with_name(f".{sj.name}.tmp-{os.getpid()}")
    tmp.write_text(json.dumps(identity, indent=1) + "\n")
    os.replace(tmp, sj)

    rcols, ccols = run_columns(study.names), consequence_columns(study.names)
    runs_path, cons_path = out / RUNS_CSV, out / CONSEQUENCES_CSV
    # read back what finished; drop failed and cut rows; rewrite cleanly before appending
    old_runs = {_key(r["record"], r["level"]): r for r in read_rows(runs_path, rcols) if r["status"] == "ok"}
    old_cons = {_key(r["record"], r["level"], r["gap_m"]): r for r in read_rows(cons_path, ccols) if r["status"] == "ok"}
    write_rows(runs_path, rcols, list(old_runs.values()))
    if study.consequence_gaps or cons_path.exists():
        write_rows(cons_path, ccols, list(old_cons.values()))
    from pounding.io.outputs import MANIFEST, record

    # recorded before the runs: the files of an interrupted study are pounding's (another command writing
    # into the folder, or a rerun, does not take them for a user's)
    record(out, "fragility", [sj, runs_path] + ([cons_path] if cons_path.exists() else []))

    jobs = []
    shared = {"scene": study.scene} | {f"record:{name}": m for name, m in study.records}
    d = study.direction
    for name, _ in study.records:
        for lv in study.levels:
            ident = {"record": name, "level": lv, "im": study.im, "record_im": study.record_im[name]}
            scale = lv / study.record_im[name]
            if _key(name, lv) not in old_runs:
                jobs.append((("free", _key(name, lv)), (Shared("scene"), Shared(f"record:{name}"), scale, d, ident)))
            for g in study.consequence_gaps:
                if _key(name, lv, g) not in old_cons:
                    jobs.append((("contact", _key(name, lv, g)), (Shared("scene"), Shared(f"record:{name}"), scale, g, d,
                                                                 {"record": name, "level": lv})))
    new_runs: dict = {}
    new_cons: dict = {}
    total = len(jobs)
    appenders = {"free": _Appender(runs_path, rcols)}
    if study.consequence_gaps:
        appenders["contact"] = _Appender(cons_path, ccols)

    def done(tag, row) -> None:
        kind, key = tag
        (new_runs if kind == "free" else new_cons)[key] = row
        appenders[kind].append(row)
        if progress is not None:
            progress(len(new_runs) + len(new_cons), total, row)

    def failed(tag, exc) -> None:
        kind, key = tag
        row = {"record": key[0], "level": key[1], "status": "error", "error": f"{type(exc).__name__}: {exc}"}
        if kind == "contact":
            row["gap_m"] = key[2]
        done(tag, row)

    try:
        n_workers = run_jobs(_dispatch, [(tag, (tag[0],) + args) for tag, args in jobs], done, failed, shared=shared, serial=serial,
                             workers=workers, scheduler=scheduler, name="pounding-fragility-run")
    except InputError:
        # the cluster could not be used (no dask, no scheduler): nothing ran, so a folder this call started is removed
        for a in appenders.values():
            a.close()
        if fresh and not new_runs and not new_cons:
            for f in (sj, runs_path, cons_path, out / MANIFEST):
                f.unlink(missing_ok=True)
            if not any(out.iterdir()):
                out.rmdir()
        raise
    finally:
        for a in appenders.values():
            a.close()

    # the final tables, in record and level order (rows of other records/levels kept after them)
    runs = {**old_runs, **new_runs}
    cons = {**old_cons, **new_cons}
    order = [_key(name, lv) for name, _ in study.records for lv in study.levels]
    ordered = [runs[k] for k in order if k in runs]
    extra = [r for k, r in runs.items() if k not in set(order)]
    write_rows(runs_path, rcols, ordered + extra)
    corder = [_key(name, lv, g) for name, _ in study.records for lv in study.levels for g in study.consequence_gaps]
    cordered = [cons[k] for k in corder if k in cons]
    if study.consequence_gaps or cons_path.exists():
        write_rows(cons_path, ccols, cordered + [r for k, r in cons.items() if k not in set(corder)])

    if gaps is None:
        gaps = default_gaps([r.get("required_gap_m") for r in ordered if r.get("status") == "ok"])
    gaps = sorted(set(float(g) for g in gaps))
    fragility, target = summarise(ordered, study.levels, gaps, list(targets), confidence=confidence)
    files = {"runs": runs_path, "study": sj}
    files["fragility"] = write_rows(out / FRAGILITY_CSV, FRAGILITY_COLUMNS, fragility)
    files["target"] = write_rows(out / TARGET_CSV, TARGET_COLUMNS, target)
    csum = []
    if study.consequence_gaps:
        files["consequences"] = cons_path
        csum = summarise_consequences(ordered, cordered, study.names, study.levels, study.consequence_gaps)
        files["consequence_summary"] = write_rows(out / CONSEQUENCES_SUMMARY_CSV, CONSEQUENCE_SUMMARY_COLUMNS, csum)
    paths = []
    if plots:
        from pounding.io.fragility_plots import plot_fragility

        paths = plot_fragility(out, ordered, fragility, target, study.levels, f"{study.im} [{study.im_unit}]",
                               plot_gaps=plot_gaps, confidence=confidence)
    record(out, "fragility", list(files.values()) + list(paths))
    return FragilityResult(ordered, fragility, target, cordered, csum, files, paths, total,
                           len([k for k in order if k in old_runs]), time.perf_counter() - t0, n_workers, study.measure,
                           study.window)


def _dispatch(kind: str, *args) -> dict:
    """The worker entry point: a contact-free run or a run with contact."""
    if kind == "free":
        return contact_free_run(*args)
    return consequence_run(*args)
