"""Contact laws own their behaviour: out-of-tree force laws written from the base class alone
(:mod:`contact_plugins`: Hertz, and Hertzdamp, whose force depends on the contact's approach
speed), used by class, as ``"module:Class"`` from a scene, and per pair of buildings, with
their contact episodes reported like an impulse law's impacts.

The physics checks use two slabs on columns so soft (periods of ~12 s) that during a contact
of ~0.06 s they are nearly free, struck at v0 = 1 m/s with no ground motion and no damping:
the closed forms of the Hertz impact of two free bodies apply, up to the columns' share.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from contact_plugins import ElasticPlastic, Hertz, Hertzdamp
from scenes_for_tests import box_building, contact_momentum_changes, modal_from_physical, physical, pointed_pair, pulse, scene
from pounding.framework.engine.driver import Driver
from pounding.framework.post.contact_forces import contact_force_history
from pounding.framework.post.run import run
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
TESTS = Path(__file__).resolve().parent

V0 = 1.0  # [m/s] closing speed of the struck pair
K_H = 1e9  # [N/m^1.5] Hertz stiffness
DT = 1e-4  # [s] ~560 steps per contact


def free_slabs(law, dt: float = DT, **params):
    """A Driver of the pointed pair (a tip at (10, 5) touching the left box's face, gap 0) on soft
    undamped columns, no ground motion, the left slab moving at V0 towards the right one."""
    data = pointed_pair(tip_y=5.0)
    for b in data["building"]:
        b["damping"] = {"type": "modal", "ratio": 0.0}
        for el in b["element"]:
            el["column"] = {**el["column"], "b": 0.05, "h": 0.05}
    data["analysis"] = {"integrator": "newmark", "dt": dt, "duration": 0.08, "contact": "penalty"}
    sc = scene(data).with_ground_motion(pulse(0.2, 0.0)).with_analysis(contact=law, contact_params=params)
    d = Driver(sc)
    d.z[:, 1] = modal_from_physical(d.model, {(0, 0): (V0, 0.0, 0.0)})
    return d


def effective_mass(d) -> float:
    """1/a of the contact point at rest [kg]: the two slabs' mass seen along the normal (eq. 12's a)."""
    W = d.model.touching(np.zeros(d.model.n), d.model.all_pairs, 1e-3, deep=True).W
    return 1.0 / float(W[0] @ W[0])


def column_share(d, duration: float, impulse: float) -> float:
    """Bound on the columns' impulse over a contact of ``duration`` [s], relative to ``impulse``
    [N s]: each slab moves at most V0 t, so its columns push at most k V0 t; over the contact
    that is k V0 duration^2 / 2 per slab."""
    k = sum(s.K[0, 0] for s in d.model.systems)
    return k * V0 * duration**2 / 2.0 / impulse


def test_hertz_impact_of_two_free_slabs_meets_the_closed_forms():
    """An elastic Hertz contact F = k_h delta^1.5 between two free bodies closing at v0:
    peak penetration delta_max = (5 m_eff v0^2 / (4 k_h))^(2/5), duration 2.943 delta_max / v0,
    impulse 2 m_eff v0 (rebound at v0), no energy dissipated.

    The run differs from the free bodies by the columns' impulse (bounded by
    :func:`column_share`, ~1e-3 here) and by the step: Newmark's average acceleration is
    second order, (dt / duration)^2 ~ 3e-6; the tolerance is the columns' share plus that."""
    d = free_slabs(Hertz, stiffness=K_H)
    r = d.run()
    assert len(r.contacts) == 1 and r.n_impacts == 1 and not r.impacts
    e = r.contacts[0]
    m_eff = effective_mass(d)
    delta = (5.0 * m_eff * V0**2 / (4.0 * K_H)) ** 0.4
    duration = 2.943 * delta / V0
    tol = column_share(d, duration, 2.0 * m_eff * V0) + (DT / duration) ** 2
    assert e.approach_velocity == pytest.approx(V0, rel=1e-12)
    assert e.peak_penetration == pytest.approx(delta, rel=tol)
    # the closed form's coefficient is given to 4 digits (2.9432...): 2e-4 more
    assert e.duration == pytest.approx(duration, rel=tol + 2e-4)
    assert e.impulse == pytest.approx(2.0 * m_eff * V0, rel=tol)
    assert e.peak_force == pytest.approx(K_H * e.peak_penetration**1.5, rel=1e-12)  # the law at the deepest step end
    assert abs(e.energy_dissipated) <= (DT / duration) ** 2 * 0.5 * m_eff * V0**2


