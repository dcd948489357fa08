"""The pounding benchmark suite: `make bench` or `.venv/bin/python benchmarks/run.py`.

    python benchmarks/run.py                 # everything (< 20 min on 2 cores)
    python benchmarks/run.py --quick         # a subset (< 2 min): paper scene, fewer dt, N <= 30
    python benchmarks/run.py --only peer     # one benchmark (comma-separate several)
    python benchmarks/run.py --list

Benchmarks: workprecision, peer, scaling, targets, profile, components, compile. Results go to
benchmarks/results/ (CSV, PNG, JSON, profile text; --quick files carry a _quick
suffix), and the headline table of benchmarks/README.md is rewritten from them.
Nothing is asserted: these are measurements.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

USER_ENV = dict(os.environ)

BENCHMARKS = ["workprecision", "peer", "scaling", "targets", "profile", "components", "compile"]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="a subset that runs in under 2 minutes")
    p.add_argument("--only", default=None, metavar="NAME[,NAME]", help="run only these benchmarks: " + ", ".join(BENCHMARKS))
    p.add_argument("--list", action="store_true", help="list the benchmarks and exit")
    p.add_argument("--blas-threads", default="1", metavar="N",
                   help="OPENBLAS/OMP/MKL threads for the benchmark processes (default 1: on a busy 2-core machine a threaded "
                        "OpenBLAS makes small factorisations up to 1000x slower); 'keep' leaves the environment alone. "
                        "The `pounding run` target is measured both with the user's environment and with 1 thread.")
    p.add_argument("--no-readme", action="store_true", help="do not rewrite the headline table in benchmarks/README.md")
    args = p.parse_args(argv)
    if args.list:
        for b in BENCHMARKS:
            print(b)
        return 0
    only = BENCHMARKS if not args.only else [x.strip() for x in args.only.split(",") if x.strip()]
    bad = [x for x in only if x not in BENCHMARKS]
    if bad:
        p.error(f"unknown benchmark(s) {', '.join(bad)}; choose from {', '.join(BENCHMARKS)}")
    if args.blas_threads != "keep":
        for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ[var] = str(args.blas_threads)  # before numpy is imported; inherited by subprocesses

    here = Path(__file__).resolve().parent
    sys.path.insert(0, str(here))
    import bench_targets
    import common

    bench_targets.USER_ENV = USER_ENV
    info = common.machine()
    common.log(f"pounding benchmarks ({'quick' if args.quick else 'full'}): {', '.join(only)}")
    common.log(f"  machine: {info['cpus']} CPUs, load {info['load_average_1_5_15']}, commit {info['git_commit']}"
               f"{' + uncommitted changes in ' + str(len(info['git_dirty_files'])) + ' files' if info['git_dirty_files'] else ''}")
    t_all = time.perf_counter()
    common.warm_up()
    outputs, timings, failed = {}, {}, []
    for name in only:
        common.log(f"\n== {name}")
        t0 = time.perf_counter()
        mod = __import__(f"bench_{name}")
        try:
            outputs[name] = mod.run(quick=args.quick)
        except Exception:  # one failing benchmark must not lose the others
            import traceback

            traceback.print_exc()
            failed.append(name)
        timings[name] = time.perf_counter() - t0
        common.log(f"   ({timings[name]:.0f} s)")
    info["benchmark_seconds"] = timings
    info["failed"] = failed
    info["load_average_at_end"] = [round(x, 2) for x in os.getloadavg()]
    info["total_seconds"] = time.perf_counter() - t_all
    tag = "_quick" if args.quick else ""
    common.write_json(f"machine{tag}.json", info)

    h = bench_targets.headline(args.quick, outputs.get("targets"))
    table = bench_targets.headline_markdown(h)
    common.write_json(f"headline{tag}.json", h)
    (common.RESULTS / f"headline{tag}.md").write_text(table + "\n")
    common.log("\n" + table)
    if not args.quick and not args.no_readme:
        update_readme(here / "README.md", table, info)
    common.log(f"\ntotal {time.perf_counter() - t_all:.0f} s" + (f"; FAILED: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


def update_readme(path: Path, table: str, info: dict) -> None:
    """Replace the text between the headline markers of the README with the new table."""
    start, end = "<!-- headline:start -->", "<!-- headline:end -->"
    if not path.exists():
        return
    text = path.read_text()
    if start not in text or end not in text:
        return
    head, rest = text.split(start, 1)
    _, tail = rest.split(end, 1)
    # the commit stays in results/machine.json: the README states the present figures, not their history
    stamp = (f"_Measured {info['when']} on {info['cpus']} CPUs (load average {info['load_average_1_5_15'][0]} at start, "
             f"{info['load_average_at_end'][0]} at end); the code's commit is in results/machine.json._")
    path.write_text(head + start + "\n" + stamp + "\n\n" + table + "\n" + end + tail)


if __name__ == "__main__":
    sys.exit(main())
