"""1. Work-precision: solver time against error, every integrator, dt range, both impact locators.

For each scene (the paper's pair and the L-shaped pair) and each of
* no pounding (contact off; for the paper scene identical to pair_gap_0.5.toml, which has no impacts),
* pounding (impulse contact, restitution 0.5, the default tolerance 1e-4 m and after-impact rule),
every integrator at every dt (and, with pounding, the locators ``crossing``, ``halving`` and ``root``)
is run over the whole record; the solver time is the median of warm runs, and the
errors are measured against the converged reference (see reference.py):

* ``err_l2_window``: relative L2 error of all slab-corner displacement histories over
  [0, first impact + 1 s]. Pounding is a sensitive (nearly chaotic) process: after many
  impacts a tiny change of an impact instant changes the later sequence, and errors
  of every method against any reference become O(1) without saying anything about the
  method's accuracy. One second after the first impact covers the first two or three
  clusters of impacts (paper: 1.91-1.98, 2.50-2.57, 2.70-2.88 s; L-shape: 2.57-2.68 and
  3.45-3.52 s), about one fundamental period of the taller building. ``err_l2_full``
  (whole record) is also written to show the loss of predictability.
* ``err_peak``: the peak corner displacement (max over time of |d| of every slab
  corner, whole record), max over corners of |P - P_ref| / max P_ref;
  ``err_peak_window``: the same over the window.

Without pounding the error measures are over the whole record (nothing is sensitive).
"""

from __future__ import annotations


import numpy as np

from common import errors, log, max_penetration, med, result_corners, subsample, timed_runs, write_csv
from reference import REF_TOL, WINDOW_AFTER_FIRST_IMPACT, convergence, reference, window_end
from scenes import SCENE_TITLES, load, no_pounding, with_method

INTEGRATORS = ["newmark", "hht", "generalized_alpha", "central_difference", "exact"]
#: the default ``crossing`` (impulses where the gap is zero) and the paper's two (struck within the tolerance)
LOCATORS = ["crossing", "halving", "root"]


def settings(quick: bool) -> dict:
    if quick:
        return dict(scenes=["paper"], dts=[0.01, 0.005], reps=1, budget=0.0, dt_ref=0.00125, dt_ref2=0.0025,
                    ref_duration=3.5, extra=[])
    return dict(scenes=["paper", "lshape"], dts=[0.02, 0.01, 0.005, 0.0025, 0.00125], reps=5, budget=2.5,
                dt_ref=0.0003125, dt_ref2=0.000625, ref_duration=None, extra=[("exact", "root", 1e-6)])


def run(quick: bool = False) -> dict:
    from pounding.errors import InputError

    cfg = settings(quick)
    rows, conv = [], []
    for name in cfg["scenes"]:
        for pounding in (False, True):
            # the no-pounding reference is exact at any dt dividing 0.02 s: no need for the finest grid
            # no pounding: exact at dt_ref is exact to rounding (the record is linear between its samples)
            dref, dref2 = cfg["dt_ref"], cfg["dt_ref2"]
            dur = cfg["ref_duration"] if pounding else None
            # the root-family reference (exact + root + 1e-8 m) its results and README section were measured
            # against; bench_accuracy_targets.py uses the crossing family, which converges faster (reference.py)
            ref = reference(name, pounding, dref, dur, method="root")
            ref2 = reference(name, pounding, dref2, dur, method="root")
            tw = window_end(reference(name, True, cfg["dt_ref"], cfg["ref_duration"], method="root"))
            c = convergence(ref, ref2, tw if pounding else None)
            c.update(scene=name, pounding=pounding, window_end_s=tw if pounding else None, tolerance=REF_TOL)
            conv.append(c)
            base = load(name) if pounding else no_pounding(load(name))
            series = [(i, loc, None) for i in INTEGRATORS for loc in (LOCATORS if pounding else [None])]
            if pounding:
                series += cfg["extra"]  # a tighter contact tolerance: shows what limits the error with pounding
            for integ, locate, tol in series:
                for dt in cfg["dts"]:
                    label = (locate or "-") + ("" if tol is None else f" tol={tol:g}")
                    row = dict(scene=name, pounding=pounding, integrator=integ, locate=label, dt=dt,
                               tolerance=tol if tol is not None else (base.analysis.contact_params.get("tolerance", 1e-4) if pounding else ""))
                    s = with_method(base, integ, dt, locate=locate, tolerance=tol)
                    try:
                        r, solver, wall = timed_runs(s, cfg["reps"], budget_s=cfg["budget"], min_reps=3 if cfg["reps"] >= 3 else 1)
                    except InputError as exc:  # central differences beyond their stability limit
                        row.update(status="unstable: " + str(exc).split(" = ")[0][:60])
                        rows.append(row)
                        continue
                    D = result_corners(r, s)
                    R = subsample(ref.corners, ref.dt, dt, len(r.t)) if dur is None else None
                    if dur is not None:  # quick mode: the reference covers the window only
                        nw = int(np.sum(r.t <= dur + 1e-9))
                        R = subsample(ref.corners, ref.dt, dt, nw)
                        e = errors(D[:nw], R, r.t[:nw], tw)
                        e["l2_full"] = e["peak"] = float("nan")
                    else:
                        e = errors(D, R, r.t, tw if pounding else None)
                    row.update(
                        status="ok", steps=r.steps, reps=len(solver), solver_median_s=med(solver), solver_min_s=min(solver),
                        wall_median_s=med(wall), n_impacts=r.n_impacts, located_events=r.info.get("located_events"),
                        err_l2_window=e.get("l2_window", e["l2_full"]), err_peak=e["peak"],
                        err_peak_window=e.get("peak_window", e["peak"]), err_l2_full=e["l2_full"],
                        error_window_end_s=tw if pounding else r.t[-1],
                        max_penetration_m=max_penetration(r, s) if pounding else 0.0,
                    )
                    rows.append(row)
                    log(f"  {name:6s} {'pound' if pounding else 'free ':5s} {integ:18s} {label:7s} dt={dt:<8g} "
                        f"{row['solver_median_s'] * 1e3:8.1f} ms  L2w={row['err_l2_window']:.2e} peak={row['err_peak']:.2e} "
                        f"impacts={r.n_impacts} overlap={row['max_penetration_m'] * 1e3:.3f} mm")
    import reference as _ref

    _ref._cache.clear()  # the fine references hold ~100 MB each
    tag = "_quick" if quick else ""
    write_csv(f"workprecision{tag}.csv", rows)
    write_csv(f"reference_convergence{tag}.csv", conv)
    plot(rows, tag)
    return {"rows": rows, "convergence": conv}


