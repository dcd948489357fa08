"""The closed-form work integrals of the exact integrator's steps (pounding.solvers.exact_work).

Checked against closed forms and against the energy theorem of the exact solution, over the
range the audit meets: omega dt from 1e-6 to 1e4, damping ratios from 0 to 10 including
critical damping; the first regime (omega dt <= max(3, 1.5 zeta), compiled) against a quadrature
of scipy's exponential of the augmented system, computed independently in the test, and its
Python path (the compiler off) against its compiled one.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding import compiler
from pounding.solvers.exact import Exact
from pounding.solvers.exact_work import work_maps

WH = [1e-6, 1e-3, 0.1, 1.0, 3.0, 10.0, 100.0, 1e4]
ZETA = [0.0, 0.05, 0.5, 1.0 - 1e-8, 1.0, 1.0 + 1e-8, 2.0, 10.0]
EPS = float(np.finfo(float).eps)


def _first_regime(seed, n=120):
    """Modes of the first regime, omega h from 1e-7 to its edge max(3, 1.5 zeta), damping ratios 0 to 3
    (a quarter at 0.05, critical damping and its neighbours among them), for a step of 1: (w h, zeta)."""
    rng = np.random.default_rng(seed)
    zeta = rng.uniform(0.0, 3.0, n)
    zeta[: n // 4] = 0.05
    zeta[n // 4: n // 4 + 4] = [0.0, 1.0 - 1e-8, 1.0, 1.0 + 1e-8]
    edge = np.maximum(3.0, 1.5 * zeta)
    wh = np.exp(rng.uniform(np.log(1e-7), np.log(edge)))
    wh[-4:] = edge[-4:]
    return wh, zeta


def _quadrature_reference(wh, zeta, h):
    """a1, a2, M of work_maps by Gauss-Legendre quadrature of the exact velocity over the step.

    In tau = s / h with y = (q, h q', h^2 p, h^3 p'), the step is y' = F y, F = [[0, 1, 0, 0], [-a^2, -b, 1, 0],
    [0, 0, 0, 1], [0, 0, 0, 0]], a = w h, b = 2 zeta a, and the velocity row of Phi(tau) = expm(F tau) (scipy,
    Pade with scaling and squaring, at every node) gives int v, int s v and int v^2 as integrals of it on
    [0, 1]. 4 panels of 16 nodes: the integrand's derivatives grow like ||F||^j (<= 48^j here) and 64 nodes
    integrate it to rounding (16 panels give the same to 9 eps of each coefficient's scale)."""
    from scipy.linalg import expm

    n = wh.size
    F = np.zeros((n, 4, 4))
    F[:, 0, 1] = 1.0
    F[:, 1, 0] = -wh * wh
    F[:, 1, 1] = -2.0 * zeta * wh
    F[:, 1, 2] = 1.0
    F[:, 2, 3] = 1.0
    x, wq = np.polynomial.legendre.leggauss(16)
    panels = 4
    tau = ((np.arange(panels)[:, None] + 0.5 * (x + 1.0)) / panels).ravel()
    weight = np.tile(wq / (2.0 * panels), panels)
    # the velocity row of Phi(tau) for x = (q0, h v0, h^2 p0, h^2 p1): r = (p1 - p0) / h takes h^2 (p1 - p0)
    inputs = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0, 0, -1.0, 1.0]])
    v = np.array([expm(F * t)[:, 1, :] @ inputs for t in tau])  # (nodes, n, 4)
    d = np.array([1.0, h, h * h, h * h])  # back to x = (q0, v0, p0, p1)
    a1 = np.einsum("k,knj->nj", weight, v) * d
    a2 = h * np.einsum("k,knj->nj", weight * tau, v) * d
    M = np.einsum("k,kni,knj->nij", weight, v, v) * np.outer(d, d) / h
    return a1, a2, M


@pytest.mark.parametrize("h", [1e-6, 1e-3, 0.0137, 0.3])
def test_first_regime_is_the_quadrature_of_scipys_exponential(h):
    """Each coefficient equals the reference to rounding of its Cauchy-Schwarz scale (|int v_k| <=
    sqrt(h M_kk), |int s v_k| <= sqrt(h^3 / 3 M_kk), |M_jk| <= sqrt(M_jj M_kk)). Both computations are
    exact to a few ulps of their O(1) entries before they double (work_maps: k = ceil(log2 max(||F||_inf,
    1 + ||F||_1)) doublings) or square (scipy: ceil(log2(||F||_1 / 5.37)) squarings), each at most
    doubling the relative error: bound 20 (2^k + 2^s) eps per mode, k <= 6 and s <= 3 here (measured: at
    most 58 eps, 0.2 of the bound; against 40-digit arithmetic the maps are within 50 eps here and the
    reference within 41)."""
    wh, zeta = _first_regime(seed=int(h * 1e4) + 11)
    w = wh / h
    got = work_maps(w, zeta, h)
    ref = _quadrature_reference(wh, zeta, h)
    a, b = wh, 2.0 * zeta * wh
    k = np.ceil(np.log2(np.maximum(a * a + b + 1.0, 1.0 + np.maximum(a * a, 1.0 + b))))
    s = np.maximum(0.0, np.ceil(np.log2(np.maximum(a * a, 1.0 + b) / 5.37)))
    tol = 20.0 * (2.0**k + 2.0**s) * EPS
    d = np.sqrt(np.einsum("njj->nj", ref[2]))
    scales = (np.sqrt(h) * d, np.sqrt(h**3 / 3.0) * d, d[:, :, None] * d[:, None, :])
    for G, R, scale in zip(got, ref, scales):
        err = np.abs(G - R) / scale
        assert np.all(err <= tol.reshape((-1,) + (1,) * (err.ndim - 1))), err.max() / EPS


def test_first_regime_runs_the_same_without_the_compiler():
    """With the compiler off the compiled function runs as Python, the same IEEE operations in the same
    order (no fast-math): the same maps, to the bit."""
    wh, zeta = _first_regime(seed=5, n=16)
    h = 0.005
    compiled = work_maps(wh / h, zeta, h)
    with compiler.interpreted():
        python = work_maps(wh / h, zeta, h)
    for C, P in zip(compiled, python):
        assert C.tobytes() == P.tobytes()


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


@pytest.mark.parametrize("w, zeta, h", [([1.0, 0.0], [0.05, 0.05], 0.01), ([1.0, -2.0], [0.05, 0.05], 0.01),
                                        ([1.0, 2.0], [0.05, -0.01], 0.01), ([1.0, np.nan], [0.05, 0.05], 0.01),
                                        ([1.0, 2.0], [0.05, np.nan], 0.01), ([1.0, 2.0], [0.05, 0.05], 0.0),
                                        ([1.0, 2.0], [0.05, 0.05], -0.01), ([1.0, 2.0], [0.05, 0.05], np.inf),
                                        ([1.0, 2.0], [0.05, 0.05], np.nan), ([], [], -0.01)])
def test_work_maps_refuse_what_has_no_oscillator(w, zeta, h):
    """The maps are defined for a finite step h > 0 and modes with w > 0, zeta >= 0 (the compiled regime
    checks them, mode by mode): anything else, a NaN included, is refused with the condition, not
    integrated, also with no mode."""
    with pytest.raises(ValueError, match="need h > 0, w > 0, zeta >= 0"):
        work_maps(np.array(w), np.array(zeta), h)
