"""Every contact law on the paper's pair at its default step: solver time and error against the same law converged.

    python benchmarks/bench_contact_laws.py [--no-docs] [--from-json]

The paper's pair at 0.03 m (El Centro 1940 NS, 0.32 g, the first 15 s), each law at its defaults
with restitution 0.5, no ``dt`` and no integrator given (the run's own choice for the law). For
each law:

* the **default run**: its step, its solver time (``runtime_s``, median of warm runs);
* the **converged run**: the same law at the default step halved, halved again, ... until two
  successive halvings change no compared quantity by more than :data:`AGREE` (relative), at most
  :data:`MAX_HALVINGS` times. For a method of order p >= 1 in its asymptotic range the finer run's
  error is change / (2^p - 1) <= change, so the reference is good to the last change (reported);
* the **errors** of the default run against the converged one: the peak x displacement of each
  building's top floor (``Result.peaks``, over the continuous trajectory), the peak contact force
  (force laws; the impulse law has none), the total impulse of the contacts and the energy lost in
  contact, this one relative to the ground motion's input energy (an elastic law loses nothing, so
  its own size is no scale).

The number of impacts is not compared: it does not converge with the step (chatter).

Writes results/contact_laws.json and .md, and (unless ``--no-docs``) the table into docs/speed.md
between its ``contact-laws`` markers (``--from-json``: the table again from the last
results/contact_laws.json, nothing run). About 80 s of CPU with today's steps.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np

from common import RESULTS, log, med, quiet_run, timed_runs, warm_up, write_json

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
LAWS = ("impulse", "kelvin", "hertz", "hertzdamp", "jankowski")
DURATION = 15.0  # [s]
RESTITUTION = 0.5
#: successive halvings agree when no quantity changes by more than this (relative)
AGREE = 1e-3
MAX_HALVINGS = 6
DOC = ROOT / "docs" / "speed.md"
START, END = "<!-- contact-laws:start -->", "<!-- contact-laws:end -->"
QUANTITIES = ("top_low", "top_high", "peak_force", "impulse", "energy")


def scene(law: str, dt: float | None = None):
    from pounding import load_scene

    s = load_scene(SCENE).with_analysis(dt=dt, integrator=None, integrator_params={}, contact=law,
                                        contact_params={"restitution": RESTITUTION}, duration=DURATION)
    return s


def figures(r) -> dict:
    """The compared quantities of a run (see the module docstring); ``input`` is the energy scale [J]."""
    eps = r.episodes()
    forces = [e.peak_force for e in eps if np.isfinite(e.peak_force)]
    return {
        "top_low": float(r.peaks("low")[-1, 0]),
        "top_high": float(r.peaks("high")[-1, 0]),
        "peak_force": float(max(forces)) if forces else float("nan"),
        "impulse": float(sum(e.impulse for e in eps)),
        "energy": float(sum(e.energy_dissipated for e in eps)),
        "input": float(sum(v["input"] for v in r.energy.values())),
        "impacts": len(r.impacts),
        "episodes": len(eps),
    }


def differences(a: dict, b: dict) -> dict:
    """Relative differences of a against b: each quantity by b's own size, the energy lost by b's input."""
    out = {}
    for k in QUANTITIES:
        if not (np.isfinite(a[k]) and np.isfinite(b[k])):
            out[k] = float("nan")
            continue
        scale = b["input"] if k == "energy" else abs(b[k])
        out[k] = abs(a[k] - b[k]) / scale
    return out


def worst(d: dict) -> float:
    return max((v for v in d.values() if np.isfinite(v)), default=0.0)


def converged(law: str, dt0: float) -> tuple[dict, float, float, float]:
    """(figures, step, last change, solver time) of the law's converged run (module docstring)."""
    prev, dt = None, dt0
    for _ in range(MAX_HALVINGS):
        dt /= 2.0
        r = quiet_run(scene(law, dt))
        f = figures(r)
        log(f"  {law} dt={dt:.3g}: {f['top_low']:.6f} {f['top_high']:.6f} force {f['peak_force']:.6g} "
            f"energy {f['energy']:.6g} ({r.runtime_s:.2f} s)")
        if prev is not None:
            change = worst(differences(prev, f))
            if change <= AGREE:
                return f, dt, change, r.runtime_s
        prev = f
    return f, dt, change, r.runtime_s


def measure() -> list[dict]:
    warm_up()
    rows = []
    for law in LAWS:
        first, solver, _ = timed_runs(scene(law), 5, budget_s=10.0, min_reps=3)
        f0 = figures(first)
        ref, dt_ref, change, t_ref = converged(law, first.dt)
        err = differences(f0, ref)
        rows.append({"law": law, "dt": first.dt, "solver_s": med(solver), "dt_ref": dt_ref, "ref_change": change,
                     "solver_ref_s": t_ref, "errors": err, "default": f0, "reference": ref})
        log(f"{law}: dt {first.dt:.3g} s, {med(solver):.3f} s; errors " + ", ".join(f"{k} {v:.2e}" for k, v in err.items()))
    return rows


def _pct(v: float) -> str:
    """A relative error in per cent, two significant digits ("-" where there is none)."""
    return "-" if not np.isfinite(v) else f"{100 * v:.2g} %"


def table(rows: list[dict]) -> str:
    head = ("| law | default dt [s] | solver [s] | top u low | top u high | peak force | impulse total | energy lost "
            "(of input) | converged dt [s] (last change) | solver at it [s] |")
    lines = [head, "|" + "---|" * 10]
    for r in rows:
        e = r["errors"]
        lines.append(f"| {r['law']} | {r['dt']:.3g} | {r['solver_s']:.3f} | {_pct(e['top_low'])} | {_pct(e['top_high'])} | "
                     f"{_pct(e['peak_force'])} | {_pct(e['impulse'])} | {_pct(e['energy'])} | "
                     f"{r['dt_ref']:.3g} ({r['ref_change']:.1e}) | {r['solver_ref_s']:.2f} |")
    return "\n".join(lines)


def write_docs(md: str) -> None:
    text = DOC.read_text()
    pattern = re.compile(re.escape(START) + ".*?" + re.escape(END), re.DOTALL)
    DOC.write_text(pattern.sub(lambda _: f"{START}\n{md}\n{END}", text))


def main(argv: list[str]) -> None:
    if "--from-json" in argv:  # the table again from the last measurement, without running
        rows = json.loads((RESULTS / "contact_laws.json").read_text())
    else:
        rows = measure()
        write_json("contact_laws.json", rows)
    md = table(rows)
    (RESULTS / "contact_laws.md").write_text(md + "\n")
    print(md)
    if "--no-docs" not in argv:
        write_docs(md)


if __name__ == "__main__":
    main(sys.argv[1:])
