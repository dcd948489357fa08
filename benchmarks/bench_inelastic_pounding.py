"""Pounding with yielding buildings: speed against the elastic solver and against OpenSeesPy.

Run: ``.venv/bin/python benchmarks/bench_inelastic_pounding.py [--quick]``; writes
``results/inelastic_pounding[_quick].json`` and prints a table.

1. **Paper pair with yielding storeys and pounding** (``examples/inelastic_pair``'s buildings, built
   by :func:`bench_inelastic.paper_springs`, at the paper's gap 0.03 m, impulse contact k = 0.5 with
   equilibrium after impacts, HHT alpha = -0.05, dt = 0.005 s, whole record) against the elastic
   solver on the same initial model with pounding (``yield_force`` removed: the compiled core).
   Solver times (``Result.runtime_s``), the fastest of warm runs, and process CPU times; the same
   yielding run stepped wholly in Python (``use_kernel=False``) beside. Target (issue 15): within 4x.
   Whole processes (``pounding run``): warm, and one cold (empty numba cache) with its compile time.
2. **Two 20-storey yielding buildings pounding** (:func:`bench_inelastic.tall_pair` moved to a
   0.05 m gap, "east" 0.6 times as stiff, shaken along x), penalty contact (1e9 N/m per facade end, k = 1) against OpenSeesPy
   (:func:`pounding.peer.opensees_springs.run_springs_gap_pounding`: Steel01 links, ElasticPPGap),
   Newmark average acceleration, dt = 0.01 s. Error of both against pounding at dt / 8: peak roof
   displacement and the L2 history error of every slab's u, relative. Target: 100x at equal error.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_inelastic import log, paper_springs, tall_pair, timed  # noqa: E402
from pounding.framework.post.energy_account import energy_balance


def _move(data: dict, building: int, shift: float) -> dict:
    b = data["building"][building]
    b["slab"] = [[x + shift, y] for x, y in b["slab"]]
    for e in b["element"]:
        e["start"] = [e["start"][0] + shift, e["start"][1]]
        e["end"] = [e["end"][0] + shift, e["end"][1]]
    return data


PAPER_CONTACT = {"name": "impulse", "restitution": 0.5, "after_impact": "equilibrium"}


def paper_data(hysteresis) -> dict:
    data = _move(paper_springs(hysteresis=hysteresis), 1, 0.03 - 0.5)
    data["analysis"]["contact"] = PAPER_CONTACT
    return data


def paper_case(reps: int) -> dict:
    """Warm in-process solver times (``Result.runtime_s``, fastest of ``reps``) of the elastic and the
    yielding paper pair, and of the yielding one stepped wholly in Python (``use_kernel=False``: the
    path every step took before the compiled stretches); the CPU time of each, less disturbed by the
    other processes of a shared machine, beside."""
    from pounding.framework.engine.driver import Driver
    from pounding.io.scene import parse_scene

    rows = {}
    for key, hyst, kernel in (("elastic", None, True), ("bilinear", "bilinear", True), ("bilinear_python_path", "bilinear", False)):
        scene = parse_scene(paper_data(hyst))
        Driver(scene, use_kernel=kernel).run()  # warm (compile)
        cpu = []

        def once():
            c0 = time.process_time()
            r = Driver(scene, use_kernel=kernel).run()
            cpu.append(time.process_time() - c0)
            return r

        r, t, all_t = timed(once, reps)
        rows[key] = {"solver_s": t, "solver_median_s": float(np.median(all_t)), "process_cpu_s_min": float(min(cpu)),
                     "impacts": r.n_impacts, "steps": r.steps, "energy_relative_error": energy_balance(r)["relative_error"]}
        if r.springs:
            rows[key]["peak_ductility"] = {n: float(np.max(sp["peak"] / sp["yield_deformation"])) for n, sp in r.springs.items()}
    rows["ratio"] = rows["bilinear"]["solver_s"] / rows["elastic"]["solver_s"]
    rows["ratio_cpu"] = rows["bilinear"]["process_cpu_s_min"] / rows["elastic"]["process_cpu_s_min"]
    log(f"paper pair with pounding: yielding {rows['bilinear']['solver_s'] * 1e3:.1f} ms ({rows['bilinear']['impacts']} impacts), "
        f"elastic {rows['elastic']['solver_s'] * 1e3:.1f} ms ({rows['elastic']['impacts']} impacts): {rows['ratio']:.1f}x "
        f"(CPU {rows['ratio_cpu']:.1f}x; target 4x); every step in Python {rows['bilinear_python_path']['solver_s'] * 1e3:.1f} ms")
    return rows


def whole_process(reps: int) -> dict:
    """``pounding run`` of the yielding and the elastic paper pair as whole processes: warm (the
    numba cache filled by a first run; median and fastest of ``reps``), and one cold process with an
    empty cache (``NUMBA_CACHE_DIR`` a fresh folder) for the yielding pair, whose summary.json says
    how much of it was compiling (``timings_s.compile``)."""
    import statistics
    import subprocess
    import tempfile

    sys.path.insert(0, str(HERE.parent / "tests"))
    from strategies import to_toml

    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        env = dict(os.environ)
        for key, hyst in (("elastic", None), ("bilinear", "bilinear")):
            path = tmp / f"{key}.toml"
            path.write_text(to_toml(paper_data(hyst)))
            cmd = [sys.executable, "-m", "pounding", "run", str(path), "--out", str(tmp / f"out_{key}")]
            subprocess.run(cmd, env=env, check=True, capture_output=True)  # fill the cache
            times = []
            for _ in range(reps):
                t0 = time.perf_counter()
                subprocess.run(cmd, env=env, check=True, capture_output=True)
                times.append(time.perf_counter() - t0)
            out[key] = {"warm_median_s": statistics.median(times), "warm_min_s": min(times), "runs": reps}
        cold_env = dict(env, NUMBA_CACHE_DIR=str(tmp / "numba_cold"))
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "pounding", "run", str(tmp / "bilinear.toml"), "--out", str(tmp / "cold")],
                       env=cold_env, check=True, capture_output=True)
        out["bilinear"]["cold_s"] = time.perf_counter() - t0
        timings = json.loads((tmp / "cold" / "summary.json").read_text())["timings_s"]
        out["bilinear"]["cold_compile_s"] = timings.get("compile")
        out["bilinear"]["cold_load_and_compile_s"] = timings.get("load_and_compile")
    log(f"whole process `pounding run`, warm: yielding {out['bilinear']['warm_median_s']:.2f} s, elastic "
        f"{out['elastic']['warm_median_s']:.2f} s; cold yielding {out['bilinear']['cold_s']:.1f} s "
        f"(compiling {out['bilinear']['cold_compile_s']:.1f} s)")
    return out


def tall_case(quick: bool) -> dict:
    from pounding.framework.post.run import run
    from pounding.io.scene import parse_scene
    from pounding.peer.opensees import load_opensees
    from pounding.peer.opensees_springs import run_springs_gap_pounding

    duration = 5.0 if quick else 15.0
    dt, stiffness = 0.01, 1e9
    data = _move(tall_pair(duration=duration, dt=dt), 1, 0.05 - 0.5)
    for e in data["building"][1]["element"]:  # "east" 0.6 times as stiff: the pair moves out of phase
        e["stiffness"] = [0.6 * k for k in e["stiffness"]]
    data["ground_motion"]["angle"] = 0.0
    data["analysis"]["contact"] = {"name": "penalty", "stiffness": stiffness, "restitution": 1.0, "tolerance": 1e-9}
    scene = parse_scene(data)
    run(scene)
    r, t_ours, _ = timed(lambda: run(scene), 3)
    ref = run(scene.with_analysis(dt=dt / 8, output_every=8))
    t0 = time.perf_counter()
    disp, _, gaps, iters = run_springs_gap_pounding(load_opensees(), scene, stiffness, dt, r.steps)
    t_os = time.perf_counter() - t0

    def err(u, name):
        u_ref = ref.cm(name)[:, :, 0]
        peak = np.abs(u_ref[:, -1]).max()
        return {"peak_roof_u": float(abs(np.abs(u[:, -1]).max() - peak) / peak),
                "l2": float(np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref))}

    out = {"duration_s": duration, "dt": dt, "steps": r.steps, "ours_s": t_ours, "opensees_s": t_os, "speedup": t_os / t_ours,
           "opensees_newton_iterations": iters, "contact_steps_opensees": int(np.sum(np.any(gaps < 0, axis=(1, 2)))),
           "errors": {}, "ductility": {n: float(np.max(sp["peak"] / sp["yield_deformation"])) for n, sp in r.springs.items()}}
    for name in r.names:
        out["errors"][name] = {"pounding": err(r.cm(name)[:, :, 0], name), "opensees": err(disp[name][:, :, 0], name)}
    log(f"two 20-storey yielding buildings pounding, {duration:g} s, dt {dt}: pounding {t_ours:.3f} s, OpenSees {t_os:.2f} s "
        f"({t_os / t_ours:.0f}x, target 100x); errors {out['errors']}; ductility {out['ductility']}")
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    reps = 3 if args.quick else 7
    results = {"paper_pair": paper_case(reps), "whole_process": whole_process(3 if args.quick else 5),
               "two_20_storey": tall_case(args.quick)}
    path = HERE / "results" / ("inelastic_pounding_quick.json" if args.quick else "inelastic_pounding.json")
    path.write_text(json.dumps(results, indent=2))
    log(f"wrote {path}")


if __name__ == "__main__":
    main()
