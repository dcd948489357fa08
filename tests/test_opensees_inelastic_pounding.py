"""Penalty pounding of yielding buildings cross-checked against OpenSeesPy (links with Steel01 and
zero-length gap elements), and the sustained contact of yielding buildings.

Set-up: two 3-storey buildings on storey springs, 15 x 10 m and 12 x 10 m, side by side along x
0.01 m apart, each symmetric about its own x axis (equal lines along y = 0 and y = 10, equal lines
along x = ends) so that El Centro along x moves them in x only: "left" yields at 0.4-0.3 MN per
line, "right" (0.6 times as stiff) at half of that. Newmark average acceleration, dt = 0.002 s,
4 s (the strong motion and the first contacts).

pounding: ``contact = {"name": "penalty", "stiffness": 1e10, "restitution": 1.0}``, the springs'
remainders iterated with the penalty forces to convergence (:mod:`pounding.framework.engine.yielding`).
OpenSees (:func:`pounding.peer.opensees_springs.run_springs_gap_pounding`): the buildings as
rigid diaphragms on ``twoNodeLink`` elements with ``Steel01`` and, at every storey, two
``zeroLength`` ``ElasticPPGap`` springs at the ends of the common facade, Newton to 1e-12 m.
Both solve the same discrete equations, so they agree to the solvers' tolerances: measured 1.6e-12
of the peak displacement and 3.2e-12 of the peak spring force (ductility up to 7.1, contact at
every storey); 0.3 s for pounding, 2.6 s for OpenSees (4064 Newton iterations in 2000 steps).
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.engine.driver import Driver
from pounding.framework.post.energy_account import building_balances
from pounding.io.scene import parse_scene

from inelastic_scenes import springs
from pounding.framework.post.energy_account import energy_balance

GAP, DT, DURATION, STIFFNESS = 0.01, 0.002, 4.0, 1e10
RTOL = 1e-5  # the figure: histories within 1e-5 of the peak


def _building(name: str, x0: float, width: float, stiffness: float, strength: float) -> dict:
    k, s = stiffness, strength
    x1 = x0 + width
    return {
        "name": name,
        "storey_heights": [3.2, 3.2, 3.2],
        "slab": [[x0, 0.0], [x1, 0.0], [x1, 10.0], [x0, 10.0]],
        "mass_per_area": 900.0,
        "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
        "element": [
            springs([x0, 0.0], [x1, 0.0], [k * 1.0e8, k * 0.8e8, k * 0.6e8], [s * 4.0e5, s * 3.5e5, s * 3.0e5]),
            springs([x0, 10.0], [x1, 10.0], [k * 1.0e8, k * 0.8e8, k * 0.6e8], [s * 4.0e5, s * 3.5e5, s * 3.0e5]),
            springs([x0, 0.0], [x0, 10.0], k * 1.0e8, s * 4.0e5),
            springs([x1, 0.0], [x1, 10.0], k * 1.0e8, s * 4.0e5),
        ],
    }


def _scene(contact) -> object:
    return parse_scene({
        "building": [_building("left", 0.0, 15.0, 1.0, 1.0), _building("right", 15.0 + GAP, 12.0, 0.6, 0.5)],
        "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": 0.0},
        "analysis": {"integrator": "newmark", "dt": DT, "duration": DURATION, "contact": contact},
    })


@pytest.fixture(scope="module")
def penalty():
    d = Driver(_scene({"name": "penalty", "stiffness": STIFFNESS, "restitution": 1.0, "tolerance": 1e-9}))
    return d, d.run()


@pytest.mark.opensees
def test_penalty_pounding_of_yielding_buildings_matches_opensees(opensees, penalty):
    """Every storey's x displacement and every yielding spring's force: max |difference| <= 1e-5 of
    the peak over the whole history (measured 1.6e-12 and 3.2e-12); the gap springs act in
    OpenSees (real contact) and the buildings yield (ductility > 2)."""
    from pounding.peer.opensees_springs import run_springs_gap_pounding

    d, r = penalty
    scene = d.scene
    disp, forces, gap_forces, _ = run_springs_gap_pounding(opensees, scene, STIFFNESS, DT, r.steps)
    assert np.min(gap_forces) < -1e5  # [N] compression: they pound
    for i, b in enumerate(scene.buildings):
        ours, peer = r.cm(b.name)[:, :, 0], disp[b.name][:, :, 0]
        assert np.abs(ours - peer).max() <= RTOL * np.abs(peer).max(), b.name
        sp = r.springs[b.name]
        assert np.max(sp["peak"] / sp["yield_deformation"]) > 2.0
        assert np.abs(sp["force"] - forces[b.name]).max() <= RTOL * np.abs(forces[b.name]).max(), b.name


def test_penalty_pounding_of_yielding_buildings_keeps_the_energy_account(penalty):
    """input + contact-force work = kinetic + strain + damping + hysteretic per building, to
    rounding (1e3 eps of the input) with Newmark average acceleration: the penalty forces and the
    springs' remainders are loads linear in each step, booked by the trapezoidal rule, the scheme's
    exact identity (measured 3e-14)."""
    d, r = penalty
    assert abs(energy_balance(r)["contact_force_work"]) > 0
    for name, b in building_balances(r).items():
        assert abs(b["relative_error"]) <= 1e3 * np.finfo(float).eps, name


def test_yielding_buildings_pressed_together_are_held_and_keep_the_energy_account():
    """Restitution 0: the impacts' rebounds vanish, so the pair is switched to sustained (held)
    contact, its constraint force solved with the springs' remainders in every step; the audit
    (input + contact-force work = kinetic + strain + damping + impact losses + hysteretic) still
    closes to rounding per building (1e3 eps of the input), and no pair overlaps beyond the
    tolerance at any output step."""
    scene = _scene("impulse").with_analysis(dt=0.01, contact_params={"restitution": 0.0, "after_impact": "equilibrium"})
    d = Driver(scene)
    r = d.run()
    assert r.n_impacts >= 1 and energy_balance(r)["contact_force_work"] != 0.0  # held contact acted
    for name, b in building_balances(r).items():
        assert abs(b["relative_error"]) <= 1e3 * np.finfo(float).eps, name
    gap = GAP + r.cm("right")[:, :, 0] - r.cm("left")[:, :, 0]
    assert gap.min() >= -d.tol
