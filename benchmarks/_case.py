"""One benchmark case in a fresh process (so peak RSS belongs to this case alone).

Usage: python benchmarks/_case.py '<json spec>'; prints one JSON line on stdout.

spec kinds:
  {"kind": "storeys", "n": 60, "contact": "impulse", "gap": 0.05, "reps": 5, "budget": 10}
  {"kind": "length", "times": 4, "contact": "impulse", "reps": 5, "budget": 10}
  {"kind": "cli_phases", "scene": "path.toml", "out": "dir"}
"""

from __future__ import annotations

import json
import resource
import sys
import time

T_PROCESS = time.perf_counter()


def maxrss_mb() -> float:
    """Peak resident set size of this process [MB].

    VmHWM of /proc/self/status, not getrusage's ru_maxrss: Linux carries ru_maxrss over
    execve from the forking parent, so a child of a big parent would report the parent's peak.
    """
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) / 1024.0  # kB
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def case_scene(spec):
    from scenes import load, no_pounding, tiled, uniform_pair

    if spec["kind"] == "storeys":
        return uniform_pair(int(spec["n"]), gap=float(spec.get("gap", 0.05)), contact=spec["contact"])
    if spec["kind"] == "length":
        s = load("paper")
        if spec["contact"] == "none":
            s = no_pounding(s)
        return tiled(s, int(spec["times"]))
    raise ValueError(spec["kind"])


def run_case(spec) -> dict:
    import tracemalloc

    import numpy as np

    from common import quiet_run, timed_runs
    from pounding.framework.engine.stacked_model import Model

    out: dict = {}
    t0 = time.perf_counter()
    scene = case_scene(spec)
    out["parse_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    model = Model(scene)
    out["assemble_s"] = time.perf_counter() - t0
    out["n_modes"] = model.n
    out["n_pairs"] = len(model.pairs)
    out["periods_1"] = [float(2 * np.pi / s.omega[0]) for s in model.systems]
    # warm: numba cache (kernel and contact geometry) and lazy imports: the paper pair up to
    # its first impacts, then a short piece of this scene
    from scenes import load

    quiet_run(load("paper").with_analysis(duration=2.5))
    quiet_run(scene.with_analysis(duration=min(1.0, scene.ground_motion.duration)))
    out["rss_before_mb"] = maxrss_mb()

    reps, budget = int(spec.get("reps", 5)), float(spec.get("budget", 10.0))
    first, solver, wall = timed_runs(scene, reps, budget_s=budget)
    out["reps"] = len(solver)
    out["solver_median_s"] = float(np.median(solver))
    out["solver_min_s"] = float(np.min(solver))
    out["wall_median_s"] = float(np.median(wall))
    out["steps"] = first.steps
    out["n_impacts"] = first.n_impacts
    out["located_events"] = first.info.get("located_events")
    out["rss_after_runs_mb"] = maxrss_mb()
    # response arrays at the output rate, and the O(n^2) model arrays
    out["response_bytes"] = int(first.q.nbytes + first.qd.nbytes)
    out["model_bytes"] = int(sum(s.K.nbytes + s.C.nbytes + s.modes.nbytes for s in model.systems) + model.rows.nbytes)
    del first  # free the results before the memory measurements below
    # one instrumented run: how many steps took the Python path, and the time spent there and in the kernel
    out.update(split_run(scene))
    # one more run under tracemalloc: peak of the Python/numpy allocations of run() (model + driver + result)
    tracemalloc.start()
    r = quiet_run(scene)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    out["tracemalloc_peak_bytes"] = int(peak)
    out["rss_peak_mb"] = maxrss_mb()
    return out


def split_run(scene) -> dict:
    """Steps and time in Driver.python_step vs Driver.advance (the compiled kernel), one run."""
    import warnings

    try:
        from pounding.framework.engine.driver import Driver

        d = Driver(scene)
        acc = {"python_steps": 0, "python_path_s": 0.0, "kernel_calls": 0, "kernel_s": 0.0}

        def wrap(fn, n_key, t_key):
            def inner(*a, **k):
                t0 = time.perf_counter()
                try:
                    return fn(*a, **k)
                finally:
                    acc[n_key] += 1
                    acc[t_key] += time.perf_counter() - t0
            return inner

        d.python_step = wrap(d.python_step, "python_steps", "python_path_s")
        d.advance = wrap(d.advance, "kernel_calls", "kernel_s")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = d.run()
        acc["split_run_solver_s"] = r.runtime_s
        return acc
    except Exception as exc:  # the driver's internals may change; the split is optional
        return {"split_error": repr(exc)[:200]}


def cli_phases(spec) -> dict:
    """Where the time of `pounding run` goes, phase by phase, in one cold process."""
    out = {}
    t0 = time.perf_counter()
    import numpy  # noqa: F401
    out["import_numpy_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    import scipy.linalg  # noqa: F401
    out["import_scipy_linalg_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    import numba  # noqa: F401
    out["import_numba_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    import pounding.cli  # noqa: F401
    from pounding.framework.engine.driver import Driver  # noqa: F401
    from pounding.framework.engine.stacked_model import Model  # noqa: F401
    from pounding.io.results import write_results
    from pounding.io.scene import load_scene
    out["import_pounding_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    import jsonschema  # noqa: F401
    out["import_jsonschema_s"] = time.perf_counter() - t0
    from pathlib import Path

    t0 = time.perf_counter()
    scene = load_scene(spec["scene"])
    out["load_scene_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    model = Model(scene)
    out["assemble_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    d = Driver(scene, model=model)
    out["driver_init_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    result = d.run()
    out["run_first_s"] = time.perf_counter() - t0
    out["run_first_solver_s"] = result.runtime_s
    t0 = time.perf_counter()
    write_results(result, Path(spec["out"]), Path(spec["scene"]).read_text())
    out["write_results_s"] = time.perf_counter() - t0
    out["total_in_process_s"] = time.perf_counter() - T_PROCESS
    return out


if __name__ == "__main__":
    spec = json.loads(sys.argv[1])
    sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parent))
    if spec["kind"] == "cli_phases":
        res = cli_phases(spec)
    else:
        res = run_case(spec)
    res["spec"] = spec
    print(json.dumps(res))
