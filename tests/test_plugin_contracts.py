"""Out-of-tree plugins written only from the base classes, registered by class, run end to end.

Each plugin below restates a built-in rule through the public contract alone
(:class:`pounding.contact.base.ContactLaw`, :class:`pounding.solvers.base.Integrator`), so the
run must give the built-in's answer: the same physics through the plugin path.
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

from pounding.contact.base import ContactLaw
from pounding.errors import InputError
from pounding.framework.engine.driver import Driver
from pounding.framework.post.run import run
from pounding.framework.model.registry import CONTACT_LAWS
from pounding.io.scene import load_scene
from pounding.solvers.base import Integrator

PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"


class SinglePointNewton(ContactLaw):
    """Newton's rule written out: one point I = (1 + k) b / a (a = W, b > 0); several points
    share the impulse that stops the closing of the pair's mean direction (never used here:
    the paper pair meets at single corners)."""

    name: ClassVar[str] = "single_point_newton"
    kind: ClassVar[str] = "impulse"
    calls = 0

    def impulses(self, W, b):
        type(self).calls += 1
        assert W.shape == (1, 1), "the paper pair meets at one point at a time"
        return np.array([(1.0 + self.restitution) * b[0] / W[0, 0]]) if b[0] > 0 else np.zeros(1)


class LinearSpring(ContactLaw):
    """A compression-only linear spring k_p [N/m], solved implicitly with the step:
    (I + k_p S_q) lambda = -k_p gap on the points that push (active set)."""

    name: ClassVar[str] = "linear_spring"
    kind: ClassVar[str] = "force"
    calls = 0

    def __init__(self, *, stiffness: float = 1e8, restitution: float = 1.0):
        super().__init__(restitution=restitution)
        self.stiffness = float(stiffness)

    def forces(self, contact):
        type(self).calls += 1
        gap, S_q = contact.gap, contact.S_q
        m = len(gap)
        active = np.ones(m, dtype=bool)
        lam = np.zeros(m)
        for _ in range(m + 1):
            idx = np.flatnonzero(active)
            if idx.size == 0:
                break
            K = np.eye(idx.size) + self.stiffness * S_q[np.ix_(idx, idx)]
            sol = np.linalg.solve(K, -self.stiffness * gap[idx])
            lam[:] = 0.0
            lam[idx] = sol
            if np.all(sol >= 0):
                break
            active[idx[sol < 0]] = False
        return np.maximum(lam, 0.0)


class AverageAcceleration(Integrator):
    """Newmark's average acceleration (beta = 1/4, gamma = 1/2) in its textbook form:
    a1 from (1 + gamma dt c + beta dt^2 k) a1 = p1 - c v_p - k q_p with the predictors
    q_p = q + dt q' + dt^2/4 q'', v_p = q' + dt/2 q''."""

    name: ClassVar[str] = "average_acceleration_plugin"
    order: ClassVar[int] = 2

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        c, k = 2.0 * zeta * omega, omega**2
        qp = q + dt * qd + 0.25 * dt * dt * qdd
        vp = qd + 0.5 * dt * qdd
        a1 = (p1 - c * vp - k * qp) / (1.0 + 0.5 * dt * c + 0.25 * dt * dt * k)
        return qp + 0.25 * dt * dt * a1, vp + 0.5 * dt * a1, a1


def _scene(**analysis):
    return load_scene(PAPER).with_analysis(duration=3.0, **analysis)


def test_impulse_law_plugin_by_class_gives_newton_impacts():
    """A third-party impulse law that does not declare ``compiled_impulses`` is asked for every
    impact's impulses by the driver. Restating Newton's single-point rule (the paper's eq. 12),
    it gives the built-in law's run: the same impacts, and responses to 1e-12 of the peak
    (the two differ only by the rounding of one division and of W = w w^T, 1e-16 relative;
    the halving locator's decisions compare gaps with a 1e-4 m tolerance and are not moved
    by it)."""
    SinglePointNewton.calls = 0
    plug = run(_scene(contact=SinglePointNewton, contact_params={"restitution": 0.5}))
    ref = run(_scene(contact="impulse", contact_params={"restitution": 0.5}))
    assert SinglePointNewton.calls >= plug.n_impacts > 0
    assert plug.n_impacts == ref.n_impacts
    for x, y in zip(plug.impacts, ref.impacts):
        assert (x.pair, x.striker, x.vertex) == (y.pair, y.striker, y.vertex)
        assert abs(x.impulse - y.impulse) <= 1e-12 * max(i.impulse for i in ref.impacts)
    assert np.abs(plug.q - ref.q).max() <= 1e-12 * np.abs(ref.q).max()


def test_force_law_plugin_by_class_is_the_undamped_penalty():
    """A third-party force law, a compression-only linear spring, is the built-in penalty law
    with restitution 1 (damping ratio xi = 0: no dashpot): the same implicit system
    (I + k_p S_q) lambda = -k_p gap, so the same response to rounding (1e-12 of the peak)."""
    LinearSpring.calls = 0
    plug = run(_scene(contact=LinearSpring, contact_params={"stiffness": 1e8}))
    ref = run(_scene(contact="penalty", contact_params={"stiffness": 1e8, "restitution": 1.0}))
    assert LinearSpring.calls > 0
    work = sum(abs(e["contact_forces"]) for e in plug.energy.values())
    assert work > 0, "the slabs never touched: the test would check nothing"
    assert np.abs(plug.q - ref.q).max() <= 1e-12 * np.abs(ref.q).max()


def test_integrator_plugin_by_class_is_newmark_average_acceleration():
    """A third-party integrator written from :class:`Integrator` alone (its transition probed
    from ``step``) is the built-in Newmark with beta = 1/4, gamma = 1/2: the paper pair with
    pounding over 3 s gives the same impacts and responses. The two step formulas are
    algebraically equal and differ by rounding (1e-16 per step); over 600 stable steps that
    stays below 1e-12 of the peak."""
    plug = run(_scene(integrator=AverageAcceleration, integrator_params={}))
    ref = run(_scene(integrator="newmark", integrator_params={}))
    assert plug.n_impacts == ref.n_impacts > 0
    assert np.abs(plug.q - ref.q).max() <= 1e-12 * np.abs(ref.q).max()


def test_a_law_breaking_its_contract_is_rejected_when_registered():
    """An impulse law without ``impulses`` is refused when looked up, naming what is missing,
    not in the middle of a run."""

    class Broken(ContactLaw):
        name: ClassVar[str] = "broken"
        kind: ClassVar[str] = "impulse"

    with pytest.raises(InputError, match="does not implement impulses"):
        CONTACT_LAWS.get(Broken)

    class Weird(ContactLaw):
        name: ClassVar[str] = "weird"
        kind: ClassVar[str] = "sticky"

    with pytest.raises(InputError, match="kind='sticky'"):
        CONTACT_LAWS.get(Weird)


def test_the_contract_names_what_the_driver_reads():
    """Every law attribute the driver reads has a declared default on the base class, so a law
    written from the base class alone never fails mid-run with AttributeError."""
    law = SinglePointNewton()
    for attr in ("name", "kind", "compiled_impulses", "tolerance", "locate", "after_impact", "restitution"):
        assert hasattr(law, attr), attr
    d = Driver(_scene(contact=SinglePointNewton, contact_params={}))
    assert d.settings.restitution == -1.0  # not declared compiled: the driver asks the law
