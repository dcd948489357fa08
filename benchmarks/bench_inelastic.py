"""Inelastic storeys (contact off): the speed of the modal stepping with yielding springs.

Run: ``.venv/bin/python benchmarks/bench_inelastic.py [--quick]``; writes
``results/inelastic[_quick].json`` and prints a table.

1. **Paper pair with yielding storeys.** The paper's 3- and 5-storey pair
   (``examples/paper/pair_gap_0.5.toml``) with every frame replaced by storey springs of the
   shear-building idealisation of that frame (storey stiffness sum 12 E I / h^3 over its columns,
   rigid beams) yielding at a drift of 0.1 % of the storey height, hardening 2 %, bilinear (and
   Bouc-Wen n = 2); El Centro NS at 0.32 g, the paper's HHT (alpha = -0.05), dt = 0.005 s, whole
   record, contact off. Compared with the elastic solver on the same initial model (the same scene
   with ``yield_force`` removed, run by the elastic driver): solver times, the fastest of warm runs
   (the machine is shared; medians are in the json).
   Also the event counts that decide between this method and event-to-event (README).
2. **Two 20-storey yielding buildings vs OpenSeesPy at equal error.** Two eccentric 20-storey
   buildings of storey springs (tests/inelastic_scenes.py pattern, 5 lines, Steel01), El Centro
   at 30 degrees, Newmark average acceleration, 15 s. OpenSees: twoNodeLink + Steel01 between
   rigid diaphragms, Newton (:mod:`pounding.peer.opensees_springs`). Error of both against
   pounding at dt / 8 (the same equations converged in time): the peak roof displacement and the
   L2 history error of every slab's (u, v), relative. At equal dt the two codes solve the same
   discrete equations (they agree to ~1e-12), so their errors are equal and the speed ratio at
   equal dt is the ratio at equal error.
"""

from __future__ import annotations

import os

# one BLAS thread, as benchmarks/run.py sets by default: on a busy 2-core machine a threaded
# OpenBLAS makes small products and factorisations (ours and OpenSees') many times slower
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import copy
import json
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "tests"))


def log(msg: str) -> None:
    print(msg, flush=True)


# --------------------------------------------------------------------------- scenes
def paper_springs(yield_drift: float = 0.001, hysteresis="bilinear") -> dict:
    """The paper pair with every frame as storey springs of its shear-building idealisation."""
    data = tomllib.loads((ROOT / "examples" / "paper" / "pair_gap_0.5.toml").read_text())
    data = copy.deepcopy(data)
    data["analysis"]["contact"] = "none"
    data["analysis"].pop("restitution", None)
    for b in data["building"]:
        h = b["storey_heights"]
        n = len(h)
        out = []
        for e in b["element"]:
            a = np.deg2rad(e.get("angle", 0.0))
            d = np.array([np.cos(a), np.sin(a)]).round(15)
            start = np.array(e["start"], float)
            cols = e["columns"]
            secs = e["column"] if isinstance(e["column"], list) else [e["column"]] * n
            k = []
            for f in range(n):
                s = secs[f]
                inertia = s["b"] * s["h"] ** 3 / 12.0
                k.append(len(cols) * 12.0 * s["E"] * inertia / h[f] ** 3)
            table = {
                "type": "storey_springs",
                "start": list(start + cols[0] * d),
                "end": list(start + cols[-1] * d),
                "stiffness": k,
            }
            if hysteresis is not None:
                table.update(yield_force=[kf * yield_drift * hf for kf, hf in zip(k, h)], hardening=0.02, hysteresis=hysteresis)
            out.append(table)
        b["element"] = out
    return data


def tall_pair(storeys: int = 20, duration: float = 15.0, dt: float = 0.01) -> dict:
    """Two eccentric storey-spring buildings side by side (no contact), ``storeys`` high."""
    from inelastic_scenes import eccentric_building

    buildings = []
    for name, x0 in (("west", 0.0), ("east", 15.5)):
        b = eccentric_building(name, x0=x0)
        b["storey_heights"] = [3.5] + [3.2] * (storeys - 1)
        taper = np.linspace(1.0, 0.4, storeys)
        for e in b["element"]:
            k0 = float(np.atleast_1d(e["stiffness"])[0]) * 2.5
            f0 = float(np.atleast_1d(e["yield_force"])[0]) * 4.0
            e["stiffness"] = list(k0 * taper)
            e["yield_force"] = list(f0 * taper)
        buildings.append(b)
    return {
        "building": buildings,
        "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": 30.0},
        "analysis": {"integrator": "newmark", "dt": dt, "duration": duration, "contact": "none"},
    }


# --------------------------------------------------------------------------- measures
def timed(fn, reps: int):
    """(first result, fastest solver time, all times): the machine is shared, so the fastest of
    several warm runs is the least disturbed measure; the median is kept in the json too."""
    out, times = None, []
    for _ in range(reps):
        r = fn()
        times.append(r.runtime_s)
        out = out or r
    return out, float(np.min(times)), times


