"""A storey with a nonlinear fluid viscous damper against a converged reference that does not use our stepping.

Run: ``.venv/bin/python benchmarks/bench_viscous_reference.py [--alpha 0.3 0.2] [--duration 2]``; writes
``results/viscous_reference.json`` and prints a table (the figures in docs/accuracy.md, "Yielding storeys").

The model: a one-storey building (300 t slab, 15 x 10 m) with a storey_springs frame of 6.0e8 N/m along x
at the slab's centre line (two along y for the plan's stability, not excited), no inherent damping, and a
damper F = c |v|^alpha sgn(v), c = 1.0e6 N (s/m)^alpha, along the same line; El Centro at 0.3 g along x,
the record linear between its 0.02 s samples. Along x the slab is the oscillator

    M x'' + K x + c |x'|^alpha sgn(x') = -M ag(t),

integrated by scipy's DOP853 (rtol 1e-8, atol 1e-11 m: the reference; the force is not Lipschitz at rest,
so the integrator shrinks its steps at every reversal: millions of evaluations, about two minutes for
2 s), against pounding's runs at 10, 5, 2.5, 1.25 and 0.625 ms. The error is the largest difference of x
at the 10 ms instants over the reference's peak; halving the step should halve it (first order: the
damper's force is the step's mean rate's, half a step late).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
M, K, C = 3.0e5, 6.0e8, 1.0e6  # slab mass [kg], storey stiffness along x [N/m], damper coefficient [N (s/m)^alpha]
SAMPLE = 0.02  # the record's sample interval [s]
STEPS = (0.01, 0.005, 0.0025, 0.00125, 0.000625)


def scene(alpha: float, dt: float, duration: float):
    """The one-storey building with its damper (``alpha``), stepped at dt [s] for ``duration`` [s]."""
    from pounding.io.scene import parse_scene

    elements = [{"type": "storey_springs", "start": [0, 5], "end": [15, 5], "stiffness": K},
                *[{"type": "storey_springs", "start": [x, 0], "end": [x, 10], "stiffness": 2.0e8} for x in (0, 15)],
                {"type": "storey_springs", "start": [0, 5], "end": [15, 5],
                 "hysteresis": {"name": "viscous", "coefficient": C, "exponent": alpha}}]
    building = {"name": "storey", "storey_heights": [3.2], "slab": [[0, 0], [15, 0], [15, 10], [0, 10]], "mass": M,
                "damping": {"type": "rayleigh", "ratio": 0.0, "modes": [1, 2]}, "element": elements}
    return parse_scene({"building": [building], "ground_motion": {"record": "elcentro", "pga": 0.3, "angle": 0.0},
                        "analysis": {"integrator": "newmark", "dt": dt, "duration": duration, "contact": "none"}})


def reference(alpha: float, duration: float, rtol: float = 1e-8) -> tuple[np.ndarray, int]:
    """x [m] at the 10 ms instants by DOP853, and the right-hand side's evaluations."""
    from scipy.integrate import solve_ivp

    tg = np.arange(0.0, duration + 2 * SAMPLE, SAMPLE)
    ag = np.asarray(scene(alpha, 0.01, duration).ground_motion.samples(tg), dtype=float).ravel()

    def rhs(t, y):
        k = min(int(t / SAMPLE), len(tg) - 2)
        w = (t - tg[k]) / SAMPLE
        return [y[1], -(K * y[0] + C * math.copysign(abs(y[1]) ** alpha, y[1])) / M - (ag[k] * (1 - w) + ag[k + 1] * w)]

    sol = solve_ivp(rhs, (0.0, duration), [0.0, 0.0], method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                    t_eval=np.arange(0.0, duration + 1e-9, 0.01))
    return sol.y[0], int(sol.nfev)


def errors(alpha: float, duration: float, ref: np.ndarray) -> list[float]:
    """pounding's largest error in x at the 10 ms instants over the reference's peak, at each of STEPS."""
    from pounding.framework.post.inelastic_run import run_inelastic

    out = []
    for dt in STEPS:
        x = run_inelastic(scene(alpha, dt, duration)).buildings[0].cm()[:: int(round(0.01 / dt)), 0, 0][: len(ref)]
        out.append(float(np.abs(x - ref).max() / np.abs(ref).max()))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alpha", type=float, nargs="+", default=[0.3, 0.2])
    parser.add_argument("--duration", type=float, default=2.0)
    args = parser.parse_args()
    out = {"when": time.strftime("%Y-%m-%d %H:%M:%S"), "steps": list(STEPS), "cases": {}}
    for alpha in args.alpha:
        t0 = time.perf_counter()
        ref, nfev = reference(alpha, args.duration)
        seconds = time.perf_counter() - t0
        err = errors(alpha, args.duration, ref)
        ratios = [err[i] / err[i + 1] for i in range(len(err) - 1)]
        out["cases"][str(alpha)] = {"errors": err, "ratios": ratios, "reference_evaluations": nfev, "reference_s": seconds}
        print(f"alpha {alpha}: errors " + " ".join(f"{e:.3g}" for e in err) + "; ratios " + " ".join(f"{r:.2f}" for r in ratios)
              + f" (reference: {nfev} evaluations, {seconds:.0f} s)", flush=True)
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "viscous_reference.json").write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
