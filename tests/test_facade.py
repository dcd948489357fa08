"""Slabs that strike a neighbour between its floors (unequal storey heights).

The struck facade moves with the Hermite shape of its storey between the floors
(:mod:`pounding.framework.model.facade`); the same shape carries the impulse back to the floors.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.elements.base import point_compliance
from pounding.framework.model.facade import end_shears, hermite

from scenes_for_tests import box_building, modal_from_physical, physical, scene


def _stepped_pair(restitution: float = 0.5, contact: dict | None = None) -> dict:
    """"left" [0, 10] x [0, 10]: floors at 3.2 and 4.8 m (storeys 3.2, 1.6); "right" [10, 22] x
    [0, 10], touching it: floors at 3.2 and 6.4 m. Left's second slab (4.8 m) meets right's second
    storey at mid-height (eta = 1/2); their first slabs share the level 3.2 m; right's roof is
    above left's. Both symmetric about y = 5."""
    left = box_building("left", 0.0, 10.0, 10.0, 2, 0.4)
    left["storey_heights"] = [3.2, 1.6]
    right = box_building("right", 10.0, 12.0, 10.0, 2, 0.45)
    return {
        "building": [left, right],
        "ground_motion": {"record": "elcentro", "pga": 0.3},
        "analysis": {"integrator": "newmark", "dt": 0.005, "duration": 2.0,
                     "contact": contact or {"name": "impulse", "restitution": restitution}},
    }


def test_the_storey_shape_is_the_fixed_fixed_member_hermite_shape():
    """N2(eta) = 3 eta^2 - 2 eta^3 is the deflection of a fixed-fixed prismatic member whose top
    end moves by 1 with no end rotation (the shear building's columns between rigid floors):
    N2(0) = 0, N2(1) = 1, N2'(0) = N2'(1) = 0, N1 + N2 = 1, and N2(1/2) = 1/2."""
    for eta in (0.0, 0.25, 0.5, 0.8, 1.0):
        n1, n2 = hermite(eta)
        assert n1 + n2 == pytest.approx(1.0, abs=1e-15)
    assert hermite(0.0) == (1.0, 0.0) and hermite(1.0) == (0.0, 1.0) and hermite(0.5)[1] == 0.5
    h = 1e-6  # slope at the ends by central differences about them: O(h^2) = 1e-12 error on a unit-size slope
    for end in (0.0, 1.0):
        assert abs((hermite(end + h)[1] - hermite(end - h)[1]) / (2 * h)) <= 1e-9


def test_model_finds_the_facade_pair():
    """Left's slab at 4.8 m lies between right's floors at 3.2 and 6.4 m: one facade pair, storey
    index 1 (the second storey), eta = 1/2; the first slabs share a level (an ordinary pair);
    right's slabs are at or above left's roof's span (3.2 shared, 6.4 above): no other pair."""
    from pounding.framework.engine.stacked_model import Model

    m = Model(scene(_stepped_pair()))
    assert len(m.pairs) == 2
    (p, F), = m.facades.items()
    assert m.pairs[p][:4] == (0, 1, 1, 1)
    assert (F.building, F.storey) == (1, 1)
    assert F.height == pytest.approx(4.8, abs=1e-14) and F.eta == pytest.approx(0.5, abs=1e-14)  # 3.2 + 1.6 in binary


