"""Headline targets: measured, never asserted.

* the paper example with pounding, whole El Centro record, dt = 0.005 s (the scene file
  as shipped: hht, halving, restitution 0.5): solver time, median of 11 warm runs;
  target < 20 ms;
* ``pounding run`` of that scene as a whole process (subprocess, median of 5), with the
  user's environment and with OPENBLAS_NUM_THREADS=1; target < 1.5 s; plus a phase
  breakdown of one cold process and the bare interpreter start-up;
* the OpenSeesPy ratio (from the peer benchmark); target >= 50x;
* two 60-storey buildings with pounding, whole record (from the scaling benchmark);
  target < 2 s solver time;
* memory: tracemalloc peak of run() against the response arrays at output rate plus the
  O(n^2) model arrays (from the scaling benchmark).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

from common import HERE, PYTHON, ROOT, log, med, read_csv, timed_runs, write_json
from scenes import SCENE_FILES, load, no_pounding

USER_ENV: dict = dict(os.environ)  # replaced by run.py with the environment before it pinned BLAS threads


def cli_time(env: dict, reps: int = 5) -> list[float]:
    exe = Path(PYTHON).parent / "pounding"
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(reps):
            t0 = time.perf_counter()
            p = subprocess.run([str(exe), "run", str(SCENE_FILES["paper"]), "--out", f"{tmp}/out{i}", "--quiet"],
                               env=env, capture_output=True, text=True, cwd=ROOT)
            times.append(time.perf_counter() - t0)
            if p.returncode != 0:
                raise RuntimeError(f"pounding run failed: {p.stderr.strip()[-300:]}")
    return times


def interpreter_start(env: dict, reps: int = 5) -> float:
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        subprocess.run([PYTHON, "-c", "pass"], env=env, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def cli_phases(env: dict) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        spec = {"kind": "cli_phases", "scene": str(SCENE_FILES["paper"]), "out": f"{tmp}/out"}
        p = subprocess.run([PYTHON, str(HERE / "_case.py"), json.dumps(spec)], env=env, capture_output=True, text=True)
    if p.returncode != 0:
        return {"status": "failed: " + p.stderr.strip()[-200:]}
    return json.loads(p.stdout.strip().splitlines()[-1])


def run(quick: bool = False) -> dict:
    out: dict = {}
    s = load("paper")
    r, solver, wall = timed_runs(s, 5 if quick else 11)
    out["paper_pounding"] = dict(solver_median_s=med(solver), solver_min_s=min(solver), wall_median_s=med(wall), runs=len(solver),
                                 n_impacts=r.n_impacts, located_events=r.info.get("located_events"), steps=r.steps)
    log(f"  paper, pounding, dt=0.005: solver {med(solver) * 1e3:.1f} ms (min {min(solver) * 1e3:.1f}), run() wall {med(wall) * 1e3:.1f} ms, "
        f"{r.n_impacts} impacts")
    r, solver, wall = timed_runs(no_pounding(s), 5 if quick else 11)
    out["paper_no_pounding"] = dict(solver_median_s=med(solver), solver_min_s=min(solver), wall_median_s=med(wall), runs=len(solver))
    log(f"  paper, contact off, dt=0.005: solver {med(solver) * 1e3:.2f} ms (min {min(solver) * 1e3:.2f})")

    pinned = dict(USER_ENV, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    for label, env in (("user_env", USER_ENV), ("blas_1_thread", pinned)):
        times = cli_time(env, reps=3 if quick else 5)
        out[f"cli_{label}"] = dict(median_s=statistics.median(times), min_s=min(times), runs=len(times),
                                   OPENBLAS_NUM_THREADS=env.get("OPENBLAS_NUM_THREADS", "(unset)"))
        log(f"  pounding run ({label}): median {statistics.median(times):.2f} s, min {min(times):.2f} s")
    out["interpreter_start_s"] = interpreter_start(USER_ENV)
    out["cli_phases_user_env"] = cli_phases(USER_ENV)
    log("  phases of one cold `pounding run` process: " + ", ".join(
        f"{k[:-2]} {v:.3f}" for k, v in out["cli_phases_user_env"].items() if k.endswith("_s")))
    write_json("targets" + ("_quick" if quick else "") + ".json", out)
    return out


# --------------------------------------------------------------------------- headline assembly
TARGETS = {
    "paper_solver": 0.020,
    "cli": 1.5,
    "opensees_ratio": 50.0,
    "sixty_storeys": 2.0,
}


def _f(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def headline(quick: bool, targets: dict | None) -> dict:
    """Collect the headline numbers from this run (or the CSV/JSON files on disk)."""
    tag = "_quick" if quick else ""
    if targets is None:
        p = HERE / "results" / f"targets{tag}.json"
        targets = json.loads(p.read_text()) if p.exists() else {}
    peer = read_csv(f"peer{tag}.csv") or read_csv("peer.csv")
    scaling = read_csv(f"scaling{tag}.csv") or read_csv("scaling.csv")
    conv = read_csv(f"reference_convergence{tag}.csv") or read_csv("reference_convergence.csv")
    h: dict = {}
    if targets:
        h["paper_solver_s"] = targets["paper_pounding"]["solver_median_s"]
        h["paper_solver_min_s"] = targets["paper_pounding"]["solver_min_s"]
        h["paper_impacts"] = targets["paper_pounding"]["n_impacts"]
        h["paper_nopound_solver_s"] = targets["paper_no_pounding"]["solver_median_s"]
        h["cli_s"] = targets["cli_user_env"]["median_s"]
        h["cli_runs"] = targets["cli_user_env"]["runs"]
        h["cli_1thread_s"] = targets["cli_blas_1_thread"]["median_s"]
        h["cli_phases"] = targets.get("cli_phases_user_env", {})
        h["interpreter_start_s"] = targets.get("interpreter_start_s")
    prow = [r for r in peer if r["scene"] == "paper"]
    if prow:
        best = max(prow, key=lambda r: _f(r["dt"]) == 0.005)
        h["peer_paper_dt"] = _f(best["dt"])
        h["peer_paper_ratio_solver"] = _f(best["ratio_solver"])
        h["peer_paper_ratio_wall"] = _f(best["ratio_wall"])
        h["peer_paper_opensees_s"] = _f(best["opensees_s"])
        h["peer_paper_ours_s"] = _f(best["ours_newmark_solver_s"])
        h["peer_paper_err_ours"] = _f(best["ours_newmark_err_l2"])
        h["peer_paper_err_os"] = _f(best["opensees_err_l2"])
        h["peer_min_ratio_solver"] = min(_f(r["ratio_solver"]) for r in peer)
        h["peer_min_ratio_wall"] = min(_f(r["ratio_wall"]) for r in peer)
    pp = read_csv(f"peer_pounding{tag}.csv") or read_csv("peer_pounding.csv")
    if pp:
        h["peer_pounding_ratio_solver"] = min(_f(r["ratio_solver"]) for r in pp)
        h["peer_pounding_ratio_wall"] = min(_f(r["ratio_wall"]) for r in pp)
        h["peer_pounding_opensees_s"] = _f(pp[0]["opensees_s"])
        h["peer_pounding_ours_s"] = _f(pp[0]["ours_solver_s"])
        h["peer_pounding_err_ours"] = max(_f(r["ours_err_l2"]) for r in pp)
        h["peer_pounding_err_os"] = max(_f(r["opensees_err_l2"]) for r in pp)
    s60 = [r for r in scaling if r.get("kind") == "storeys" and r.get("storeys") == "60" and r.get("contact") == "impulse" and r.get("status") == "ok"]
    if s60:
        h["sixty_solver_s"] = _f(s60[0]["solver_median_s"])
        h["sixty_impacts"] = int(_f(s60[0]["n_impacts"]))
        h["sixty_wall_s"] = _f(s60[0]["wall_median_s"])
    s60n = [r for r in scaling if r.get("kind") == "storeys" and r.get("storeys") == "60" and r.get("contact") == "none" and r.get("status") == "ok"]
    if s60n:
        h["sixty_nopound_solver_s"] = _f(s60n[0]["solver_median_s"])
    big = [r for r in scaling if r.get("kind") == "storeys" and r.get("status") == "ok"]
    if big:
        top = max(big, key=lambda r: (_f(r["storeys"]), r["contact"] == "impulse"))
        h["mem_storeys"] = int(_f(top["storeys"]))
        h["mem_contact"] = top["contact"]
        h["mem_tracemalloc_MB"] = _f(top["tracemalloc_peak_MB"])
        h["mem_response_MB"] = _f(top["response_MB"])
        h["mem_model_MB"] = _f(top["model_MB"])
        h["mem_ratio"] = _f(top["peak_over_response_plus_model"])
    pc = [r for r in conv if r.get("pounding") == "True"]
    if pc:
        h["ref_conv"] = [(r["scene"], _f(r["l2_window"]), _f(r.get("peak", "nan"))) for r in pc]
    return h


def headline_markdown(h: dict) -> str:
    def ms(x):
        return f"{1e3 * x:.1f} ms" if x == x else "n/a"

    def ok(val, target, less=True):
        if val is None or val != val:
            return "not measured"
        return "met" if (val < target if less else val >= target) else "**missed**"

    lines = ["| target | measured | status |", "|---|---|---|"]
    if "paper_solver_s" in h:
        lines.append(f"| paper example with pounding, whole record, dt = 0.005 s: solver time < 20 ms | "
                     f"{ms(h['paper_solver_s'])} median (min {ms(h['paper_solver_min_s'])}), {h['paper_impacts']} impacts; "
                     f"contact off: {ms(h['paper_nopound_solver_s'])} | {ok(h['paper_solver_s'], 0.020)} |")
        lines.append(f"| `pounding run` of it as a whole process < 1.5 s | {h['cli_s']:.2f} s median of {h.get('cli_runs', 5)} "
                     f"({h['cli_1thread_s']:.2f} s with OPENBLAS_NUM_THREADS=1) | {ok(h['cli_s'], 1.5)} |")
    if "peer_paper_ratio_solver" in h:
        lines.append(f"| >= 50x faster than OpenSeesPy at equal or smaller error | paper, dt = {h['peer_paper_dt']:g} s: "
                     f"{h['peer_paper_ratio_solver']:.0f}x (solver), {h['peer_paper_ratio_wall']:.0f}x (run() incl. assembly); "
                     f"OpenSees {h['peer_paper_opensees_s']:.1f} s vs {ms(h['peer_paper_ours_s'])}, errors {h['peer_paper_err_ours']:.2e} vs "
                     f"{h['peer_paper_err_os']:.2e}; smallest ratio over all scenes and dt: {h['peer_min_ratio_solver']:.0f}x / "
                     f"{h['peer_min_ratio_wall']:.0f}x | {ok(h['peer_min_ratio_wall'], 50, less=False)} |")
    if "peer_pounding_ratio_solver" in h:
        lines.append(f"| the same with pounding (penalty pair against OpenSees gap elements, dt = 0.002 s, 10 s) | "
                     f"{h['peer_pounding_ratio_solver']:.0f}x (solver), {h['peer_pounding_ratio_wall']:.0f}x (run()); OpenSees "
                     f"{h['peer_pounding_opensees_s']:.1f} s vs {ms(h['peer_pounding_ours_s'])}, errors {h['peer_pounding_err_ours']:.2e} vs "
                     f"{h['peer_pounding_err_os']:.2e} | {ok(h['peer_pounding_ratio_wall'], 50, less=False)} |")
    if "sixty_solver_s" in h:
        lines.append(f"| two 60-storey buildings with pounding, whole record: solver < 2 s | {h['sixty_solver_s']:.2f} s "
                     f"({h['sixty_impacts']} impacts; contact off {h.get('sixty_nopound_solver_s', float('nan')):.2f} s) | "
                     f"{ok(h['sixty_solver_s'], 2.0)} |")
    if "mem_tracemalloc_MB" in h:
        lines.append(f"| memory: response arrays at output rate + O(n^2) | {h['mem_storeys']} storeys ({h['mem_contact']}): "
                     f"tracemalloc peak {h['mem_tracemalloc_MB']:.1f} MB = {h['mem_ratio']:.2f} x (response {h['mem_response_MB']:.1f} MB "
                     f"+ K, C, modes, rows {h['mem_model_MB']:.1f} MB) | {'met' if h['mem_ratio'] < 3 else '**missed**'} (< 3x) |")
    return "\n".join(lines)
