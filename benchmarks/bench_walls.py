"""A base-isolated building beside a fixed-base neighbour, with and without a moat wall: solver time.

Run: ``.venv/bin/python benchmarks/bench_walls.py [--reps N]``; writes ``results/walls.json`` and prints
a table (the figures in docs/speed.md, "Retaining walls").

The scene (the issue's engineer): "isolated", 12 x 8 m, its isolation layer as storey 1 (1.0 m: four
lines of isolators, storey springs) and four 3.2 m storeys of storey springs above (``first_storey = 2``),
beside "fixed", a fixed-base 6-storey neighbour 0.10 m to its east (storey 1 of 4.2 m: the isolated
building's floors 2-5 meet its floors 1-4 at common levels, the base slab strikes its facade); El Centro
at 0.5 g along x, the whole record, impulse contact (e = 0.5). With the wall: a moat wall on the west
side, its top at the base slab's level (1.0 m), at three distances from the base slab: 0.25 m (the walls'
issue's scene: the lead-rubber base slab, 0.29 m at its peak without the wall, strikes it), 0.10 m (a
stress case: the base slab strikes it five times as often and rests against it) and 1.0 m, which the
base slab never reaches (the cost of watching a wall, apart from the impacts it adds). Two isolator
models: linear (the elastic solver, compiled whole) and lead-rubber (bilinear, yielding: the links' Newton).
Solver times (``Result.runtime_s``), the fastest of ``--reps`` warm runs (the machine is shared).
Target (the walls' issue): the wall costs at most 2x.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import copy
import json
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
GAP, MOAT = 0.10, 0.25  # [m] to the neighbour (east), to the moat wall (west: the scene)
#: [m] the moat distances measured beside the issue's: a stress case the base slab rests against, and one it never reaches
STRESS, NEVER = 0.10, 1.0


def _springs(start, end, k, **kw) -> dict:
    return {"type": "storey_springs", "start": start, "end": end, "stiffness": k, **kw}


def scene_data(yielding: bool, wall: bool, moat: float = MOAT) -> dict:
    iso = {"storeys": 1, **({"yield_force": 1.5e5, "hardening": 0.1, "hysteresis": "bilinear"} if yielding else {})}
    isolated = {
        "name": "isolated", "storey_heights": [1.0, 3.2, 3.2, 3.2, 3.2], "slab": [[0, 0], [12, 0], [12, 8], [0, 8]],
        "mass": [150000.0, 135000.0, 135000.0, 135000.0, 120000.0], "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
        "element": [_springs([0, 0], [12, 0], 5.0e6, **iso), _springs([0, 8], [12, 8], 5.0e6, **iso),
                    _springs([0, 0], [0, 8], 5.0e6, **iso), _springs([12, 0], [12, 8], 5.0e6, **iso),
                    _springs([0, 0], [12, 0], 2.0e8, first_storey=2), _springs([0, 8], [12, 8], 2.0e8, first_storey=2),
                    _springs([6, 0], [6, 8], 4.0e8, first_storey=2)],
    }
    x0 = 12.0 + GAP
    fixed = {
        "name": "fixed", "storey_heights": [4.2, 3.2, 3.2, 3.2, 3.2, 3.2], "slab": [[x0, 0], [x0 + 10, 0], [x0 + 10, 8], [x0, 8]],
        "mass_per_area": 1000.0, "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
        "element": [_springs([x0, 0], [x0 + 10, 0], 1.5e8), _springs([x0, 8], [x0 + 10, 8], 1.5e8),
                    _springs([x0 + 5, 0], [x0 + 5, 8], 3.0e8)],
    }
    data = {"building": [isolated, fixed], "ground_motion": {"record": "elcentro", "pga": 0.5},
            "analysis": {"contact": {"name": "impulse", "restitution": 0.5}, "silence": ["soft_storey", "isolation_damping"]}}
    if wall:
        data["wall"] = [{"name": "moat", "face": [[-moat, -1.0], [-moat, 9.0]], "top": 1.0}]
    return data


def measure(yielding: bool, wall: bool, reps: int, moat: float = MOAT) -> dict:
    from pounding.framework.engine.driver import Driver
    from pounding.io.scene import parse_scene

    scene = parse_scene(copy.deepcopy(scene_data(yielding, wall, moat)))
    times, result = [], None
    for _ in range(reps + 1):  # the first run loads (or compiles) the core: not counted
        result = Driver(scene).run()
        times.append(result.runtime_s)
    on_wall = [i for i in result.impacts if result.struck_building(i) == "moat"]
    return {"solver_s": float(np.min(times[1:])), "times_s": times[1:], "steps": result.steps, "dt": result.dt,
            "impacts": len(result.impacts), "on_wall": len(on_wall), "contact_episodes": len(result.contact_episodes()),
            "peak_base_u": float(np.max(np.abs(result.cm("isolated")[:, 0, 0])))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reps", type=int, default=5)
    args = parser.parse_args()
    out = {"when": time.strftime("%Y-%m-%d %H:%M:%S"), "cpus": os.cpu_count(), "load": os.getloadavg(), "cases": {}}
    print(f"{'isolators':<12} {'wall [m]':<9} {'solver [ms]':>12} {'impacts (on wall)':>18} {'peak base u [m]':>16}")
    for yielding in (False, True):
        name = "lead-rubber" if yielding else "linear"
        cases = [(name, False, MOAT), (f"{name} + wall", True, MOAT), (f"{name} + wall at {STRESS:g} m", True, STRESS),
                 (f"{name} + wall never struck", True, NEVER)]
        for key, wall, moat in cases:
            m = measure(yielding, wall, args.reps, moat=moat)
            out["cases"][key] = m
            print(f"{name:<12} {f'{moat:g}' if wall else 'none':<9} {1e3 * m['solver_s']:>12.1f} "
                  f"{m['impacts']:>11} ({m['on_wall']:>3}) {m['peak_base_u']:>16.4f}", flush=True)
        base = out["cases"][name]["solver_s"]
        for key, wall, _ in cases[1:]:
            out["cases"][key]["ratio"] = out["cases"][key]["solver_s"] / base
        print(f"  with the wall / without: {out['cases'][f'{name} + wall']['ratio']:.2f}x at {MOAT:g} m (target <= 2x), "
              f"{out['cases'][f'{name} + wall at {STRESS:g} m']['ratio']:.2f}x at {STRESS:g} m; "
              f"a wall never struck: {out['cases'][f'{name} + wall never struck']['ratio']:.2f}x")
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "walls.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