@pytest.mark.parametrize("compiled", [True, False], ids=["kernel", "python"])
def test_a_slab_striking_a_facade_at_mid_storey_sees_the_floors_effective_mass(compiled):
    """Left's upper slab (mass m_s, 4.8 m) moves at b = 1 m/s into right's facade at the middle
    of its second storey (eta = 1/2, N1 = N2 = 1/2); everything else is still; k = 0.5.

    The facade moves as N1 u_1 + N2 u_2 of right's floors (masses m_1, m_2): a head-on central
    impact with a = 1/m_s + N1^2/m_1 + N2^2/m_2 (the effective mass of the facade point is
    1 / (N1^2/m_1 + N2^2/m_2) = 2 m for equal floors), so the total impulse is I = (1 + k) b / a,
    the striking slab changes by -I/m_s, right's floors by +N1 I/m_1 and +N2 I/m_2. Momentum is
    kept (N1 + N2 = 1) and the kinetic energy lost is (1 - k^2) b^2 / (2 a). The pair at 3.2 m
    touches but separates (right's first floor is pushed away): no impulse there. Tolerance
    1e-12 relative: W^-1 of a 2 x 2 system built from the complete modal basis."""
    from pounding.framework.engine.driver import Driver
    from pounding.framework.engine.kernel import impulses_at
    from test_impacts import kinetic

    k, b = 0.5, 1.0
    d = Driver(scene(_stepped_pair(k)))
    m = d.model
    d.z[:, 1] = modal_from_physical(m, {(0, 1): (b, 0.0, 0.0)})
    before = d.z[:, 1].copy()
    if compiled:
        cand = np.ones(len(m.pairs), dtype=np.bool_)
        impulses_at(None, 0.0, d.ag[0], d.z, d.fc, m.modes, d.settings._replace(restitution=float(d.law.restitution)), d.dt, d.log, m.geo, cand)
        d.drain_kernel_events()
    else:
        d.contact_at(0.0)
    ms = m.systems[0].slabs[1].mass
    m1, m2 = m.systems[1].slabs[0].mass, m.systems[1].slabs[1].mass
    a = 1 / ms + 0.25 / m1 + 0.25 / m2
    I = (1 + k) * b / a
    assert {i.pair for i in d.impacts} == set(m.facades)
    assert sum(i.impulse for i in d.impacts) == pytest.approx(I, rel=1e-12)
    v = physical(m, d.z[:, 1])
    assert v[(0, 1)][0] == pytest.approx(b - I / ms, rel=1e-12)
    assert v[(1, 0)][0] == pytest.approx(0.5 * I / m1, rel=1e-12)
    assert v[(1, 1)][0] == pytest.approx(0.5 * I / m2, rel=1e-12)
    for key in v:
        assert np.allclose(v[key][1:], 0.0, atol=1e-12 * b)
    momentum = sum(s.mass * v[(bb, f)][0] for bb, sys in enumerate(m.systems) for f, s in enumerate(sys.slabs))
    assert momentum == pytest.approx(ms * b, rel=1e-12)
    lost = kinetic(m, before) - kinetic(m, d.z[:, 1])
    assert lost == pytest.approx((1 - k**2) * b**2 / (2 * a), rel=1e-12)
    assert sum(i.energy_loss for i in d.impacts) == pytest.approx(lost, rel=1e-12)


def test_impacts_csv_names_the_struck_storey_height_and_element(tmp_path):
    """A run of the stepped pair (0.02 m apart) under El Centro at 0.6 g pounds on the facade: every impacts.csv
    row names the striking and the struck building; facade rows give right's storey 2, the height
    4.8 m, a frame of right, eta 1/2, a positive local stiffness, and struck shears below and
    above that split the equivalent peak force by the fixed-fixed end reactions (1/2 each at
    mid-height), to rounding (1e-12)."""
    import csv

    from pounding.framework.post.run import run
    from pounding.io.results import write_results

    data = _stepped_pair()
    data["ground_motion"]["pga"] = 0.6
    # right moved 0.02 m away: the pair starts apart
    data["building"][1]["slab"] = [[10.02, 0], [22, 0], [22, 10], [10.02, 10]]
    for e in data["building"][1]["element"]:
        e["start"] = [max(e["start"][0], 10.02), e["start"][1]]
        if "end" in e:
            e["end"] = [max(e["end"][0], 10.02), e["end"][1]]
        e["columns"] = [0.0, float(np.hypot(e["end"][0] - e["start"][0], e["end"][1] - e["start"][1]))]
    r = run(scene(data))
    write_results(r, tmp_path / "o")
    rows = list(csv.DictReader(open(tmp_path / "o" / "impacts.csv")))
    assert rows and all(row["struck_building"] and row["striking_building"] for row in rows)
    facade_rows = [row for row in rows if row["struck_element"] != "slab"]
    assert facade_rows, "the slab at 4.8 m must strike right's facade"
    for row in facade_rows:
        assert (row["striking_building"], row["struck_building"], row["struck_storey"]) == ("left", "right", "2")
        assert float(row["struck_height [m]"]) == pytest.approx(4.8, abs=1e-12)
        assert float(row["struck_fraction"]) == pytest.approx(0.5, abs=1e-12)
        assert row["struck_element"].endswith(":frame")
        assert float(row["local_stiffness [N/m]"]) > 0
        f = float(row["peak_force [N]"])
        assert float(row["struck_shear_below [N]"]) == pytest.approx(0.5 * f, rel=1e-12)
        assert float(row["struck_shear_above [N]"]) == pytest.approx(0.5 * f, rel=1e-12)


