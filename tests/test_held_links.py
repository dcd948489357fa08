"""Held contact with yielding storey springs: the fixed point around the held step, compiled.

The scene (benchmarks/bench_walls.py's): a base-isolated building on lead-rubber (bilinear) isolators
0.10 m from a fixed-base neighbour, with a moat wall 0.10 m west of its base slab, El Centro at 0.5 g
along x, impulse contact (e = 0.5). The wall stops the base slab, which chatters against it and is held
pressed against it while the isolators and the storeys above keep yielding: every held step solves the
springs' end remainders by a fixed point around the rigid held step
(:func:`pounding.framework.engine.held.held_fixed_point`), in the driver's Python step and in the
compiled held stretch (:func:`pounding.framework.engine.held.held_stretch`) alike.
"""

from __future__ import annotations

import copy
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding import compiler
from pounding.framework.engine.driver import Driver
from pounding.framework.post.energy_account import building_balances
from pounding.io.scene import parse_scene

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import bench_walls  # noqa: E402  (the scene the walls' benchmark times)

EPS = np.finfo(float).eps


def isolated_beside_a_wall(duration: float | None = None) -> dict:
    """benchmarks/bench_walls.py's scene with lead-rubber isolators and the moat wall at its stress distance
    (0.10 m: the base slab rests against it); ``duration`` [s] of El Centro (None: the whole record)."""
    data = bench_walls.scene_data(yielding=True, wall=True, moat=bench_walls.STRESS)
    if duration is not None:
        data["analysis"]["duration"] = duration
    return data


#: [N] an isolator line's yield force (the scene's)
YIELD = float(isolated_beside_a_wall()["building"][0]["element"][0]["yield_force"])


class FirstYieldingHeldStep(Driver):
    """The run, stopped at the first held grid step with a contact force in which the isolators'
    remainders change by more than 1e-3 of their yield force (they yield through the step: pressed
    against the wall on their yield plateau they change by rounding only), with that step taken
    twice from the same state: ``compiled`` (:meth:`Driver.held_trial`: the compiled fixed point)
    and ``interpreted`` (the same function with the compiler off)."""

    class Found(Exception):
        pass

    def advance_held(self, k0, k1):
        t, h, sp = float(self.t_grid[k0]), self.dt, self.springs
        compiled = self.held_trial(self.z, t, h)
        if not (np.max(np.abs(compiled.sp.f - sp.f)) > 1e-3 * YIELD and np.any(compiled.f1 != 0.0)):
            return super().advance_held(k0, k0 + 1)
        with compiler.interpreted():
            interpreted = self.held_trial(self.z, t, h)
        self.steps = {"compiled": compiled, "interpreted": interpreted}
        raise self.Found


@pytest.fixture(scope="module")
def wall_run():
    scene = parse_scene(copy.deepcopy(isolated_beside_a_wall()))
    driver = Driver(scene)
    return driver, driver.run()


def test_a_held_yielding_step_is_the_same_compiled_and_interpreted():
    """The first held step in which the isolators yield (:class:`FirstYieldingHeldStep`), from the same state: the compiled
    fixed point and the same function interpreted do the same operations in the same order on the
    same numbers; they differ by rounding only, and only where the compiled and numpy arithmetic
    order differ (a matrix product's sums: n ~ 30 terms). Tolerance: 30 n eps of each quantity's
    largest magnitude (a rounding per term of such sums, the pass's contraction below 1 not
    amplifying it; measured: within one rounding of the largest magnitude)."""
    driver = FirstYieldingHeldStep(parse_scene(copy.deepcopy(isolated_beside_a_wall(duration=6.5))))
    with pytest.raises(FirstYieldingHeldStep.Found):
        driver.run()
    ref = driver.steps["compiled"]
    n = ref.z1.shape[0]
    for name in ("interpreted",):
        other = driver.steps[name]
        for a, b in ((ref.z1, other.z1), (ref.f1, other.f1), (ref.sp.f, other.sp.f), (ref.sp.state, other.sp.state), (ref.sp.g, other.sp.g)):
            assert np.max(np.abs(a - b)) <= 30 * n * EPS * np.max(np.abs(a)), name


