"""The default time step: chosen for accuracy from the modes that matter, not from the record.

Without ``[analysis] dt`` the step is the largest divisor dt_rec / m (m = 2^a 5^b) of the
record's sample interval dt_rec that resolves the shortest *significant* period T_s with
``N`` steps: dt <= T_s / N. A mode is significant when its effective modal mass along a
shaking direction is at least ``SIGNIFICANT_MASS`` (1 %) of its building's mass. Staying a
divisor of dt_rec keeps every record sample on the grid (the piecewise-linear record is then
integrated exactly by ``exact`` and with the scheme's own order by the others).

``N`` comes from an error target. For the second-order schemes (Newmark's average
acceleration, HHT, generalized-alpha, central differences) the relative period error of a
mode is about (omega dt)^2 / 12; ``STEPS_PER_PERIOD`` = 32 keeps it within 0.3 % for T_s
and within 0.3 % (T_s / T)^2 for the longer, dominant modes, which puts the peaks of the
paper pair and the L-shape scene within 0.1 % of the converged rigid-impact limit
(benchmarks/bench_accuracy_targets.py). ``exact`` has no period error: its step only
samples the response (step-end outputs and peaks), ``EXACT_STEPS_PER_PERIOD`` = 8 samples
per shortest significant period.
"""

from __future__ import annotations

import numpy as np

#: effective modal mass ratio [-] from which a mode counts for the step
SIGNIFICANT_MASS = 0.01
#: steps per shortest significant period, second-order schemes (period error <= 0.3 %)
STEPS_PER_PERIOD = 32
#: steps per shortest significant period for the exact integrator (sampling only)
EXACT_STEPS_PER_PERIOD = 8
#: the step when the record has no uniform sample interval [s] (an upper bound, divided as above)
FALLBACK_DT = 0.01


def shortest_significant_period(systems, directions) -> float:
    """Shortest period [s] among the modes with effective mass >= SIGNIFICANT_MASS of their building's
    along any of the shaking ``directions`` (c, 2); inf when no mode qualifies."""
    best = np.inf
    for s in systems:
        total = float(np.sum(s.mass)) / 3.0  # the translational mass of one direction (mass holds m, m, J per slab)
        for d in np.asarray(directions, dtype=float).reshape(-1, 2):
            b = s.influence(d)
            m_dir = float(np.sum(s.mass * b * b))
            gamma = s.participation(b)
            share = gamma**2 / (m_dir if m_dir > 0 else total)
            for om, r in zip(s.omega, share):
                if r >= SIGNIFICANT_MASS and om > 0:
                    best = min(best, 2.0 * np.pi / om)
    return best


def default_dt(systems, directions, record_dt: float | None, integrator: str) -> float:
    """The step [s] when the scene gives none (see the module docstring)."""
    n = EXACT_STEPS_PER_PERIOD if integrator == "exact" else STEPS_PER_PERIOD
    target = shortest_significant_period(systems, directions) / n
    base = float(record_dt) if record_dt else FALLBACK_DT
    if not np.isfinite(target) or target >= base:
        return base
    need = base / target
    # the smallest m >= need of the form 2^a 5^b: steps that are decimal fractions of the record's
    m = min(2**a * 5**b for a in range(40) for b in range(20) if 2**a * 5**b >= need - 1e-9)
    return base / m
