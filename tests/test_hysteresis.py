"""Hysteresis laws: closed forms of their loops, their limits, and OpenSees' materials as the peer.

A law is driven here on its own (a spring under a prescribed deformation history, no dynamics):
each trial starts from the committed state and is committed, as a converged step would be.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.model.registry import HYSTERESIS
from pounding.hysteresis.bilinear import Bilinear
from pounding.hysteresis.bouc_wen import BoucWen

K0, FY, B = 5.0e7, 2.0e5, 0.05  # [N/m], [N], [-]
UY = FY / K0  # 4 mm


def drive(law, params, path):
    """Forces (len(path),), tangents, and the states after each deformation of ``path`` [m]."""
    cls = type(law)
    state = np.zeros((1, cls.n_state))
    trial = np.zeros((1, cls.n_state))
    params = np.atleast_2d(params)
    force, tangent, states = [], [], []
    for u in path:
        r, kt, _ = cls.update(float(u), 0.0, state, params, trial, 0)
        state[:] = trial
        force.append(r)
        tangent.append(kt)
        states.append(state[0].copy())
    return np.array(force), np.array(tangent), np.array(states)


def cycle_path(u_max, steps):
    """0 -> u_max, then u_max -> -u_max -> u_max (one full cycle), ``steps`` increments per quarter."""
    up = np.linspace(0.0, u_max, steps + 1)
    down = np.linspace(u_max, -u_max, 2 * steps + 1)[1:]
    back = np.linspace(-u_max, u_max, 2 * steps + 1)[1:]
    return np.concatenate([up, down, back]), len(up) - 1


def test_registry_lists_the_built_in_laws_and_checks_plugins():
    """The family is a registry like elements, integrators and contact laws: names, classes, a clear error."""
    assert {"bilinear", "bouc_wen"} <= set(HYSTERESIS.names())
    assert HYSTERESIS.get("bilinear") is Bilinear
    assert HYSTERESIS.get(BoucWen) is BoucWen
    with pytest.raises(InputError, match="known: bilinear, bouc_wen"):
        HYSTERESIS.get("takeda")


def test_bilinear_symmetric_loop_area_and_corners():
    """A symmetric cycle between -u_max and u_max after loading to u_max (kinematic hardening: the
    loop is stable from the first cycle) is a parallelogram:

    * slopes k0 (elastic) and b k0 (yielding); on the bounds r = b k0 u +- (1 - b) Fy;
    * unloading from u_max is elastic over 2 u_y, to u_max - 2 u_y;
    * the area (dissipated energy) is 4 Fy (1 - b) (u_max - u_y): each yielding branch runs over
      2 (u_max - u_y) with plastic deformation (1 - b) times that, dissipating Fy per unit of it.

    The law's dissipated energy is exact per step (u_p moves one way in a step), so the cycle sum
    equals the closed form to the rounding of ~800 additions (1e-12 relative). The shoelace area
    of the sampled (u, r) polygon equals it too when the corners are sampled: u_max = 5 u_y on a grid
    of u_y / 25 puts u_max - 2 u_y on the grid.
    """
    law = Bilinear()
    params = law.pack(K0, FY, B)
    u_max = 5.0 * UY
    path, k_top = cycle_path(u_max, 125)
    r, kt, st = drive(law, params, path)
    loop = 4.0 * FY * (1.0 - B) * (u_max - UY)
    dissipated = st[-1, 2] - st[k_top, 2]
    assert dissipated == pytest.approx(loop, rel=1e-12)
    u, f = path[k_top:], r[k_top:]
    shoelace = 0.5 * abs(np.sum(u * np.roll(f, -1) - np.roll(u, -1) * f))
    assert shoelace == pytest.approx(loop, rel=1e-12)
    top = B * K0 * u_max + (1.0 - B) * FY
    assert r[k_top] == pytest.approx(top, rel=1e-14)
    turn = u_max - 2.0 * UY
    i_turn = k_top + int(round((u_max - turn) / (path[1] - path[0])))
    assert path[i_turn] == pytest.approx(turn, rel=1e-12)
    assert r[i_turn] == pytest.approx(B * K0 * turn - (1.0 - B) * FY, rel=1e-12)
    assert np.all(kt[k_top + 1 : i_turn] == K0)  # elastic unloading
    assert np.all(kt[i_turn + 1 : k_top + 250] == B * K0)  # on the lower bound down to -u_max
    assert np.max(r) == pytest.approx(top, rel=1e-14) and np.min(r) == pytest.approx(-top, rel=1e-14)


def test_bilinear_elastic_branch_is_exactly_linear_before_yield():
    """Before any yielding the force is k0 u bit for bit (the stepping's exact elastic reduction needs it)."""
    law = Bilinear()
    path = np.linspace(-0.9 * UY, 0.9 * UY, 37)
    r, kt, _ = drive(law, law.pack(K0, FY, B), path)
    assert np.array_equal(r, K0 * path)
    assert np.all(kt == K0)


@pytest.mark.parametrize("law", [Bilinear(), BoucWen(n=2.0, beta=0.6, gamma=0.4)], ids=["bilinear", "bouc_wen"])
def test_the_hysteresis_laws_are_rate_independent_link_laws(law):
    """The link-law contract passes the rate v [m/s] with the deformation: a hysteresis law's force,
    tangent and trial state depend on the deformation path only, so any rate (here 0 and +-10 m/s,
    far beyond a storey's) gives the same numbers bit for bit, and its damping tangent dr/dv is 0."""
    cls = type(law)
    params = np.atleast_2d(law.pack(K0, FY, B))
    path = UY * np.concatenate([np.linspace(0.0, 3.0, 40), np.linspace(3.0, -2.0, 50)])
    state = np.zeros((1, cls.n_state))
    for u in path:
        answers = []
        for v in (0.0, 10.0, -10.0):
            trial = np.zeros((1, cls.n_state))
            r, kt, c = cls.update(float(u), v, state, params, trial, 0)
            answers.append((r, kt, c, trial.copy()))
        for r, kt, c, trial in answers:
            assert c == 0.0
            assert (r, kt) == answers[0][:2] and np.array_equal(trial, answers[0][3])
        state[:] = answers[0][3]


def test_bouc_wen_monotonic_loading_converges_to_tanh_at_first_order():
    """n = 2, beta + gamma = 1, monotonic loading from rest: dz/du = (1 - z^2)/u_y, so z = tanh(u/u_y)
    and r = b k0 u + (1 - b) Fy tanh(u/u_y). The update is backward Euler on z, first order: the error
    at u = 2 u_y halves when the increment halves (ratio 2 up to O(du) terms: within [1.9, 2.1] for
    du <= u_y/100)."""
    law = BoucWen(n=2.0, beta=0.6, gamma=0.4)
    params = law.pack(K0, FY, B)
    errors = []
    for steps in (200, 400, 800):
        path = np.linspace(0.0, 2.0 * UY, steps + 1)
        r, _, _ = drive(law, params, path)
        exact = B * K0 * path + (1.0 - B) * FY * np.tanh(path / UY)
        errors.append(abs(r[-1] - exact[-1]))
    assert 1.9 < errors[0] / errors[1] < 2.1
    assert 1.9 < errors[1] / errors[2] < 2.1


def test_bouc_wen_n1_monotonic_closed_form():
    """n = 1: dz/du = (1 - (beta + gamma) z)/u_y, z = (1 - exp(-(beta+gamma) u/u_y))/(beta + gamma),
    saturating at z_u = 1/(beta + gamma). Backward Euler again converges at first order."""
    beta, gamma = 0.7, 0.1
    law = BoucWen(n=1.0, beta=beta, gamma=gamma)
    params = law.pack(K0, FY, B)
    s = beta + gamma
    errors = []
    for steps in (200, 400):
        path = np.linspace(0.0, 3.0 * UY, steps + 1)
        r, _, st = drive(law, params, path)
        z_exact = (1.0 - np.exp(-s * path / UY)) / s
        errors.append(abs(st[-1, 3] - z_exact[-1]))
    assert 1.9 < errors[0] / errors[1] < 2.1


def test_bouc_wen_tangent_tends_to_hardening_when_saturated():
    """Far beyond yield z saturates (tanh(u/u_y) -> 1) and the tangent tends to b k0: at u = 12 u_y
    the hysteretic part adds (1 - b) Fy/u_y (1 - z^2) ~ 4 e^-24 k0 ~ 1.5e-10 k0."""
    law = BoucWen(n=2.0, beta=0.5, gamma=0.5)
    path = np.linspace(0.0, 12.0 * UY, 4801)
    _, kt, _ = drive(law, law.pack(K0, FY, B), path)
    assert kt[-1] == pytest.approx(B * K0, abs=1e-9 * K0)
    assert kt[0] == pytest.approx(K0, rel=1e-12)


def test_bouc_wen_loop_dissipation_is_the_loop_area():
    """Over a closed cycle the stored energy returns to its value, so the dissipated energy the law
    books per step (trapezoid of the hysteretic force over the slider's motion) sums to the area of the
    (u, r) loop (trapezoidal rule on the same samples = the shoelace area), to rounding."""
    law = BoucWen(n=1.5, beta=0.75, gamma=0.25)
    path, k_top = cycle_path(4.0 * UY, 200)
    path = np.concatenate([path, np.linspace(4.0 * UY, -4.0 * UY, 401)[1:], np.linspace(-4.0 * UY, 4.0 * UY, 401)[1:]])
    r, _, st = drive(law, law.pack(K0, FY, B), path)
    k2 = k_top + 800  # the second full cycle, closer to the stable loop
    u, f = path[k2:], r[k2:]
    trapezoid = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)))
    stored = [BoucWen.stored_energy(st[k], law.pack(K0, FY, B)) for k in (k2, len(path) - 1)]
    assert st[-1, 2] - st[k2, 2] == pytest.approx(trapezoid - (stored[1] - stored[0]), rel=1e-10)
    assert st[-1, 2] - st[k2, 2] > 0.0


