"""Start-up targets of the compiled core (issue 12): measured, never asserted.

Whole processes, median of N (default 5), in one run beside the baseline
``python -c "import numpy, scipy.linalg"``:

* cold ``pounding run`` of the paper pair with pounding: an empty numba cache
  (``NUMBA_CACHE_DIR`` a fresh temporary folder for every process); target < 10 s;
* warm ``pounding run`` of it (the cache filled by a first run); target < 0.8 s and
  < 2x the baseline: with the extension module built at install (:mod:`pounding.aot`, as
  ``make`` builds it; ``warm_run``) and with numba's cache alone (``POUNDING_AOT=0``,
  ``warm_run_numba``);
* the user's first-ever run after the install (``cold_run_after_install``: numba's cache empty,
  the extension module built) and with nothing built (``cold_run``: numba's cache empty,
  ``POUNDING_AOT=0``);
* ``pounding info`` of it; target < 1.5x the baseline;
* warm in-process solver time (``Result.runtime_s``, median of 7; numba's dispatch, what a
  program importing pounding gets, and ``solver_aot`` with the extension module forced on) of the paper pair and
  of two 60-storey buildings with pounding, with today's defaults and with the contact rules
  they had when the target was set (``*_rules``: halving, keep, 1e-4 m); target: no worse than before;
* where a cold run's time goes: every compiled function and its compile time
  (one cold process);
* the install-time warm-up (``python -m pounding.warmup --warm``, what ``make demo`` and
  ``make test`` run once per version of the compiled modules) from an empty cache, in 2
  processes and in 1, wall and CPU time, and the user's first ``pounding run`` after it.

Cold figures depend heavily on the load of the machine: each is given with the load average
read before and after.

``--python`` and ``--root`` measure another checkout the same way (e.g. the code
before the change, for the "before" column): ``--python /work/main/.venv/bin/python
--root /work/main``.

    .venv/bin/python benchmarks/bench_compile.py [--reps 5] [--cold-reps 5] [--out results/compile.json]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def timed(cmd: list[str], env: dict, cwd: Path) -> float:
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {p.stderr.strip()[-400:]}")
    return dt


def timed_cpu(cmd: list[str], env: dict, cwd: Path) -> dict:
    """Wall and CPU (user + system of the process and its children) time [s] of one command."""
    import resource

    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    load0 = os.getloadavg()[0]
    wall = timed(cmd, env, cwd)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return {"wall_s": wall, "cpu_s": cpu, "load_before": load0, "load_after": os.getloadavg()[0]}


def median_of(cmd, env, cwd, reps) -> dict:
    """Median wall time [s] of ``reps`` runs, and their median CPU time (on a loaded machine the
    wall time measures the other jobs as much as this one; the CPU time much less)."""
    runs = [timed_cpu(cmd, env, cwd) for _ in range(reps)]
    walls = [r["wall_s"] for r in runs]
    return {"median_s": statistics.median(walls), "min_s": min(walls), "median_cpu_s": statistics.median(r["cpu_s"] for r in runs),
            "runs": reps, "load": [runs[0]["load_before"], runs[-1]["load_after"]]}


SOLVER = r"""
import json, statistics, sys, warnings
warnings.simplefilter("ignore")
sys.path.insert(0, {bench!r})
from pounding.io.scene import load_scene
from pounding.framework.post.run import run
from scenes import uniform_pair
out = {{}}
def paper_rules(scene):
    # the contact rules these scenes ran with when issue 12 set "no worse than today" (halving, keep, 1e-4 m):
    # the like-for-like comparison; without them the run gets today's defaults (crossing, equilibrium)
    return scene.with_analysis(contact_params={{**scene.analysis.contact_params, "locate": "halving", "after_impact": "keep",
                                                "tolerance": 1e-4}})
