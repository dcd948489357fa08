"""Each force law against OpenSees' material of the same name, on two free bodies that collide.

The problem: body 1 (1e5 kg) at 0.5 m/s strikes body 2 (2e5 kg) at rest; m_eff = 6.67e4 kg.

OpenSees (openseespy 3.7.1): a 1-D model (ndm 1, ndf 1), two nodes with those masses, a
``zeroLength`` element between them with the material, the initial velocity set with
``setNodeVel``, Newmark's average acceleration (0.5, 0.25), Newton with ``NormDispIncr 1e-14``,
a constant step h. The element's deformation is u2 - u1 (negative when the bodies close), and
every material takes the gap as a negative deformation: here -1e-12 m, so contact begins in the
first step, as in pounding's stepping (:mod:`two_bodies`) from a zero gap.

- ``ViscoelasticGap K C gap``: kelvin with ``tension = true`` (its force K delta + C delta' is not
  clamped: it pulls at the end of the contact), given C = 2 xi sqrt(K m_eff).
- ``Hertzdamp Kh xiNorm gap n``: the force (Kh + xi delta') delta^n with xi = xiNorm Kh / v_i, where
  v_i is the closing rate of the first *trial* state in contact (recomputed at each Newton
  iteration of the first contact step: the end of that step), where hertzdamp uses the closing speed
  at the first touch (the approach speed); the two agree as h -> 0. OpenSees' force pulls when the
  bracket turns negative (delta' < -v_i / xiNorm), which hertzdamp clamps; with Ye's xi that needs
  e < 3/8, so the comparison is at e = 0.5 and 0.8, where neither pulls.
- ``JankowskiImpact Kh xi mEff gap n``: jankowski, given xi (from e by Jankowski's formula) and m_eff.
- OpenSees has no elastic Hertz material: hertz is compared with ``Hertzdamp`` with xiNorm = 0.

pounding: the same bodies stepped by the same Newmark scheme with the law's own end-of-step solve
(:meth:`pounding.contact.pointwise.PointwiseLaw.forces`, :func:`two_bodies.step_two_bodies`).

The tolerance: both are first- or second-order in h (measured: kelvin's rebound 2nd order, its peak
force 1st; hertzdamp 2nd; jankowski ~1.25), so in their asymptotic range each is within
|x(h) - x(h/2)| of its limit at h/2 (error(h/2) = change / (2^p - 1) <= change for p >= 1); the
two therefore agree at h/2 within the sum of their changes, whatever their common limit (the
converged two-body contact of tests/test_contact_laws.py). Measured (relative, 400 -> 800 steps a
contact, e = 0.5 and 0.8): kelvin, hertz and jankowski agree to 9e-10, 1e-12 and 6e-11 (they solve the same
discrete equations, to OpenSees' Newton tolerance), against bounds of 7e-6 to 2e-3; hertzdamp to
1.1e-6 in the rebound and 2e-7 in the peak force (its impact velocity differs, above), against
bounds of 6e-6 and 1e-5. Runtime: ~0.1 s an OpenSees run.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.contact.hertz import Hertz
from pounding.contact.hertzdamp import HertzDamp
from pounding.contact.jankowski import Jankowski
from pounding.contact.kelvin import Kelvin
from pounding.contact.rebound import rebound
from two_bodies import step_two_bodies

M1, M2, V0 = 1e5, 2e5, 0.5
M_EFF = M1 * M2 / (M1 + M2)
GAP = 1e-12  # [m] OpenSees' gap (as -GAP): contact from the first step
STEPS = (400, 800)  # steps per contact duration: h and h/2


def material(law) -> tuple:
    """The OpenSees uniaxialMaterial arguments (tag 1) of ``law`` for the contact of M_EFF."""
    p = law.params(np.array([M_EFF]))[0]
    if law.name == "kelvin":
        return ("ViscoelasticGap", 1, p[0], p[1], -GAP)  # K, C = 2 xi sqrt(K m_eff)
    if law.name == "hertzdamp":
        return ("Hertzdamp", 1, p[0], p[2], -GAP, p[1])  # Kh, xiNorm, gap, n
    if law.name == "hertz":
        return ("Hertzdamp", 1, p[0], 0.0, -GAP, p[1])  # Hertz: Hertzdamp without damping
    return ("JankowskiImpact", 1, p[0], p[1], M_EFF, -GAP, 1.5)  # Kh, xi, mEff, gap, n


def two_body_model(ops, mat: tuple) -> None:
    """The two bodies in OpenSees: nodes 1 and 2 with masses M1 and M2 [kg] on one axis, joined by a
    ``zeroLength`` element (tag 1) of the uniaxialMaterial ``mat`` (its type, its tag 1, its arguments)."""
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.mass(1, M1)
    ops.mass(2, M2)
    ops.uniaxialMaterial(*mat)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)


def newmark_analysis(ops, tol: float) -> None:
    """A transient analysis by Newmark's average acceleration (0.5, 0.25), Newton to ``NormDispIncr tol`` [m]."""
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", tol, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def opensees_collision(ops, mat: tuple, h: float, t_end: float) -> tuple[float, float]:
    """(rebound [-], largest force at a step's end [N]) of the two bodies in OpenSees, stepped by h [s] to t_end."""
    two_body_model(ops, mat)
    ops.setNodeVel(1, 1, V0, "-commit")
    newmark_analysis(ops, 1e-14)
    peak = 0.0
    for _ in range(int(np.ceil(t_end / h))):
        assert ops.analyze(1, h) == 0
        peak = max(peak, abs(ops.eleForce(1)[1]))
    ratio = (ops.nodeVel(2, 1) - ops.nodeVel(1, 1)) / V0
    ops.wipe()
    return ratio, peak


def pounding_collision(law, h: float) -> tuple[float, float]:
    """(rebound [-], largest force at a step's end [N]) of the two bodies stepped by pounding's law."""
    s = step_two_bodies(law, m1=M1, m2=M2, v1=V0, v2=0.0, h=h)
    return s.rebound(), float(s.force.max())


LAWS = [Kelvin(restitution=e, tension=True) for e in (0.5, 0.8)] + [Hertz()] + [HertzDamp(restitution=e) for e in (0.5, 0.8)] \
    + [Jankowski(restitution=e) for e in (0.5, 0.8)]


@pytest.mark.parametrize("law", LAWS, ids=lambda law: f"{law.name}-e{law.restitution}")
def test_law_agrees_with_the_opensees_material_of_the_same_name(opensees, law):
    """Rebound and peak force of the collision, pounding's law against OpenSees' material, agree at h/2
    within the sum of both codes' changes from h to h/2 (the module docstring derives the bound)."""
    duration = rebound(law, m1=M1, m2=M2, approach_speed=V0).duration
    os_runs = [opensees_collision(opensees, material(law), duration / n, 1.3 * duration) for n in STEPS]
    pd_runs = [pounding_collision(law, duration / n) for n in STEPS]
    for k in (0, 1):  # the rebound, the peak force
        change = abs(os_runs[0][k] - os_runs[1][k]) + abs(pd_runs[0][k] - pd_runs[1][k])
        assert abs(os_runs[1][k] - pd_runs[1][k]) <= change, ("rebound", "peak force")[k]
