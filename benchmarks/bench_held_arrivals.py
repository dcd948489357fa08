"""Held pairs' arriving points on the paper pair with every default: energy, accuracy, events, time.

    python benchmarks/bench_held_arrivals.py [--arrivals]

The paper pair at 0.03 m (examples/paper/pair_gap_0.03.toml) with every default (``exact``,
``crossing``, ``equilibrium``, dt from the modes: 0.01 s; 15 s of El Centro at 0.32 g, k = 0.5),
against the same scene at dt = 0.001 s:

* the contact work of the run [kJ] (``contact_force_work`` of the energy balance: <= 0 for a
  passive contact) and whether the balance is ``ok``;
* the largest difference of any slab corner's displacement from the dt = 0.001 s run at the
  coarse run's output instants, in % of that run's peak corner displacement, per building;
* the arrivals struck: points of held pairs located and struck where they reach contact
  (``Driver.strike_arrival`` calls, counted by wrapping it; the driver's other impacts are in
  ``n_impacts``);
* the solver time of the default run (median of warm runs, summary.json's ``runtime_s``).

``--arrivals`` also counts, with the compiler off (slow: about a minute), the plastic stops of
arriving points at a held step's start, for code that still has them (``held.stop_closing`` called
from ``held_step``). Writes results/held_arrivals.json.
"""

from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"


def paper(dt):
    from pounding.io.scene import load_scene

    return load_scene(PAPER).with_analysis(integrator=None, integrator_params={}, dt=dt, contact_params={"restitution": 0.5})


def run_counting(sc):
    """(result, arrivals struck) of one run of scene ``sc``."""
    from pounding.framework.engine.driver import Driver

    count = [0]
    d = Driver(sc)
    strike = getattr(d, "strike_arrival", None)
    if strike is not None:
        def counted(*a, **k):
            count[0] += 1
            return strike(*a, **k)

        d.strike_arrival = counted
    return d.run(), count[0], strike is not None


def corner_difference(coarse, fine):
    """{building: max |corner displacement difference| / peak of the fine run's corners} at the coarse outputs."""
    step = int(round(coarse.dt / fine.dt))
    out = {}
    for name in coarse.names:
        vc, vf = coarse.vertices(name), fine.vertices(name)[::step][: len(coarse.t)]
        out[name] = float(np.nanmax(np.abs(vc - vf)) / np.nanmax(np.abs(vf)))
    return out


def old_stops():
    """Plastic stops of arriving points at held steps' starts (the compiler off; 0 where held_step has none)."""
    os.environ["NUMBA_DISABLE_JIT"] = "1"
    from pounding.framework.engine import held
    from pounding.framework.engine.driver import Driver

    calls = [0]
    original = held.stop_closing

    def watched(z, W, v_min):
        dv = original(z, W, v_min)
        if sys._getframe(1).f_code.co_name == "held_step" and np.any(dv != 0.0):
            calls[0] += 1
        return dv

    held.stop_closing = watched
    Driver(paper(None)).run()
    return calls[0]


def main(argv):
    from pounding.framework.post.energy_account import energy_balance

    if "--arrivals" in argv:
        print("arriving points stopped at a held step's start:", old_stops())
        return
    run_counting(paper(None))  # warm
    times = []
    for _ in range(5):
        coarse, arrivals, counted = run_counting(paper(None))
        times.append(coarse.runtime_s)
    fine, fine_arrivals, _ = run_counting(paper(0.001))
    eb, ebf = energy_balance(coarse), energy_balance(fine)
    row = {
        "contact_work_kJ": eb["contact_force_work"] / 1e3,
        "ok": eb["ok"],
        "contact_work_dt0.001_kJ": ebf["contact_force_work"] / 1e3,
        "corner_difference_of_peak": corner_difference(coarse, fine),
        "impacts": coarse.n_impacts,
        "arrivals_struck": arrivals if counted else None,
        "arrivals_struck_dt0.001": fine_arrivals if counted else None,
        "solver_ms_median": 1e3 * statistics.median(times),
        "solver_ms_all": [1e3 * t for t in times],
    }
    for k, v in row.items():
        print(f"{k}: {v}")
    if "--no-write" not in argv:
        import json

        out = ROOT / "benchmarks" / "results" / "held_arrivals.json"
        out.write_text(json.dumps(row, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