def test_the_episode_impulse_is_the_momentum_change_and_momentum_is_conserved():
    """Across the episode the contact's equal and opposite forces change the two slabs' x momentum
    by -I and +I (the episode's impulse, along the normal (1, 0) to the slabs' rotation ~1e-7) and
    the total only by the columns' impulse. Newmark's velocity update is the trapezoidal rule of the
    forces, and so are the episode's impulse and the columns' impulse taken on the step ends here:
    the balances hold to rounding of the sums (1e-9 of the impulse covers 1e4 steps of 1e-16 and the
    normal's tilt)."""
    d = free_slabs(Hertz, stiffness=K_H)
    r = d.run()
    e = r.contacts[0]
    change = contact_momentum_changes(d.model, r)
    assert change[0] == pytest.approx(-e.impulse, rel=1e-9)
    assert change[1] == pytest.approx(e.impulse, rel=1e-9)
    assert abs(change[0] + change[1]) <= 1e-9 * e.impulse


def test_a_history_dependent_law_gets_the_approach_speed_and_dissipates_what_the_rebound_loses():
    """Hertzdamp, F = k_h delta^1.5 (1 + xi delta'/delta'_0), needs the closing speed at the start of
    the contact: the driver gives it (v0) at every step of the episode. The energy the episode
    reports dissipated is the relative kinetic energy lost, m_eff (v0^2 - v1^2) / 2 with v1 the
    separation speed, to the columns' share and the step's second-order error; and it is > 0 (a
    passive contact)."""
    d = free_slabs(Hertzdamp, stiffness=K_H, restitution=0.8)
    r = d.run()
    assert len(r.contacts) == 1
    e = r.contacts[0]
    seen = d.laws[0]._approaches
    assert len(seen) == 1 and seen.pop() == pytest.approx(V0, rel=1e-12)
    v = physical(d.model, r.qd[-1])
    n = e.normal
    v1 = (v[(1, 0)][:2] - v[(0, 0)][:2]) @ n  # separation speed along the normal (rotation-free at the tip)
    m_eff = effective_mass(d)
    lost = 0.5 * m_eff * (V0**2 - v1**2)
    tol = column_share(d, e.duration, e.impulse) + (DT / e.duration) ** 2
    assert 0.0 < e.energy_dissipated == pytest.approx(lost, rel=tol)
    # exactly: undamped, unforced, the kinetic energy at the start is what the buildings hold at the end
    # plus what the contact took (average acceleration conserves the energy of the linear part, and the
    # episode books the energy account's rule: rounding of ~1e4 steps)
    e0 = 0.5 * float(np.sum(r.qd[0] ** 2))
    held = sum(x["kinetic"] + x["strain"] for x in r.energy.values())
    assert e.energy_dissipated == pytest.approx(e0 - held, rel=1e-9)
    # the contact work the energy account booked is the episode's, to the rule's rounding
    work = sum(x["contact_forces"] for x in r.energy.values())
    assert -work == pytest.approx(e.energy_dissipated, rel=1e-9)


