"""The impact search compiled whole is the same function run with the compiler off.

``crossing_search`` (pounding.framework.engine.event_search) runs compiled on the integrator's own
solution (its compiled maps: ``exact``, HHT, Newmark, generalized-alpha) where nothing but the
ground acts in a step, and interpreted on the driver's Python callable otherwise; the two gap
functions step the integrator with the same arithmetic, so everything here is
asserted bit for bit: numpy's ``interp`` of the record, the modal load at any instant, and the
impact instants (with everything that follows from them) of whole runs with pounding.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from pounding import compiler
from pounding.compiler import njit
from pounding.framework.engine.driver import Driver
from pounding.solvers.base import Integrator
from pounding.solvers.hht import HHT
from pounding.solvers.newmark import alpha_step, alpha_transition
from pounding.framework.engine.event_search import modal_load_at, record_at
from pounding.io.motion_pair import GroundMotionPair
from pounding.io.scene import load_scene
from scenes_for_tests import scene, side_by_side

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
LSHAPE = ROOT / "benchmarks" / "scenes" / "l_shape_8_rect_4.toml"


def _exact(path, **analysis):
    return load_scene(path).with_analysis(integrator=None, integrator_params={}, dt=None,
                                           contact_params={"restitution": 0.5}, **analysis)


def test_the_record_is_numpys_interp_to_one_rounding():
    """At the record's samples, between them (random and halfway), at and beyond both ends.

    Both evaluate slope (x - t_j) + a_j. A numpy built to fuse that multiply-add (processors where
    the compiler contracts by default) rounds once where this rounds twice: at most half an ulp of
    the product, |slope (x - t_j)| <= |a_j+1 - a_j| <= 2 max|a|, plus half an ulp of the sum, so
    the bound is 2 eps max|a|. At the samples and outside the record nothing is computed: equal."""
    d = Driver(_exact(PAPER))
    t, acc = d.record
    rng = np.random.default_rng(7)
    x = np.concatenate([t, 0.5 * (t[1:] + t[:-1]), rng.uniform(-0.1, t[-1] + 0.1, 20_000),
                        [t[0], t[-1], np.nextafter(t[-1], 0.0), np.nextafter(t[0], 1.0), -1e-300, t[-1] + 1e-12]])
    ours = np.array([record_at(float(v), t, acc)[0] for v in x])
    theirs = np.interp(x, t, acc[:, 0], left=0.0, right=0.0)
    assert np.max(np.abs(ours - theirs)) <= 2 * np.finfo(float).eps * np.abs(acc).max()
    exact = np.isin(x, t) | (x < t[0]) | (x > t[-1])
    assert np.array_equal(ours[exact], theirs[exact])


@pytest.mark.parametrize("angle", [None, 30.0])
def test_the_modal_load_at_any_instant_is_the_drivers(angle):
    """One component, and two (the record turned by 30 degrees with its orthogonal companion): the
    grid rows at grid instants (and within 1e-9 steps of them), the record in between (the driver
    interpolates it with the same compiled record_at)."""
    sc = scene(side_by_side(0.02, integrator="exact", dt=0.004))
    if angle is not None:  # a second component (synthetic: the first reversed in time, scaled by 0.7)
        first = sc.ground_motion
        second = replace(first, acc=np.ascontiguousarray(0.7 * first.acc[::-1]))
        sc = sc.with_ground_motion(GroundMotionPair(first, second, angle=angle))
    d = Driver(sc)
    t, acc = d.search_record
    rng = np.random.default_rng(3)
    times = np.concatenate([d.t_grid[:200], d.t_grid[1:200] + 1e-12 * d.dt, rng.uniform(0.0, d.t_grid[-1], 2_000)])
    for s in times:
        p = modal_load_at(float(s), d.dt, d.ag, t, acc, d.model.L)
        assert np.array_equal(p, d.load(float(s)))


def _digest(d: Driver) -> str:
    h = hashlib.sha256()
    for a in (d.Q, d.V, d.E, np.array([[i.time, i.impulse, i.energy_loss] for i in d.impacts]).ravel()):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def _as_given(path, **analysis):
    """The scene's own integrator and step (the paper pair's file: HHT, alpha = -0.05, dt = 5 ms)."""
    return load_scene(path).with_analysis(**analysis)


@pytest.mark.parametrize("path, duration, dt, make", [(PAPER, 8.0, None, _exact), (PAPER, 4.0, 0.001, _exact), (LSHAPE, 8.0, None, _exact),
                                                      (PAPER, 8.0, None, _as_given), (LSHAPE, 6.0, None, _as_given)])
def test_runs_with_the_compiled_search_are_the_drivers_bit_for_bit(path, duration, dt, make):
    """Every located impact of the paper pair (exact at the default step and 0.001 s; HHT as its file
    gives it) and the L-shape scene (exact; HHT): the recorded states, the energy account and every
    impulse are the same bits with the compiled search, on the integrator's compiled maps
    (``Integrator.search_maps``), as with the driver's own, on its transitions."""
    sc = make(path, duration=duration) if dt is None else make(path, duration=duration).with_analysis(dt=dt)
    runs = []
    for compiled in (True, False):
        d = Driver(sc)
        assert d.search_record is not None
        if not compiled:
            d.search_record = None
        d.run()
        runs.append(d)
    assert runs[0].n_located >= 10
    assert _digest(runs[0]) == _digest(runs[1])


