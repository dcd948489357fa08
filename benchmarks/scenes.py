"""Scenes for the benchmarks: the two work-precision scenes, generated scaling scenes, tiled records.

Everything here builds scenes through the public input path (``load_scene`` /
``parse_scene``), so a benchmark scene is validated exactly like a user's.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
HERE = Path(__file__).resolve().parent

#: name -> scene file of the work-precision / peer scenes
SCENE_FILES = {
    "paper": ROOT / "examples" / "paper" / "pair_gap_0.03.toml",
    "lshape": HERE / "scenes" / "l_shape_8_rect_4.toml",
}

SCENE_TITLES = {
    "paper": "paper: 3 + 5 storeys, gap 0.03 m",
    "lshape": "L-shaped 8 storeys + 4 storeys with wall, gap 0.04 m",
}


def load(name: str):
    from pounding import load_scene

    return load_scene(SCENE_FILES[name])


def no_pounding(scene):
    """The same scene with contact off (for the paper scene this equals pair_gap_0.5.toml: no impacts there)."""
    return scene.with_analysis(contact="none", contact_params={})


def with_method(scene, integrator: str, dt: float, locate: str | None = None, tolerance: float | None = None):
    """A copy with the integrator (default parameters), dt and, for impulse contact, the locator/tolerance."""
    changes = {"integrator": integrator, "integrator_params": {}, "dt": dt}
    if scene.analysis.contact == "impulse":
        params = dict(scene.analysis.contact_params)
        if locate is not None:
            params["locate"] = locate
        if tolerance is not None:
            params["tolerance"] = tolerance
        changes["contact_params"] = params
    return scene.with_analysis(**changes)


# --------------------------------------------------------------------------- scaling scenes
E = 30e9


def _frame(start, end, columns, col, beam_h=0.6):
    return {
        "type": "frame",
        "start": list(map(float, start)),
        "end": list(map(float, end)),
        "columns": [float(c) for c in columns],
        "column": {"E": E, "b": col, "h": col},
        "beam": {"E": E, "b": 0.35, "h": beam_h},
    }


def _box(name, x0, width, depth, storeys, col, strong_x, strong_y):
    """A uniform-plan building [x0, x0+width] x [0, depth]: 3 frames along x, 3 along y.

    Non-symmetric: the x-frame at y = 0 has columns ``strong_x`` times wider and the
    y-frame at the far end x0+width has columns ``strong_y`` times wider than the rest,
    and the middle frames are off centre, so the centre of rigidity is eccentric in both
    directions.
    """
    x1 = x0 + width
    xs = np.linspace(0.0, width, 5)  # column lines along x
    ys = np.linspace(0.0, depth, 4)  # column lines along y
    elements = [
        _frame([x0, 0.0], [x1, 0.0], xs, col * strong_x),
        _frame([x0, 0.4 * depth], [x1, 0.4 * depth], xs, col),
        _frame([x0, depth], [x1, depth], xs, col),
        _frame([x0, 0.0], [x0, depth], ys, col),
        _frame([x0 + 0.35 * width, 0.0], [x0 + 0.35 * width, depth], ys, col),
        _frame([x1, 0.0], [x1, depth], ys, col * strong_y),
    ]
    return {
        "name": name,
        "storey_heights": [3.2] * storeys,
        "slab": [[x0, 0.0], [x1, 0.0], [x1, depth], [x0, depth]],
        "mass_per_area": 900.0,
        "element": elements,
    }


def column_size(storeys: int) -> float:
    """Square column side [m] growing with height, so periods stay plausible (T1 ~ 0.1-0.15 N s)."""
    return float(min(0.40 + 0.02 * storeys, 2.4))


def uniform_pair(storeys: int, gap: float = 0.05, contact: str = "impulse", dt: float = 0.005, duration: float | None = None,
                 integrator: str = "hht"):
    """Two adjacent uniform-plan buildings of ``storeys`` storeys each, ``gap`` apart along x.

    "west" is 24 x 16 m, "east" 18 x 16 m with slenderer columns (different periods, so
    they move out of phase), both with eccentric stiffness. El Centro at 0.32 g, 20 deg
    from x. Every storey has a partner at the same level: ``storeys`` slab pairs.
    """
    from pounding.io.scene import parse_scene

    c = column_size(storeys)
    data = {
        "title": f"uniform pair, {storeys} storeys, gap {gap} m",
        "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": 20.0},
        "analysis": {"integrator": integrator, "dt": dt, "contact": contact},
        "building": [
            _box("west", 0.0, 24.0, 16.0, storeys, c, 1.4, 1.0),
            _box("east", 24.0 + gap, 18.0, 16.0, storeys, 0.85 * c, 1.0, 1.5),
        ],
    }
    if contact == "impulse":
        data["analysis"]["restitution"] = 0.5
    if duration is not None:
        data["analysis"]["duration"] = duration
    return parse_scene(data, source=None)


def uniform_row(n: int, storeys: int, gap: float = 0.05, dt: float = 0.005, duration: float | None = None):
    """A row of ``n`` uniform-plan buildings of ``storeys`` storeys along x, ``gap`` apart, alternating
    the two types of :func:`uniform_pair` ("west"-like 24 m wide, "east"-like 18 m with slenderer
    columns), so that the first two are ``uniform_pair``'s pair. Every neighbour shares every level.
    """
    from pounding.io.scene import parse_scene

    c = column_size(storeys)
    types = [(24.0, c, 1.4, 1.0), (18.0, 0.85 * c, 1.0, 1.5)]
    buildings, x0 = [], 0.0
    for k in range(n):
        width, col, sx, sy = types[k % 2]
        buildings.append(_box(f"b{k + 1}", x0, width, 16.0, storeys, col, sx, sy))
        x0 += width + gap
    data = {
        "title": f"uniform row of {n}, {storeys} storeys, gap {gap} m",
        "ground_motion": {"record": "elcentro", "pga": 0.32, "angle": 20.0},
        "analysis": {"integrator": "hht", "dt": dt, "contact": "impulse", "restitution": 0.5},
        "building": buildings,
    }
    if duration is not None:
        data["analysis"]["duration"] = duration
    return parse_scene(data, source=None)


def tiled(scene, times: int):
    """The scene with its record repeated ``times`` times end to end (same dt and scaling)."""
    from pounding.io.ground_motion import GroundMotion

    gm = scene.ground_motion
    dt = gm.dt
    acc = np.tile(np.asarray(gm.acc), times)
    t = gm.t[0] + np.arange(acc.size) * dt
    new = GroundMotion(t=t, acc=acc, name=f"{gm.name} x{times}", source=gm.source, angle=gm.angle)
    return scene.with_ground_motion(new).with_analysis(duration=None)
