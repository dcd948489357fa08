"""The cost of a located contact event, and the solver times it adds up to (issue 13, item 5).

For the paper pair and the L-shape scene (restitution 0.5) and three settings:

* ``newmark``: Newmark's average acceleration, the step from the modes (pounding.framework.engine.timestep),
  the ``crossing`` locator (the default integrator until elastic scenes got ``exact``);
* ``exact``: the exact integrator at its own default step, ``crossing`` (these scenes' defaults);
* ``before``: the defaults before issue 13 (HHT at the record's 0.02 s, ``halving``, ``keep``, 1e-4 m).

Reported: warm in-process solver time (summary ``runtime_s``, median of ``REPS`` runs after one
warm-up run), the located events, and the cost of an event: the wall time spent in the driver's
Python steps (:meth:`pounding.framework.engine.driver.Driver.python_step`: the step holding the event,
its search, impulses and the rest of the step) per located event, median over the runs. The
machine is shared: note its load (``os.getloadavg`` is recorded).

Run: ``.venv/bin/python benchmarks/bench_events.py [REPS]`` -> benchmarks/results/events.json
"""

from __future__ import annotations

import os
import statistics
import sys
import time
import warnings

from common import log, write_json
from scenes import load

REPS = 5


def settings(name: str) -> dict:
    base = load(name).with_analysis(integrator="newmark", integrator_params={}, dt=None, contact_params={"restitution": 0.5})
    return {
        "newmark": base,
        "exact": base.with_analysis(integrator="exact"),
        "before": base.with_analysis(integrator="hht", dt=0.02, contact_params={"restitution": 0.5, "locate": "halving",
                                                                                 "after_impact": "keep", "tolerance": 1e-4}),
    }


def measure(scene, reps: int) -> dict:
    from pounding.framework.engine.driver import Driver

    solver, per_event, in_steps = [], [], []
    for r in range(reps + 1):
        d = Driver(scene)
        spent = [0.0]
        step = d.python_step

        def timed(k, step=step, spent=spent):
            t0 = time.perf_counter()
            step(k)
            spent[0] += time.perf_counter() - t0

        d.python_step = timed
        res = d.run()
        if r:  # the first run loads the compiled core
            solver.append(res.runtime_s)
            in_steps.append(spent[0])
            per_event.append(spent[0] / max(d.n_located, 1))
    return {"dt": d.dt, "steps": d.nsteps, "impacts": len(d.impacts), "located_events": d.n_located,
            "solver_median_ms": 1e3 * statistics.median(solver), "python_steps_ms": 1e3 * statistics.median(in_steps),
            "per_event_ms": 1e3 * statistics.median(per_event)}


def main(reps: int = REPS) -> dict:
    warnings.simplefilter("ignore")
    out = {"reps": reps, "load_average": os.getloadavg(), "rows": []}
    for name in ("paper", "lshape"):
        for label, scene in settings(name).items():
            row = {"scene": name, "settings": label, **measure(scene, reps)}
            out["rows"].append(row)
            log(f"{name:6s} {label:8s} dt={row['dt']:<8.4g} {row['located_events']:3d} events  solver {row['solver_median_ms']:7.1f} ms  "
                f"per event {row['per_event_ms']:.3f} ms")
    write_json("events.json", out)
    return out


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else REPS)