@pytest.mark.parametrize(
    "params, field, words",
    [
        ({"n": 0.5}, "n", ">= 1"),
        ({"beta": 0.0}, "beta", "> 0"),
        ({"beta": 0.3, "gamma": 0.5}, "gamma", "-beta < gamma <= beta"),
        ({"beta": 0.3, "gamma": -0.3}, "gamma", "-beta < gamma <= beta"),
        ({"n": "two"}, "n", "finite number"),
    ],
)
def test_bouc_wen_parameters_out_of_range_are_rejected(params, field, words):
    """Outside n >= 1, beta > 0, -beta < gamma <= beta the loop is unbounded or creates energy
    (Ikhouane et al. 2007): one InputError naming the parameter and the valid range."""
    with pytest.raises(InputError) as exc:
        BoucWen(**params)
    assert exc.value.field == field
    assert words in exc.value.message


# ----------------------------------------------------------------------------- OpenSees materials
def _opensees_material_path(ops, material_args, path):
    ops.wipe()
    ops.uniaxialMaterial(*material_args)
    ops.testUniaxialMaterial(1)
    force, tangent = [], []
    for u in path:
        ops.setStrain(float(u))
        force.append(ops.getStress())
        tangent.append(ops.getTangent())
    ops.wipe()
    return np.array(force), np.array(tangent)


