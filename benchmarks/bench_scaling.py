"""3. Scaling: run time, per-step cost and peak memory against storeys and record length.

Every case runs in its own subprocess (benchmarks/_case.py), so its peak RSS
(VmHWM from /proc/self/status) is its own; ``tracemalloc`` gives the peak
of the Python/numpy allocations of one ``run()`` (model, driver, response arrays,
result), measured in a separate run from the timed ones.

Storeys: two uniform-plan buildings (scenes.uniform_pair: 24 x 16 m and 18 x 16 m,
three frames in each direction, eccentric stiffness in both), N storeys each,
0.05 m apart, El Centro at 0.32 g and 20 degrees, dt = 0.005 s, hht; with impulse
contact (N slab pairs checked every step) and with contact off.

Record length: the paper's pair, El Centro tiled 1, 2, 4, 8 times end to end.
"""

from __future__ import annotations

import json
import subprocess
import time

import numpy as np

from common import HERE, PYTHON, log, loglog_fit, write_csv, write_json


def settings(quick: bool) -> dict:
    if quick:
        return dict(storeys=[3, 10, 30], times=[1, 2, 4], reps=1, budget=0.0, timeout=120)
    return dict(storeys=[3, 10, 30, 60, 100], times=[1, 2, 4, 8], reps=5, budget=12.0, timeout=600)


