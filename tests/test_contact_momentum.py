"""The momentum of the pair across every contact episode of a force law: the contact forces are equal and opposite.

Two shear buildings pound (:mod:`contact_pair`: storeys 1-3 face to face). For building b, the
relative equations of motion M x'' + C x' + K x = -M b a_g + (contact forces), summed along x
(b^T, b the x influence vector), give

    P_b(t1) - P_b(t0) = integral of F_b dt + J_b,        P_b = b^T M x',   F_b = -b^T (M b a_g + C x' + K x),

J_b the x impulse of the contact forces on b. Contact forces act in pairs, equal and opposite at
one point, so J_low + J_high = 0 over any interval: across every episode (from the step end at or
before its start to the one at or after its end, where every contact force is zero), the two
buildings' momentum changes minus their external impulses sum to zero. Each building alone
receives the impulse its episodes report (``ContactEpisode.impulse``), pushed apart along the
normal (+x for "high", -x for "low"), over a cluster of episodes whose intervals overlap.

The external impulse is the trapezoidal rule on the step ends:

* ``newmark`` (average acceleration) advances the velocities by exactly that rule, so the
  balance holds to rounding: each step's identity holds to a few units of rounding of the
  largest terms in it, P and h F of both buildings, summed in dot products over the n_dof = 9
  slab DOFs: the bound n_dof eps sum_steps (|P_n| + |P_n+1| + h |F_n| + h |F_n+1|) (measured:
  residuals up to 1.5e-14 of the episodes' impulses, the bound ~1e-12 of them).
* ``exact`` integrates the structure exactly under contact forces linear in each step (whose
  trapezoid is then exact, as it is for the ground term, linear between the record's 1 ms samples
  at h = 1 ms): what is left is the rule's error on the structure's forces, -h^3 F''/12 a step.
  F'' is estimated by second differences, h^2 F'' ~ F_n+1 - 2 F_n + F_n-1, the larger of the two
  around each step, doubled for F'' varying inside the step: the bound (h/12) sum 2 max|Delta^2 F|
  over both buildings (measured: the residuals are up to 0.5 of it, and the bound at most 7e-4 of
  the episodes' impulses, so a missing or one-sided contact force would be seen).

Each run takes < 1 s (900 steps).
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_pair import pair_scene, x_momentum_and_external_force
from pounding.framework.post.run import run

EPS = np.finfo(float).eps
H = 1e-3  # [s], the record's sample interval
DURATION = 0.9  # [s]: the pulse and the first group of episodes (storeys 1-3)
N_DOF = 9  # 3 storeys x (u, v, phi)

LAWS = [
    {"name": "kelvin", "restitution": 0.5},
    {"name": "kelvin", "restitution": 0.5, "tension": True},
    {"name": "hertz"},
    {"name": "hertzdamp", "restitution": 0.5},
    {"name": "jankowski", "restitution": 0.5},
]


def _trapezoid(f: np.ndarray, i0: int, i1: int) -> float:
    """The trapezoidal rule of samples f[i0..i1] at step H [N s]."""
    part = f[i0 : i1 + 1]
    return H * (float(part.sum()) - 0.5 * float(part[0] + part[-1]))


def _rounding(P: dict, F: dict, i0: int, i1: int) -> float:
    """The newmark bound of the module docstring [N s]: N_DOF eps times the magnitudes each step's identity sums."""
    total = 0.0
    for name in P:
        p, f = np.abs(P[name][i0 : i1 + 1]), np.abs(F[name][i0 : i1 + 1])
        total += float(np.sum(p[:-1] + p[1:] + H * (f[:-1] + f[1:])))
    return N_DOF * EPS * total


def _quadrature(F: dict, i0: int, i1: int) -> float:
    """The exact integrator's bound of the module docstring [N s]: (h/12) sum over the steps i0..i1 of 2 max|Delta^2 F|."""
    total = 0.0
    for f in F.values():
        d2 = np.abs(f[2:] - 2.0 * f[1:-1] + f[:-2])  # at samples 1 .. n-2
        d2 = np.concatenate([d2[:1], d2, d2[-1:]])  # at every sample (the ends: their neighbour's)
        per_step = np.maximum(d2[i0:i1], d2[i0 + 1 : i1 + 1])
        total += float(np.sum(2.0 * per_step)) * H / 12.0
    return total


def _clusters(episodes, n: int) -> list[tuple[int, int, list]]:
    """Unions of episodes whose step intervals overlap: (first step end, last step end, episodes)."""
    spans = sorted(((int(np.floor(e.start / H + 1e-9)), min(int(np.ceil(e.end / H - 1e-9)), n - 1), e) for e in episodes),
                   key=lambda s: s[0])
    out = []
    for i0, i1, e in spans:
        if out and i0 <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], i1), out[-1][2] + [e])
        else:
            out.append((i0, i1, [e]))
    return out


def _balance(contact: dict, integrator: str):
    """(scene, result, P {name: (nt,)}, F {name: (nt,)}) of a run of the pair."""
    scene = pair_scene(contact, H, DURATION, integrator=integrator)
    result = run(scene)
    P, F = {}, {}
    for name in result.names:
        P[name], F[name] = x_momentum_and_external_force(result, scene, name)
    return scene, result, P, F


@pytest.mark.parametrize("integrator", ["newmark", "exact"])
@pytest.mark.parametrize("contact", LAWS, ids=lambda c: "-".join(f"{v}" for v in c.values()))
def test_the_pairs_momentum_balances_across_every_contact_episode(contact, integrator):
    """Across every episode: sum over both buildings of (change of momentum - external impulse) = 0 (the contact
    forces are equal and opposite), within the rule's bound; and over each cluster of overlapping episodes each
    building's imbalance is the episodes' impulse, -x on "low", +x on "high"."""
    scene, result, P, F = _balance(contact, integrator)
    n = len(result.t)
    assert np.allclose(np.diff(result.t), H)  # every step end is an output
    episodes = result.episodes()
    assert len({result.pairs[e.pair][1] for e in episodes}) >= 2  # contact at several storeys
    low, high = result.names
    assert all(result.names[result.pairs[e.pair][0]] == low for e in episodes)  # each pair's first slab is low's
    for i0, i1, group in _clusters(episodes, n):
        residual = {name: P[name][i1] - P[name][i0] - _trapezoid(F[name], i0, i1) for name in result.names}
        tol = _rounding(P, F, i0, i1) + (_quadrature(F, i0, i1) if integrator != "newmark" else 0.0)
        impulse = sum(e.impulse for e in group)
        assert tol < 1e-2 * impulse  # the check can see the contact impulse
        assert abs(residual[low] + residual[high]) <= tol, (group[0].start, residual, tol)
        assert abs(residual[high] - impulse) <= tol, (group[0].start, residual[high], impulse, tol)
        assert abs(residual[low] + impulse) <= tol, (group[0].start, residual[low], impulse, tol)
