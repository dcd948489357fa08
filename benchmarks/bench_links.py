"""The paper pair linked by two viscous dampers at the top of the lower building: solver time beside
the same scene without links, and what the dampers do.

    python benchmarks/bench_links.py [--no-write]

The paper pair at 0.03 m (examples/paper/pair_gap_0.03.toml, the whole El Centro record, 31 s at 0.32 g) with two
linear viscous dampers (c = 2e6 N s/m each) between the top slab of "low" (storey 3) and the slab of
"high" at the same level, along x at y = 2 m and y = 8 m, from x = 14.9 m on "low" to x = 15.13 m on
"high". Two settings:

* the scene file's own (``hht`` alpha = -0.05, dt = 0.005 s): the same integrator with and without links;
* every default (dt from the modes; ``exact`` without links, ``newmark`` with them: links are stepped
  with the Newton of the yielding springs, :mod:`pounding.framework.engine.integrator_choice`);
* the scene file's, contact off: the links' own cost, without the impacts the unlinked pair has
  (the dampers keep the linked pair apart, and impacts cost more than the links).

For each: the solver time (median of 5 warm runs, summary.json's ``runtime_s``), the ratio linked /
unlinked (target: at most 2), the impacts, the peak drift ratio of each building, the dampers' peak
force and dissipated energy, and whether the energy account is ``ok``. Writes results/links.json.
"""

from __future__ import annotations

import json
import statistics
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
DAMPER = {"name": "viscous", "coefficient": 2.0e6, "exponent": 1.0}


def linked(scene):
    """``scene`` with the two dampers of the module docstring."""
    from pounding.io.scene_links import parse_links

    tables = [{"name": f"damper-{i + 1}", "between": ["low", "high"], "storeys": [3, 3],
               "points": [[14.9, y], [15.13, y]], "law": DAMPER} for i, y in enumerate((2.0, 8.0))]
    return replace(scene, links=parse_links(tables, list(scene.buildings)))


def timed(scene, repeats: int = 5):
    """(result of the last run, median solver time [ms]) of warm runs of ``scene``."""
    from pounding.framework.post.run import run

    run(scene)  # warm: compile or load the compiled core
    times, res = [], None
    for _ in range(repeats):
        res = run(scene)
        times.append(res.runtime_s)
    return res, 1e3 * statistics.median(times)


def describe(res) -> dict:
    from pounding.framework.post.energy_account import energy_balance
    from pounding.framework.post.response import peaks
    from pounding.io.results import response_histories

    hist = response_histories(res)
    drift = {name: float(np.max(peaks(hist[name])["peak_drift_ratio_cm"])) for name in res.names}
    eb = energy_balance(res)
    return {"impacts": res.n_impacts, "peak_drift_ratio": drift, "energy_ok": eb["ok"],
            "integrator": res.integrator.get("name"), "dt": res.dt,
            "dampers": {n: {"peak_force_kN": r["peak_force"] / 1e3, "stroke_mm": r["peak"] * 1e3,
                            "dissipated_kJ": r["energy_dissipated"] / 1e3} for n, r in res.links.items()}}


def main(argv):
    from pounding.io.scene import load_scene

    base = load_scene(PAPER)
    settings = {"file": base, "defaults": base.with_analysis(integrator=None, integrator_params={}, dt=None),
                "file_no_contact": base.with_analysis(contact="none", contact_params={})}
    out = {}
    for key, scene in settings.items():
        free, t_free = timed(scene)
        tied, t_tied = timed(linked(scene))
        out[key] = {"unlinked_ms": t_free, "linked_ms": t_tied, "ratio": t_tied / t_free,
                    "unlinked": describe(free), "linked": describe(tied)}
        print(key, json.dumps(out[key], indent=1))
    if "--no-write" not in argv:
        (ROOT / "benchmarks" / "results" / "links.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
