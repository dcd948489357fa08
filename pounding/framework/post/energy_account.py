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

import numpy as np

#: contact-law settings that create energy: (parameter, value, why)
ENERGY_CREATING_RULES = (("after_impact", "keep", "the accelerations of before each impact are kept, out of equilibrium with the new velocities"),)


def impact_work(result) -> dict[str, float]:
    """Work done on every building by the impulses it received [J] (its kinetic-energy jumps)."""
    from pounding.framework.engine.event_record import impact_velocity_changes

    work = {name: 0.0 for name in result.names}
    for _, state, _, dv in impact_velocity_changes(result):
        v = state[1]
        for b, name in enumerate(result.names):
            sl = slice(int(result.mode_start[b]), int(result.mode_start[b]) + result.systems[b].n_dof)
            work[name] += float(v[sl] @ dv[sl] + 0.5 * dv[sl] @ dv[sl])
    return work


def building_balances(result) -> dict[str, dict]:
    """Per building: its terms [J], ``error`` = input + contact_forces + impacts + links - kinetic - strain
    - damping - hysteretic [J], and ``relative_error`` (of its input)."""
    imp = impact_work(result)
    out = {}
    for name in result.names:
        e = dict(result.energy[name])
        e["impacts"] = imp[name]
        err = (e["input"] + e["contact_forces"] + e["impacts"] + e.get("links", 0.0)
               - e["kinetic"] - e["strain"] - e["damping"] - e.get("hysteretic", 0.0))
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
    # [analysis] contact's, or the impulse law a table or a wall gives beside a force law there
    law = result.contact.get("impulses") or result.contact
    for key, value, why in ENERGY_CREATING_RULES:
        if law.get(key) == value:
            eb = energy_balance(result)
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
            stacklevel=4,
        )



#: terms of the account whose sign physics fixes: (key in :meth:`Result.energy_balance`, sign, why).
#: ``sign`` +1: the term is >= 0 (energy taken out of the buildings), -1: <= 0
SIGNED_TERMS = (
    ("damping", +1, "viscous damping only dissipates"),
    ("impact_loss", +1, "an impact with restitution in [0, 1] only dissipates"),
    ("hysteretic", +1, "a hysteresis loop only dissipates"),
    ("contact_force_work", -1, "a passive contact only takes energy out of the buildings"),
    ("link_work", -1, "a passive link only takes energy out of the buildings (it dissipates or stores it)"),
)


def rounding_bound(result) -> float:
    """How far [J] a term of the run's account may stray past zero by rounding alone.

    Every term is a running sum over the run's bookings (grid steps, the sub-steps of located
    events and the impulses: ``N = steps + 2 events``) of one step's work, each an inner product
    over the n modes of a step's closed-form work maps (4 x 4 products per mode) or quadrature.
    One booking then carries at most (16 + n) roundings of quantities no larger than the
    energies flowing through the account, ``E_s`` = the sum of the magnitudes of its terms,
    and its addition to the running sum one more: |rounding| <= N (17 + n) eps E_s
    (Higham's bound for recursive summation, with the per-term error of an n-term dot product).
    On the paper pair (1500 steps, 24 modes, 1.2 MJ) that is 2e-5 J, against kJ for an
    energy the scheme creates.
    """
    eb = pair_terms(result)
    n = int(sum(s.n_dof for s in result.systems))
    bookings = int(result.steps) + 2 * len(getattr(result, "event_t", ()))
    scale = sum(abs(eb[k]) for k in ("input", "damping", "contact_force_work", "impact_loss", "hysteretic", "kinetic_plus_strain",
                                     "link_work"))
    return float(bookings * (17 + n) * np.finfo(float).eps * scale)


