"""The time step that resolves contact, and the contact episodes that converge with it.

A force law declares how long one contact lasts (:meth:`ContactLaw.contact_duration`); the
default step spans the run's shortest contact with STEPS_PER_CONTACT steps
(:mod:`pounding.framework.engine.timestep`, :mod:`pounding.framework.engine.contact_step`), a
coarser given step warns, and the peaks at the default step are within 0.5 % of the converged
run. Contact episodes merge a pair's chatter (:mod:`pounding.framework.engine.chatter`) so that
their count, unlike the number of impacts, does not depend on the step.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import gamma

from pounding.contact.hertz import Hertz
from pounding.contact.hertzdamp import HertzDamp
from pounding.contact.impulse import Impulse
from pounding.contact.jankowski import Jankowski
from pounding.contact.kelvin import Kelvin
from pounding.contact.none import NoContact
from pounding.contact.penalty import Penalty
from pounding.contact.rebound import rebound
from pounding.errors import AnalysisWarning
from pounding.framework.engine.timestep import STEPS_PER_CONTACT
from pounding.io.scene import load_scene
from pounding.framework.post.run import run

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
#: the rebound ODE (DOP853, rtol 1e-12) puts the end of contact within ~1e-11 of its length
#: (pounding.contact.rebound); 1e-9 leaves a hundredfold margin
ODE_ACCURACY = 1e-9
M1, M2 = 1e5, 1e5  # the rebound's two bodies [kg]
M_EFF = M1 * M2 / (M1 + M2)


def paper(**analysis):
    return load_scene(PAPER).with_analysis(**analysis)


# ------------------------------------------------------------------ the laws' durations
@pytest.mark.parametrize("e", [0.3, 0.5, 0.8])
def test_kelvin_with_tension_lasts_half_a_damped_period(e):
    """A Kelvin contact whose dashpot may pull: delta = (v0 / omega_d) exp(-xi omega t) sin(omega_d t)
    returns to zero after pi / omega_d, omega_d = sqrt(k / m_eff) sqrt(1 - xi^2): the declared
    duration is that, and the ODE of two free masses ends there."""
    law = Kelvin(stiffness=1e9, restitution=e, tension=True)
    xi = law.damping_ratio
    closed = math.pi / (math.sqrt(1e9 / M_EFF) * math.sqrt(1.0 - xi * xi))
    assert law.contact_duration(M_EFF, 0.5) == pytest.approx(closed, rel=1e-14)
    assert rebound(law, m1=M1, m2=M2).duration == pytest.approx(closed, rel=ODE_ACCURACY)


def _force_zero_time(law, v0=0.5):
    """When the compression-only force of ``law`` first returns to zero for two free masses meeting
    at v0 [m/s] (DOP853, rtol 1e-12, the force's zero located by an event)."""
    p = law.params(np.array([M_EFF]))[0]

    def rhs(t, y):
        return [y[1], -law.law_force(float(y[0]), float(y[1]), v0, p)[0] / M_EFF]

    def force(t, y):  # the unclamped force k delta + c delta'
        return p[0] * y[0] + p[1] * y[1]

    force.terminal, force.direction = True, -1.0
    scale = law.contact_duration(M_EFF, v0)
    sol = solve_ivp(rhs, (0.0, 10.0 * scale), [0.0, v0], method="DOP853", rtol=1e-12, atol=[1e-12 * v0 * scale, 1e-12 * v0],
                    events=force, max_step=scale / 50.0)
    return float(sol.t_events[0][0])


@pytest.mark.parametrize("e", [0.05, 0.5, 0.9])
def test_compression_only_kelvin_ends_where_its_force_returns_to_zero(e):
    """The force k delta + c delta' of a compression-only Kelvin contact first returns to zero at
    omega_d t = pi - 2 arcsin(xi): the declared duration is the ODE's zero of the force, and the
    penalty law (the same spring and dashpot, never pulling) declares the same for its xi."""
    law = Kelvin(stiffness=1e9, restitution=e)
    assert law.contact_duration(M_EFF, 0.5) == pytest.approx(_force_zero_time(law), rel=ODE_ACCURACY)
    pen = Penalty(stiffness=1e9, restitution=e)
    twin = Kelvin(stiffness=1e9, restitution=e)
    twin.damping_ratio = pen.damping_ratio
    assert pen.contact_duration(M_EFF, 3.0) == pytest.approx(twin.contact_duration(M_EFF, 0.1), rel=1e-14)


def test_critically_and_over_damped_compression_only_contacts():
    """The force's zero for xi = 1 is t = 2 / omega (delta = v0 t exp(-omega t)); for xi > 1 the
    declared closed form is the ODE's zero of the force (Kelvin with the dashpot set by hand)."""
    for xi in (1.0, 1.5, 3.0):
        law = Kelvin(stiffness=1e9, restitution=0.5)
        law.damping_ratio = xi
        got = law.contact_duration(M_EFF, 0.5)
        assert got == pytest.approx(_force_zero_time(law), rel=ODE_ACCURACY)
        if xi == 1.0:
            assert got == pytest.approx(2.0 / math.sqrt(1e9 / M_EFF), rel=1e-14)


@pytest.mark.parametrize("v0", [0.1, 0.5, 2.0])
def test_hertz_duration_is_the_closed_form(v0):
    """Hertz (n = 1.5): delta_max = (5 m_eff v0^2 / (4 k_h))^(2/5), duration 2.943 delta_max / v0
    (2 sqrt(pi) Gamma(7/5) / Gamma(9/10) = 2.9432); the ODE of two free masses ends there. At n = 1
    the same formula is the linear spring's pi sqrt(m_eff / k)."""
    law = Hertz()
    d_max = (5.0 * M_EFF * v0**2 / (4.0 * law.stiffness)) ** 0.4
    constant = 2.0 * math.sqrt(math.pi) * gamma(1.4) / gamma(0.9)
    assert constant == pytest.approx(2.943, abs=5e-4)
    assert law.contact_duration(M_EFF, v0) == pytest.approx(constant * d_max / v0, rel=1e-14)
    assert rebound(law, approach_speed=v0, m1=M1, m2=M2).duration == pytest.approx(constant * d_max / v0, rel=ODE_ACCURACY)
    linear = Hertz(stiffness=1e9, exponent=1.0)
    assert linear.contact_duration(M_EFF, v0) == pytest.approx(math.pi * math.sqrt(M_EFF / 1e9), rel=1e-14)


@pytest.mark.parametrize("e", [0.3, 0.5, 0.8, 0.95])
def test_the_damped_hertz_laws_are_bounded_by_the_elastic_duration(e):
    """Hertzdamp and Jankowski declare the elastic Hertz duration T_H of their spring. Their
    restitution phase alone lasts at least T_H / 2 (a strict bound: the penetration is shallower
    and the rebound force no larger than the spring's); measured on two free masses, hertzdamp's
    whole contact lasts at least T_H and Jankowski's at least 0.98 T_H (the estimate's margin,
    stated in the laws' docstrings)."""
    for law, floor in ((HertzDamp(restitution=e), 1.0), (HertzDamp(restitution=e, damping="lankarani_nikravesh"), 1.0),
                       (Jankowski(restitution=e), 0.98)):
        declared = law.contact_duration(M_EFF, 0.5)
        assert declared == pytest.approx(Hertz().contact_duration(M_EFF, 0.5), rel=1e-14)
        assert rebound(law, m1=M1, m2=M2).duration >= floor * declared


def test_impulse_and_no_contact_put_no_bound_on_the_step():
    """Laws that act at instants, or not at all, declare no duration (inf) at any mass and speed."""
    for law in (Impulse(), NoContact()):
        assert math.isinf(law.contact_duration(1e4, 10.0))


# ------------------------------------------------------------------ the default step
def test_default_step_resolves_the_shortest_contact():
    """Without a dt, a run with a stiff Kelvin contact (k = 1e10 N/m) takes at least STEPS_PER_CONTACT
    steps over the shortest contact; that contact is the Kelvin closed form for the pair's effective
    mass bound, which lies below the two floors' translational m1 m2 / (m1 + m2) and below the
    effective mass at the facing corners with the normal along y (the slabs turn about their
    centres: 1 / (1/m1 + 7.5^2/J1 + 1/m2 + 6.03^2/J2) at the corner x = 15 m, y = 0). The impulse law keeps the modal step."""
    from pounding.framework.engine.driver import Driver

    d = Driver(paper(contact="kelvin", contact_params={"stiffness": 1e10}, dt=None))
    ct = d.contact_time
    assert ct.duration / d.dt >= STEPS_PER_CONTACT
    law = Kelvin(stiffness=1e10)
    assert ct.duration == pytest.approx(law.contact_duration(ct.m_eff, 0.0), rel=1e-14)
    m1, j1 = d.model.systems[0].mass[:3:2]
    m2, j2 = d.model.systems[1].mass[:3:2]
    assert ct.m_eff <= m1 * m2 / (m1 + m2)
    assert ct.m_eff <= 1.0 / (1.0 / m1 + 7.5**2 / j1 + 1.0 / m2 + 6.03**2 / j2) * (1.0 + 1e-12)
    modal = Driver(paper(contact="impulse", dt=None)).dt
    assert d.dt < modal and math.isinf(Driver(paper(contact="impulse", dt=None)).contact_time.duration)


def test_the_default_step_asks_the_integrator_whether_it_is_exact_within_the_step():
    """The default step samples the response EXACT_STEPS_PER_PERIOD times a period for an integrator
    that declares itself exact within the step (no period error) and takes STEPS_PER_PERIOD for the
    others: a third party's subclass of ``exact`` under a name of its own, passed as a class, gets the
    exact integrator's step, and average acceleration (``newmark``) a step EXACT / STEPS times as long
    or shorter (the grid's divisors of the record's interval round it down)."""
    from pounding.framework.engine.stacked_model import Model
    from pounding.framework.engine.timestep import EXACT_STEPS_PER_PERIOD, STEPS_PER_PERIOD, default_dt
    from pounding.solvers.exact import Exact

    class OwnExact(Exact):
        name = "own_exact"

    scene = paper(contact="impulse", dt=None)
    m = Model(scene)
    step = {k: default_dt(m.systems, m.directions, scene.ground_motion.dt, k) for k in ("exact", OwnExact, "newmark")}
    assert step[OwnExact] == step["exact"]
    assert step["newmark"] <= step["exact"] * EXACT_STEPS_PER_PERIOD / STEPS_PER_PERIOD


def test_a_coarse_given_dt_warns_with_the_number_of_steps_per_contact():
    """A given dt = 0.005 s over a k = 1e10 N/m Kelvin contact (3.9 ms on the paper's pair): one
    warning naming the steps per contact (duration / dt, below 1) and the dt that resolves it
    (duration / STEPS_PER_CONTACT); the default step gives none."""
    from pounding.framework.post.run import warn_if_contact_unresolved

    with pytest.warns(AnalysisWarning, match="spans the shortest kelvin contact") as got:
        r = run(paper(contact="kelvin", contact_params={"stiffness": 1e10}, dt=0.005, duration=0.2))
    ct = r.info["contact_time"]
    mine = [str(w.message) for w in got if "spans the shortest" in str(w.message)]
    assert len(mine) == 1
    assert f"in {ct['duration'] / 0.005:.3g} steps" in mine[0] and f"dt <= {ct['duration'] / STEPS_PER_CONTACT:.3g} s" in mine[0]
    fine = run(paper(contact="kelvin", contact_params={"stiffness": 1e10}, dt=None, duration=0.2))
    assert fine.info["contact_time"]["steps_per_contact"] >= STEPS_PER_CONTACT
    with warnings.catch_warnings():
        warnings.simplefilter("error", AnalysisWarning)
        assert warn_if_contact_unresolved(fine) is None


def _peaks(result) -> np.ndarray:
    """Peak |u|, |v| of every slab, (buildings, 2) lists of (storeys,) arrays flattened by building."""
    return [result.peaks(n)[:, :2] for n in result.names]


#: the window of the peak tests [s]: two contact episodes (1.9 s and 2.5 s), each several contacts.
#: The whole record's figures (and hertzdamp's strikes at 4.66 s and 5.26 s, which set the 40 steps)
#: are benchmarks/bench_contact_step.py's: a test stays within seconds
WINDOW = 2.6
FORCE_LAWS = ["kelvin", "penalty", "hertz", "hertzdamp", "jankowski"]


@pytest.mark.parametrize("law", FORCE_LAWS)
def test_default_step_peaks_are_within_half_a_percent_of_the_converged_run(law):
    """The paper's pair at 0.03 m with each force law at its default parameters, over a window of a
    few contact episodes (WINDOW): the peak |u| and |v| of every slab at the default step are within
    0.5 % of the converged run, relative to the building's largest peak in that direction. The
    converged run is the default step / 4; its own error is estimated by its difference from the
    default step / 2 (the error falls about as dt, so the finer run's error is about that
    difference) and counted against the 0.5 %. The approach speed bound holds: no contact of the
    converged run closes faster than its pair's bound. No run breaks a sign of the energy account."""
    base = paper(contact=law, contact_params={}, dt=None, duration=WINDOW)
    default = run(base)
    dt = default.dt
    assert default.info["contact_time"]["steps_per_contact"] >= STEPS_PER_CONTACT and len(default.contacts) >= 2
    half, fine = run(base.with_analysis(dt=dt / 2)), run(base.with_analysis(dt=dt / 4))
    from pounding.framework.post.energy_account import sign_violations

    # a passive contact creates no energy at any step (an elastic law's face contact included)
    assert [sign_violations(r) for r in (default, half, fine)] == [[], [], []], law
    for p_def, p_half, p_fine in zip(_peaks(default), _peaks(half), _peaks(fine)):
        scale = p_fine.max(axis=0)  # (2,): the building's largest peak along u and along v
        err = np.abs(p_def - p_fine) / scale
        own = np.abs(p_half - p_fine) / scale
        assert np.all(err + own <= 5e-3), (law, err.max(), own.max())
    from pounding.framework.engine.contact_step import pair_bounds, record_peaks
    from pounding.framework.engine.stacked_model import Model

    model = Model(base)
    _, v0 = pair_bounds(model.geo, model.n, *record_peaks(model, base))
    assert all(e.approach_velocity <= v0[e.pair] for e in fine.contacts)


# ------------------------------------------------------------------ contact episodes
def test_contact_episodes_do_not_change_with_the_step_while_impacts_do():
    """The paper's pair at 0.03 m with the impulse law (its own HHT integrator), whole record, at
    dt = 0.01 s and 0.002 s: the impacts differ (a chatter's micro-impacts are resolved down to
    about a step), the contact episodes are the same, pair by pair, and each begins at the same
    instant to within a quarter of the merge interval tau (T1 / 8 = 73 ms): an instant would have to
    move by about the distance between an interval and tau to change the count. Every impact
    belongs to exactly one episode (their strikes add up to the impacts)."""
    coarse, fine = run(paper(dt=0.01)), run(paper(dt=0.002))
    assert len(coarse.impacts) < len(fine.impacts)
    a, b = coarse.contact_episodes(), fine.contact_episodes()
    assert len(a) == len(b) >= 10
    from pounding.framework.engine.chatter import merge_intervals

    tau = merge_intervals(fine.systems, fine.pairs)
    for x, y in zip(a, b):
        assert x.pair == y.pair and abs(x.start - y.start) < tau[x.pair] / 4
    assert sum(e.strikes for e in a) == len(coarse.impacts) and sum(e.strikes for e in b) == len(fine.impacts)
    assert sum(e.impulse for e in b) == pytest.approx(sum(i.impulse for i in fine.impacts), rel=1e-12)


def test_summary_and_printed_summary_report_episodes_and_what_converges(tmp_path):
    """summary.json carries n_contact_episodes, contact_episodes (count, strikes, merge intervals),
    convergence (what converges with dt and what does not) and contact_time; contacts.csv numbers
    every row's episode, and the printed summary of `pounding run` says the episodes beside the
    impacts and which results converge."""
    import csv
    import json

    from pounding.cli import human_summary
    from pounding.io.results import write_results

    r = run(paper(duration=6.0))
    write_results(r, tmp_path / "out")
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    rows = list(csv.DictReader(open(tmp_path / "out" / "contacts.csv")))
    eps = r.contact_episodes()
    assert s["n_contact_episodes"] == s["contact_episodes"]["n"] == len(eps) == max(int(row["episode"]) for row in rows)
    assert s["contact_episodes"]["strikes"] == len(r.impacts) == s["n_impacts"] > len(eps)
    assert "contact episodes" in s["convergence"]["converge_with_dt"]
    assert any("impacts" in x for x in s["convergence"]["depend_on_dt"])
    assert s["contact_time"]["duration"] is None  # the impulse law has none
    text = human_summary(r, tmp_path / "out")
    assert f"{len(eps)} contact episodes" in text and f"{len(r.impacts)} impacts in them" in text
    assert "converge as dt falls" in text


def test_a_zeno_chatter_is_one_episode_and_a_fresh_approach_another():
    """A ball-like chatter of one pair: rebound speeds r_k = e^k r_0 against a steady closing
    acceleration a, so the strikes come 2 r_k / a apart and the sequence ends 2 r_0 / (a (1 - e))
    after its first strike (a geometric series). With every interval below tau the whole sequence
    is one episode lasting that long, holding every strike, its impulses summed; a strike that
    comes more than tau after it starts a second one; a sequence whose first interval exceeds tau
    keeps its first strike apart and merges the rest (the intervals only shrink)."""
    from pounding.framework.engine.chatter import merge_chatter
    from pounding.framework.engine.results import ContactEpisode

    def strike(t, impulse, pair=0):
        return ContactEpisode(t, t, pair, np.zeros(2), np.array([1.0, 0.0]), 0.1, math.nan, 0.0, impulse, 1.0)

    e, a, r0, tau = 0.5, 10.0, 0.2, np.array([0.073])
    times = np.concatenate([[0.0], np.cumsum(2.0 * r0 * e ** np.arange(30) / a)])  # 31 strikes
    seq = [strike(t, 1.0) for t in times]
    got = merge_chatter(seq + [strike(times[-1] + 2 * tau[0], 5.0)], tau)
    assert len(got) == 2 and got[0].strikes == 31 and got[1].strikes == 1
    assert got[0].end - got[0].start == pytest.approx(2.0 * r0 / (a * (1.0 - e)) * (1.0 - e**30), rel=1e-12)
    assert got[0].impulse == pytest.approx(31.0) and got[1].impulse == 5.0
    slow = merge_chatter([strike(t, 1.0) for t in times * 3.0], tau)  # first interval 0.12 s > tau, then 0.06 s
    assert [x.strikes for x in slow] == [1, 30]


def test_a_pair_with_a_building_between_its_slabs_does_not_set_the_step():
    """Three boxes in a row under kelvin: the end buildings' slabs face each other only through the
    middle one, which they strike first (the gap study's rule, ``placement.adjacent_pairs``), so their
    contact never comes and does not set the default step: the step is the one the same row takes with
    that pair under the impulse law (no duration), and the shortest contact is an adjacent pair's."""
    from pounding.framework.engine.driver import Driver
    from pounding.framework.model.placement import adjacent_pairs
    from pounding.io.scene import parse_scene
    from tests.test_mixed_laws import KELVIN, row

    kelvin = {"name": "kelvin", **KELVIN}
    d = Driver(parse_scene(row((0.005, 0.005), contact=kelvin)))
    names = [b.name for b in d.scene.buildings]
    adjacent, screened = adjacent_pairs(d.scene)
    assert [(names[i], names[j]) for i, j in screened] == [("west", "east")]
    faces = {(names[a], names[b]): d.model.faces(p) for p, (a, _, b, _, _) in enumerate(d.model.pairs)}
    assert faces == {("west", "middle"): True, ("west", "east"): False, ("middle", "east"): True}
    ends_by_impulses = Driver(parse_scene(row((0.005, 0.005), contact=kelvin, rules=[(("west", "east"), {"name": "impulse"})])))
    assert d.dt == ends_by_impulses.dt
    a, _, b, _, _ = d.model.pairs[d.contact_time.pair]
    assert (names[a], names[b]) in {("west", "middle"), ("middle", "east")}