def test_the_stretch_runs_through_grazes_and_hands_the_driver_its_zeros():
    """The compiled stretch searches a step its screen suspects as the driver's Python step would
    (``event_search.step_touches``: the same suspects, the same search, the same end-of-step check):
    a step in which no pair touches, a graze the bounds could not exclude, is committed by the
    stretch, and a zero it finds is handed to the driver's step, which takes it rather than searching
    again. The paper pair at its defaults gives the same bits as with a stretch that stops at every
    suspected step, in fewer Python steps, and the driver searches again none of the steps the
    stretch searched."""
    sc = _exact(PAPER, duration=8.0)
    runs = []
    for graze in (True, False):
        d = Driver(sc)
        if not graze:
            d._graze = False  # (graze_search: none for this run)
        count = {"python": 0, "taken": 0}
        python_step, found = d.python_step, d.found_by_stretch

        def counted_step(k, _step=python_step, _count=count):
            _count["python"] += 1
            return _step(k)

        def counted_found(t, h, _found=found, _count=count):
            hs = _found(t, h)
            _count["taken"] += hs is not None
            return hs

        d.python_step, d.found_by_stretch = counted_step, counted_found
        d.run()
        runs.append((d, count))
    (searched, by_stretch), (stopped, by_driver) = runs
    assert _digest(searched) == _digest(stopped)
    assert by_stretch["python"] < by_driver["python"] and by_stretch["taken"] >= 10 and by_driver["taken"] == 0
    assert searched.n_located == stopped.n_located


@njit
def _own_alpha_maps(omega, zeta, dt, params):
    """A plugin's compiled maps: HHT's, written in the plugin's own module."""
    return alpha_transition(omega, zeta, dt, params[0], params[1], params[2], params[3])


class OwnMapsHHT(Integrator):
    """An out-of-tree integrator written from :class:`Integrator` alone: HHT's step (alpha = -0.05),
    its transitions probed from that step, and compiled maps of its own for the impact search."""

    name = "own_maps_hht"

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        return alpha_step(q, qd, qdd, p0, p1, omega, zeta, dt, beta=HHT().beta, gamma=HHT().gamma, alpha_m=0.0, alpha_f=0.05)

    def transition(self, omega, zeta, dt):
        return HHT().transition(omega, zeta, dt)

    def search_maps(self):
        return _own_alpha_maps, np.array([HHT().beta, HHT().gamma, 0.0, 0.05])


@pytest.mark.skipif(not compiler.enabled(), reason="the compiled search needs numba")
def test_a_plugins_compiled_maps_run_the_compiled_search_as_the_built_in_ones():
    """A third-party integrator's maps (a compiled function of its own module, passed to the search
    as an argument: ``event_search.locate_with``) locate the same impacts as HHT's built-in maps,
    bit for bit: the same arithmetic, called through another function."""
    sc = load_scene(PAPER).with_analysis(duration=3.0)
    runs = []
    for integrator in ("hht", OwnMapsHHT):
        d = Driver(sc.with_analysis(integrator=integrator, integrator_params={} if integrator is OwnMapsHHT else {"alpha": -0.05}))
        assert d.search_record is not None
        d.run()
        runs.append(d)
    assert runs[0].n_located >= 3
    assert _digest(runs[0]) == _digest(runs[1])