def test_a_law_with_a_state_of_its_own_commits_its_plastic_set_with_the_accepted_steps():
    """ElasticPlastic (contact_plugins) is an elastic-perfectly-plastic spring k, F_y whose plastic set
    delta_p it keeps point by point and moves only when the engine commits a step
    (:meth:`ContactLaw.commit`). Two free bodies closing at v0 with v0 sqrt(m_eff k) = 2 F_y: the spring
    yields, the relative motion stops at delta_max = F_y / (2 k) + m_eff v0^2 / (2 F_y), the point unloads
    along k to delta_p = delta_max - F_y / k, and the bodies part at v1 = F_y / sqrt(m_eff k) (the elastic
    energy F_y^2 / (2 k) given back), the contact having dissipated F_y delta_p.

    The committed plastic set is the episode's peak penetration less F_y / k to rounding: the engine
    committed the end states of the steps it accepted, the deepest among them. The run differs from the
    free bodies by the columns' impulse (:func:`column_share`) and by the step: the force's kinks (yield,
    unloading) leave the step's error first order, bounded by its change when the step is halved."""
    m_eff = effective_mass(free_slabs(Hertz, stiffness=K_H))
    k = 1e9
    fy = 0.5 * np.sqrt(m_eff * k) * V0
    runs = []
    for dt in (DT, DT / 2):
        d = free_slabs(ElasticPlastic, dt=dt, stiffness=k, yield_force=fy)
        runs.append((d, d.run()))
    (d, r), (_, fine) = runs
    assert len(r.contacts) == 1 and len(fine.contacts) == 1
    e, law = r.contacts[0], d.laws[0]
    assert len(law._plastic) == 1  # one point pressed, the pointed slab's tip
    delta_p = law._plastic.popitem()[1]
    assert delta_p == pytest.approx(e.peak_penetration - fy / k, abs=4 * np.finfo(float).eps * e.peak_penetration)
    assert law._commits >= 2

    delta_max = fy / (2 * k) + m_eff * V0**2 / (2 * fy)
    v1_exact = fy / np.sqrt(m_eff * k)

    def parting(run) -> float:  # the separation speed along the normal at the first step end after the contact
        v = physical(d.model, run.qd[int(np.searchsorted(run.t, run.contacts[0].end))])
        return float((v[(1, 0)][:2] - v[(0, 0)][:2]) @ e.normal)

    v1 = parting(r)
    change = abs(e.peak_penetration - fine.contacts[0].peak_penetration) / e.peak_penetration
    change += abs(v1 - parting(fine)) / v1_exact
    tol = column_share(d, e.duration, e.impulse) + change
    assert e.peak_penetration == pytest.approx(delta_max, rel=tol)
    assert v1 == pytest.approx(v1_exact, rel=tol)
    assert 0.0 < e.energy_dissipated == pytest.approx(fy * (delta_max - fy / k), rel=tol)
    # the forces rebuilt after the run (a fresh law committed at every recorded step in turn) follow the
    # same plastic set: the episode's peak force comes back, to the solves' tolerance (as for every law)
    assert contact_force_history(r).pair_force.max() == pytest.approx(e.peak_force, rel=1e-9)


def test_the_trials_of_a_step_are_not_committed():
    """With yielding storeys the engine solves a step's links and contact forces together by a fixed
    point that asks the law for forces at every pass (trials), then commits the step once: the law
    commits once per accepted step with points pressed, is asked more often than that, and what it
    committed is the accepted states', its plastic set at each pair the deepest accepted penetration
    less F_y / k (to rounding)."""
    k, fy = 1e9, 5e5
    sc = load_scene(ROOT / "examples" / "inelastic_pair" / "pair_yielding_gap_0.03.toml").with_analysis(
        contact=ElasticPlastic, contact_params={"stiffness": k, "yield_force": fy}, duration=8.0)
    d = Driver(sc)
    accepted = []  # the steps the driver accepts with points pressed
    accept = d.commit

    def counted(st, t, h):
        if st.contacts is not None and st.contacts.state is not None and len(st.contacts.state.gap):
            accepted.append(t)
        return accept(st, t, h)

    d.commit = counted
    r = d.run()
    law = d.laws[0]
    assert r.contacts and law._trials > law._commits == len(accepted) > 0
    for p in {e.pair for e in r.contacts}:
        peak = max(e.peak_penetration for e in r.contacts if e.pair == p)
        assert peak > fy / k  # (it yielded)
        delta_p = max(v for key, v in law._plastic.items() if key[0] == p)
        assert delta_p == pytest.approx(peak - fy / k, abs=4 * np.finfo(float).eps * peak)