def plot(rows, tag=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from common import RESULTS

    colors = dict(zip(INTEGRATORS, ["C0", "C1", "C2", "C3", "C4"]))
    scenes = sorted({r["scene"] for r in rows}, key=["paper", "lshape"].index)
    for name in scenes:
        fig, axes = plt.subplots(2, 2, figsize=(12, 9.5))
        for i, pounding in enumerate((False, True)):
            for j, (key, label) in enumerate((("err_l2_window", "relative L2 error of corner histories"), ("err_peak", "relative error of peak corner displacement"))):
                ax = axes[i, j]
                labels = sorted({r["locate"] for r in rows if r["pounding"] == pounding}, key=lambda x: (len(x), x))
                for integ in INTEGRATORS:
                    for locate in labels:
                        pts = [r for r in rows if r["scene"] == name and r["pounding"] == pounding and r["integrator"] == integ
                               and r["locate"] == locate and r.get("status") == "ok"]
                        if not pts:
                            continue
                        if key == "err_peak" and not np.isfinite(pts[0][key]):
                            key_used = "err_peak_window"
                        else:
                            key_used = key
                        x = np.maximum([p[key_used] for p in pts], 1e-16)
                        y = [p["solver_median_s"] for p in pts]
                        ax.loglog(x, y, marker="o", ms=4, color=colors[integ], ls="--" if locate == "root" else ":" if "tol" in locate else "-." if locate == "crossing" else "-",
                                  label=integ + ("" if locate == "-" else f" / {locate}"))
                        for p, xx, yy in zip(pts, x, y):
                            if p["dt"] in (0.02, 0.00125, 0.01) and integ == "newmark" and locate in ("-", "halving"):
                                ax.annotate(f"dt={p['dt']:g}", (xx, yy), fontsize=7, xytext=(3, 3), textcoords="offset points")
                window = f", t <= first impact + {WINDOW_AFTER_FIRST_IMPACT:g} s"
                if pounding:
                    whole = all(np.isfinite(r[key]) for r in rows if r["pounding"] and r.get("status") == "ok")
                    win = window if key == "err_l2_window" or not whole else ", whole record"
                else:
                    win = ", whole record"
                ax.set_xlabel(label + win)
                ax.set_ylabel("solver time [s] (median of warm runs)")
                ax.set_title(("with pounding" if pounding else "no pounding") + f" - {SCENE_TITLES[name]}", fontsize=10)
                ax.grid(True, which="both", alpha=0.3)
                if j == 0:
                    ax.legend(fontsize=7, ncol=2)
        dts = sorted({r["dt"] for r in rows}, reverse=True)
        fig.suptitle(f"Work-precision: El Centro 1940 NS, 0.32 g, dt = {', '.join(f'{d:g}' for d in dts)} s (points), "
                     "reference: exact + root, tol 1e-8 m")
        fig.tight_layout()
        path = RESULTS / f"workprecision_{name}{tag}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        log(f"  wrote {path.name}")
