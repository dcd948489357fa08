"""Any link law as a contact law (``material``, :mod:`pounding.contact.material`): the law of the
``pounding.hysteresis`` family at every contact point, in series with a gap that carries no
tension, as OpenSees' zero-length contact element with a uniaxial material. The physics checks use
the two nearly free slabs of tests/test_contact_law_contract.py (soft undamped columns, struck at
v0 = 1 m/s), where the closed forms of two free bodies apply up to the columns' share."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from contact_plugins import Hertz
from scenes_for_tests import physical, scene
from test_contact_law_contract import DT, K_H, V0, column_share, effective_mass, free_slabs
from pounding.contact.material import MaterialContact
from pounding.errors import InputError
from pounding.framework.post.contact_forces import contact_force_history
from pounding.hysteresis.bilinear import PLASTIC

K = 1e9  # [N/m] the materials' initial stiffness


def test_an_elastic_material_is_the_undamped_kelvin_law():
    """``elastic`` (k) at each point carries lambda = share k delta, the built-in ``kelvin`` law with
    restitution 1 (its spring, no dashpot): the same contact episode, to the end-of-step solves'
    tolerance accumulated over the contact's steps (1e-9)."""
    a = free_slabs(MaterialContact, material={"name": "elastic", "stiffness": K}).run()
    b = free_slabs("kelvin", stiffness=K, restitution=1.0).run()
    assert len(a.contacts) == len(b.contacts) == 1
    ea, eb = a.contacts[0], b.contacts[0]
    for field in ("peak_force", "peak_penetration", "impulse", "end"):
        assert getattr(ea, field) == pytest.approx(getattr(eb, field), rel=1e-9), field
    # elastic: no loss but the step's, a difference of two kinetic energies; to 1e-9 of the impact's energy
    assert ea.energy_dissipated == pytest.approx(eb.energy_dissipated, abs=1e-9 * 0.5 * ea.impulse * V0)


def test_a_bilinear_material_meets_the_elastic_plastic_impact_and_keeps_its_plastic_set():
    """``bilinear`` with no hardening (k, F_y) is an elastic-perfectly-plastic spring: two free bodies
    closing at v0 = 2 F_y / sqrt(m_eff k) reach delta_max = F_y / (2 k) + m_eff v0^2 / (2 F_y), part at
    F_y / sqrt(m_eff k) and lose F_y (delta_max - F_y / k); the material keeps its plastic set
    delta_max - F_y / k (to rounding of the deepest accepted step's penetration), where it unloaded to
    no force as the surfaces parted. The run differs from the free bodies by the columns'
    impulse and by the step, first order at the force's kinks: bounded by the change when it is halved."""
    m_eff = effective_mass(free_slabs(Hertz, stiffness=K_H))
    fy = 0.5 * np.sqrt(m_eff * K) * V0
    spring = {"name": "bilinear", "stiffness": K, "yield_force": fy, "hardening": 0.0}
    runs = []
    for dt in (DT, DT / 2):
        d = free_slabs(MaterialContact, dt=dt, material=spring)
        runs.append((d, d.run()))
    (d, r), (_, fine) = runs
    assert len(r.contacts) == 1 and len(fine.contacts) == 1
    e, contact = r.contacts[0], d.laws[0]
    (key, state), = contact._state.items()  # one point pressed: the pointed slab's tip
    eps = np.finfo(float).eps
    assert state[PLASTIC] == pytest.approx(e.peak_penetration - fy / K, abs=4 * eps * e.peak_penetration)
    assert state[0] == pytest.approx(state[PLASTIC], abs=4 * eps * e.peak_penetration)  # parted at its set, unloaded

    def parting(run) -> float:  # the separation speed along the normal at the first step end after the contact
        v = physical(d.model, run.qd[int(np.searchsorted(run.t, run.contacts[0].end))])
        return float((v[(1, 0)][:2] - v[(0, 0)][:2]) @ e.normal)

    delta_max = fy / (2 * K) + m_eff * V0**2 / (2 * fy)
    v1 = fy / np.sqrt(m_eff * K)
    change = abs(e.peak_penetration - fine.contacts[0].peak_penetration) / e.peak_penetration
    change += abs(parting(r) - parting(fine)) / v1
    tol = column_share(d, e.duration, e.impulse) + change
    assert e.peak_penetration == pytest.approx(delta_max, rel=tol)
    assert parting(r) == pytest.approx(v1, rel=tol)
    assert 0.0 < e.energy_dissipated == pytest.approx(fy * (delta_max - fy / K), rel=tol)
    # the forces rebuilt after the run (a fresh law committed at every recorded step) give the peak back
    assert contact_force_history(r).pair_force.max() == pytest.approx(e.peak_force, rel=1e-9)


