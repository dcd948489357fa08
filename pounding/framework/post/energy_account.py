"""The energy account of every building on its own, and of the pair.

Each building's equation of motion, multiplied by its velocity and integrated
over the run, gives (mass-normalised modal coordinates, one building's modes):

    input + contact-force work + impact work = kinetic + strain + damping

* ``input``: work of the ground motion, ``-int q'^T L ag dt`` [J];
* ``damping``: ``int q'^T C q' dt`` [J];
* ``contact_forces``: work done on this building by the contact forces of
  sustained (held) and penalty contact, and by the plastic stops of held pairs
  (the run books these per building already, :mod:`pounding.framework.engine.held`);
* ``impacts``: work done on this building by the impulses it received, i.e.
  the jump of its kinetic energy at every impact instant,
  ``sum_i (v_i dv_i + dv_i^2 / 2)`` over its modes, v the velocities just
  before the instant and dv = sum_j w_j I_j the velocity change of the
  instant's impulses (:func:`pounding.framework.engine.event_record.impact_velocity_changes`);
* ``kinetic``, ``strain``: at the end of the run.

Energy passes between the buildings through the impacts and the contact
forces: the pair's impact work is the negative of the energy the impacts
dissipate, ``sum_b impacts_b = -sum impact energy_loss``, and the contact forces
of a rigid held pair do no net work on the pair. So each building balances on
its own, and the pair's balance is the sum of the two.

The impact work is computed from the run's record of every impact instant
(the state just before the impulses, ``Result.event_q``/``event_qd``, and each
impulse with its point and normal), in the same arithmetic the run applied
them, so the account closes to rounding where the scheme's own work identity
is exact (Newmark average acceleration with ``after_impact = "equilibrium"``).

A rule that creates energy: ``after_impact = "keep"`` (the paper's: keep the
accelerations of before the impact) leaves the next step starting from an
acceleration out of equilibrium with the new velocities; the step then does
work that no force did. The pair's balance error measures it; the run flags it.
"""

from __future__ import annotations

#: contact-law settings that create energy: (parameter, value, why)
ENERGY_CREATING_RULES = (("after_impact", "keep", "the accelerations of before each impact are kept, out of equilibrium with the new velocities"),)


def impact_work(result) -> dict[str, float]:
    """Work done on every building by the impulses it received [J] (its kinetic-energy jumps)."""
    from pounding.framework.post.response import impact_velocity_changes

    work = {name: 0.0 for name in result.names}
    for _, state, _, dv in impact_velocity_changes(result):
        v = state[1]
        for b, name in enumerate(result.names):
            sl = slice(int(result.mode_start[b]), int(result.mode_start[b]) + result.systems[b].n_dof)
            work[name] += float(v[sl] @ dv[sl] + 0.5 * dv[sl] @ dv[sl])
    return work


def building_balances(result) -> dict[str, dict]:
    """Per building: its terms [J], ``error`` = input + contact_forces + impacts - kinetic - strain - damping
    [J], and ``relative_error`` (of its input)."""
    imp = impact_work(result)
    out = {}
    for name in result.names:
        e = dict(result.energy[name])
        e["impacts"] = imp[name]
        err = e["input"] + e["contact_forces"] + e["impacts"] - e["kinetic"] - e["strain"] - e["damping"] - e.get("hysteretic", 0.0)
        out[name] = {**e, "error": err, "relative_error": err / e["input"] if e["input"] else 0.0}
    return out


def energy_creating_rule(result) -> dict | None:
    """The contact rule of the run that creates energy, with what it created, or None.

    Returns ``{"rule": "after_impact = 'keep'", "why": ..., "energy_created": J,
    "relative": of the input}`` when the run used such a rule and had impacts;
    the energy created is minus the pair's balance error.
    """
    if not result.impacts:
        return None
    for key, value, why in ENERGY_CREATING_RULES:
        if result.contact.get(key) == value:
            eb = result.energy_balance()
            return {"rule": f"{key} = {value!r}", "why": why, "energy_created": -eb["error"], "relative": -eb["relative_error"]}
    return None


def warn_if_energy_created(result) -> None:
    """Warn (AnalysisWarning: stderr in the CLI) when the run's contact rule creates energy."""
    import warnings

    from pounding.errors import AnalysisWarning

    rule = energy_creating_rule(result)
    if rule is not None:
        warnings.warn(
            f"the contact rule {rule['rule']} creates energy ({rule['why']}): {rule['energy_created']:.4g} J, "
            f"{100 * rule['relative']:.2g} % of the input; after_impact = 'equilibrium' does not "
            "(summary.json: energy_balance.energy_creating_rule)",
            AnalysisWarning,
            stacklevel=3,
        )