def _random_path(seed, n=400):
    """Cycles of growing amplitude (to 6 u_y) with random increments: partial unloadings, reloadings,
    reversals inside the elastic range; no increment is zero (Steel01 keeps its last tangent there)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n + 1)
    return UY * (6.0 * k / n * np.sin(2.0 * np.pi * k / 60.0) + np.concatenate([[0.0], rng.normal(0.0, 0.4, n)]))


@pytest.mark.opensees
def test_bilinear_is_steel01_without_isotropic_hardening(opensees):
    """A random deformation path (cycles growing to 6 u_y, random increments): forces and tangents equal
    OpenSees' Steel01(Fy, k0, b) to rounding (1e-12 of Fy: both clip the same elastic trial; pounding
    writes it k0 (u - u_p), Steel01 Cstress + k0 du)."""
    law = Bilinear()
    path = _random_path(1)
    r, kt, _ = drive(law, law.pack(K0, FY, B), path)
    r_os, kt_os = _opensees_material_path(opensees, ("Steel01", 1, FY, K0, B), path)
    assert np.max(np.abs(r - r_os)) <= 1e-12 * FY
    assert np.array_equal(kt, kt_os)


@pytest.mark.opensees
@pytest.mark.parametrize("n, beta, gamma", [(1.0, 0.5, 0.5), (2.0, 0.6, 0.4), (3.0, 0.9, -0.2)])
def test_bouc_wen_is_opensees_boucwen(opensees, n, beta, gamma):
    """The same random path through OpenSees' BoucWen(alpha = b, ko = k0, n, gamma / u_y^n,
    beta / u_y^n, Ao = 1, no degradation) with its z tolerance at 1e-14 u_y: both solve the same
    backward-Euler equation for z, so forces agree to the root tolerance (1e-9 of Fy covers
    OpenSees' start of Newton at z = 0.01 and its absolute tolerance)."""
    law = BoucWen(n=n, beta=beta, gamma=gamma)
    path = _random_path(2)
    r, kt, _ = drive(law, law.pack(K0, FY, B), path)
    args = ("BoucWen", 1, B, K0, n, gamma / UY**n, beta / UY**n, 1.0, 0.0, 0.0, 0.0, 1e-14 * UY, 200)
    r_os, kt_os = _opensees_material_path(opensees, args, path)
    assert np.max(np.abs(r - r_os)) <= 1e-9 * FY
    assert np.max(np.abs(kt - kt_os)) <= 1e-7 * K0
