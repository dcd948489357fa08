"""The rebound of a force law: two free bodies that meet, integrated through their contact.

Two bodies of masses m1, m2 [kg] move along one line and meet at closing speed v0 [m/s]. Their
relative motion is one degree of freedom, the penetration delta [m]:

    m_eff delta'' = -F(delta, delta', v0),    m_eff = m1 m2 / (m1 + m2),
    delta(0) = 0,  delta'(0) = v0,

and the contact ends where delta returns to zero (a law whose force has fallen to zero before
that leaves the bodies in free flight, at constant delta'). The *rebound* is -delta' / v0 there:
the coefficient of restitution the law actually gives, to compare with the e it was calibrated
from. Each body's velocity follows from momentum, which the contact force (equal and opposite on
the two) conserves: v1' = v1 - (1 + r) v0 m_eff / m1, v2' = v2 + (1 + r) v0 m_eff / m2.

The integration is scipy's DOP853 (8th order, dense output, the end located as a root of delta)
with relative tolerance :data:`RTOL` and absolute tolerances that scale with the contact's own
sizes (the elastic peak penetration and v0), so the answer does not depend on units: the
rebound changes by 3e-9 at most from RTOL = 1e-10 to 1e-12 (tests/test_contact_laws.py checks
< 1e-8), and as the error of an 8th-order method scales with its tolerance, the rebound at 1e-12
is good to ~1e-11: far below the 4 digits tabulated. A kink of the force (Kelvin's and Hertzdamp's force clamped at zero,
Jankowski's damping switched off at delta' = 0) is a jump of the acceleration, which the error
control meets with smaller steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: relative tolerance of the integration (see the module docstring)
RTOL = 1e-12
#: the closing speed of the rebound table [m/s]
TABLE_SPEED = 0.5
#: the restitutions of the rebound table
TABLE_RESTITUTIONS = (0.3, 0.5, 0.65, 0.8, 0.95)


@dataclass(frozen=True)
class Rebound:
    """What one contact of two free bodies did.

    Attributes
    ----------
    ratio : float
        Separation speed over approach speed [-].
    peak_penetration : float
        Largest delta [m].
    peak_force : float
        Largest contact force [N].
    duration : float
        Time from the first touch to the end of contact [s] (delta back to zero).
    """

    ratio: float
    peak_penetration: float
    peak_force: float
    duration: float


def elastic_penetration(stiffness: float, exponent: float, m_eff: float, v0: float) -> float:
    """Largest penetration [m] of the law's spring alone, k delta^n, stopping m_eff [kg] from v0
    [m/s]: k delta^(n+1) / (n + 1) = m_eff v0^2 / 2 (Hertz's (5 m_eff v0^2 / (4 k))^(2/5) at n = 1.5)."""
    return ((exponent + 1.0) * m_eff * v0 * v0 / (2.0 * stiffness)) ** (1.0 / (exponent + 1.0))


def rebound(law, *, approach_speed: float = TABLE_SPEED, m1: float = 1e5, m2: float = 1e5, rtol: float = RTOL) -> Rebound:
    """The rebound of ``law`` (a :class:`~pounding.contact.pointwise.PointwiseLaw`) for two free
    bodies of masses m1, m2 [kg] meeting at ``approach_speed`` [m/s] (see the module docstring)."""
    from scipy.integrate import solve_ivp

    v0 = float(approach_speed)
    m_eff = m1 * m2 / (m1 + m2)
    params = law.params(np.array([m_eff]))[0]
    force = law.law_force

    def rhs(t, y):
        return [y[1], -force(float(y[0]), float(y[1]), v0, params)[0] / m_eff]

    def back(t, y):  # delta returns to zero: the contact ends
        return y[0]

    back.terminal, back.direction = True, -1.0

    def turn(t, y):  # delta' = 0 going down: the deepest penetration
        return y[1]

    turn.direction = -1.0
    d_el = elastic_penetration(law.stiffness, law.exponent, m_eff, v0)
    t_el = d_el / v0
    sol = solve_ivp(rhs, (0.0, 1e3 * t_el), [0.0, v0], method="DOP853", rtol=rtol, atol=[rtol * d_el, rtol * v0],
                    events=(back, turn), dense_output=True, max_step=t_el / 20.0)
    if sol.status != 1:
        raise RuntimeError(f"the contact of {law.name!r} did not end within {1e3 * t_el:.3g} s")
    t_end = float(sol.t_events[0][0])
    v_end = float(sol.y_events[0][0][1])
    deepest = float(sol.y_events[1][0][0])
    return Rebound(-v_end / v0, deepest, _peak_force(sol.sol, force, v0, params, t_end), t_end)


def _peak_force(path, force, v0: float, params: np.ndarray, t_end: float) -> float:
    """Largest force [N] along the dense solution ``path`` over [0, t_end] [s]: the largest of a fine
    grid, refined by Brent's bounded search between its neighbours (the force is smooth there)."""
    from scipy.optimize import minimize_scalar

    def f(t):
        d, v = path(t)
        return force(float(d), float(v), v0, params)[0]

    t = np.linspace(0.0, t_end, 2001)
    values = np.array([f(x) for x in t])
    j = int(np.argmax(values))
    lo, hi = t[max(j - 1, 0)], t[min(j + 1, t.size - 1)]
    best = minimize_scalar(lambda x: -f(x), bounds=(lo, hi), method="bounded", options={"xatol": 1e-12 * t_end})
    return float(max(values[j], -best.fun))


def table_laws(e: float) -> dict:
    """The laws of the rebound table at restitution e: name -> law."""
    from pounding.contact.hertz import Hertz
    from pounding.contact.hertzdamp import HertzDamp
    from pounding.contact.jankowski import Jankowski
    from pounding.contact.kelvin import Kelvin

    return {
        "kelvin, tension = true": Kelvin(restitution=e, tension=True),
        "kelvin, tension = false (default)": Kelvin(restitution=e),
        "hertz": Hertz(),
        "hertzdamp, damping = ye (default)": HertzDamp(restitution=e),
        "hertzdamp, damping = lankarani_nikravesh": HertzDamp(restitution=e, damping="lankarani_nikravesh"),
        "jankowski": Jankowski(restitution=e),
    }


def rebound_table(restitutions=TABLE_RESTITUTIONS, approach_speed: float = TABLE_SPEED) -> dict:
    """{law: [rebound ratio at each e]} for two bodies of 1e5 kg meeting at ``approach_speed`` [m/s],
    every law with its default stiffness."""
    out: dict = {}
    for e in restitutions:
        for name, law in table_laws(e).items():
            out.setdefault(name, []).append(rebound(law, approach_speed=approach_speed).ratio)
    return out


def table_markdown(table: dict, restitutions=TABLE_RESTITUTIONS) -> str:
    """The rebound table as Markdown: one row per law, one column per e, 4 decimals, and the largest
    relative departure from e of each law (none for an elastic law, which rebounds with 1 whatever e:
    it has no calibration to be off)."""
    head = "| law | " + " | ".join(f"e = {e:g}" for e in restitutions) + " | largest (r - e) / e |"
    rule = "|---|" + "---|" * (len(restitutions) + 1)
    rows = [head, rule]
    for name, ratios in table.items():
        off = max((r - e) / e for r, e in zip(ratios, restitutions))
        worst = min((r - e) / e for r, e in zip(ratios, restitutions))
        dev = off if abs(off) >= abs(worst) else worst
        elastic = all(abs(r - 1.0) < 1e-6 for r in ratios)
        rows.append(f"| {name} | " + " | ".join(f"{r:.4f}" for r in ratios) + (" | elastic |" if elastic else f" | {dev:+.1%} |"))
    return "\n".join(rows)
