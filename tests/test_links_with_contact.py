"""Yielding links and a force law's contact, solved together in one step.

With yielding storey springs and a force law the step's links and contact forces depend on each
other; the engine solves them by one compiled fixed point that takes the links' laws and the contact
law's solve as plugins (:func:`pounding.framework.engine.spring_core.contact_fixed_point`), run as
Python, the same function, where the law's solve only Python knows.

The scene: the eccentric yielding pair of ``test_inelastic_pounding`` 0.01 m apart, Hertz contact
(k_h = 1e9 N/m^1.5), stopped at the first step in which points press while the springs yield.
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_plugins import Hertz as GaussSeidelHertz
from test_inelastic_pounding import pair
from pounding import compiler
from pounding.contact.hertz import Hertz, hertz_force
from pounding.framework.engine.driver import Driver

EPS = np.finfo(float).eps
K_H = 1e9  # [N/m^1.5]


class PythonKernelHertz(Hertz):
    """The built-in Hertz law with its point kernel as plain Python (a third party's law written
    without the compiler): its solve, and so the step's whole fixed point, runs as Python."""

    law_force = staticmethod(hertz_force.py_func)


class FirstPressedYieldingStep(Driver):
    """The run, stopped at the first trial step in which a force law's points press while the
    springs' remainders change, with that step taken again from the same state by the laws in
    ``others`` ({name: law}) and, as ``interpreted``, with the compiler off."""

    others: dict = {}

    class Found(Exception):
        pass

    def spring_trial(self, z, t, h):
        st = super().spring_trial(z, t, h)
        if st.contacts is None or not len(st.contacts.pair) or not np.any(st.sp.f != self.springs.f):
            return st
        self.steps = {"compiled": st}
        with compiler.interpreted():
            self.steps["interpreted"] = super().spring_trial(z, t, h)
        laws = self.laws
        for name, law in self.others.items():
            self.laws = [law] * len(laws)
            self.steps[name] = super().spring_trial(z, t, h)
        self.laws = laws
        raise self.Found


@pytest.fixture(scope="module")
def first_step():
    driver = FirstPressedYieldingStep(pair(0.01, contact="hertz", contact_params={"stiffness": K_H}))
    driver.others = {"python_kernel": PythonKernelHertz(stiffness=K_H), "gauss_seidel": GaussSeidelHertz(stiffness=K_H)}
    with pytest.raises(FirstPressedYieldingStep.Found):
        driver.run()
    return driver


def _same_step(a, b, n: int) -> None:
    """Two trials of one step agree to rounding: end state, contact forces, links' remainders and states."""
    for x, y in ((a.z1, b.z1), (a.f1, b.f1), (a.contacts.force, b.contacts.force), (a.sp.f, b.sp.f), (a.sp.state, b.sp.state)):
        assert np.max(np.abs(x - y)) <= 30 * n * EPS * np.max(np.abs(x))


def test_the_step_is_the_same_compiled_and_interpreted(first_step):
    """The compiled fixed point and the same function with the compiler off do the same operations in
    the same order; they differ by rounding only, where the compiled and numpy orders of a sum differ
    (n ~ 30 terms: the modal rows' products). Tolerance: 30 n eps of each quantity's largest magnitude
    (measured: bit for bit)."""
    steps = first_step.steps
    _same_step(steps["compiled"], steps["interpreted"], first_step.model.n)


def test_a_law_only_python_knows_runs_through_the_same_fixed_point(first_step):
    """Hertz with its point kernel as plain Python: the contact solve and the fixed point around it
    run as Python (the same functions), and the step is the compiled law's to rounding (tolerance as
    above)."""
    steps = first_step.steps
    _same_step(steps["compiled"], steps["python_kernel"], first_step.model.n)


def test_a_law_given_only_as_forces_is_solved_with_the_links(first_step):
    """A law written from the base class alone (``contact_plugins.Hertz``: forces() by Gauss-Seidel
    and Brent, no face shares) with yielding springs: each point's force is the law's at the step's
    end penetration, which the links' remainders moved. The law's own solve stops at 1e-13 of the
    largest force, and Brent at 1e-14 of its bracket (the force closing the penetration alone): the
    forces meet k_h delta^1.5 to 1e-12 of the largest. The links' end deformations are those their
    laws give at the end displacements, to the fixed point's tolerance (each group's Newton
    tolerance, as the springs' own Newton)."""
    st = first_step.steps["gauss_seidel"]
    c = st.contacts
    assert len(c.force) > 0 and np.all(c.force > 0.0)
    delta = -c.gap  # the end gaps with the forces (StepContacts.gap)
    assert np.max(np.abs(c.force - K_H * np.maximum(delta, 0.0) ** 1.5)) <= 1e-12 * np.max(c.force)
    sp = first_step.springs
    trial = sp.at(st.z1[:, 0], first_step.dt)
    for j in range(len(sp.links.bounds) - 1):
        lo, hi = sp.links.bounds[j], sp.links.bounds[j + 1]
        assert np.max(np.abs(trial.state[lo:hi, 0] - st.sp.state[lo:hi, 0])) <= sp.links.tol[j]
