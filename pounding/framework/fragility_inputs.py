"""What a fragility study needs from the ground-motion side: a record set and an intensity measure.

The study engine (:mod:`pounding.framework.fragility`) uses only this small
interface:

* a record set: a list of ``(name, motion)``, where ``motion`` is anything
  ``Scene.with_ground_motion`` accepts and that has ``scaled(factor)``;
* an intensity measure: ``(label, unit, fn)`` with ``fn(motion) -> float``,
  positive and proportional to the motion's amplitude (``fn(m.scaled(s)) ==
  s * fn(m)``), so a record is brought to a level by one factor,
  ``level / fn(motion)``. It runs only in the calling process.

Today it offers what exists in the package: a folder of AT2 records (each a
single component, shaken along the scene's ``ground_motion.angle``), or the
scene's own record; and PGA. The ground-motion work of issue #14 (pairs,
named sets such as the FEMA P695 far-field set, Sa(T1), geometric mean,
RotD50/RotD100) plugs in here: :func:`record_set` and
:func:`intensity_measure` are the only two functions to point at it.
"""

from __future__ import annotations

from pathlib import Path

from pounding.errors import InputError

__all__ = ["INTENSITY_MEASURES", "intensity_measure", "record_set"]

#: Intensity measures available today: name -> (label, unit).
INTENSITY_MEASURES = {"pga": ("PGA", "g")}


def _pga(motion) -> float:
    from pounding.io.ground_motion import G

    return motion.pga / G


def intensity_measure(name: str, scene):
    """``(label, unit, fn)`` for the intensity measure ``name`` (case-insensitive).

    Parameters
    ----------
    name : str
        ``"pga"`` (peak ground acceleration, in g).
    scene : Scene
        For measures that depend on the buildings (Sa(T1)); unused by PGA.
    """
    key = str(name).strip().lower()
    if key not in INTENSITY_MEASURES:
        raise InputError(f"unknown intensity measure {name!r}; expected one of: {', '.join(INTENSITY_MEASURES)}", field="--im")
    label, unit = INTENSITY_MEASURES[key]
    return label, unit, _pga


def record_set(spec, scene) -> list[tuple[str, object]]:
    """The records of a study, ``[(name, motion)]`` in a stable order.

    Parameters
    ----------
    spec : None or path
        None: the scene's own record (one record). A folder: every ``.AT2``
        file in it (any case), by file name, named by the file's stem.
    scene : Scene
        Each record shakes along the scene's ``ground_motion.angle``.
    """
    from pounding.io.ground_motion import read_at2

    if spec is None:
        m = scene.ground_motion
        return [(m.name or "record", m)]
    folder = Path(spec)
    if not folder.is_dir():
        raise InputError(f"{str(folder)!r} is not a folder of records", field="--records")
    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() == ".at2")
    if not files:
        raise InputError(f"no .AT2 files in {str(folder)!r}", field="--records")
    angle = scene.ground_motion.angle
    out: dict[str, object] = {}
    for p in files:
        if p.stem in out:
            raise InputError(f"two records named {p.stem!r} in {str(folder)!r}", field="--records")
        m = read_at2(p)  # an unreadable record names its file and line
        out[p.stem] = m.rotated(angle - m.angle)
    return list(out.items())