def test_a_dashpot_material_dissipates_and_never_pulls():
    """``viscous`` (a linear dashpot c) pushes while the slabs close and parts as they open: the
    contact only takes energy out, and its forces are never negative."""
    d = free_slabs(MaterialContact, material={"name": "viscous", "coefficient": 2.0 * np.sqrt(4e4 * K), "exponent": 1.0})
    r = d.run()
    assert r.contacts
    assert all(c.energy_dissipated > 0.0 and c.peak_force > 0.0 for c in r.contacts)
    assert sum(x["contact_forces"] for x in r.energy.values()) < 0.0
    assert contact_force_history(r).pair_force.min() >= 0.0


@pytest.mark.parametrize("material, field", [
    (None, "material"),
    ({"name": "no_such_law"}, "material.name"),
    ({"name": "bilinear", "stiffness": K}, "material"),
    ({"name": "elastic", "stiffness": -1.0}, "material.stiffness"),
])
def test_a_bad_material_is_named(material, field):
    """The material's table is checked as a [[link]]'s law, the error naming the key under ``material``."""
    with pytest.raises(InputError) as err:
        MaterialContact(material=material)
    assert err.value.field == field


def test_a_scene_names_the_material_and_its_run_is_written(tmp_path):
    """``contact = { name = "material", material = { ... } }`` in a scene: the paper's pair with a
    bilinear material at every contact point runs, its contacts are episodes that only take energy
    out, the energy account closes, and its run folder (summary.json with the law's table) is
    written and read back."""
    import json
    import tomllib

    from pounding.framework.post.energy_account import energy_balance
    from pounding.framework.post.run import run
    from pounding.io.results import load_result, write_results

    data = tomllib.loads((Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml").read_text())
    spring = {"name": "bilinear", "stiffness": 2.0e9, "yield_force": 2.0e6, "hardening": 0.02}
    data["analysis"] = {"contact": {"name": "material", "material": spring}, "duration": 6.0, "dt": 0.001}
    r = run(scene(data))
    assert r.contacts and all(c.energy_dissipated > 0.0 for c in r.contacts)
    eb = energy_balance(r)
    assert eb["ok"] and not eb["sign_violations"] and eb["contact_force_work"] < 0.0
    folder = write_results(r, tmp_path / "run")
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["contact"]["name"] == "material" and summary["contact"]["material"] == spring
    assert len(load_result(folder)[1].contacts) == len(r.contacts)


def test_the_solve_is_one_function_compiled_or_not():
    """The forces of three points pressed together (a symmetric positive definite compliance) by the
    compiled solve and by the same function with the compiler off agree to rounding (a few eps of
    the largest force: the same arithmetic, the linear solves by LAPACK both); each point's force is
    its share of the material's at its end deformation (the residual the solve drives to zero)."""
    from pounding.compiler import interpreted
    from pounding.contact.material import material_forces

    law = MaterialContact(material={"name": "bilinear", "stiffness": K, "yield_force": 2e6, "hardening": 0.05})
    m = 3
    rng = np.random.default_rng(7)
    R = rng.normal(size=(m, m)) * 1e-9
    S_q = R @ R.T + np.eye(m) * 2e-9  # [m/N]
    u0 = np.array([4e-3, 2.5e-3, 1e-3])  # [m]
    share = np.array([0.5, 0.5, 1.0])
    state = np.zeros((m, law.material.n_state))
    params = np.ascontiguousarray(np.broadcast_to(law.values, (m, len(law.values))))
    args = (law._laws, u0, share, S_q, 0.01, state, params)
    lam, settled = material_forces(*args)
    with interpreted():
        lam_py, settled_py = material_forces(*args)
    assert settled and settled_py
    assert np.max(np.abs(lam - lam_py)) <= 8 * np.finfo(float).eps * lam.max()
    u = u0 - S_q @ lam
    new = np.empty_like(state)
    r = np.array([law.material.update(u[i], u[i] / 0.01, state, params, new, i)[0] for i in range(m)])
    assert lam == pytest.approx(share * np.maximum(r, 0.0), rel=1e-11)


def test_a_bumper_refuses_a_law_with_a_state_of_its_own():
    """A bumper sums its layer's and its slabs' forces, which no commit could split: a law that keeps
    a state of its own (``keeps_state``) is refused as either, naming it."""
    from pounding.contact.bumper import BumperLaw
    from pounding.contact.kelvin import Kelvin

    crushing = MaterialContact(material={"name": "bilinear", "stiffness": K, "yield_force": 2e6, "hardening": 0.0})
    with pytest.raises(ValueError, match="material"):
        BumperLaw(layer=crushing, slabs=Kelvin(), thickness=0.05, compressible=0.5)
    with pytest.raises(ValueError, match="material"):
        BumperLaw(layer=Kelvin(), slabs=crushing, thickness=0.05, compressible=0.5)


def test_the_end_of_a_face_is_one_point_whichever_slab_presses_it():
    """Two boxes whose facing facades end in line: a face end is a vertex of the one or of the other
    slab depending on the sign of their sliding along the face, and the contact names it the same
    either way (the first slab's vertex), so a law's state at that end follows it."""
    from scenes_for_tests import box_building, modal_from_physical
    from pounding.framework.engine.stacked_model import Model

    data = {"building": [box_building("A", 0.0, 10.0, 10.0, 1, 0.5, 0.5), box_building("B", 10.0, 10.0, 10.0, 1, 0.5, 0.5)],
            "analysis": {"contact": {"name": "kelvin"}}}
    model = Model(scene(data))
    names = []
    for slide in (1e-6, -1e-6):  # B slides along the face by +-1 um and presses 0.1 mm into A
        q = modal_from_physical(model, {(1, 0): (-1e-4, slide, 0.0)})
        pts = model.touching_shares(q, model.all_pairs, 1e-3, named=True)
        names.append(sorted(map(tuple, pts.point[pts.gap < 0].tolist())))
    assert len(names[0]) == 2 and names[0] == names[1]


def test_laws_that_share_a_step_commit_the_gaps_their_forces_were_solved_at():
    """Points of two laws pressed in one step are coupled through the compliance: each law solves its
    points with the other's forces as known loads, and commits them as it saw them then, its end gaps
    gap + S_q @ forces of the whole step (the contract's end gaps)."""
    from pounding.contact.base import ContactLaw, ContactState
    from pounding.framework.engine.contact_laws import commit_laws

    class Recorder(ContactLaw):
        kind = "force"

        def forces(self, contact):
            return np.zeros(len(contact.gap))

        def commit(self, contact, forces):
            self.seen = contact.gap + contact.S_q @ forces

    laws = [Recorder(), Recorder()]
    S_q = np.array([[2.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 1.5]]) * 1e-9
    gap = np.array([-1e-3, -2e-3, -5e-4])
    lam = np.array([3e5, 4e5, 1e5])
    m = 3
    state = ContactState(0.01, 0.01, gap, np.zeros(m), S_q, np.zeros((m, m)), np.eye(m), np.array([0, 0, 1]), np.zeros(m),
                         np.zeros(m), np.full(m, np.inf), np.ones(m), np.array([[0, 0, 1], [0, 0, 2], [1, 1, 0]]))
    pressing = commit_laws(laws, np.array([0, 1]), state, lam, set())
    end = gap + S_q @ lam
    assert pressing == {0, 1}
    assert laws[0].seen == pytest.approx(end[:2], rel=1e-14) and laws[1].seen == pytest.approx(end[2:], rel=1e-14)
    # the next accepted step with none of their points pressed commits each once more, with no point
    laws[0].seen = laws[1].seen = None
    assert commit_laws(laws, np.array([0, 1]), None, None, pressing) == set()
    assert len(laws[0].seen) == 0 and len(laws[1].seen) == 0


def test_a_linear_spring_is_one_solve_whichever_family_states_it():
    """A linear spring pushing only is the ``elastic`` link law at contact points (``material``) or the
    ``kelvin`` point law with no dashpot (restitution 1): both are solved by the one Newton iteration
    (:func:`pounding.contact.newton.solve_forces`), so three points pressed together under a coupled
    compliance get the same forces from either, to a few eps of the largest force (the same arithmetic,
    one evaluator's tangent k against the other's k + 0 / h), and each is its share of k delta at its
    end penetration (the residual the solve drives to zero)."""
    from pounding.contact.base import ContactState
    from pounding.contact.kelvin import Kelvin

    m = 3
    rng = np.random.default_rng(11)
    R = rng.normal(size=(m, m)) * 1e-9
    S_q = R @ R.T + np.eye(m) * 2e-9  # [m/N]
    gap = np.array([-4e-3, -2.5e-3, 1e-4])  # [m]: the third point opens once the others push
    share = np.array([0.5, 0.5, 1.0])
    state = ContactState(0.01, 0.01, gap, np.zeros(m), S_q, S_q / 0.01, np.eye(m) * 1e-5, np.array([0, 0, 1]), np.zeros(m),
                         np.full(m, 0.3), np.full(m, np.inf), share, np.array([[0, 0, 1], [0, 0, 2], [1, 1, 0]]))
    spring = MaterialContact(material={"name": "elastic", "stiffness": K}).forces(state)
    point = Kelvin(stiffness=K, restitution=1.0).forces(state)
    assert np.max(np.abs(spring - point)) <= 8 * np.finfo(float).eps * spring.max()
    delta = -(gap + S_q @ spring)
    assert spring[2] == 0.0 and delta[2] < 0.0
    assert spring[:2] == pytest.approx(share[:2] * K * delta[:2], rel=1e-11)