# --------------------------------------------------------------------------- three buildings, a law per pair
def row_of_three(gap: float = 0.01) -> dict:
    """Buildings A, B, C in a row along x (B the softest), gaps ``gap``, shaken along x for 3 s."""
    return {
        "building": [box_building("A", 0.0, 10.0, 10.0, 1, 0.55, 0.55),
                     box_building("B", 10.0 + gap, 10.0, 10.0, 1, 0.30, 0.30),
                     box_building("C", 20.0 + 2 * gap, 10.0, 10.0, 1, 0.50, 0.50)],
        "ground_motion": {"record": "elcentro", "pga": 0.5},
        "analysis": {"integrator": "newmark", "dt": 0.001, "duration": 3.0,
                     "contact": {"name": "penalty", "stiffness": 2e9, "restitution": 1.0}},
    }


def test_a_law_per_pair_of_buildings():
    """[[contact]] gives the pairs of A and B the Hertz law ("contact_plugins:Hertz"); B and C keep
    [analysis] contact, an undamped linear spring. Each pair's episodes follow its own law: at
    every step end the force is the law's of the penetration, so the peak force of a face-to-face
    contact (two corners, pressed equally: the buildings are symmetric about y = 5) is
    2 k_h delta_max^1.5 for A-B and 2 k_p delta_max for B-C, to rounding."""
    data = row_of_three()
    data["contact"] = [{"between": ["B", "A"], "law": {"name": "contact_plugins:Hertz", "stiffness": K_H}}]
    sc = scene(data)
    r = run(sc)
    names = {frozenset((r.names[a], r.names[b])): p for p, (a, _, b, _, _) in enumerate(r.pairs)}
    ab, bc = names[frozenset("AB")], names[frozenset("BC")]
    by_pair = {p: [e for e in r.contacts if e.pair == p] for p in (ab, bc)}
    assert by_pair[ab] and by_pair[bc], "both pairs must pound for the test to check anything"
    for e in by_pair[ab]:
        assert e.peak_force == pytest.approx(2 * K_H * e.peak_penetration**1.5, rel=1e-9)
    for e in by_pair[bc]:
        assert e.peak_force == pytest.approx(2 * 2e9 * e.peak_penetration, rel=1e-9)
    assert r.contact["between"] == [{"between": ["B", "A"], **Hertz(stiffness=K_H).describe()}]


def test_a_law_named_module_class_from_a_scene_file_beside_it(tmp_path):
    """A scene names its law "beside_laws:Hertzdamp", a module next to the scene file (not on the
    Python path, not installed): the run loads it, and `pounding run` reports its contacts in
    contacts.csv, summary.json and the printed summary, one row per episode with the same columns
    an impulse run writes; the impulse run of the same scene writes its impacts there too."""
    (tmp_path / "beside_laws.py").write_text((TESTS / "contact_plugins.py").read_text())
    data = (ROOT / "examples" / "paper" / "pair_gap_0.03.toml").read_text()
    text = data.replace('contact = "impulse"', 'contact = { name = "beside_laws:Hertzdamp", stiffness = 2e10, restitution = 0.7 }\nduration = 6.0', 1)
    text = text.replace('integrator = { name = "hht", alpha = -0.05 }', 'integrator = "newmark"', 1)
    assert "beside_laws" in text and '"newmark"' in text
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(tmp_path / "scene.toml"), "--out", str(out)],
                          capture_output=True, text=True, cwd=tmp_path.parent)
    assert proc.returncode == 0, proc.stderr
    summ = json.loads((out / "summary.json").read_text())
    rows = list(csv.DictReader(open(out / "contacts.csv")))
    assert summ["contact"]["name"] == "hertzdamp"
    assert summ["n_contacts"] == summ["contacts"]["n"] == len(rows) > 0
    assert "contacts by forces" in proc.stdout and "no impacts" not in proc.stdout
    assert {r["law"] for r in rows} == {"hertzdamp"}
    # the episodes' dissipation is the energy account's contact work (one rule: average acceleration's)
    dissipated = sum(float(r["energy_dissipated [J]"]) for r in rows)
    assert dissipated > 0.0
    assert -summ["energy_balance"]["contact_force_work"] == pytest.approx(dissipated, rel=1e-9)
    for r in rows:
        assert float(r["end [s]"]) > float(r["start [s]"])
        assert float(r["peak_force [N]"]) > 0.0 and float(r["impulse [N s]"]) > 0.0


