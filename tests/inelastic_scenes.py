"""Scenes of storey-spring buildings for the inelastic tests (TOML-like dicts, see scenes_for_tests)."""

from __future__ import annotations


def springs(start, end, stiffness, yield_force=None, *, hardening=0.02, hysteresis="bilinear") -> dict:
    table = {"type": "storey_springs", "start": list(start), "end": list(end), "stiffness": stiffness}
    if yield_force is not None:
        table.update(yield_force=yield_force, hardening=hardening, hysteresis=hysteresis)
    return table


def eccentric_building(name: str = "tower", *, hysteresis="bilinear", hardening: float = 0.02, x0: float = 0.0,
                       strength: float = 1.0) -> dict:
    """A 3-storey, 15 m x 10 m building on storey springs, stiff and strong on its y = 0 side.

    Three lines along x (y = 0, 6, 10) with unequal stiffness and strength, two along y (x = 0 and
    x = 15, the far one stiffer): the centres of rigidity and strength are off the centre of mass in
    both directions, so shaking at an angle twists every floor and the springs yield unequally.
    """
    s = strength
    return {
        "name": name,
        "storey_heights": [3.5, 3.2, 3.2],
        "slab": [[x0, 0.0], [x0 + 15.0, 0.0], [x0 + 15.0, 10.0], [x0, 10.0]],
        "mass_per_area": 900.0,
        "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
        "element": [
            springs([x0, 0.0], [x0 + 15.0, 0.0], [1.2e8, 1.0e8, 0.8e8], [s * 4.0e5, s * 3.2e5, s * 2.4e5], hardening=hardening, hysteresis=hysteresis),
            springs([x0, 6.0], [x0 + 15.0, 6.0], [0.7e8, 0.6e8, 0.5e8], [s * 2.2e5, s * 1.8e5, s * 1.4e5], hardening=hardening, hysteresis=hysteresis),
            springs([x0, 10.0], [x0 + 15.0, 10.0], 0.5e8, s * 1.5e5, hardening=hardening, hysteresis=hysteresis),
            springs([x0, 0.0], [x0, 10.0], [1.0e8, 0.9e8, 0.7e8], [s * 3.0e5, s * 2.6e5, s * 2.0e5], hardening=hardening, hysteresis=hysteresis),
            springs([x0 + 15.0, 0.0], [x0 + 15.0, 10.0], [1.6e8, 1.4e8, 1.1e8], s * 4.5e5, hardening=hardening, hysteresis=hysteresis),
        ],
    }


def single(building: dict, *, angle: float = 30.0, pga: float = 0.32, dt: float = 0.01, duration: float = 10.0,
           integrator="newmark") -> dict:
    return {
        "building": [building],
        "ground_motion": {"record": "elcentro", "pga": pga, "angle": angle},
        "analysis": {"integrator": integrator, "dt": dt, "duration": duration, "contact": "none"},
    }
