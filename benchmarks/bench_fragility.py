"""Benchmark of `pounding fragility`: 22 records x 10 levels of the paper pair on the local Dask cluster.

    .venv/bin/python benchmarks/bench_fragility.py [--records FOLDER] [--repeat 3]

Measures (nothing asserted):

* the whole study (22 records x 10 PGA levels = 220 contact-free runs) on a local cluster of 2 worker
  processes, wall clock including the cluster's start-up, the tables and the plots; and serially in
  this process;
* the cost of one run, split into the contact-free time history and the required-gap geometry;
* how the study grows with records and levels (runs on the cluster) and with the gap grid (statistics only);

and writes ``benchmarks/results/fragility.json``. Without ``--records`` it uses the 22 synthetic records of
``examples/fragility/synthetic_records.py`` (El Centro's amplitude spectrum and length, 31.2 s).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
LEVELS = [round(0.1 * i, 10) for i in range(1, 11)]


def study(records, out, levels, n_records=None, **kw):
    from pounding.framework.studies.fragility import run_fragility

    folder = Path(records)
    if n_records is not None:  # a sub-set: the first n records, linked into a folder of their own
        sub = Path(out).with_name(Path(out).name + "_records")
        sub.mkdir()
        for p in sorted(folder.glob("*.at2"))[:n_records]:
            (sub / p.name).symlink_to(p)
        folder = sub
    t0 = time.perf_counter()
    res = run_fragility(PAPER, out, records=folder, levels=levels, **kw)
    return time.perf_counter() - t0, res


def per_run_cost(records, repeat=20):
    """Median times [s] of the pieces of one contact-free run (first record, PGA 0.5 g)."""
    from pounding.framework.post.run import run
    from pounding.framework.studies.fragility import contact_free_run
    from pounding.framework.studies.gap import gap_from_result, no_contact
    from pounding.framework.model.units import G
    from pounding.io.ground_motion import read_at2
    from pounding.io.scene import load_scene

    scene = load_scene(PAPER)
    m = read_at2(sorted(Path(records).glob("*.at2"))[0])
    s = scene.with_ground_motion(m.scaled(0.5 * G / m.pga))
    contact_free_run(scene, m, 0.5 * G / m.pga, None, {})  # compile / warm
    t_run, t_gap, t_full, t_all, steps = [], [], [], [], 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = run(no_contact(s))
        t1 = time.perf_counter()
        gap_from_result(s, res, full=False)  # what the study does: only the steps that can govern
        t2 = time.perf_counter()
        contact_free_run(scene, m, 0.5 * G / m.pga, None, {})
        t3 = time.perf_counter()
        gap_from_result(s, res)  # every step, as `pounding gap` does
        t4 = time.perf_counter()
        t_run.append(t1 - t0), t_gap.append(t2 - t1), t_all.append(t3 - t2), t_full.append(t4 - t3)
        steps = len(res.t) - 1
    return {"steps": steps, "history_s": statistics.median(t_run), "gap_geometry_s": statistics.median(t_gap),
            "gap_geometry_every_step_s": statistics.median(t_full),
            "contact_free_run_s": statistics.median(t_all), "solver_s": res.runtime_s}


def cluster_start_cost():
    """Wall time [s] to start a local cluster of 2 workers, run one trivial task on each and close it."""
    from pounding.framework.studies.cluster import run_jobs

    t0 = time.perf_counter()
    run_jobs(abs, [(0, (-1,)), (1, (-2,))], lambda tag, v: None, lambda tag, e: None, workers=2)
    return time.perf_counter() - t0


def gap_grid_cost(rows, levels):
    from pounding.framework.studies.fragility import summarise

    out = {}
    top = max(r["required_gap_m"] for r in rows)
    for n in (10, 100, 1000):
        gaps = [top * i / (n - 1) for i in range(n)]
        t0 = time.perf_counter()
        summarise(rows, levels, gaps, [0.1])
        out[n] = time.perf_counter() - t0
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--records", type=Path, default=None, help="a folder of 22 .AT2 records (default: the synthetic set)")
    p.add_argument("--repeat", type=int, default=3, help="repetitions of the full study on the cluster")
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT / "examples" / "fragility"))
    from synthetic_records import synthetic_records

    with tempfile.TemporaryDirectory(prefix="bench-fragility-") as tmp:
        tmp = Path(tmp)
        records = args.records or synthetic_records(tmp / "records")
        n_rec = len(list(Path(records).glob("*.[aA][tT]2")))
        out = {"records": n_rec, "levels": len(LEVELS), "cpus": os.cpu_count(), "load_before": os.getloadavg()[0]}
        walls = []
        for i in range(args.repeat):
            wall, res = study(records, tmp / f"dask{i}", LEVELS, plots=True)
            walls.append(wall)
            print(f"cluster run {i + 1}: {wall:.2f} s for {res.n_run} runs on {res.workers} workers ({len(res.failed)} failed)", flush=True)
        rows = res.runs
        out["cluster_wall_s"] = walls
        out["cluster_wall_median_s"] = statistics.median(walls)
        out["runtime_in_worker_mean_s"] = statistics.mean(r["runtime_s"] for r in rows)
        wall, sres = study(records, tmp / "serial", LEVELS, serial=True, plots=True)
        strip = (lambda rs: [{k: v for k, v in r.items() if k != "runtime_s"} for r in rs])
        out["serial_wall_s"] = wall
        out["serial_equals_cluster"] = strip(sres.runs) == strip(rows)
        print(f"serial: {wall:.2f} s; rows identical to the cluster's: {out['serial_equals_cluster']}", flush=True)
        out["cluster_start_s"] = cluster_start_cost()
        print(f"cluster start-up and shut-down: {out['cluster_start_s']:.2f} s", flush=True)
        out["per_run"] = per_run_cost(records)
        print(f"per run: {out['per_run']}", flush=True)
        growth = []
        for n_r, levels in ((22, LEVELS[:2]), (22, LEVELS[:5]), (11, LEVELS), (22, LEVELS)):
            n_r = min(n_r, n_rec)
            wall, r = study(records, tmp / f"grow_{n_r}_{len(levels)}", levels, n_records=n_r, plots=False)
            growth.append({"records": n_r, "levels": len(levels), "runs": r.n_run, "wall_s": wall})
            print(f"growth: {n_r} records x {len(levels)} levels: {wall:.2f} s", flush=True)
        out["growth"] = growth
        out["gap_grid_statistics_s"] = gap_grid_cost(rows, LEVELS)
        print(f"statistics for 10/100/1000 gaps: {out['gap_grid_statistics_s']}", flush=True)
        out["load_after"] = os.getloadavg()[0]
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "fragility.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
