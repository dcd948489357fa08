"""Shared helpers: timing, error measures against a reference, CSV output, machine notes."""

from __future__ import annotations

import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
RESULTS = HERE / "results"
PYTHON = sys.executable


def log(msg: str) -> None:
    print(msg, flush=True)


# --------------------------------------------------------------------------- timing
def quiet_run(scene, **kw):
    """pounding.run with its AnalysisWarnings (energy balance) silenced."""
    from pounding import run

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run(scene, **kw)


def timed_runs(scene, reps: int, *, budget_s: float | None = None, min_reps: int = 1):
    """Run ``scene`` ``reps`` times (fewer if ``budget_s`` of wall time is spent, at least ``min_reps``).

    Returns (first Result, list of solver times ``runtime_s``, list of wall times of ``run()``).
    The wall time includes building the model (assembly, eigenproblem) and the Result.
    """
    solver, wall, first = [], [], None
    t_start = time.perf_counter()
    for i in range(reps):
        t0 = time.perf_counter()
        r = quiet_run(scene)
        wall.append(time.perf_counter() - t0)
        solver.append(r.runtime_s)
        if first is None:
            first = r
        if budget_s is not None and i + 1 >= min_reps and time.perf_counter() - t_start > budget_s:
            break
    return first, solver, wall


def med(xs) -> float:
    return float(statistics.median(xs)) if xs else float("nan")


def warm_up() -> None:
    """Load the numba cache and the lazy imports once, so every timed run is warm."""
    from scenes import load, with_method

    s = load("paper")  # its first impacts are at 1.9 s: the contact code is loaded too
    for integ in ("newmark", "exact"):
        quiet_run(with_method(s, integ, 0.01).with_analysis(duration=2.5))


# --------------------------------------------------------------------------- error measures
def corner_history(cm: dict, scene) -> np.ndarray:
    """Plan displacement of every slab vertex of every building: (nt, n_corners, 2) [m].

    ``cm`` maps building name -> (nt, storeys, 3) = (u, v, phi) at each centre of mass
    (from :meth:`Result.cm` or from OpenSees master nodes). Small rotations, as in pounding.
    """
    cols = []
    for b in scene.buildings:
        x = cm[b.name]
        for f, slab in enumerate(b.slabs):
            r = slab.vertices - slab.centre  # (k, 2)
            u, v, phi = x[:, f, 0:1], x[:, f, 1:2], x[:, f, 2:3]
            cols.append(np.stack([u - phi * r[:, 1], v + phi * r[:, 0]], axis=-1))  # (nt, k, 2)
    return np.concatenate(cols, axis=1)


def result_corners(result, scene) -> np.ndarray:
    return corner_history({n: result.cm(n) for n in result.names}, scene)


def max_penetration(result, scene) -> float:
    """Largest overlap [m] of any slab pair over the output steps (0 if none): the contact constraint's violation.

    A cheap bound (rest gap minus the largest corner displacements) selects the instants
    where the exact polygon gap is computed.
    """
    from pounding.contact.geometry import displaced, signed_gap
    from pounding.framework.engine.stacked_model import Model

    if scene.analysis.contact == "none":
        return 0.0
    m = Model(scene, systems=result.systems)
    worst = 0.0
    for a, fa, b, fb, rest in m.pairs:
        d = []
        for bld, f in ((a, fa), (b, fb)):
            s = m.slab_index(bld, f)
            n = m.systems[bld].n_dof
            i0 = m.mode_start[bld]
            x = result.q[:, i0 : i0 + n] @ m.rows[s, :, :n].T  # (nt, 3)
            d.append((s, x))
        bound = rest - sum(np.hypot(x[:, 0], x[:, 1]) + np.abs(x[:, 2]) * m.radii[s] for s, x in d)
        for k in np.flatnonzero(bound < 1e-3):
            (sa, xa), (sb, xb) = d
            pa = displaced(m.verts[sa, : m.nvert[sa]], m.centres[sa], xa[k, 0], xa[k, 1], xa[k, 2])
            pb = displaced(m.verts[sb, : m.nvert[sb]], m.centres[sb], xb[k, 0], xb[k, 1], xb[k, 2])
            worst = max(worst, -float(signed_gap(pa, pb)))
    return worst