def paper_case(reps: int) -> dict:
    from pounding.framework.post.run import run
    from pounding.framework.post.inelastic_run import run_inelastic
    from pounding.io.scene import parse_scene

    rows = {}
    elastic_scene = parse_scene(paper_springs(hysteresis=None))
    run(elastic_scene)  # warm
    _, t_el, all_el = timed(lambda: run(elastic_scene), reps)
    rows["elastic_driver_s"] = t_el
    rows["elastic_driver_median_s"] = float(np.median(all_el))
    for name, hyst in (("bilinear", "bilinear"), ("bouc_wen", {"name": "bouc_wen", "n": 2.0})):
        scene = parse_scene(paper_springs(hysteresis=hyst))
        run_inelastic(scene)  # compile
        r, t, all_t = timed(lambda: run_inelastic(scene), reps)
        rows[name] = {
            "solver_s": t,
            "solver_median_s": float(np.median(all_t)),
            "ratio_to_elastic": t / t_el,
            "steps": r.steps,
            "peak_ductility": {b.name: float(b.ductility.max()) for b in r.buildings},
            "energy_relative_error": {b.name: b.energy["relative_error"] for b in r.buildings},
            "counts": {b.name: b.counts for b in r.buildings},
            "springs": {b.name: b.springs.size for b in r.buildings},
        }
        log(f"paper pair, {name}: {t * 1e3:.2f} ms vs elastic {t_el * 1e3:.2f} ms ({t / t_el:.2f}x); "
            f"ductility {rows[name]['peak_ductility']}; counts {rows[name]['counts']}")
    # What event-to-event would pay per event (a spring yields or unloads): the tangent stiffness is
    # no longer diagonal in the initial modes, so the new modes (a generalized eigenproblem of the
    # building, scipy.linalg.eigh) and their transitions; plus the location of the instant, which the
    # driver does for impacts with a root search on trial steps (~250 us each, benchmarks/README.md).
    from scipy.linalg import eigh

    from pounding.framework.model.assembly import assemble

    costs = {}
    for b in elastic_scene.buildings:
        system = assemble(b)
        t0 = time.perf_counter()
        for _ in range(200):
            eigh(system.K, np.diag(system.mass))
        costs[b.name] = (time.perf_counter() - t0) / 200
    rows["eigh_per_event_s"] = costs
    events = sum(rows["bilinear"]["counts"][b]["tangent_changes"] for b in costs)
    per_event = float(np.mean(list(costs.values()))) + 250e-6
    rows["event_to_event_estimate"] = {
        "events": events,
        "cost_per_event_s": per_event,
        "events_only_s": events * per_event,
        "fna_newton_s": rows["bilinear"]["solver_s"],
    }
    log(f"event-to-event estimate: {events} events x {per_event * 1e6:.0f} us = {events * per_event * 1e3:.0f} ms "
        f"for the events alone, vs {rows['bilinear']['solver_s'] * 1e3:.1f} ms for the whole run here")
    return rows


def tall_case(quick: bool) -> dict:
    from pounding.framework.post.inelastic_run import run_inelastic
    from pounding.io.scene import parse_scene
    from pounding.peer.opensees import load_opensees
    from pounding.peer.opensees_springs import run_springs_transient

    duration = 5.0 if quick else 15.0
    dt = 0.01
    scene = parse_scene(tall_pair(duration=duration, dt=dt))
    ref_scene = scene.with_analysis(dt=dt / 8, output_every=8)
    run_inelastic(scene)
    r, t_ours, _ = timed(lambda: run_inelastic(scene), 3)
    ref = run_inelastic(ref_scene)
    ops = load_opensees()
    t0 = time.perf_counter()
    disp, _, iters = run_springs_transient(ops, scene.buildings, scene.ground_motion, dt, r.steps)
    t_os = time.perf_counter() - t0

    def err(hist, name):
        ref_cm = ref.building(name).cm()[:, :, :2]
        h = hist[:, :, :2]
        peak_ref = np.abs(ref_cm[:, -1, 0]).max()
        return {
            "peak_roof_u": float(abs(np.abs(h[:, -1, 0]).max() - peak_ref) / peak_ref),
            "l2": float(np.linalg.norm(h - ref_cm) / np.linalg.norm(ref_cm)),
        }

    out = {"duration_s": duration, "dt": dt, "steps": r.steps, "ours_s": t_ours, "opensees_s": t_os, "speedup": t_os / t_ours,
           "opensees_newton_iterations": iters, "errors": {}, "codes_apart": {}, "ductility": {}}
    for b in r.buildings:
        out["errors"][b.name] = {"pounding": err(b.cm(), b.name), "opensees": err(disp[b.name], b.name)}
        out["codes_apart"][b.name] = float(np.abs(b.cm() - disp[b.name]).max() / np.abs(disp[b.name]).max())
        out["ductility"][b.name] = float(b.ductility.max())
    log(f"two 20-storey buildings, {duration:g} s, dt {dt}: pounding {t_ours * 1e3:.1f} ms, OpenSees {t_os:.2f} s "
        f"({t_os / t_ours:.0f}x); errors {out['errors']}; codes apart {out['codes_apart']}; ductility {out['ductility']}")
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    reps = 5 if args.quick else 15
    results = {"paper_pair": paper_case(reps), "two_20_storey": tall_case(args.quick)}
    path = HERE / "results" / ("inelastic_quick.json" if args.quick else "inelastic.json")
    path.write_text(json.dumps(results, indent=2))
    log(f"wrote {path}")


if __name__ == "__main__":
    main()