YIELDING = ROOT / "examples" / "inelastic_pair" / "pair_yielding_gap_0.03.toml"


def _walls_scene():
    """benchmarks/bench_walls.py's lead-rubber (bilinear) isolated building beside a fixed-base
    neighbour, with the moat wall at the benchmark's stress distance (0.10 m), which it strikes and is held
    pressed against."""
    import copy
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        from bench_walls import STRESS, scene_data
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
    from pounding.io.scene import parse_scene

    return parse_scene(copy.deepcopy(scene_data(True, True, STRESS)))


def _counted(d: Driver) -> dict:
    """Count the driver's searches as it runs them: impact searches with and without held pairs,
    and the held pairs' arrival searches that found an arrival."""
    seen = {"free": 0, "held": 0, "arrivals": 0}
    locate, arrival = d.locate, d.locate_arrival

    def counted_locate(*args):
        seen["held" if d.sustained else "free"] += 1
        return locate(*args)

    def counted_arrival(*args):
        hs = arrival(*args)
        seen["arrivals"] += hs is not None
        return hs

    d.locate, d.locate_arrival = counted_locate, counted_arrival
    return seen


@pytest.mark.skipif(not compiler.enabled(), reason="the compiled search needs numba")
@pytest.mark.parametrize("make, duration, least", [(lambda: load_scene(YIELDING), None, {"free": 5}),
                                                   (_walls_scene, 8.0, {"free": 20, "held": 3, "arrivals": 1})])
def test_yielding_runs_with_the_compiled_search_are_the_drivers_bit_for_bit(make, duration, least):
    """With yielding storey springs each of the search's trial steps is the links' own step (their
    Newton with the step's compliance, ``spring_core.spring_step``; with held pairs the fixed point
    around the held step, ``held.held_fixed_point``), compiled inside the search as the driver's
    interpreted search takes it: the same functions, so the same bits. The paper pair with bilinear
    storeys and pounding (its whole record), and the lead-rubber isolated building that strikes a
    moat wall, is held pressed against it and whose held points arrive at contact (impact searches
    with held pairs, arrival searches): the recorded states, the energy account and every impulse
    are equal with the compiled search and with the driver's."""
    sc = make() if duration is None else make().with_analysis(duration=duration)
    runs, counts = [], []
    for compiled in (True, False):
        d = Driver(sc)
        assert d.springs is not None and d.search_record is not None
        if not compiled:
            d.search_record = None
        counts.append(_counted(d))
        d.run()
        runs.append(d)
    assert counts[0] == counts[1]
    assert all(counts[0][k] >= n for k, n in least.items()), counts[0]
    assert _digest(runs[0]) == _digest(runs[1])
    assert np.array_equal(runs[0].springs.state, runs[1].springs.state)


def test_the_links_compliance_is_g_diag_b1_g_transposed():
    """spring_core.compliance, the step's compliance every path steps the links with: S = G diag(B1)
    G^T on each Newton group's block (the paper pair with yielding storeys: one group per building),
    zero between groups. Against numpy's product, each entry a sum of nm products: rounding of at
    most nm eps sum_i |G_ai B1_i G_bi| (two roundings per product and one per sum, each below eps/2)."""
    from pounding.framework.engine.spring_core import compliance

    d = Driver(load_scene(YIELDING))
    links = d.springs.links
    B1 = np.ascontiguousarray(d.cache(0.37 * d.dt).B[:, 0, 1])
    S = compliance(links, B1)
    expect, bound = np.zeros_like(S), np.zeros_like(S)
    for j in range(links.bounds.shape[0] - 1):
        lo, hi, (m0, nm) = links.bounds[j], links.bounds[j + 1], links.gmodes[j]
        Gg = links.G[lo:hi, :nm]
        expect[lo:hi, lo:hi] = (Gg * B1[m0:m0 + nm]) @ Gg.T
        bound[lo:hi, lo:hi] = nm * np.finfo(float).eps * (np.abs(Gg * B1[m0:m0 + nm]) @ np.abs(Gg).T)
    assert links.bounds.shape[0] - 1 == 2
    assert np.all(np.abs(S - expect) <= bound)
    assert np.all(S[expect == 0.0] == 0.0)
