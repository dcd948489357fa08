"""The default step with force contact laws: peaks and run time against the converged run.

    python benchmarks/bench_contact_step.py [--duration S] [--laws kelvin,hertz,...]

The paper's pair at 0.03 m (examples/paper/pair_gap_0.03.toml: HHT, El Centro 1940 NS at 0.32 g),
its [analysis] contact set to each force law at its default parameters and no dt given, over
the first ``--duration`` seconds (15 by default). For each law: the default step (which resolves
the law's declared shortest contact with STEPS_PER_CONTACT steps), the step the modes alone
would give (what a run took before the contact entered the step), and the converged run at the
default step / 8, whose own error is estimated from the default step / 4 (errors fall about as
dt). Error: max over slabs of |peak - converged| / the building's largest peak in that direction
(|u| and |v|). Time: wall time of the run (compiled core warm). The impulse law at its own
default step, against its own run at dt / 8, for comparison.

Writes benchmarks/results/contact_step.json and contact_step.md (figures quoted in docs/accuracy.md).
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
LAWS = ("kelvin", "penalty", "hertz", "hertzdamp", "jankowski")


def peaks(result) -> list[np.ndarray]:
    """Peak |u|, |v| (storeys, 2) of every building."""
    return [result.peaks(n)[:, :2] for n in result.names]


def error(a, ref) -> float:
    """Largest |peak - reference| over slabs, relative to the building's largest reference peak in that direction."""
    return float(max(np.max(np.abs(x - r) / r.max(axis=0)) for x, r in zip(a, ref)))


def timed(scene):
    from pounding.framework.post.run import run

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run(scene)
    return r, time.perf_counter() - t0


def measure(law: str, duration: float) -> dict:
    from pounding.framework.engine.stacked_model import Model
    from pounding.framework.engine.integrator_choice import chosen_integrator
    from pounding.framework.engine.timestep import default_dt
    from pounding.io.scene import load_scene

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(
        contact=law, contact_params={}, dt=None, duration=duration)
    default, t_default = timed(scene)
    dt = default.dt
    half, _ = timed(scene.with_analysis(dt=dt / 4))
    ref, t_ref = timed(scene.with_analysis(dt=dt / 8))
    m = Model(scene)
    modal_dt = default_dt(m.systems, m.directions, scene.ground_motion.dt, chosen_integrator(scene))
    row = {"law": law, "dt": dt, "time_s": t_default, "error": error(peaks(default), peaks(ref)),
           "reference_dt": dt / 8, "reference_time_s": t_ref, "reference_error": error(peaks(half), peaks(ref)),
           "contact_time": default.info["contact_time"], "modal_dt": modal_dt,
           "episodes": len(ref.contact_episodes()), "contacts": len(ref.contacts),
           "largest_approach_speed": max((e.approach_velocity for e in ref.contacts), default=0.0)}
    if law != "impulse" and modal_dt > dt:
        old, t_old = timed(scene.with_analysis(dt=modal_dt))
        row.update(modal_error=error(peaks(old), peaks(ref)), modal_time_s=t_old)
    return row


def markdown(rows: list[dict], duration: float) -> str:
    lines = [f"Paper pair at 0.03 m, first {duration:g} s, each law at its default parameters (HHT, the scene's).",
             "",
             "| law | shortest contact [ms] | default dt [s] | steps per contact | peak error | run time [s] | "
             "modes-only dt [s] | its peak error | its run time [s] | converged run's own error | "
             "approach speed bound / largest seen [m/s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ct = r["contact_time"]
        dur = f"{ct['duration'] * 1e3:.3g}" if ct["duration"] else "-"
        spc = f"{ct['steps_per_contact']:.3g}" if ct["duration"] else "-"
        bound = f"{ct['approach_speed']:.3g} / {r['largest_approach_speed']:.3g}" if ct["duration"] else "-"
        lines.append(f"| {r['law']} | {dur} | {r['dt']:g} | {spc} | {r['error']:.2e} | {r['time_s']:.2f} | "
                     f"{r['modal_dt']:g} | {r.get('modal_error', float('nan')):.2e} | {r.get('modal_time_s', float('nan')):.2f} | "
                     f"{r['reference_error']:.1e} | {bound} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=15.0)
    ap.add_argument("--laws", default=",".join(LAWS + ("impulse",)))
    args = ap.parse_args()
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene

    run(load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=0.5))  # warm the core
    rows = []
    for law in args.laws.split(","):
        rows.append(measure(law, args.duration))
        print(json.dumps(rows[-1]), flush=True)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "contact_step.json").write_text(json.dumps(rows, indent=1) + "\n")
    (RESULTS / "contact_step.md").write_text(markdown(rows, args.duration))
    print(markdown(rows, args.duration))


if __name__ == "__main__":
    main()
