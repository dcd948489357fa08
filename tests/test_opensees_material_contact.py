"""The ``material`` contact law against its link law's OpenSees gap material, on two free bodies that collide.

The problem and the OpenSees model are tests/test_opensees_contact_laws.py's: body 1 (1e5 kg) at
V0 = 0.5 m/s strikes body 2 (2e5 kg) at rest (m_eff = 6.67e4 kg); in OpenSees (openseespy 3.7.1)
two nodes of a 1-D model joined by a ``zeroLength`` element with the material, Newmark's average
acceleration, Newton, a constant step h; the material takes the gap as the negative deformation
-GAP = -1e-12 m. The material is the law's own (:meth:`MaterialContact.opensees_material`, one
whole contact: share 1):

- ``elastic`` (k): ``ElasticPPGap k -1e30 gap 0 noDamage``, k delta where delta > 0;
- ``bilinear`` (k0, Fy, b): ``ElasticPPGap k0 -Fy gap b damage``: elastic from its gap to the line
  Fy + b k0 (delta - Fy / k0), and on commit past it the gap moves to where the force unloads to zero,
  the plastic set, kept while apart (``damage``). Steel01's kinematic rule gives the same law until
  its lower bound pushes, past a penetration of (1 + 1/b) Fy / k0 = 51 mm here, far beyond the
  collisions' 8 mm at most.

pounding: the same bodies stepped by the same Newmark scheme with the law's end-of-step solve and
its commit at every accepted step (:func:`two_bodies.step_two_bodies`), started GAP apart so that
contact begins where OpenSees' does. A second collision replays the first (both bodies back at zero
displacement, body 1 at V0, body 2 at rest) with the state the first left: in OpenSees the
material's committed state, in pounding the law instance's.

The tolerance. Both codes then solve the same discrete equations: each step's end displacement is
the root of the same Newmark step with the same piecewise-linear law at its end. They differ only
where each stops its Newton iteration and by rounding. OpenSees stops when the last correction is
below TAU [m] (``NormDispIncr``), so its end displacement is within TAU of the root (a correction
from the root's branch of a piecewise-linear law lands on it); pounding's stops at a force residual
of 1e-12 of the largest force, a displacement S_q 1e-12 F below 1e-18 m (inside TAU); rounding adds
eps |u| to each, |u| <= V0 N h (neither body moves faster than V0). So each step's end displacement
agrees within eps_step = TAU + 2 eps V0 N h. An end displacement off by e changes that step's
velocity by 2 e / h (Newmark's average acceleration), which the trapezoidal rule carries on without
growth (it keeps a perturbation's energy at a fixed tangent); after N steps the velocities agree
within 2 N eps_step / h and the displacements within 2 N^2 eps_step (that velocity error acting for
the whole run, N h). Hence the bounds, N the steps since the first collision began: rebound
2 N eps_step / (h V0), peak force 2 k0 N^2 eps_step (a force whose slope is at most k0), plastic set
2 N^2 eps_step. With TAU = 1e-16 m and 200 steps a contact they are, relative, 0.9e-9 to 1.7e-8
(rebound), 2.9e-9 to 3.3e-7 (peak force) and 1.6e-8 to 5.6e-8 (set). Measured: all three agree to
2.5e-14 (rounding) in both collisions, elastic and bilinear alike, and the same with TAU = 1e-14 or
1e-18 m: the Newton iterations land on the same roots. So the comparison checks the material, not
the time step: the bound of tests/test_opensees_contact_laws.py from halving h (here 7e-6 to 1.5e-5
in the rebound at 400 -> 800 steps a contact) would let pass a material that differs by 1e-5. For
scale: ``ElasticPPGap`` with eta 0.0201 for 0.02 differs by 1e-4 to 2e-4 in the rebound and 3e-4 to
6e-4 in the peak force, and with ``noDamage`` (the set forgotten as the surfaces part) by 2e-2 in the
rebound and 6e-2 in the peak force of the second collision.

The plastic set is read the same way from both histories: delta - F / k0 at the last step that
pushes, on the elastic unloading branch (delta the penetration past the gap, F the force).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from pounding.contact.material import MaterialContact
from pounding.contact.newton import NEWTON_RTOL
from test_opensees_contact_laws import GAP, M1, M2, M_EFF, V0, newmark_analysis, two_body_model
from two_bodies import step_two_bodies

TAU = 1e-16  # [m] OpenSees' NormDispIncr tolerance here (it converges down to 1e-18 m: its increments round below that)
STEPS = 200  # steps per elastic contact duration pi sqrt(m_eff / k0)
K0 = 2e9  # [N/m]
BILINEAR = {"name": "bilinear", "stiffness": K0, "yield_force": 2e6, "hardening": 0.02}  # yields: elastic peak 5.8e6 N
ELASTIC = {"name": "elastic", "stiffness": K0}
EPS = np.finfo(float).eps
ROOT = Path(__file__).resolve().parents[1]


@dataclass
class Collision:
    """One collision: rebound [-] (separation over approach speed at its end), and at every step end
    the penetration past the gap delta (n,) [m] and the contact force (n,) [N]."""

    rebound: float
    delta: np.ndarray
    force: np.ndarray

    @property
    def peak(self) -> float:
        """The largest force at a step's end [N]."""
        return float(self.force.max())

    def plastic_set(self) -> float:
        """delta - F / k0 [m] at the last step that pushes (on the elastic unloading branch): the
        deformation at which the material carries no force as the bodies part."""
        last = np.flatnonzero(self.force > 0.0)[-1]
        return float(self.delta[last] - self.force[last] / K0)


