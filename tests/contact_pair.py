"""Two 3-storey shear buildings facing along x, shaken by a short pulse: the force laws' building scene.

"low" (15 x 10 m, soft: storey springs 4.0e7, 3.5e7, 3.0e7 N/m on each of its two x lines) and
"high" (12 x 10 m, stiff: 2.0e8, 1.8e8, 1.5e8 N/m), ``GAP`` = 0.01 m apart, both 900 kg/m^2 (slabs
of 1.35e5 and 1.08e5 kg), 5 % Rayleigh damping at modes 1 and 3 of each, the same storey heights
(3.2 m). Each is a shear building: springs along x at y = 0 and y = 10 (the facade lines, so
nothing twists under x shaking: the pair is doubly symmetric) and one along y through the centre
(for a stable y and twist). The ground: a half sine of 4 m/s^2 for 0.6 s along x, sampled every
1 ms (the steps of the tests are multiples or divisors of it), then still. The soft building swings towards the
stiff one and the slabs pound at the three storeys (storey 3 from t = 0.635 s, storey 2 from
0.641 s, storey 1 briefly around 0.67 s, again at 2 and 3 from 0.73 s); the slab facades are
collinear, so each storey's contact is a face with two points (its ends, y = 0 and 10).
"""

from __future__ import annotations

import numpy as np

from pounding.io.ground_motion import GroundMotion
from pounding.io.scene import parse_scene

GAP = 0.01  # [m] clear distance between the facing facades
PULSE = 0.6  # [s] half-sine length
PEAK = 4.0  # [m/s^2]
RECORD_DT = 0.001  # [s]


def _springs(start, end, stiffness) -> dict:
    return {"type": "storey_springs", "start": list(start), "end": list(end), "stiffness": stiffness}


def _building(name: str, x0: float, width: float, k_x, k_y: float, depth: float = 10.0) -> dict:
    x1, xc = x0 + width, x0 + 0.5 * width
    return {
        "name": name,
        "storey_heights": [3.2] * 3,
        "slab": [[x0, 0.0], [x1, 0.0], [x1, depth], [x0, depth]],
        "mass_per_area": 900.0,
        "damping": {"type": "rayleigh", "ratio": 0.05, "modes": [1, 3]},
        "element": [_springs([x0, 0.0], [x1, 0.0], k_x), _springs([x0, depth], [x1, depth], k_x),
                    _springs([xc, 0.0], [xc, depth], k_y)],
    }


def pulse(duration: float) -> GroundMotion:
    """The half-sine ground acceleration along x [m/s^2], then zero, up to ``duration`` [s]."""
    t = np.arange(0.0, duration + 0.5 * RECORD_DT, RECORD_DT)
    acc = np.where(t < PULSE, PEAK * np.sin(np.pi * t / PULSE), 0.0)
    return GroundMotion(t, acc, name="half sine", source="test", angle=0.0)


def pair_scene(contact, dt: float, duration: float = 1.0, integrator: str = "newmark"):
    """The scene with ``contact`` (a law's name, class or table) at step ``dt`` [s] for ``duration`` [s]."""
    data = {
        "building": [_building("low", 0.0, 15.0, [4.0e7, 3.5e7, 3.0e7], 1.2e8),
                     _building("high", 15.0 + GAP, 12.0, [2.0e8, 1.8e8, 1.5e8], 4.0e8)],
        "ground_motion": {"record": "elcentro"},  # replaced by the pulse below
        "analysis": {"integrator": integrator, "dt": dt, "duration": duration, "contact": "none"},
    }
    scene = parse_scene(data).with_ground_motion(pulse(duration))
    if isinstance(contact, dict):
        params = {k: v for k, v in contact.items() if k != "name"}
        return scene.with_analysis(contact=contact["name"], contact_params=params)
    return scene.with_analysis(contact=contact, contact_params={})


def x_momentum_and_external_force(result, scene, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Building ``name``'s x momentum P (nt,) [N s] and the x force on it from outside (nt,) [N] at the output times.

    P = b^T M x' (b the x influence vector, x' the slabs' velocities relative to the ground: the
    momentum whose rate the relative equations of motion give); the force from outside is
    -b^T (M b a_g + C x' + K x): the ground's inertia load and what the storeys and dampers transmit
    to the ground. The contact forces are the rest of dP/dt.
    """
    i = result.names.index(name)
    system = result.systems[i]
    b = system.influence(np.array([1.0, 0.0]))
    t = result.t
    x = result.cm(name).reshape(len(t), -1)
    v = result.cm(name, velocity=True).reshape(len(t), -1)
    gm = scene.ground_motion
    a_g = np.interp(t, gm.t, gm.acc, left=0.0, right=0.0)
    momentum = v @ (system.mass * b)
    external = -(b @ (system.mass * b)) * a_g - v @ (system.C @ b) - x @ (system.K @ b)
    return momentum, external
