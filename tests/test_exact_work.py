"""The closed-form work integrals of the exact integrator's steps (pounding.solvers.exact_work).

Checked against closed forms and against the energy theorem of the exact solution, over the
range the audit meets: omega dt from 1e-6 to 1e4, damping ratios from 0 to 10 including
critical damping. The helper that derived them also checked every coefficient against a
90-digit reference (worst 2.7e-14 of its scale); these tests keep the properties that matter.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.solvers.exact import Exact
from pounding.solvers.exact_work import work_maps

WH = [1e-6, 1e-3, 0.1, 1.0, 3.0, 10.0, 100.0, 1e4]
ZETA = [0.0, 0.05, 0.5, 1.0 - 1e-8, 1.0, 1.0 + 1e-8, 2.0, 10.0]


def test_undamped_free_vibration_integrals_match_the_closed_form():
    """q = cos(w s), v = -w sin(w s): int v = cos(w h) - 1, int s v and int v^2 in closed form, 1e-13."""
    w = np.array([0.7, 2.0, 50.0])
    h = 0.37
    a1, a2, M = work_maps(w, np.zeros(3), h)
    x = np.array([1.0, 0.0, 0.0, 0.0])
    th = w * h
    iv0 = np.cos(th) - 1.0
    iv1 = h * np.cos(th) - np.sin(th) / w  # int s (-w sin ws) ds
    ivv = w * (th - np.sin(th) * np.cos(th)) / 2.0  # int w^2 sin^2
    assert a1 @ x == pytest.approx(iv0, rel=1e-13, abs=1e-15)
    assert a2 @ x == pytest.approx(iv1, rel=1e-13, abs=1e-15)
    assert np.einsum("j,njk,k->n", x, M, x) == pytest.approx(ivv, rel=1e-13)


@pytest.mark.parametrize("zeta", ZETA)
def test_energy_theorem_of_the_exact_step(zeta):
    """For the exact solution, change of kinetic + strain energy = load work - damping work. With the
    end state from the exact integrator's own transition (computed independently), the identity
    holds to 1e-12 of the largest term for every omega dt from 1e-6 to 1e4."""
    rng = np.random.default_rng(7)
    h = 0.01
    w = np.array(WH) / h
    n = len(w)
    zeta_v = np.full(n, zeta)
    a1, a2, M = work_maps(w, zeta_v, h)
    tr = Exact().transition(w, zeta_v, h)
    for _ in range(5):
        q0 = rng.normal(size=n) / w  # strain energy of order 1
        v0 = rng.normal(size=n)
        p0, p1 = rng.normal(size=n) * w, rng.normal(size=n) * w
        z0 = np.stack([q0, v0, p0 - 2 * zeta_v * w * v0 - w**2 * q0], axis=1)
        z1 = np.einsum("nij,nj->ni", tr.A, z0) + tr.B[:, :, 0] * p0[:, None] + tr.B[:, :, 1] * p1[:, None]
        x = np.stack([q0, v0, p0, p1], axis=1)
        iv0 = np.einsum("nk,nk->n", a1, x)
        iv1 = np.einsum("nk,nk->n", a2, x)
        ivv = np.einsum("nj,njk,nk->n", x, M, x)
        work = p0 * iv0 + (p1 - p0) / h * iv1
        damp = 2 * zeta_v * w * ivv
        dE = 0.5 * (z1[:, 1] ** 2 - v0**2) + 0.5 * w**2 * (z1[:, 0] ** 2 - q0**2)
        scale = np.abs(work) + np.abs(damp) + 0.5 * (z1[:, 1] ** 2 + v0**2) + 0.5 * w**2 * (z1[:, 0] ** 2 + q0**2)
        assert np.all(np.abs(dE - (work - damp)) <= 1e-12 * scale), (dE - (work - damp)) / scale
        assert np.all(ivv >= -1e-15 * scale)