def opensees_collisions(ops, mat: tuple, h: float, n: int) -> list[Collision]:
    """``n`` collisions of the two bodies in OpenSees with the material ``mat`` (uniaxialMaterial arguments
    after the tag), each from zero displacements with body 1 at V0 and body 2 at rest, stepped by h [s]
    until the bodies are apart again; the material keeps its state from one to the next."""
    two_body_model(ops, (mat[0], 1, *mat[1:]))
    out = []
    for _ in range(n):
        for node, v in ((1, V0), (2, 0.0)):
            ops.setNodeDisp(node, 1, 0.0, "-commit")
            ops.setNodeVel(node, 1, v, "-commit")
            ops.setNodeAccel(node, 1, 0.0, "-commit")
        ops.wipeAnalysis()  # a new analysis reads the nodes' state; the element keeps its material's
        newmark_analysis(ops, TAU)
        delta, force, touched = [], [], False
        while True:
            assert ops.analyze(1, h) == 0
            delta.append(ops.nodeDisp(1, 1) - ops.nodeDisp(2, 1) - GAP)
            force.append(-ops.eleForce(1)[1])  # minus node 2's resisting force: the push on it, along +x
            touched = touched or delta[-1] > 0.0
            if touched and delta[-1] < 0.0 and force[-1] == 0.0:  # apart again (step_two_bodies' end)
                break
            assert len(delta) < 100 * STEPS
        out.append(Collision((ops.nodeVel(2, 1) - ops.nodeVel(1, 1)) / V0, np.array(delta), np.array(force)))
    ops.wipe()
    return out


def pounding_collisions(law, h: float, n: int) -> list[Collision]:
    """The same ``n`` collisions stepped by pounding's ``law`` (one instance: its state carries over)."""
    out = []
    for _ in range(n):
        s = step_two_bodies(law, m1=M1, m2=M2, v1=V0, v2=0.0, h=h, gap0=GAP)
        out.append(Collision(s.rebound(), -s.gap[1:], s.force[1:]))
    return out