def energy_balance(result) -> dict:
    """Balance of the pair: input - (kinetic + strain + damping + impact losses) + contact-force work [J].

    ``ok`` when the balance closes within ``energy_tolerance`` of the input and no term breaks the sign
    physics fixes (``sign_violations``, :func:`sign_violations`)."""
    out = pair_terms(result)
    err = (out["input"] + out["contact_force_work"] + out["link_work"] - out["kinetic_plus_strain"] - out["damping"]
           - out["impact_loss"] - out["hysteretic"])
    out.update(tolerance=result.energy_tolerance, error=err, relative_error=err / out["input"] if out["input"] else 0.0)
    # a run that breaks a sign is not ok, however well its account closes
    out["sign_violations"] = sign_violations(result, out)
    out["ok"] = bool(abs(out["relative_error"]) <= result.energy_tolerance) and not out["sign_violations"]
    links = link_account(result)
    if links is not None:
        out["links"] = links
        out["ok"] = out["ok"] and abs(links["relative_error"]) <= result.energy_tolerance
    return out


def link_account(result) -> dict | None:
    """The links between slabs' own account [J], or None without links: ``work`` (what they did on
    the buildings, the sum of the buildings' ``links`` terms), ``dissipated`` (their laws' own
    dissipation along their paths), ``stored`` (what their laws store at the end), and ``error`` =
    work + dissipated + stored, which a passive link closes: the work the buildings did on it is
    what it dissipated plus what it stores. By the stepping's energy rule (the trapezoid of the
    force for average acceleration) the work of a law whose own dissipation is that trapezoid
    (``maxwell``, ``elastic``, a bilinear spring off its kinks) closes to rounding; a dashpot at the
    step's mean rate dissipates F(v) du while the rule books (F0 + F1) du / 2, a difference of
    the order of the force's change per step (``relative_error``, of the input)."""
    own = getattr(result, "link_energy", None)
    if own is None:
        return None
    work = sum(e.get("links", 0.0) for e in result.energy.values())
    err = work + own["dissipated"] + own["stored"]
    total = sum(e["input"] for e in result.energy.values())
    return {"work": work, "dissipated": own["dissipated"], "stored": own["stored"], "error": err,
            "relative_error": err / total if total else 0.0}


def pair_terms(result) -> dict[str, float]:
    """The pair's account terms [J]: every building's input, kinetic_plus_strain, damping,
    contact_force_work, hysteretic and link_work (its ``links`` term) summed, and the impacts' impact_loss."""
    e = result.energy
    return {
        "input": sum(v["input"] for v in e.values()),
        "kinetic_plus_strain": sum(v["kinetic"] + v["strain"] for v in e.values()),
        "damping": sum(v["damping"] for v in e.values()),
        "contact_force_work": sum(v["contact_forces"] for v in e.values()),
        "impact_loss": sum(i.energy_loss for i in result.impacts),
        "hysteretic": sum(v.get("hysteretic", 0.0) for v in e.values()),
        "link_work": sum(v.get("links", 0.0) for v in e.values()),
    }


def sign_violations(result, terms: dict | None = None) -> list[dict]:
    """The terms of the pair's account [J] whose sign breaks physics by more than
    :func:`rounding_bound`: a list of ``{"term", "value", "bound", "why"}`` (empty when every sign holds).

    Damping, impact loss and hysteretic dissipation are >= 0 and the work of the contact forces
    (held and penalty contact, the plastic stops of held pairs) on the pair is <= 0 (a passive
    contact: energy passes between the buildings through it but none is created). Checked on the
    pair, not per building: contact forces and impulses move energy from one building to the other.
    """
    terms = pair_terms(result) if terms is None else terms
    bound = rounding_bound(result)
    out = []
    for key, sign, why in SIGNED_TERMS:
        value = float(terms[key])
        if sign * value < -bound:
            out.append({"term": key, "value": value, "bound": bound, "why": why})
    return out


def warn_if_sign_broken(result) -> None:
    """Warn (AnalysisWarning: stderr in the CLI) naming every term of the account whose sign breaks
    physics (:func:`sign_violations`); summary.json then says ``ok: false``."""
    import warnings

    from pounding.errors import AnalysisWarning

    for v in sign_violations(result):
        want = "<= 0" if v["term"] in ("contact_force_work", "link_work") else ">= 0"
        warnings.warn(
            f"energy account: {v['term']} = {v['value']:.4g} J, expected {want} ({v['why']}; rounding allows "
            f"{v['bound']:.2g} J): the run created energy (summary.json: energy_balance.sign_violations)",
            AnalysisWarning,
            stacklevel=4,
        )
