"""Small scenes built in code for the pounding tests, and helpers that read a model physically.

Every builder returns the TOML-like dict that :func:`pounding.io.scene.parse_scene`
takes, so a test states its geometry in the same words a scene file would.
Element lines are given by ``start``/``end`` (never ``angle``): a frame at
``angle = 90`` has the direction ``(cos 90deg, sin 90deg) = (6e-17, 1)`` and
would couple x and y by rounding, which the symmetry tests must not see.
"""

from __future__ import annotations

import numpy as np

from pounding.io.ground_motion import GroundMotion
from pounding.io.scene import parse_scene

E_RC = 30e9  # [Pa]


def frame(start, end, column: float, beam: float = 0.5, columns=None) -> dict:
    """A moment frame from ``start`` to ``end`` with square columns (side ``column``) at both ends."""
    length = float(np.hypot(end[0] - start[0], end[1] - start[1]))
    return {
        "type": "frame",
        "start": list(start),
        "end": list(end),
        "columns": list(columns) if columns is not None else [0.0, length],
        "column": {"E": E_RC, "b": column, "h": column},
        "beam": {"E": E_RC, "b": 0.3, "h": beam},
    }


def box_building(name: str, x0: float, width: float, depth: float, storeys: int, column_x: float, column_y: float | None = None,
                 *, y0: float = 0.0, height: float = 3.2, mass_per_area: float = 900.0, damping: dict | None = None,
                 column_x_far: float | None = None) -> dict:
    """A rectangular building [x0, x0 + width] x [y0, y0 + depth], symmetric unless ``column_x_far`` is given.

    Two frames along x (at y = y0 and y = y0 + depth: the first has columns ``column_x``,
    the far one ``column_x_far`` or the same) and two along y (x = x0 and x = x0 + width).
    """
    cy = column_x if column_y is None else column_y
    far = column_x if column_x_far is None else column_x_far
    x1, y1 = x0 + width, y0 + depth
    table = {
        "name": name,
        "storey_heights": [height] * storeys,
        "slab": [[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
        "mass_per_area": mass_per_area,
        "element": [
            frame([x0, y0], [x1, y0], column_x),
            frame([x0, y1], [x1, y1], far),
            frame([x0, y0], [x0, y1], cy),
            frame([x1, y0], [x1, y1], cy),
        ],
    }
    if damping is not None:
        table["damping"] = damping
    return table


def side_by_side(gap: float, *, storeys=(1, 1), widths=(10.0, 12.0), depth: float = 10.0, columns=(0.40, 0.55),
                 columns_y=(0.5, 0.6), restitution: float = 0.5, contact: dict | None = None, integrator="newmark",
                 dt: float = 0.005, duration: float = 2.0, pga: float = 0.32, damping: dict | None = None,
                 right_y0: float = 0.0) -> dict:
    """Two box buildings along x, "left" on [0, w0] x [0, depth], "right" starting ``gap`` further along x.

    The right one spans y in [right_y0, right_y0 + depth]; with right_y0 = 0 and symmetric frames the
    pair is symmetric about y = depth / 2 and centred head-on impacts follow.
    """
    return {
        "building": [
            box_building("left", 0.0, widths[0], depth, storeys[0], columns[0], columns_y[0], damping=damping),
            box_building("right", widths[0] + gap, widths[1], depth, storeys[1], columns[1], columns_y[1], damping=damping,
                         y0=right_y0),
        ],
        "ground_motion": {"record": "elcentro", "pga": pga, "angle": 0.0},
        "analysis": {
            "integrator": integrator,
            "dt": dt,
            "duration": duration,
            "contact": contact or {"name": "impulse"},
            "restitution": restitution,
        },
    }


def pointed_pair(*, tip_y: float = 3.0, restitution: float = 0.5) -> dict:
    """A box "left" [0, 10] x [0, 10] and a pentagon "right" whose only vertex on x = 10 is (10, tip_y).

    At rest the tip touches the left slab's face x = 10 (gap 0): a single-point,
    eccentric contact with normal +x, lever arms ``-(tip_y - c_y)`` about each centre.
    """
    right = {
        "name": "right",
        "storey_heights": [3.2],
        "slab": [[10.0, tip_y], [14.0, 0.0], [20.0, 0.0], [20.0, 10.0], [14.0, 10.0]],
        "mass_per_area": 900.0,
        "element": [
            frame([14.0, 0.0], [20.0, 0.0], 0.45),
            frame([14.0, 10.0], [20.0, 10.0], 0.40),
            frame([14.0, 0.0], [14.0, 10.0], 0.45),
            frame([20.0, 0.0], [20.0, 10.0], 0.50),
        ],
    }
    return {
        "building": [box_building("left", 0.0, 10.0, 10.0, 1, 0.40, 0.50, column_x_far=0.35), right],
        "ground_motion": {"record": "elcentro", "pga": 0.32},
        "analysis": {"integrator": "newmark", "dt": 0.005, "duration": 1.0, "contact": "impulse", "restitution": restitution},
    }


def scene(data: dict):
    return parse_scene(data)


def pulse(duration: float, amplitude: float, *, rise: float = 0.2, dt: float = 0.005, angle: float = 0.0) -> GroundMotion:
    """A ground acceleration ramped from 0 to ``amplitude`` [m/s^2] in ``rise`` s and held to ``duration``."""
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    acc = amplitude * np.clip(t / rise, 0.0, 1.0)
    acc[0] = 0.0
    return GroundMotion(t, acc, name="pulse", source="test", angle=angle)


# --------------------------------------------------------------------------- physical views of a modal state
def physical(model, x: np.ndarray) -> dict:
    """Slab DOFs (u, v, phi) or their rates for a stacked modal vector: {(building, storey): (3,)}."""
    return {(b, f): model.slab_dofs(x, b, f) for b, s in enumerate(model.systems) for f in range(s.n_storeys)}


def contact_momentum_changes(model, result) -> list[float]:
    """What the contact forces gave each building's first slab along x [N s]: its x momentum change
    over the run less its columns' impulse, the columns' x force -(K x)_0 summed by the trapezoidal
    rule on the output steps (Newmark's velocity update is that rule of the forces). One entry per
    building (single-slab buildings: the whole building)."""
    out = []
    for s in model.systems:
        x = result.cm(s.name)[:, 0, :]  # (nt, 3) slab dofs
        spring = -(x @ s.K.T)[:, 0]  # the columns' x force [N]
        columns = float(np.sum(0.5 * (spring[1:] + spring[:-1]) * np.diff(result.t)))
        v = result.cm(s.name, velocity=True)[:, 0, 0]
        out.append(float(s.mass[0] * (v[-1] - v[0]) - columns))
    return out


def modal_from_physical(model, slab_values: dict) -> np.ndarray:
    """Stacked modal vector q = Phi^T M x from slab DOFs {(building, storey): (u, v, phi)} (others 0)."""
    out = np.zeros(model.n)
    for b, s in enumerate(model.systems):
        x = np.zeros(s.n_dof)
        for f in range(s.n_storeys):
            if (b, f) in slab_values:
                x[3 * f : 3 * f + 3] = slab_values[(b, f)]
        i0 = model.mode_start[b]
        out[i0 : i0 + s.n_dof] = s.modes.T @ (s.mass * x)
    return out


def point_velocity(dofs: np.ndarray, rates: np.ndarray, centre0: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Velocity of a plan point of a rigid slab: (u' - phi' r_y, v' + phi' r_x), r from the current centre."""
    c = centre0 + dofs[:2]
    r = point - c
    return np.array([rates[0] - rates[2] * r[1], rates[1] + rates[2] * r[0]])


def pressed_position(model, amplitude: float) -> float:
    """Static x displacement [m] of two one-storey buildings pressed together by a constant ground
    acceleration ``amplitude`` [m/s^2] along +x: u = -(m_a + m_b) a_g / (k_a + k_b). Asserts that
    apart the second one would move further, so that they do press together."""
    ka, kb = model.systems[0].K[0, 0], model.systems[1].K[0, 0]
    ma, mb = model.systems[0].mass[0], model.systems[1].mass[0]
    assert mb / kb > ma / ka, "apart, the second building would move further: they press together"
    return -(ma + mb) * amplitude / (ka + kb)