def collide(opensees, material: dict, n: int) -> tuple[list[Collision], list[Collision], float]:
    """(OpenSees' collisions, pounding's, h [s]) of ``n`` collisions with the material law of ``material``."""
    law = MaterialContact(material=material)
    h = law.contact_duration(M_EFF, V0) / STEPS
    mat = law.opensees_material(1.0, M_EFF, GAP)
    return opensees_collisions(opensees, mat, h, n), pounding_collisions(law, h, n), h


def step_bound(runs: list[Collision], h: float) -> float:
    """eps_step [m] of the module docstring over ``runs``: TAU and both codes' rounding of displacements
    that stay below V0 N h (neither body moves faster than V0), N the runs' steps."""
    return TAU + 2.0 * EPS * V0 * h * sum(len(r.delta) for r in runs)


def bounds(runs: list[Collision], h: float) -> tuple[float, float, float]:
    """(rebound [-], force [N], set [m]) bounds of the module docstring after ``runs`` (N their steps)."""
    n, step = sum(len(r.delta) for r in runs), step_bound(runs, h)
    return 2.0 * n * step / (h * V0), K0 * 2.0 * n * n * step, 2.0 * n * n * step


def test_an_elastic_material_collides_as_its_elastic_gap(opensees):
    """``elastic`` as ``ElasticPPGap`` with no yield: rebound and peak force agree within the bounds of
    the same discrete equations (module docstring). The collision is the spring's: the trapezoidal rule
    keeps the energy of a linear spring (to the solve's residual, NEWTON_RTOL of the force a step), so
    the step ends sample the peak V0 sqrt(m_eff k) to within a factor cos(omega h / 2) (omega h =
    pi / STEPS), and the one step in which the surfaces part, where a force of at most k V0 h acts
    over at most V0 h, moves the rebound from 1 by at most (omega h)^2."""
    (os_,), (pd,), h = collide(opensees, ELASTIC, 1)
    d_rebound, d_force, _ = bounds([os_], h)
    assert abs(os_.rebound - pd.rebound) <= d_rebound
    assert abs(os_.peak - pd.peak) <= d_force
    wh = np.pi / STEPS
    assert abs(pd.rebound - 1.0) <= wh**2
    peak = V0 * np.sqrt(M_EFF * K0)
    assert peak * np.cos(wh / 2) <= pd.peak <= peak * (1.0 + NEWTON_RTOL * len(pd.delta))


def test_a_yielding_bilinear_material_collides_as_elastic_pp_gap_and_both_keep_its_plastic_set(opensees):
    """``bilinear`` as ``ElasticPPGap ... damage``, yielding in the collision: rebound, peak force and
    plastic set agree within the bounds of the same discrete equations (module docstring), in the first
    collision and in a second one from the same approach. The second shows both keep the set: no force
    until the penetration passes the first collision's set, then k0 (delta - set) (the reloading
    branch, read at the first step that pushes, equal to it within two steps' eps_step), and it
    hardens further: a larger set and a larger rebound (b > 0), the same in both codes."""
    os_runs, pd_runs, h = collide(opensees, BILINEAR, 2)
    for k, (os_, pd) in enumerate(zip(os_runs, pd_runs)):
        d_rebound, d_force, d_set = bounds(os_runs[:k + 1], h)
        assert abs(os_.rebound - pd.rebound) <= d_rebound, f"collision {k + 1}: rebound"
        assert abs(os_.peak - pd.peak) <= d_force, f"collision {k + 1}: peak force"
        assert abs(os_.plastic_set() - pd.plastic_set()) <= d_set, f"collision {k + 1}: plastic set"
    first = pd_runs[0]
    assert 0.0 < first.rebound < 1.0 and first.plastic_set() > 0.0 and first.peak > BILINEAR["yield_force"]
    step = step_bound(os_runs, h)
    for name, (one, two) in (("OpenSees", os_runs), ("pounding", pd_runs)):
        held = one.plastic_set()
        assert np.all(two.force[two.delta <= held] == 0.0) and np.any((two.delta > 0.0) & (two.delta <= held)), name
        first_push = np.flatnonzero(two.force > 0.0)[0]
        assert abs(two.delta[first_push] - two.force[first_push] / K0 - held) <= 2.0 * step, name
        assert two.plastic_set() > held and two.rebound > one.rebound, name