paper, sixty = load_scene({paper!r}), uniform_pair(60)
for name, scene in (("paper", paper), ("sixty", sixty), ("paper_rules", paper_rules(paper)), ("sixty_rules", paper_rules(sixty))):
    run(scene)  # warm: compiled or loaded once
    t = [run(scene).runtime_s for _ in range({reps})]
    out[name] = {{"solver_median_s": statistics.median(t), "solver_min_s": min(t), "runs": len(t)}}
print(json.dumps(out))
"""

BREAKDOWN = r"""
import json, sys, time
t0 = time.perf_counter()
from pounding.io.scene import load_scene
scene = load_scene({paper!r})
t1 = time.perf_counter()
from pounding.framework.post.run import run
r = run(scene)
t2 = time.perf_counter()
rows = []
for name, mod in list(sys.modules.items()):
    if not name.startswith("pounding"):
        continue
    for attr, obj in list(vars(mod).items()):
        d = getattr(obj, "_dispatcher", None) or obj
        if type(d).__name__ != "CPUDispatcher" or getattr(d, "__module__", None) != name or not d.signatures:
            continue
        secs = sum((cr.metadata or {{}}).get("timers", {{}}).get("compiler_lock", 0.0) for cr in d.overloads.values())
        rows.append({{"function": name + "." + attr, "signatures": len(d.signatures), "compile_s": secs}})
rows.sort(key=lambda x: -x["compile_s"])
print(json.dumps({{"load_scene_s": t1 - t0, "run_s": t2 - t1, "timings": getattr(r, "timings", {{}}),
                  "functions": rows}}))