def subsample(ref_corners: np.ndarray, dt_ref: float, dt: float, nt: int) -> np.ndarray:
    """Reference samples at the times k dt of a run with nt output rows (dt a multiple of dt_ref)."""
    m = int(round(dt / dt_ref))
    if abs(m * dt_ref - dt) > 1e-9 * dt:
        raise ValueError(f"dt = {dt} is not a multiple of the reference dt = {dt_ref}")
    out = ref_corners[::m][:nt]
    if out.shape[0] != nt:
        raise ValueError(f"reference too short: {out.shape[0]} rows for {nt}")
    return out


def errors(D: np.ndarray, R: np.ndarray, t: np.ndarray, t_window: float | None) -> dict:
    """Error measures of the corner histories D against the reference R (same times t).

    * ``l2_window``: ||D - R|| / ||R|| over every corner, both components, all samples with
      t <= t_window (the discrete relative L2 norm of the history);
    * ``l2_full``: the same over the whole record;
    * ``peak``: max over corners of |P - P_ref| / max P_ref, where P = max_t |d(t)| is the peak
      displacement magnitude of each corner over the whole record;
    * ``peak_window``: the same with the peaks taken over t <= t_window.
    """
    def rel(a, b):
        nb = float(np.linalg.norm(b))
        return float(np.linalg.norm(a - b)) / nb if nb > 0 else float("nan")

    def peak_err(a, b):
        pa = np.max(np.hypot(a[..., 0], a[..., 1]), axis=0)
        pb = np.max(np.hypot(b[..., 0], b[..., 1]), axis=0)
        return float(np.max(np.abs(pa - pb)) / np.max(pb))

    out = {"l2_full": rel(D, R), "peak": peak_err(D, R)}
    if t_window is not None:
        w = t <= t_window + 1e-12
        out["l2_window"] = rel(D[w], R[w])
        out["peak_window"] = peak_err(D[w], R[w])
    return out


# --------------------------------------------------------------------------- output
def write_csv(name: str, rows: list[dict]) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / name
    keys: list[str] = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt(r.get(k, "")) for k in keys})
    log(f"  wrote {path.relative_to(ROOT)}")
    return path


def read_csv(name: str) -> list[dict]:
    path = RESULTS / name
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return v


def write_json(name: str, data) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / name
    path.write_text(json.dumps(data, indent=1, default=str) + "\n")
    log(f"  wrote {path.relative_to(ROOT)}")
    return path


def machine() -> dict:
    """What the numbers were measured on (written next to the results)."""
    def git(*args):
        try:
            return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, timeout=10).stdout.strip()
        except Exception:  # pragma: no cover - no git
            return ""

    try:
        load = os.getloadavg()
    except OSError:  # pragma: no cover
        load = (float("nan"),) * 3
    import numba
    import numpy
    import scipy

    return {
        "when": time.strftime("%Y-%m-%d %H:%M:%S"),
        "python": platform.python_version(),
        "platform": platform.platform(),
        "cpus": os.cpu_count(),
        "load_average_1_5_15": [round(x, 2) for x in load],
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "OPENBLAS_NUM_THREADS": os.environ.get("OPENBLAS_NUM_THREADS", "(unset)"),
        "git_commit": git("rev-parse", "--short", "HEAD"),
        "git_dirty_files": [l[3:] for l in git("status", "--porcelain").splitlines() if not l[3:].startswith("benchmarks/")],
    }


def loglog_fit(x, y) -> float:
    """Exponent p of y ~ x^p by least squares in log-log."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0) & np.isfinite(y)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)[0])
