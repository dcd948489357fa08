"""The clearance every building needs to every retaining wall, from one run without contact.

A wall never moves, so the clearance a building needs to it is its own motion toward the wall:
for a face segment with unit normal n pointing from the face toward the building's side, a slab
vertex i (rest position r_i, displacement d_i(t), rotation included) approaches the face by
``-d_i(t) . n``. The face, moved parallel to itself to a clear distance c from the nearest of the
slab's vertices that face it at rest (those whose foot on the face's line falls within the
segment), is never touched when

    c > required = max over t and i of ( -d_i(t) . n - (s_i - s_min) ),

s_i the rest distance of vertex i to the face's line and s_min their smallest (a vertex set back
from the nearest must move that much farther). Only slabs at or below the wall's top count. The
maximum is over the run's step ends (the no-contact run records every step).

A vertex whose straight path to the face at rest passes through another building at its level
(a slab of it, or its facade) is *screened*: it would strike that building first, so it asks no
clearance of the wall (the rule that screens a pair of buildings with a third between them,
:func:`pounding.framework.model.walls.open_vertices`). A building screened from a wall at every
slab is not in the report.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.model.levels import reaches
from pounding.framework.model.walls import open_vertices, segment_frame, segments, side


@dataclass
class WallClearance:
    """The clearance [m] building ``building`` needs to wall ``wall``, and what it has at rest.

    required : the smallest clear distance at rest at which no slab ever touches the face (above).
    current : the clear distance at rest in the scene (the nearest facing vertex of the governing slab).
    storey : 1-based storey of the governing slab; time [s] of the governing instant; segment: its
    0-based face segment. ``storey`` 0 when no slab of the building faces the wall.
    """

    building: str
    wall: str
    required: float
    current: float
    storey: int
    time: float
    segment: int

    @property
    def ok(self) -> bool:
        """Whether the clearance at rest exceeds the required one."""
        return self.current > self.required

    def to_dict(self) -> dict:
        return {"building": self.building, "wall": self.wall, "required": self.required, "current": self.current,
                "storey": self.storey, "time": self.time, "segment": self.segment, "ok": self.ok}


def wall_clearances(scene, result) -> list[WallClearance]:
    """:class:`WallClearance` of every building and wall of ``scene`` that face each other, no other
    building between them (module docstring), from the histories of ``result`` (a run of the scene,
    without contact for the building's free motion)."""
    out = []
    for wall in scene.walls:
        for i in range(len(scene.buildings)):
            c = _clearance(scene, i, wall, result)
            if c is not None:
                out.append(c)
    return out


def _clearance(scene, i: int, wall, result) -> WallClearance | None:
    """The clearance building i of ``scene`` needs to ``wall`` (its governing slab and segment), or
    None where none of its slabs faces the wall unscreened."""
    building = scene.buildings[i]
    best = None
    for f, slab in enumerate(building.slabs):
        if not reaches(slab.elevation, wall.top):
            continue
        for k, (p0, p1) in enumerate(segments(wall.face)):
            s = side(p0, p1, slab.centre)
            if s == 0.0:
                continue
            _, facing, left = open_vertices(scene, i, f, p0, p1)
            n = s * segment_frame(p0, p1)[2]  # from the face toward the slab's side
            dist = s * left
            if not np.any(facing):
                continue
            d = result.contact_offsets(building.name, f)[:, facing]  # (nt, m, 2), as the contact geometry moves them
            toward = -(d @ n) - (dist[facing] - dist[facing].min())[None, :]  # (nt, m)
            t_i, v_i = np.unravel_index(int(np.argmax(toward)), toward.shape)
            need = max(float(toward[t_i, v_i]), 0.0)
            if best is None or need > best.required:
                best = WallClearance(building.name, wall.name, need, float(dist[facing].min()), f + 1, float(result.t[t_i]), k)
    return best


def wall_gaps(scene, *, progress=None) -> list[WallClearance]:
    """:func:`wall_clearances` from one run of ``scene`` without contact."""
    from pounding.framework.post.run import run

    # without contact, recording every step (as the pairs' study runs it)
    return wall_clearances(scene, run(scene.with_analysis(contact="none", contact_params={}, output_every=1), progress=progress))


def format_walls(clearances: list[WallClearance]) -> str:
    """The clearances as text, one line each."""
    lines = []
    for c in clearances:
        verdict = "OK" if c.ok else "TOO CLOSE"
        lines.append(f"clearance of {c.building!r} to wall {c.wall!r}: needs {c.required:.4f} m (storey {c.storey} toward face "
                     f"segment {c.segment} at t = {c.time:.3f} s), has {c.current:.4f} m at rest  {verdict}")
    return "\n".join(lines)
