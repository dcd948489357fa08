"""Simultaneous impacts: the Newton impulse problem over every touching feature at once.

At an instant, every touching and approaching feature of every slab pair linked through a
shared building is one Newton problem (Delassus matrix W = Wr Wr^T of the stacked modal
rows, :func:`pounding.contact.base.newton_group`): a building struck from both sides is
handled together, not pair after pair.
"""

from __future__ import annotations

import numpy as np
import pytest

from pounding.framework.engine.driver import Driver
from pounding.framework.engine.kernel import impulses_at

from scenes_for_tests import box_building, modal_from_physical, physical, scene


def _cradle(storeys: int, restitution: float) -> dict:
    """Three equal box buildings (10 x 10 m, equal columns) in a row along x, touching at rest."""
    return {
        "building": [box_building(name, 10.0 * i, 10.0, 10.0, storeys, 0.4) for i, name in enumerate(("one", "two", "three"))],
        "ground_motion": {"record": "elcentro", "pga": 0.3},
        "analysis": {"integrator": "newmark", "dt": 0.005, "duration": 1.0,
                     "contact": {"name": "impulse", "restitution": restitution}},
    }


def _struck(storeys: int, restitution: float, compiled: bool):
    """Driver on the cradle with every floor of "one" moving at 1 m/s towards "two", the rest
    still; the impulses applied at t = 0 by the kernel (compiled) or the Python path."""
    d = Driver(scene(_cradle(storeys, restitution)))
    m = d.model
    d.z[:, 1] = modal_from_physical(m, {(0, f): (1.0, 0.0, 0.0) for f in range(storeys)})
    before = d.z[:, 1].copy()
    if compiled:
        candidates = np.ones(len(m.pairs), dtype=np.bool_)
        acted, _ = impulses_at(None, 0.0, d.ag[0], d.z, d.fc, m.modes, d.settings._replace(restitution=float(d.law.restitution)), d.dt, d.log, m.geo, candidates)
        d.drain_kernel_events()
    else:
        acted = d.contact_at(0.0)
    assert acted
    return d, before


def _slab_velocities(d, qd) -> np.ndarray:
    """(buildings, storeys, 3) slab velocities (u', v', phi')."""
    x = physical(d.model, qd)
    nb, ns = len(d.model.systems), d.model.systems[0].n_storeys
    return np.array([[x[(b, f)] for f in range(ns)] for b in range(nb)])


@pytest.mark.parametrize("storeys", [1, 3], ids=["1 storey: 4 points, enumerated", "3 storeys: 12 points, pivoting"])
@pytest.mark.parametrize("compiled", [True, False], ids=["kernel", "python"])
def test_newtons_cradle_of_three_equal_slabs(storeys, compiled):
    """Newton's cradle: three equal slabs in a row, touching; the first closes at b = 1 m/s, k = 1.

    The law as implemented (all approaching points active, Newton rebound -k b on each; a
    point that does not approach just stops closing) with equal masses m and the two contacts
    solved together: W = (1/m) [[2, -1], [-1, 2]], targets ((1 + k) b, 0) = (2, 0) give
    m I = (4/3, 2/3), both >= 0, so the velocities after are (1 - 4/3, 4/3 - 2/3, 2/3) =
    (-1/3, 2/3, 2/3): momentum 1 and energy 1/2 kept (k = 1). (Solved pair after pair it would
    be (0, 0, 1).) Each face meets face to face, two points per pair; the slabs are symmetric
    about the line of impact, so v' = phi' = 0. With three storeys every floor is one cradle
    (the floors' masses are independent at an instant: W = G M^-1 G^T), 12 points at once, past
    the enumeration (principal pivoting). Tolerance 1e-12 m/s: the result is W^-1 of a matrix of
    condition ~10 built from the complete modal basis (Phi Phi^T = M^-1 to ~1e-15 relative)."""
    d, _ = _struck(storeys, 1.0, compiled)
    v = _slab_velocities(d, d.z[:, 1])
    for f in range(storeys):
        assert np.allclose(v[:, f, 0], [-1 / 3, 2 / 3, 2 / 3], rtol=0, atol=1e-12)
        assert np.allclose(v[:, f, 1:], 0.0, rtol=0, atol=1e-12)
    assert len({i.time for i in d.impacts}) == 1 and len({i.pair for i in d.impacts}) == 2 * storeys


@pytest.mark.parametrize("compiled", [True, False], ids=["kernel", "python"])
def test_simultaneous_impacts_keep_momentum_and_lose_what_they_log(compiled):
    """The cradle (3 storeys) with k = 0.5: the impulses of both pairs at once conserve the row's
    linear momentum (every floor: sum m u' = m), and the kinetic energy lost equals the sum of
    the logged losses 0.5 I (b + b_after) >= 0 of the impacts. Tolerance 1e-12 of the energy
    before (0.5 m per floor) and of the momentum: rounding of W^-1 as above."""
    from test_impacts import kinetic

    d, before = _struck(3, 0.5, compiled)
    v0, v1 = _slab_velocities(d, before), _slab_velocities(d, d.z[:, 1])
    assert np.allclose(v1[:, :, 0].sum(axis=0), v0[:, :, 0].sum(axis=0), rtol=0, atol=1e-12)
    k0, k1 = kinetic(d.model, before), kinetic(d.model, d.z[:, 1])
    lost = sum(i.energy_loss for i in d.impacts)
    assert all(i.energy_loss >= -1e-12 * k0 for i in d.impacts)
    assert lost > 0.1 * k0, "k = 0.5 loses energy"
    assert abs((k0 - k1) - lost) <= 1e-12 * k0


def test_every_impact_instant_of_a_row_keeps_the_energy_law():
    """A row of three 3-storey buildings 0.01 m apart under El Centro at 0.5 g (both pairs pound):
    at every impact instant the kinetic energy of all slabs drops by exactly the logged losses of
    its impulses, each >= 0 (Newton's law with k = 0.5 only loses energy). Tolerance 1e-12 of the
    kinetic energy before (rounding of the modal products)."""
    from test_impacts import RecordingDriver, kinetic
    from test_rows import _row

    d = RecordingDriver(scene(_row(0.01)))
    d.run()
    assert d.events
    for ev in d.events:
        k0, k1 = kinetic(d.model, ev["before"]), kinetic(d.model, ev["after"])
        lost = sum(i.energy_loss for i in ev["impacts"])
        assert all(i.energy_loss >= -1e-12 * k0 for i in ev["impacts"]), ev["t"]
        assert abs((k0 - k1) - lost) <= 1e-12 * k0, ev["t"]