def _paper_pair_with(material: dict):
    """The paper's pair, 0.03 m apart, with the material contact law of ``material``."""
    from pounding.io.scene import load_scene

    return load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(
        contact="material", contact_params={"material": material})


def test_the_export_writes_the_bilinear_gap_material_and_notes_where_it_differs():
    """``pounding export opensees`` of the paper pair with a bilinear material contact writes its contact
    elements with ``ElasticPPGap``: half of k0 and of Fy at each end of a face (the face rule), Fy and the gap
    negative, eta = b, ``damage``; and it says where the material differs (b > 0: past (1 + 1/b) Fy / k0)."""
    from pounding.peer.export import opensees_script

    text, notes = opensees_script(_paper_pair_with(BILINEAR))
    calls = [ast.literal_eval(line.strip()[len("ops.uniaxialMaterial"):]) for line in text.splitlines()
             if line.strip().startswith("ops.uniaxialMaterial('ElasticPPGap'")]
    assert calls and "'zeroLength'" in text
    for _, _, e, fy, gap, eta, damage in calls:  # (name, tag, E, Fy, gap, eta, damage)
        assert (e, fy, eta, damage) == (0.5 * K0, -0.5 * BILINEAR["yield_force"], BILINEAR["hardening"], "damage")
        assert gap == pytest.approx(-0.03, abs=1e-12)  # the clear distance of the pair_gap_0.03 scene
    assert [n for n in notes if n.startswith("contact law 'material'") and "lower bound" in n and "0.051 m" in n]


def test_a_material_with_no_gap_counterpart_is_left_out_with_a_note():
    """A Bouc-Wen material has no OpenSees gap material: the script has no contact element, and the note
    names the law and the ones that have one."""
    from pounding.peer.export import opensees_script

    text, notes = opensees_script(_paper_pair_with({"name": "bouc_wen", "stiffness": K0, "yield_force": 2e6}))
    assert "'zeroLength'" not in text
    assert [n for n in notes if "contact law 'material' has no OpenSees material" in n and "bilinear" in n]


@pytest.mark.opensees
def test_the_exported_bilinear_material_contact_pounds_as_the_tools(tmp_path):
    """The exported script of tests/contact_pair.py's two shear buildings with a bilinear material contact
    (k0 = 2e9 N/m, Fy = 2e6 N, b = 0.02: the slabs' contacts yield, and storey 2 is struck twice, the
    second time from the set the first left) runs in OpenSees and its floor displacements are the tool's
    to the export's 1e-6 of the peak (tests/test_opensees_export.py; measured 1.0e-13 and 3.6e-13: the
    same discrete equations), at 2.5e-4 s, the step that resolves the shortest contact (10 ms) in the
    default step's 40."""
    from contact_pair import pair_scene
    from test_opensees_export import RTOL, _run_script
    from pounding.framework.post.run import run

    scene = pair_scene({"name": "material", "material": BILINEAR}, 2.5e-4, 0.85)
    result = run(scene)
    episodes = [c.pair for c in result.contacts]
    assert max(c.peak_force for c in result.contacts) > BILINEAR["yield_force"] and max(map(episodes.count, episodes)) > 1
    _, peer = _run_script(scene, tmp_path, modes=0)
    assert "ElasticPPGap" in (tmp_path / "model.py").read_text()
    for bld in scene.buildings:
        ours = result.cm(bld.name)[:, :, 0]
        assert np.abs(peer[bld.name][:, :, 0] - ours).max() <= RTOL * np.abs(ours).max(), bld.name