def test_the_lead_rubber_and_wall_run_closes_every_account_and_its_contacts_create_no_energy(wall_run):
    """The whole record with the base slab struck and held against the wall: every building's energy
    account (input + contact forces + impacts = kinetic + strain + damping + hysteretic) closes, and
    the contacts are passive: the held contact forces' work and the impacts' summed over the buildings
    are not positive. The account books the work of the loads each step applied on the step's own
    trajectory (the springs' remainders as they were solved, whatever the fixed point's tolerance),
    so it closes to rounding: a few roundings of the input per step, accumulated over every step
    (tolerance 10 eps per step; measured: 5e-14 of the input)."""
    driver, result = wall_run
    accounts = building_balances(result)
    assert len([i for i in result.impacts if result.struck_building(i) == "moat"]) >= 10
    assert accounts["isolated"]["contact_forces"] < 0.0  # the held contact acted (its plastic stops took energy)
    for name, acc in accounts.items():
        assert abs(acc["error"]) <= 10 * EPS * result.steps * acc["input"], (name, acc)
    total_input = sum(acc["input"] for acc in accounts.values())
    assert sum(acc["contact_forces"] for acc in accounts.values()) <= 10 * EPS * result.steps * total_input
    assert sum(acc["impacts"] for acc in accounts.values()) < 0.0


class CountingHeldSteps(Driver):
    """The driver, counting the grid steps its compiled held stretch takes."""

    held_steps = 0

    def advance_held(self, k0, k1):
        end = super().advance_held(k0, k1)
        self.held_steps += end.k - k0
        return end


def test_the_compiled_held_stretch_with_yielding_springs_gives_the_python_path():
    """The first 4 s (the base slab struck, held against the wall and the neighbour, released), run
    with the compiled stretches (the held grid steps in :func:`~pounding.framework.engine.held.held_stretch`)
    and with every step in Python (``use_kernel=False``). The stretch takes each held step with the
    Python step's functions in its order (the plastic stop, :func:`held_fixed_point`, the same
    energy rules and commits), so the runs agree to rounding (measured: bit for bit). Tolerance, as
    for the stretches between impacts (tests/test_inelastic_pounding.py): ~1e2 roundings of the peak
    per step, accumulated over every step; the same impacts, each located within (2 eps + delta) / b
    of the other run's (the search stops within Driver.eps [m] of the zero gap; delta [m] the
    vertices' allowed difference, b the approach speed)."""
    scene = parse_scene(copy.deepcopy(isolated_beside_a_wall(duration=4.0)))
    compiled = CountingHeldSteps(scene)
    a, b = compiled.run(), Driver(scene, use_kernel=False).run()
    assert compiled.held_steps >= 10 and len(a.impacts) >= 20
    tol = 1e2 * EPS * a.steps
    assert [x.pair for x in a.impacts] == [y.pair for y in b.impacts]
    delta = tol * max(np.nanmax(np.abs(b.vertices(n))) for n in b.names)
    for x, y in zip(a.impacts, b.impacts):
        assert abs(x.time - y.time) <= (2.0 * compiled.eps + delta) / y.approach_velocity
    assert np.abs(a.q - b.q).max() <= tol * np.abs(b.q).max()
    for name in b.springs:
        assert np.abs(a.springs[name]["deformation"] - b.springs[name]["deformation"]).max() <= tol * np.abs(
            b.springs[name]["deformation"]).max(), name
    for name in b.energy:
        scale = max(abs(v) for v in b.energy[name].values())
        for key, value in b.energy[name].items():
            assert abs(a.energy[name][key] - value) <= tol * scale, (name, key)
