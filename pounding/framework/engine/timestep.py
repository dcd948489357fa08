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
(benchmarks/bench_accuracy_targets.py). An integrator exact within the step (``exact``; one that
declares ``exact_within_step``) has no period error: its step only samples the response (step-end outputs and peaks), ``EXACT_STEPS_PER_PERIOD`` = 8 samples
per shortest significant period.

With a force contact law the step also resolves the shortest contact of the run: dt <= tau_c /
``STEPS_PER_CONTACT``, tau_c the duration the law declares for the pair's effective mass and
approach speed (:mod:`pounding.framework.engine.contact_step`). ``STEPS_PER_CONTACT`` = 40 is
measured on the paper's pair at 0.03 m (its HHT integrator, El Centro at 0.32 g, every force law
at its default parameters), the peaks |u|, |v| of every slab against the same law at a step 8 or more
times finer, relative to the building's largest peak (benchmarks/bench_contact_step.py, docs/accuracy.md).
Over the first 8 s, about 20 steps per declared duration put every law within 1e-3 of its
converged run but hertzdamp (3e-3), and about 10 steps leave hertzdamp 7.7e-3 off. Over 15 s,
hertzdamp at 23 and 29 steps is 5.2e-3 off: its contact at 4.66 s is not seen to end before
the next strike at 5.26 s, which then reuses the first one's approach speed in its damping
factor; at 37 and 46 steps the strikes part and the peaks are within 1e-4. 40 steps give every
law a margin on that record. The default step is the largest 2^a 5^b divisor of the record's
sample interval under the bound, so a run takes 40 to 64 steps per declared duration.
"""

from __future__ import annotations

import numpy as np

#: effective modal mass ratio [-] from which a mode counts for the step
SIGNIFICANT_MASS = 0.01
#: steps per shortest significant period, second-order schemes (period error <= 0.3 %)
STEPS_PER_PERIOD = 32
#: steps per shortest significant period for the exact integrator (sampling only)
EXACT_STEPS_PER_PERIOD = 8
#: steps per shortest contact duration with a force contact law (see the module docstring)
STEPS_PER_CONTACT = 40
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


def default_dt(systems, directions, record_dt: float | None, integrator, contact_duration: float = np.inf) -> float:
    """The step [s] when the scene gives none (see the module docstring): ``integrator`` the run's (its
    registered name or class: one exact within the step, :attr:`~pounding.solvers.base.Integrator.exact_within_step`,
    has no period error and samples the response with ``EXACT_STEPS_PER_PERIOD``); ``contact_duration``
    [s] the run's shortest contact (inf: none to resolve)."""
    from pounding.framework.model.registry import INTEGRATORS

    exact = INTEGRATORS.get(integrator, field="analysis.integrator").exact_within_step
    n = EXACT_STEPS_PER_PERIOD if exact else STEPS_PER_PERIOD
    target = min(shortest_significant_period(systems, directions) / n, contact_duration / STEPS_PER_CONTACT)
    base = float(record_dt) if record_dt else FALLBACK_DT
    if not np.isfinite(target) or target >= base:
        return base
    need = base / target
    # the smallest m >= need of the form 2^a 5^b: steps that are decimal fractions of the record's
    m = min(2**a * 5**b for a in range(40) for b in range(20) if 2**a * 5**b >= need - 1e-9)
    return base / m


def steps_per_contact(dt: float, contact_duration: float) -> float:
    """How many steps of dt [s] one contact of ``contact_duration`` [s] spans (inf: no contact to resolve)."""
    return contact_duration / dt