"""


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--python", default=sys.executable, help="interpreter of the checkout to measure")
    ap.add_argument("--root", default=str(HERE.parent), help="that checkout's folder")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--cold-reps", type=int, default=5)
    ap.add_argument("--warm-reps", type=int, default=1, help="repetitions of the install-time warm-up (per job count)")
    ap.add_argument("--out", default=None, help="JSON file for the figures")
    args = ap.parse_args(argv)
    root = Path(args.root)
    py = args.python
    exe = str(Path(py).parent / "pounding")
    paper = str(root / "examples" / "paper" / "pair_gap_0.03.toml")
    env = dict(os.environ)
    env.pop("NUMBA_CACHE_DIR", None)
    res: dict = {"root": str(root), "python": py}
    log = lambda m: print(m, file=sys.stderr, flush=True)  # noqa: E731

    res["baseline_numpy_scipy"] = median_of([py, "-c", "import numpy, scipy.linalg"], env, root, args.reps)
    log(f"baseline import numpy, scipy.linalg: {res['baseline_numpy_scipy']['median_s']:.3f} s")
    numba_only = dict(env, POUNDING_AOT="0")
    with tempfile.TemporaryDirectory() as tmp:
        timed([exe, "run", paper, "--out", f"{tmp}/warmup", "--quiet"], numba_only, root)  # fill the cache
        # the extension module (pounding.aot), as make builds it after the warm-up
        res["aot_build"] = timed_cpu([py, "-m", "pounding.aot", "--quiet", "--if-needed"], env, root)
        res["aot_build"]["manifest"] = _aot_manifest(py, root, env)
        log(f"extension module: {res['aot_build']}")
        res["info"] = median_of([exe, "info", paper], env, root, args.reps)
        log(f"pounding info: {res['info']['median_s']:.3f} s")
        res["warm_run"] = median_of([exe, "run", paper, "--out", f"{tmp}/w", "--quiet"], env, root, args.reps)
        log(f"warm pounding run (extension module): {res['warm_run']['median_s']:.3f} s")
        res["warm_run_numba"] = median_of([exe, "run", paper, "--out", f"{tmp}/wn", "--quiet"], numba_only, root, args.reps)
        log(f"warm pounding run (numba's cache): {res['warm_run_numba']['median_s']:.3f} s")
        for key, base_env in (("cold_run", numba_only), ("cold_run_after_install", env)):
            cold = []
            for i in range(args.cold_reps):
                with tempfile.TemporaryDirectory() as cache:
                    cold.append(timed_cpu([exe, "run", paper, "--out", f"{tmp}/c{key}{i}", "--quiet"], dict(base_env, NUMBA_CACHE_DIR=cache), root))
                log(f"{key} {i + 1}: {cold[-1]}")
            walls = [c["wall_s"] for c in cold]
            res[key] = {"median_s": statistics.median(walls), "min_s": min(walls), "runs": len(cold), "each": cold}
        res["warm_up"] = {}
        for jobs in (2, 1):
            reps = []
            for i in range(args.warm_reps):
                with tempfile.TemporaryDirectory() as cache:
                    cenv = dict(numba_only, NUMBA_CACHE_DIR=cache)
                    w = timed_cpu([py, "-m", "pounding.warmup", "--warm", "--jobs", str(jobs), "--quiet"], cenv, root)
                    if jobs == 2:  # the user's first run after the install-time warm-up
                        w["first_run_after_s"] = timed([exe, "run", paper, "--out", f"{tmp}/a{i}", "--quiet"], cenv, root)
                reps.append(w)
                log(f"warm-up with {jobs} process(es) {i + 1}: {w}")
            res["warm_up"][f"jobs_{jobs}"] = {"median_wall_s": statistics.median(r["wall_s"] for r in reps),
                                              "median_cpu_s": statistics.median(r["cpu_s"] for r in reps), "each": reps}
        with tempfile.TemporaryDirectory() as cache:
            p = subprocess.run([py, "-c", BREAKDOWN.format(paper=paper)], env=dict(numba_only, NUMBA_CACHE_DIR=cache), cwd=root,
                               capture_output=True, text=True)
        res["cold_breakdown"] = json.loads(p.stdout.strip().splitlines()[-1]) if p.returncode == 0 else {"failed": p.stderr[-400:]}
    # in-process, as a program that imports pounding runs (numba's dispatch), and with the module forced on
    for key, senv in (("solver", dict(env, POUNDING_AOT="0")), ("solver_aot", dict(env, POUNDING_AOT="1"))):
        p = subprocess.run([py, "-c", SOLVER.format(paper=paper, bench=str(HERE), reps=7)], env=senv, cwd=root, capture_output=True, text=True)
        res[key] = json.loads(p.stdout.strip().splitlines()[-1]) if p.returncode == 0 else {"failed": p.stderr[-400:]}
        log(f"warm {key}: {res[key]}")
    base = res["baseline_numpy_scipy"]["median_s"]
    res["ratios_to_baseline"] = {"warm_run": res["warm_run"]["median_s"] / base, "warm_run_numba": res["warm_run_numba"]["median_s"] / base,
                                 "info": res["info"]["median_s"] / base}
    base_cpu = res["baseline_numpy_scipy"]["median_cpu_s"]
    res["cpu_ratios_to_baseline"] = {"warm_run": res["warm_run"]["median_cpu_s"] / base_cpu, "info": res["info"]["median_cpu_s"] / base_cpu}
    if args.out:
        Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))
    return res


def _aot_manifest(py, root, env) -> dict:
    """Entry points and build time of the extension module (pounding.aot), or why there is none."""
    code = ("import json; from pounding.compiler import prebuilt; w = prebuilt.folder(); m = w / 'manifest.json' if w else None; "
            "print(json.dumps(json.loads(m.read_text()) if m and m.exists() else None))")
    p = subprocess.run([py, "-c", code], env=env, cwd=root, capture_output=True, text=True)
    m = json.loads(p.stdout.strip().splitlines()[-1]) if p.returncode == 0 else None
    return {"built": False} if not m else {"built": True, "entry_points": len(m["exports"]), "seconds": m.get("seconds")}


def run(quick: bool = False) -> dict:
    """Entry of ``benchmarks/run.py --only compile``: results/compile[_quick].json."""
    tag = "_quick" if quick else ""
    reps = ["--reps", "3", "--cold-reps", "1"] if quick else []
    return main(reps + ["--out", str(HERE / "results" / f"compile{tag}.json")])


if __name__ == "__main__":
    main()
