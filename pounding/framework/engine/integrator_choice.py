"""The integrator a scene gets when it names none: chosen from the work-precision measurements.

* Every building elastic and contact by impulses (or none): ``exact``. Between impacts the
  response of a linear building to a piecewise-linear record is a sum of modal oscillators in
  closed form, so the step only samples it (:mod:`pounding.framework.engine.timestep`: 8 steps per
  shortest significant period) and carries no period error; impacts are struck where the gap is
  zero on that solution, and the peaks are the extremes of it. This is also what ETABS and SAP2000
  run for a modal linear time history. Measured (benchmarks/results/accuracy_targets.md), against
  the converged rigid-impact limit: peak corner displacements within 1.4e-4 (paper pair) and
  1.1e-5 (L-shape scene) in 1.7x and 2.2x less solver time than Newmark's average acceleration at
  its own default step (32 steps per period), which lands within 2.5e-4 and 5.7e-5.
* A building that yields, links between slabs, or a force contact law on any pair (``[analysis]
  contact``, a ``[[contact]]`` table's, a wall's, a bumper): ``newmark`` (average acceleration). Their restoring or contact forces depend on the state inside the step, which the
  closed form does not follow; Newmark's implicit step is the usual choice there (OpenSees'
  ``Newmark 0.5 0.25``).

A scene that names an integrator gets it, with its own parameters.
"""

from __future__ import annotations

#: the integrator of elastic buildings with impulse contact (or none)
ELASTIC = "exact"
#: the integrator of yielding buildings or force contact laws
OTHERWISE = "newmark"


def chosen_integrator(scene) -> str:
    """The registered name of the integrator a run of ``scene`` uses (see the module docstring)."""
    an = scene.analysis
    if an.integrator is not None:
        return an.integrator
    if any(getattr(e, "yields", False) for b in scene.buildings for e in b.elements) or getattr(scene, "links", ()):
        return OTHERWISE
    from pounding.framework.model.registry import CONTACT_LAWS

    default = CONTACT_LAWS.get(an.contact)
    if not default.watches():  # contact off: no pair's law is asked (rules.pair_laws)
        return ELASTIC
    laws = [default] + [CONTACT_LAWS.get(r.law) for r in getattr(scene, "contacts", ())]
    laws += [CONTACT_LAWS.get(w.law) for w in getattr(scene, "walls", ()) if w.law is not None]
    if any(getattr(r, "bumper", None) is not None for r in getattr(scene, "contacts", ())) or any(law.with_step for law in laws):
        return OTHERWISE
    return ELASTIC