def case(spec: dict, timeout: float) -> dict:
    t0 = time.perf_counter()
    try:
        p = subprocess.run([PYTHON, str(HERE / "_case.py"), json.dumps(spec)], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": f"timeout > {timeout:g} s"}
    if p.returncode != 0:
        return {"status": "failed: " + p.stderr.strip().splitlines()[-1][:200]}
    out = json.loads(p.stdout.strip().splitlines()[-1])
    out["status"] = "ok"
    out["process_s"] = time.perf_counter() - t0
    return out


def run(quick: bool = False) -> dict:
    cfg = settings(quick)
    rows = []
    for kind, values, key in (("storeys", cfg["storeys"], "n"), ("length", cfg["times"], "times")):
        for v in values:
            for contact in ("impulse", "none"):
                spec = {"kind": kind, key: v, "contact": contact, "reps": cfg["reps"], "budget": cfg["budget"]}
                res = case(spec, cfg["timeout"])
                row = {"kind": kind, "storeys" if kind == "storeys" else "record_times": v, "contact": contact, "status": res.get("status")}
                if res.get("status") == "ok":
                    row.update(
                        steps=res["steps"], n_modes=res["n_modes"], n_pairs=res["n_pairs"], T1_s=max(res["periods_1"]),
                        solver_median_s=res["solver_median_s"], solver_min_s=res["solver_min_s"], reps=res["reps"],
                        per_step_us=1e6 * res["solver_median_s"] / res["steps"], wall_median_s=res["wall_median_s"],
                        parse_s=res["parse_s"], assemble_s=res["assemble_s"], n_impacts=res["n_impacts"],
                        located_events=res["located_events"],
                        response_MB=res["response_bytes"] / 1e6, model_MB=res["model_bytes"] / 1e6,
                        tracemalloc_peak_MB=res["tracemalloc_peak_bytes"] / 1e6,
                        peak_over_response_plus_model=res["tracemalloc_peak_bytes"] / (res["response_bytes"] + res["model_bytes"]),
                        rss_before_MB=res["rss_before_mb"], rss_peak_MB=res["rss_peak_mb"],
                        rss_growth_MB=res["rss_peak_mb"] - res["rss_before_mb"],
                        python_steps=res.get("python_steps"), python_path_s=res.get("python_path_s"),
                        kernel_calls=res.get("kernel_calls"), kernel_s=res.get("kernel_s"),
                        us_per_python_step=(1e6 * res["python_path_s"] / res["python_steps"]) if res.get("python_steps") else None,
                        kernel_us_per_step=(1e6 * res["kernel_s"] / max(1, res["steps"] - res["python_steps"])) if res.get("kernel_calls") else None,
                    )
                    log(f"  {kind:7s} {v:>4} {contact:7s} {row['solver_median_s'] * 1e3:9.1f} ms (min {row['solver_min_s'] * 1e3:.1f})  "
                        f"{row['per_step_us']:8.1f} us/step  python steps {row['python_steps']} "
                        f"({(row['us_per_python_step'] or 0):.0f} us each), kernel {(row['kernel_us_per_step'] or 0):.1f} us/step  "
                        f"impacts {row['n_impacts']:5d}  tracemalloc {row['tracemalloc_peak_MB']:7.1f} MB  "
                        f"(response {row['response_MB']:.1f} + model {row['model_MB']:.1f})  rss {row['rss_peak_MB']:.0f} MB")
                else:
                    log(f"  {kind:7s} {v:>4} {contact:7s} {row['status']}")
                rows.append(row)
    fits = fit(rows)
    tag = "_quick" if quick else ""
    write_csv(f"scaling{tag}.csv", rows)
    write_json(f"scaling_fits{tag}.json", fits)
    plot(rows, fits, tag)
    return {"rows": rows, "fits": fits}


def _sel(rows, kind, contact):
    return [r for r in rows if r["kind"] == kind and r["contact"] == contact and r["status"] == "ok"]


def fit(rows) -> dict:
    out = {}
    for contact in ("impulse", "none"):
        pts = _sel(rows, "storeys", contact)
        N = [r["storeys"] for r in pts]
        big = [r for r in pts if r["storeys"] >= 30]
        out[f"storeys_{contact}"] = {
            "solver_time_exponent_all": loglog_fit(N, [r["solver_median_s"] for r in pts]),
            "solver_time_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["solver_median_s"] for r in big]),
            "per_step_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["per_step_us"] for r in big]),
            "solver_min_time_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["solver_min_s"] for r in big]),
            "kernel_per_step_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["kernel_us_per_step"] or float("nan") for r in big]),
            "python_step_cost_exponent_N>=10": loglog_fit([r["storeys"] for r in pts if r["storeys"] >= 10],
                                                          [r["us_per_python_step"] or float("nan") for r in pts if r["storeys"] >= 10]),
            "tracemalloc_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["tracemalloc_peak_MB"] for r in big]),
            "assemble_exponent_N>=30": loglog_fit([r["storeys"] for r in big], [r["assemble_s"] for r in big]),
        }
        pts = _sel(rows, "length", contact)
        steps = [r["steps"] for r in pts]
        out[f"length_{contact}"] = {
            "solver_time_exponent": loglog_fit(steps, [r["solver_median_s"] for r in pts]),
            "tracemalloc_exponent": loglog_fit(steps, [r["tracemalloc_peak_MB"] for r in pts]),
        }
    return out


def plot(rows, fits, tag=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from common import RESULTS

    fig, axes = plt.subplots(2, 3, figsize=(16, 9))
    for i, (kind, xkey, xlabel) in enumerate((("storeys", "storeys", "storeys per building N"), ("length", "steps", "steps (El Centro tiled 1, 2, 4, 8 x; dt = 0.005 s)"))):
        for contact, style in (("impulse", "o-"), ("none", "s--")):
            pts = _sel(rows, kind, contact)
            if not pts:
                continue
            x = np.array([r[xkey] for r in pts], float)
            lab = "with pounding" if contact == "impulse" else "contact off"
            p = fits[f"{kind}_{contact}"]["solver_time_exponent_N>=30" if kind == "storeys" else "solver_time_exponent"]
            axes[i, 0].loglog(x, [r["solver_median_s"] for r in pts], style, label=f"{lab} (slope {p:.2f})")
            axes[i, 1].loglog(x, [r["per_step_us"] for r in pts], style, label=f"{lab}: solver time / steps")
            if contact == "impulse":
                k = [r["kernel_us_per_step"] or np.nan for r in pts]
                py = [r["us_per_python_step"] or np.nan for r in pts]
                axes[i, 1].loglog(x, k, "v-", color="C2", label="with pounding: compiled kernel, per step")
                axes[i, 1].loglog(x, py, "^-", color="C3", label="with pounding: one step on the Python path")
            axes[i, 2].loglog(x, [r["tracemalloc_peak_MB"] for r in pts], style, label=f"{lab}: tracemalloc peak of run()")
            if contact == "none":
                axes[i, 2].loglog(x, [r["response_MB"] + r["model_MB"] for r in pts], "k:", label="response arrays + K, C, modes, rows")
                axes[i, 2].loglog(x, [r["rss_growth_MB"] for r in pts], "x-", color="grey", label="RSS growth during runs")
        if kind == "storeys":
            xs = np.array([10, 100.0])
            axes[i, 1].loglog(xs, 30 * (xs / 10) ** 2, "k:", lw=0.8, label="~N^2")
            axes[i, 1].loglog(xs, 30 * (xs / 10), "k-.", lw=0.8, label="~N")
        axes[i, 0].set_ylabel("solver time [s]")
        axes[i, 1].set_ylabel("solver time per step [us]")
        axes[i, 2].set_ylabel("memory [MB]")
        for ax in axes[i]:
            ax.set_xlabel(xlabel)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.suptitle("Scaling (median of warm runs, one subprocess per case)")
    fig.tight_layout()
    path = RESULTS / f"scaling{tag}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    log(f"  wrote {path.name}")