def test_an_impulse_run_reports_its_impacts_as_episodes_of_no_duration(tmp_path):
    """contacts.csv of an impulse run: one row per impact with the same columns, end = start, no
    penetration, the impulse and energy lost of impacts.csv: a penalty and an impulse run compare
    on one table."""
    from pounding.io.results import CONTACT_COLUMNS, contact_rows
    from pounding.io.scene import load_scene

    r = run(load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=6.0))
    rows = contact_rows(r)
    assert len(rows) == len(r.impacts) > 0 and len(rows[0]) == len(CONTACT_COLUMNS)
    col = {c: i for i, c in enumerate(CONTACT_COLUMNS)}
    assert all(row[col["end [s]"]] == row[col["start [s]"]] and row[col["peak_penetration [m]"]] == 0.0 for row in rows)
    assert sum(row[col["impulse [N s]"]] for row in rows) == pytest.approx(sum(i.impulse for i in r.impacts), rel=1e-12)
    assert sum(row[col["energy_dissipated [J]"]] for row in rows) == pytest.approx(sum(i.energy_loss for i in r.impacts), rel=1e-12)
    # one peak force for the same impacts: summary.json's is the largest of contacts.csv's (each impact's equivalent force)
    from pounding.io.results import contacts_summary

    assert contacts_summary(r)["peak_force"] == max(row[col["peak_force [N]"]] for row in rows) > 0.0


def test_penalty_and_facade_penalty_run_through_the_contract():
    """The built-in force laws take the same ContactState as a plugin (no second path): on a pair that
    meets only slab to slab, facade_penalty's springs are penalty's (the struck element's local
    stiffness is inf at a slab), so the two runs agree to the rounding of the dashpot matrices'
    two formulas (1e-12 of the peak)."""
    from pounding.io.scene import load_scene

    base = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=4.0)
    a = run(base.with_analysis(contact="penalty", contact_params={"stiffness": 1e9}))
    b = run(base.with_analysis(contact="facade_penalty", contact_params={"stiffness": 1e9}))
    assert a.contacts and len(a.contacts) == len(b.contacts)
    assert np.abs(a.q - b.q).max() <= 1e-12 * np.abs(a.q).max()


