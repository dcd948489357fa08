"""True peaks (issue 13 item 2): how far the step-end peaks were off, and what the continuous ones cost.

The paper pair (3 + 5 storeys, gap 0.03 m) with rigid impacts (restitution 1), at the record's
dt = 0.02 s, each integrator with the ``root`` locator and tolerance 1e-8 m, against the converged
reference (``exact``, root, 1e-8 m, dt = 0.001 s; its own continuous peaks). Reported per building:
the top storey's peak |u| at step ends and over the continuous trajectory
(:mod:`pounding.framework.engine.peaks`), each as an error relative to the reference. Cost: the time to
compute the continuous slab peaks and drift peaks after a run (output every step), and the solve
time with thinned output (the kernel tracks the Hermite extreme of every step) against full output.

Run: ``.venv/bin/python benchmarks/bench_peaks.py`` -> benchmarks/results/peaks.json
"""

from __future__ import annotations

import time

import numpy as np

from common import log, quiet_run, write_json
from scenes import load, no_pounding, with_method

DT = 0.02
DT_REF = 0.001
TOL = 1e-8


def rigid(scene):
    params = dict(scene.analysis.contact_params)
    params["restitution"] = 1.0
    return scene.with_analysis(contact_params=params)


def top_peaks(result):
    return {n: (float(result.step_end_peaks(n)[-1, 0]), float(result.peaks(n)[-1, 0])) for n in result.names}


def main():
    base = rigid(load("paper"))
    ref = quiet_run(with_method(base, "exact", DT_REF, locate="root", tolerance=TOL))
    ref_pk = {n: float(ref.peaks(n)[-1, 0]) for n in ref.names}
    ref_end = {n: float(ref.step_end_peaks(n)[-1, 0]) for n in ref.names}
    log(f"reference exact dt={DT_REF}: top peak |u| " + ", ".join(f"{n} {v * 1e3:.4f} mm (step ends {ref_end[n] * 1e3:.4f})" for n, v in ref_pk.items()))
    rows = []
    for integ in ("exact", "newmark", "hht"):
        r = quiet_run(with_method(base, integ, DT, locate="root", tolerance=TOL))
        for n, (end, cont) in top_peaks(r).items():
            row = {"integrator": integ, "dt": DT, "building": n, "reference_mm": ref_pk[n] * 1e3,
                   "step_end_mm": end * 1e3, "continuous_mm": cont * 1e3,
                   "step_end_error": end / ref_pk[n] - 1.0, "continuous_error": cont / ref_pk[n] - 1.0}
            rows.append(row)
            log(f"{integ:8s} {n:5s} step ends {row['step_end_error']:+.3%}  continuous {row['continuous_error']:+.3%}")
    # the scene as given (restitution 0.5): every storey's peak |u|, largest error over the storeys
    scene_k = load("paper")
    ref_k = quiet_run(with_method(scene_k, "exact", DT_REF, locate="root", tolerance=TOL))
    r_k = quiet_run(with_method(scene_k, "exact", DT, locate="root", tolerance=TOL))
    as_given = {}
    for n in r_k.names:
        R = ref_k.peaks(n)[:, 0]
        as_given[n] = {"step_end_errors": (r_k.step_end_peaks(n)[:, 0] / R - 1).tolist(),
                       "continuous_errors": (r_k.peaks(n)[:, 0] / R - 1).tolist()}
        log(f"restitution 0.5, exact {n}: step ends {as_given[n]['step_end_errors']}, continuous {as_given[n]['continuous_errors']}")
    # cost of the post-processing (full output): slab peaks and drift peaks over the continuous trajectory
    from pounding.framework.engine import peaks

    r = quiet_run(with_method(base, "exact", DT, locate="root", tolerance=TOL))
    cost = {}
    for label, fn in (("slab_peaks_s", lambda: peaks.slab_peaks(r)),
                      ("drift_peaks_s", lambda: [peaks.drift_peaks(r, n) for n in r.names])):
        t0 = time.perf_counter()
        for _ in range(3):
            fn()
        cost[label] = (time.perf_counter() - t0) / 3
    cost["solve_s_exact_dt_0.02"] = r.runtime_s
    r_n = quiet_run(with_method(base, "newmark", DT, locate="root", tolerance=TOL))
    t0 = time.perf_counter()
    peaks.slab_peaks(r_n)
    cost["slab_peaks_s_newmark"] = time.perf_counter() - t0
    cost["solve_s_newmark_dt_0.02"] = r_n.runtime_s
    # thinned output: the kernel tracks the Hermite extreme of every step (no-pounding run, long stretches)
    free = with_method(no_pounding(base), "newmark", 0.005)
    times = {}
    for every in (1, 2):
        s = free.with_analysis(output_every=every)
        quiet_run(s)
        ts = [quiet_run(s).runtime_s for _ in range(5)]
        times[every] = float(np.median(ts))
    cost["solve_s_free_dt_0.005_every_1"] = times[1]
    cost["solve_s_free_dt_0.005_every_2_tracked"] = times[2]
    log("cost: " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in cost.items()))
    write_json("peaks.json", {"rows": rows, "reference": {"dt": DT_REF, "top_peak_m": ref_pk, "top_peak_step_ends_m": ref_end},
                              "restitution_0.5_exact_every_storey": as_given, "cost": cost})


if __name__ == "__main__":
    main()