def test_end_shears_are_the_fixed_fixed_reactions():
    """A point load P at a on a fixed-fixed member of length L: end reactions P b^2 (3a + b) / L^3
    (bottom) and P a^2 (a + 3b) / L^3 (top), summing to P (statics): a = 1, L = 4 gives 27/32 and
    5/32 exactly in binary."""
    lo, hi = end_shears(1.0, 4.0)
    assert (lo, hi) == (27 / 32, 5 / 32)


@pytest.mark.opensees
@pytest.mark.parametrize("a", [0.8, 1.6, 2.5])
def test_local_stiffness_of_a_column_matches_opensees(opensees, a):
    """A fixed-fixed column (L = 3.2 m, E = 30 GPa, 0.4 x 0.4 m) with a lateral point load at a
    from its bottom: OpenSees (two elasticBeamColumn elements meeting at the load, fixed ends,
    linear static analysis) and k = 3 E I L^3 / (a^3 b^3) agree. Euler-Bernoulli elements with
    cubic shape functions are exact for point loads at nodes, so the agreement is to the solver's
    rounding (1e-9 relative: stiffness terms ~1e9 N/m, cancellation in the 6 x 6 solve)."""
    ops = opensees
    E, bb, h, L = 30e9, 0.4, 0.4, 3.2
    A, I = bb * h, bb * h**3 / 12
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for tag, y in ((1, 0.0), (2, a), (3, L)):
        ops.node(tag, 0.0, y)
    ops.fix(1, 1, 1, 1)
    ops.fix(3, 1, 1, 1)
    ops.geomTransf("Linear", 1)
    ops.element("elasticBeamColumn", 1, 1, 2, A, E, I, 1)
    ops.element("elasticBeamColumn", 2, 2, 3, A, E, I, 1)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 1000.0, 0.0, 0.0)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.integrator("LoadControl", 1.0)
    ops.algorithm("Linear")
    ops.analysis("Static")
    assert ops.analyze(1) == 0
    k_ops = 1000.0 / ops.nodeDisp(2, 1)
    ops.wipe()
    assert 1.0 / point_compliance(E, I, L, a) == pytest.approx(k_ops, rel=1e-9)
    assert 1.0 / point_compliance(E, I, L, a) == pytest.approx(3 * E * I * L**3 / (a**3 * (L - a) ** 3), rel=1e-14)


def test_facade_penalty_with_stiff_columns_tends_to_the_plain_penalty():
    """facade_penalty puts the struck column's local stiffness in series with the slab spring:
    with columns a million times stiffer (E x 1e6) the series spring is k_p to 1e-6 relative
    and the run follows the plain penalty law's to ~1e-6 of the peak (the series spring's
    relative change, amplified at most tenfold by the contact's timing); with the real columns it
    differs (the facade is softer)."""
    from pounding.framework.post.run import run

    def peak_difference(scale: float) -> float:
        data = _stepped_pair(contact={"name": "facade_penalty", "stiffness": 1e9, "restitution": 0.5})
        data["ground_motion"]["pga"] = 0.6
        for e in data["building"][1]["element"]:
            e["column"]["E"] *= scale
            e["beam"]["E"] *= scale
        a = run(scene(data))
        data["analysis"]["contact"] = {"name": "penalty", "stiffness": 1e9, "restitution": 0.5}
        b = run(scene(data))
        return float(np.abs(a.cm("left") - b.cm("left")).max() / np.abs(b.cm("left")).max())

    assert peak_difference(1e6) <= 1e-5
    assert peak_difference(1.0) > 1e-3


