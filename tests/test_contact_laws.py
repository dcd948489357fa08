"""The force laws of pounding.contact (kelvin, hertz, hertzdamp, jankowski): closed forms, the
rebound each gives, the face rule, momentum, and the end-of-step solve.

The contact problem throughout is two free bodies meeting at v0: their relative motion is
m_eff delta'' = -F(delta, delta', v0), integrated to convergence by
:func:`pounding.contact.rebound.rebound` (DOP853, rtol 1e-12; its error is ~1e-11, see that
module), or stepped with the law's own implicit solve (:mod:`two_bodies`, Newmark's average
acceleration, the way the engine steps it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.special import beta

from pounding.contact.hertz import Hertz
from pounding.contact.hertzdamp import HertzDamp
from pounding.contact.jankowski import Jankowski
from pounding.contact.kelvin import Kelvin
from pounding.contact.rebound import TABLE_RESTITUTIONS, rebound, rebound_table, table_markdown
from two_bodies import contact, step_two_bodies

ROOT = Path(__file__).resolve().parents[1]
EPS = np.finfo(float).eps
#: the ODE's rebound is good to ~1e-11 (rtol 1e-12 on an 8th-order method, whose error scales with
#: its tolerance: 1e-10 moves it by 3e-9 at most); 1e-9 leaves that a hundredfold margin
ODE_ACCURACY = 1e-9


def laws(e: float = 0.5) -> list:
    """One of each law at restitution e, default stiffness."""
    return [Kelvin(restitution=e, tension=True), Kelvin(restitution=e), Hertz(), HertzDamp(restitution=e),
            HertzDamp(restitution=e, damping="lankarani_nikravesh"), Jankowski(restitution=e)]


def test_hertz_peak_penetration_and_duration_are_the_closed_forms():
    """Hertz, two free bodies (1e5 and 2e5 kg) meeting at 0.5 m/s: delta_max = (5 m_eff v0^2 / (4 k_h))^(2/5)
    (energy: k_h delta^2.5 / 2.5 = m_eff v0^2 / 2) and the contact lasts 2 * (2/5) B(2/5, 1/2) delta_max / v0
    = 2.9433 delta_max / v0 (the time integral of d delta / delta' over the loading and unloading halves),
    to the integration's accuracy; the peak force is k_h delta_max^1.5."""
    law, m1, m2, v0 = Hertz(), 1e5, 2e5, 0.5
    m_eff = m1 * m2 / (m1 + m2)
    r = rebound(law, approach_speed=v0, m1=m1, m2=m2)
    d_max = (5.0 * m_eff * v0**2 / (4.0 * law.stiffness)) ** 0.4
    assert r.peak_penetration == pytest.approx(d_max, rel=ODE_ACCURACY)
    constant = 2.0 * 0.4 * beta(0.4, 0.5)
    assert round(constant, 3) == 2.943
    assert r.duration == pytest.approx(constant * d_max / v0, rel=ODE_ACCURACY)
    assert r.peak_force == pytest.approx(law.stiffness * d_max**1.5, rel=ODE_ACCURACY)


@pytest.mark.parametrize("e", TABLE_RESTITUTIONS)
def test_kelvin_with_tension_rebounds_with_exactly_e(e):
    """Kelvin with a dashpot that may pull: the contact is a damped oscillator of ratio xi over half its
    damped period, which returns delta' = -exp(-xi pi / sqrt(1 - xi^2)) v0 = -e v0 for
    xi = -ln e / sqrt(pi^2 + ln^2 e) (Anagnostopoulos): exactly e, to the integration's accuracy."""
    assert rebound(Kelvin(restitution=e, tension=True)).ratio == pytest.approx(e, abs=ODE_ACCURACY)


def test_the_rebound_table_in_the_docs_is_what_rebound_table_computes():
    """docs/contact-laws.md and README.md hold the table :func:`rebound_table` computes (4 decimals), and
    the table holds exactly e for kelvin with tension and 1 for hertz (elastic)."""
    table = rebound_table()
    for page in (ROOT / "docs" / "contact-laws.md", ROOT / "README.md"):
        assert table_markdown(table) in page.read_text(), page.name
    assert np.allclose(table["kelvin, tension = true"], TABLE_RESTITUTIONS, atol=ODE_ACCURACY, rtol=0)
    assert np.allclose(table["hertz"], 1.0, atol=ODE_ACCURACY, rtol=0)


@pytest.mark.parametrize("law", laws(0.3) + laws(0.8), ids=lambda law: law.name)
def test_the_rebound_depends_on_neither_speed_nor_masses(law):
    """Every calibration is scale free (xi makes the law's loss a fixed fraction whatever k, m_eff and v0:
    Kelvin's c ~ sqrt(k m_eff), Jankowski's c ~ sqrt(k_h sqrt(delta) m_eff), Hertzdamp's damping
    relative to delta'_0): the table at 0.5 m/s and 1e5 kg holds at 2 m/s and 3e4 / 7e5 kg, to the
    integration's accuracy."""
    base = rebound(law).ratio
    assert rebound(law, approach_speed=2.0, m1=3e4, m2=7e5).ratio == pytest.approx(base, abs=ODE_ACCURACY)


@pytest.mark.parametrize("law", laws(0.3) + laws(0.95), ids=lambda law: law.name)
def test_the_rebound_is_converged_in_the_integration_tolerance(law):
    """Tightening the relative tolerance from 1e-10 to 1e-12 moves the rebound by < 1e-8 (measured: 3e-9
    at most), so the tabulated 4 decimals are the law's, not the integrator's."""
    assert abs(rebound(law, rtol=1e-10).ratio - rebound(law).ratio) < 1e-8


@pytest.mark.parametrize("law", laws(0.5), ids=lambda law: law.name)
def test_momentum_is_conserved_across_the_contact(law):
    """Two bodies of 1e5 and 2e5 kg, the first at 0.5 m/s, stepped through their contact with the law's
    end-of-step forces (equal and opposite on the two): m1 v1 + m2 v2 stays m1 v0 to rounding (a few
    eps of m1 v0 per step)."""
    m1, m2, v0 = 1e5, 2e5, 0.5
    h = rebound(law, m1=m1, m2=m2).duration / 400
    s = step_two_bodies(law, m1=m1, m2=m2, v1=v0, v2=0.0, h=h)
    p = m1 * s.v1 + m2 * s.v2
    assert np.max(np.abs(p - m1 * v0)) <= 4 * EPS * m1 * v0 * len(s.t)


@pytest.mark.parametrize("law", laws(0.5), ids=lambda law: law.name)
def test_the_stepped_end_of_step_solve_converges_to_the_rebound(law):
    """The law's implicit end-of-step solve (:meth:`PointwiseLaw.forces`, Newton with the tangent) in
    Newmark steps converges to the integrated contact: the velocities after it are
    v1' = v0 - (1 + r) v0 m_eff / m1, v2' = (1 + r) v0 m_eff / m2 with r the converged rebound, to the
    stepped result's own error, bounded by its change when the step is halved (a method of order
    p >= 1 in its asymptotic range has error(h/2) = change / (2^p - 1) <= change)."""
    m1, m2, v0 = 1e5, 2e5, 0.5
    m_eff = m1 * m2 / (m1 + m2)
    ref = rebound(law, m1=m1, m2=m2)
    coarse, fine = (step_two_bodies(law, m1=m1, m2=m2, v1=v0, v2=0.0, h=ref.duration / n) for n in (800, 1600))
    change = abs(coarse.v1[-1] - fine.v1[-1]) + abs(coarse.v2[-1] - fine.v2[-1])
    v1 = v0 - (1 + ref.ratio) * v0 * m_eff / m1
    v2 = (1 + ref.ratio) * v0 * m_eff / m2
    assert abs(fine.v1[-1] - v1) + abs(fine.v2[-1] - v2) <= change + ODE_ACCURACY * v0


@pytest.mark.parametrize("law", laws(0.5), ids=lambda law: law.name)
@pytest.mark.parametrize("coupled", [False, True], ids=["alone", "with the step"])
def test_a_uniform_face_of_m_points_carries_the_laws_force(law, coupled):
    """The face rule: m points of one pair with one row (W = a 1 1^T, so each point's m_eff = 1/a), each
    standing for 1/m of the contact (``share``; a face's two ends: 1/2 each), at one penetration and rate
    carry, together, what one point of the same contact carries, for m = 2 and 3, alone (S_q = S_v = 0:
    the force F(delta)) and solved with the step (S = alpha W: the total T solves the one-point equation
    T = F(delta - alpha a T, ...)); points that stand for a whole contact each carry the whole law,
    whatever their pair. To the Newton tolerance (1e-12 of the force)."""
    a, gap, rate, v0 = 1.0 / 5e4, -2e-3, -0.1, 0.5
    sq, sv = (1e-7, 1e-5) if coupled else (0.0, 0.0)
    one = law.forces(contact(gap, rate, sq * a, sv * a, a, 0, v0))[0]
    assert one > 0.0
    for m in (2, 3):
        W = np.full((m, m), a)
        face = law.forces(contact(np.full(m, gap), np.full(m, rate), sq * W, sv * W, W, np.zeros(m), np.full(m, v0),
                                  share=np.full(m, 1.0 / m)))
        assert face.sum() == pytest.approx(one, rel=1e-11)
        assert np.allclose(face, one / m, rtol=1e-11, atol=0)
    apart = law.forces(contact([gap, gap], [rate, rate], np.diag([sq * a] * 2), np.diag([sv * a] * 2), np.diag([a, a]),
                               [0, 0], [v0, v0]))
    assert apart == pytest.approx([one, one], rel=1e-11)


@pytest.mark.parametrize("law", laws(0.5), ids=lambda law: law.name)
@pytest.mark.parametrize("rate", [0.3, 0.0, -0.2])
def test_the_tangents_are_the_derivatives_of_the_force(law, rate):
    """d F / d delta and d F / d delta' the law gives (Newton's Jacobian) are the central differences of
    its force, at delta = 1 mm and 0.5 m/s approach: the relative step 1e-5 leaves a truncation of
    ~1e-10 relative and a rounding of ~eps / 1e-5 = 2e-11, so 1e-7 is conservative."""
    m_eff, d, v0 = 5e4, 1e-3, 0.5
    p = law.params(np.array([m_eff]))[0]
    f, fd, fr = law.law_force(d, rate, v0, p)
    hd, hr = 1e-5 * d, 1e-5 * v0
    num_d = (law.law_force(d + hd, rate, v0, p)[0] - law.law_force(d - hd, rate, v0, p)[0]) / (2 * hd)
    assert fd == pytest.approx(num_d, rel=1e-7)
    if rate != 0.0:  # Jankowski's damping switches on at delta' = 0: a kink, no derivative there
        num_r = (law.law_force(d, rate + hr, v0, p)[0] - law.law_force(d, rate - hr, v0, p)[0]) / (2 * hr)
        assert fr == pytest.approx(num_r, rel=1e-7, abs=1e-7 * abs(f) / v0)


@pytest.mark.parametrize("law", laws(0.3)[1:], ids=lambda law: law.name)
def test_a_law_never_pulls(law):
    """Apart from Kelvin with tension, no law's force is negative, however fast the slabs separate; and no
    law acts on slabs apart (delta <= 0). Kelvin with tension does pull when its dashpot outweighs the
    spring (k delta + c delta' < 0)."""
    p = law.params(np.array([5e4]))[0]
    for d in (1e-6, 1e-3):
        for rate in (-100.0, -1.0, -0.01, 0.0, 1.0):
            assert law.law_force(d, rate, 0.5, p)[0] >= 0.0
    assert law.law_force(0.0, 1.0, 0.5, p) == (0.0, 0.0, 0.0)
    assert law.law_force(-1e-3, 1.0, 0.5, p) == (0.0, 0.0, 0.0)
    pulling = Kelvin(restitution=0.3, tension=True)
    assert pulling.law_force(1e-6, -100.0, 0.5, pulling.params(np.array([5e4]))[0])[0] < 0.0


def test_hertzdamp_and_jankowski_forces_are_the_formulas_of_their_papers():
    """At delta = 1 mm, delta' = 0.2 m/s, delta'_0 = 0.5 m/s, m_eff = 5e4 kg, e = 0.5, default k_h:
    Hertzdamp k_h delta^1.5 (1 + xi delta'/delta'_0) with Ye's xi = 8 (1 - e) / (5 e) = 1.6, and
    Lankarani-Nikravesh's 3 (1 - e^2) / 4 = 0.5625; Jankowski k_h delta^1.5 + 2 xi sqrt(k_h sqrt(delta)
    m_eff) delta' with xi = 9 sqrt(5) / 2 (1 - e^2) / (e (e (9 pi - 16) + 16)) (approaching) and
    k_h delta^1.5 (separating); Kelvin k delta + 2 xi sqrt(k m_eff) delta' with
    xi = -ln e / sqrt(pi^2 + ln^2 e). To rounding."""
    k, d, r, r0, m, e = 2.75e9, 1e-3, 0.2, 0.5, 5e4, 0.5
    spring = k * d**1.5

    def force(law, rate=r):
        return law.point_force(d, rate, r0, m)[0]

    assert force(HertzDamp(restitution=e)) == pytest.approx(spring * (1 + 1.6 * r / r0), rel=4 * EPS)
    assert force(HertzDamp(restitution=e, damping="lankarani_nikravesh")) == pytest.approx(spring * (1 + 0.5625 * r / r0), rel=4 * EPS)
    xi = 9 * math.sqrt(5) / 2 * (1 - e * e) / (e * (e * (9 * math.pi - 16) + 16))
    assert force(Jankowski(restitution=e)) == pytest.approx(spring + 2 * xi * math.sqrt(k * math.sqrt(d) * m) * r, rel=8 * EPS)
    assert force(Jankowski(restitution=e), -r) == pytest.approx(spring, rel=4 * EPS)
    ln = math.log(e)
    xk = -ln / math.sqrt(math.pi**2 + ln**2)
    assert force(Kelvin(stiffness=1e9, restitution=e)) == pytest.approx(1e9 * d + 2 * xk * math.sqrt(1e9 * m) * r, rel=8 * EPS)