def test_laws_on_pairs_that_share_a_building_are_solved_together():
    """Two undamped linear springs (penalty with restitution 1: no dashpot), k_1 on the points of one
    pair and k_2 on those of another that shares a building (compliances coupled through S_q): the
    forces of :func:`~pounding.framework.engine.contact_laws.solve_forces` are the coupled linear system's,
    (I + K S_q) lambda = -K gap with K = diag(k).

    Tolerance: solve_forces sweeps the laws in turn (block Gauss-Seidel, iteration matrix
    G = -(D + L)^-1 U of A = I + K S_q split by law) and stops when a sweep changes no force by more
    than COUPLING_RTOL max |lambda|; with g = ||G||_inf < 1 the error left is at most g / (1 - g) times
    that change. Each side also carries its solves' rounding, solve_rel(A) (tests/rounding.py). Here
    g = 0.024: the bound is 4.7e-14 of the largest force (measured 1.2e-16)."""
    from pounding.contact.base import ContactState
    from pounding.contact.penalty import Penalty
    from pounding.framework.engine.contact_laws import COUPLING_RTOL, solve_forces
    from rounding import solve_rel

    rng = np.random.default_rng(7)
    Wr = rng.normal(size=(3, 6)) * 1e-3  # rows of three points over six modes [1/sqrt(kg)]
    S_q = (Wr * 1e-5) @ Wr.T  # a step's displacement compliance B01 = 1e-5 s^2 per mode
    gap = np.array([-1e-3, -2e-3, -1.5e-3])
    k = np.array([1e9, 1e9, 3e8])
    state = ContactState(0.01, 0.01, gap, np.zeros(3), S_q, np.zeros((3, 3)), Wr @ Wr.T, np.array([0, 0, 1]),
                         np.zeros(3), np.ones(3), np.full(3, np.inf))
    laws = [Penalty(stiffness=1e9, restitution=1.0), Penalty(stiffness=3e8, restitution=1.0)]
    lam = solve_forces(laws, np.array([0, 0, 1]), state)
    A = np.eye(3) + k[:, None] * S_q
    ref = np.linalg.solve(A, -k * gap)
    assert np.all(ref > 0), "every point pushes: the linear system is the whole answer"
    lower = np.tril(A)
    lower[0, 1] = A[0, 1]  # the first law's 2 x 2 diagonal block is solved whole
    G = -np.linalg.solve(lower, A - lower)
    g = float(np.abs(G).sum(axis=1).max())
    assert g < 1.0, "the sweeps contract in the infinity norm: the bound below holds"
    sweeps = g / (1.0 - g) * COUPLING_RTOL * np.abs(lam).max()
    assert np.abs(lam - ref).max() <= sweeps + 2.0 * solve_rel(A) * np.abs(ref).max()


def test_a_force_law_with_the_old_positional_signature_is_refused_when_registered():
    """forces() takes one ContactState: a law written against positional arguments is refused when
    it is looked up, saying what the contract expects, not in the middle of a run."""
    from typing import ClassVar

    from pounding.contact.base import ContactLaw
    from pounding.errors import InputError
    from pounding.framework.model.registry import CONTACT_LAWS

    class Old(ContactLaw):
        name: ClassVar[str] = "old"
        kind: ClassVar[str] = "force"

        def forces(self, gap, rate, S_q, S_v, W):
            return np.zeros(len(gap))

    with pytest.raises(InputError, match=r"forces\(\) takes one ContactState"):
        CONTACT_LAWS.get(Old)


def test_an_impulse_law_only_python_knows_strikes_as_the_built_in_law():
    """The one impulse step serves a law that does not declare compiled impulses: it runs with the
    compiler off around the law's own ``impulses(W, b)``. A Newton law written from the base class
    alone (contact_plugins.NewtonInPython, e = 0.5) gives the built-in impulse law's impacts on the
    first 3 s of the paper pair: the same pairs, strikers and vertices, at the same instants and
    with the same impulses and histories to rounding (1e-12 of the peaks: the two paths form the
    Delassus products with numpy and with numba, 1e-16 relative, over some 20 events)."""
    from contact_plugins import NewtonInPython
    from pounding.io.scene import load_scene

    base = load_scene(str(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")).with_analysis(duration=3.0)
    a = run(base.with_analysis(contact="impulse", contact_params={"restitution": 0.5}))
    b = run(base.with_analysis(contact=NewtonInPython, contact_params={"restitution": 0.5}))
    assert a.n_impacts == b.n_impacts > 0
    peak = max(i.impulse for i in a.impacts)
    for x, y in zip(a.impacts, b.impacts):
        assert (x.pair, x.striker, x.vertex) == (y.pair, y.striker, y.vertex)
        assert abs(x.time - y.time) <= 1e-12 * max(1.0, x.time)
        assert abs(x.impulse - y.impulse) <= 1e-12 * peak
    assert np.abs(a.q - b.q).max() <= 1e-12 * np.abs(a.q).max()