def test_forces_rebuilt_after_a_facade_penalty_run_give_each_episodes_peak_force():
    """The contact forces rebuilt from the recorded states (:mod:`pounding.framework.post.contact_forces`)
    put the struck column's local stiffness in series with the slab spring at facade points, as the
    run did: every episode's peak force comes back (the pair is symmetric about y = 5 and shaken
    along x: nothing twists, so the law at a committed state's points is the equation the run solved
    at that step's end). Tolerance: the end-of-step solve's 1e-9, plus the rounding of a gap (plan
    coordinates up to 22 m, 64 eps of them) relative to the episode's peak penetration (a graze of
    1e-9 m is an episode too)."""
    from pounding.framework.post.contact_forces import contact_force_history
    from pounding.framework.post.run import run

    data = _stepped_pair(contact={"name": "facade_penalty", "stiffness": 1e9, "restitution": 0.5})
    data["ground_motion"]["pga"] = 0.6
    data["analysis"].update(duration=4.0)
    del data["analysis"]["dt"]
    r = run(scene(data))
    forces = contact_force_history(r)
    assert sum(e.pair in r.facades for e in r.contacts) >= 3
    for e in r.contacts:
        i0, i1 = int(np.floor(e.start / r.dt + 1e-9)), int(np.ceil(e.end / r.dt - 1e-9))
        rounding = 64 * np.finfo(float).eps * 22.0 / e.peak_penetration
        assert forces.pair_force[i0 : i1 + 1, e.pair].max() == pytest.approx(e.peak_force, rel=1e-9 + rounding)


def test_every_facade_impulse_of_a_run_conserves_momentum():
    """The stepped pair 0.02 m apart under El Centro at 0.6 g: left's slab at 4.8 m strikes right's
    second storey between its floors, in displaced states. Each impulse reaches right's floors
    below and above as the force at the contact point with its moment about each floor's own
    displaced centre (the facade's contact row is the floors' rows weighted by N1, N2), so the
    linear and angular momentum of all slabs (no ground share: the struck storey is not the first)
    are unchanged to 1e-12 of the size of the jumps, as for slab against slab (test_impacts)."""
    from test_impacts import RTOL, RecordingDriver, momenta

    data = _stepped_pair()
    data["ground_motion"]["pga"] = 0.6
    data["building"][1]["slab"] = [[10.02, 0], [22, 0], [22, 10], [10.02, 10]]
    for e in data["building"][1]["element"]:
        e["start"] = [max(e["start"][0], 10.02), e["start"][1]]
        e["end"] = [max(e["end"][0], 10.02), e["end"][1]]
        e["columns"] = [0.0, float(np.hypot(e["end"][0] - e["start"][0], e["end"][1] - e["start"][1]))]
    d = RecordingDriver(scene(data))
    d.run()
    facade_events = [ev for ev in d.events if any(i.pair in d.model.facades for i in ev["impacts"])]
    assert facade_events, "the slab at 4.8 m must strike the facade"
    for ev in d.events:
        assert np.abs(d.model.slab_dofs(ev["q"], 0, 1)).max() > 0, "a displaced state"
        p0, L0, _, _ = momenta(d.model, ev["q"], ev["before"])
        _, _, ps, Ls = momenta(d.model, ev["q"], ev["after"] - ev["before"])
        p1, L1, _, _ = momenta(d.model, ev["q"], ev["after"])
        assert np.all(np.abs(p1 - p0) <= RTOL * ps), ev["t"]
        assert abs(L1 - L0) <= RTOL * Ls, ev["t"]
