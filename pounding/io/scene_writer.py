"""Write a :class:`~pounding.framework.model.scene.Scene` back to a scene file (TOML) that loads back equal.

Everything is written explicitly, in SI units, as :func:`pounding.io.scene.load_scene` reads it:
every storey's slab polygon, mass, centre of mass and polar inertia (so nothing is re-derived
from defaults), each element's own table (:meth:`~pounding.elements.base.PlanarElement.to_table`),
damping, P-Delta, stiffness modifiers, the analysis options and the ground motion. The ground
motion is written as the samples the scene holds (after any scaling, baseline correction or
intensity target), one two-column file per component beside the scene
(``<scene stem>.ground_motion.txt``, or ``.first.txt`` / ``.second.txt`` for a pair), in m/s2,
with ``repr`` floats: the scene that loads back has the same numbers. Element lines are written
as start and angle (or end), so their unit directions come back to rounding (a few ulp).

:func:`scene_differences` compares two scenes field by field (used by the round-trip tests).
"""

from __future__ import annotations

from functools import cached_property

import json
import math
import re
from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

import numpy as np

#: relative tolerance of :func:`scene_differences` on a field, in units of the field's largest magnitude:
#: an element direction read from an angle is cos/sin of atan2 of the written one, a few roundings
ULPS = 8


# --------------------------------------------------------------------------- the tables
def scene_table(scene, record_stem: str) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The scene as a TOML-ready dict, and the record files it names: file name -> (m, 2) array of
    (time [s], acceleration [m/s2]). ``record_stem`` is the stem of those file names."""
    ground, records = _ground_motion(scene.ground_motion, record_stem)
    table: dict[str, Any] = {}
    if scene.source is not None:
        table["title"] = f"written by pounding from {Path(scene.source).name}"
    table["building"] = [_building(b) for b in scene.buildings]
    table["ground_motion"] = ground
    table["analysis"] = _analysis(scene.analysis)
    if scene.links:
        from pounding.io.scene_links import link_table

        table["link"] = [link_table(k) for k in scene.links]
    if scene.contacts:
        table["contact"] = [_contact(r) for r in scene.contacts]
    if scene.walls:
        table["wall"] = [_wall(w) for w in scene.walls]
    return table, records


def _law_name(law) -> str:
    """A contact law as the scene names it: its registered name, ``module:Class`` for a class."""
    return law if isinstance(law, str) else getattr(law, "name", "") or f"{law.__module__}:{law.__qualname__}"


def _contact(r) -> dict[str, Any]:
    """A ``[[contact]]`` table: the pair, its law and its bumper (when it has one)."""
    out: dict[str, Any] = {"between": list(r.between), "law": {"name": _law_name(r.law), **r.params}}
    b = getattr(r, "bumper", None)
    if b is not None:
        out["bumper"] = {"on": b.on, "storeys": list(b.storeys), "thickness": float(b.thickness),
                         "compressible": float(b.compressible), "law": {"name": _law_name(b.law), **b.params}}
    return out


def _wall(w) -> dict[str, Any]:
    out: dict[str, Any] = {"name": w.name, "face": [[float(x), float(y)] for x, y in w.face], "top": float(w.top)}
    if w.law is not None:
        out["contact"] = {"name": _law_name(w.law), **w.params}
    elif w.params:
        out["contact"] = dict(w.params)
    return out


def _building(b) -> dict[str, Any]:
    out: dict[str, Any] = {
        "name": b.name,
        "storey_heights": [float(h) for h in b.storey_heights],
        **_slabs([[[float(x), float(y)] for x, y in s.vertices] for s in b.slabs]),
        "mass": _one_or_list([float(s.mass) for s in b.slabs]),
        "centre_of_mass": [[float(c) for c in s.centre] for s in b.slabs],
        "polar_inertia": [float(s.polar_inertia) for s in b.slabs],
        "damping": _damping(b.damping),
    }
    if b.p_delta is not None:
        out["p_delta"] = {"loads": list(b.p_delta.loads)} if b.p_delta.loads is not None else {"load_factor": b.p_delta.load_factor}
    modifiers = b.element_modifiers()
    out["element"] = [
        {"type": e.name, **({"first_storey": e.first_storey} if e.first_storey != 1 else {}), **e.to_table(),
         **({"stiffness_modifier": m} if m != 1.0 else {})}
        for e, m in zip(b.elements, modifiers)
    ]
    return out


def _slabs(polygons: list) -> dict[str, Any]:
    """``slab`` (one polygon for every storey) when the storeys agree, else ``slabs``."""
    return {"slab": polygons[0]} if all(p == polygons[0] for p in polygons) else {"slabs": polygons}


def _one_or_list(values: list) -> Any:
    """One value for every storey when they agree, else the list (the loader reads both)."""
    return values[0] if all(v == values[0] for v in values) else values


def _damping(d) -> dict[str, Any]:
    ratio = list(d.ratio) if isinstance(d.ratio, tuple) else d.ratio
    out: dict[str, Any] = {"type": d.kind, "ratio": ratio}
    if d.kind == "rayleigh" and d.periods is not None:
        out["periods"] = list(d.periods)
    elif d.kind != "modal":
        out["modes"] = list(d.modes)
    return out


def _analysis(a) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if a.integrator is not None:
        out["integrator"] = {"name": a.integrator, **a.integrator_params}
    for key in ("dt", "duration"):
        if getattr(a, key) is not None:
            out[key] = float(getattr(a, key))
    out["contact"] = {"name": a.contact, **a.contact_params}
    out["output_every"] = a.output_every
    out["energy_tolerance"] = a.energy_tolerance
    if a.impact_force:
        out["impact_force"] = dict(a.impact_force)
    if a.silence:
        out["silence"] = list(a.silence)
    return out


def _ground_motion(gm, stem: str) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The [ground_motion] table and its record files (one component: ``record``; a pair: ``components``)."""
    comps = gm.components
    if len(comps) == 1:
        name = f"{stem}.ground_motion.txt"
        return ({"record": name, "format": "two_columns", "units": "m/s2", "angle": float(gm.angle)},
                {name: np.column_stack([comps[0].t, comps[0].acc])})
    names = [f"{stem}.ground_motion.{which}.txt" for which in ("first", "second")]
    records = {n: np.column_stack([c.t, c.acc]) for n, c in zip(names, (gm.first, gm.second))}
    return ({"components": [{"record": n, "format": "two_columns", "units": "m/s2"} for n in names],
             "angle": float(gm.angle)}, records)


# --------------------------------------------------------------------------- TOML text
_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE_KEY.match(k) else json.dumps(k)


def _value(v: Any) -> str:
    """One TOML value: inline tables and arrays, floats with ``repr`` (read back to the same double)."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        x = float(v)
        return "nan" if math.isnan(x) else ("inf" if x == math.inf else ("-inf" if x == -math.inf else repr(x)))
    if isinstance(v, str):
        return json.dumps(v)  # a JSON string is a TOML basic string
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def to_toml(table: dict[str, Any]) -> str:
    """TOML text of a scene table: top-level values, then ``[[building]]`` (with ``[[building.element]]``),
    ``[ground_motion]`` and ``[analysis]``; deeper tables inline."""
    lines = [f"{_key(k)} = {_value(v)}" for k, v in table.items() if k not in ("building", "ground_motion", "analysis", "link")]
    for b in table.get("building", []):
        lines += ["", "[[building]]"]
        lines += [f"{_key(k)} = {_value(v)}" for k, v in b.items() if k != "element"]
        for e in b.get("element", []):
            lines += ["", "[[building.element]]"]
            lines += [f"{_key(k)} = {_value(v)}" for k, v in e.items()]
    for section in ("ground_motion", "analysis"):
        if section in table:
            lines += ["", f"[{section}]"]
            lines += [f"{_key(k)} = {_value(v)}" for k, v in table[section].items()]
    for link in table.get("link", []):
        lines += ["", "[[link]]"] + [f"{_key(k)} = {_value(v)}" for k, v in link.items()]
    return "\n".join(lines) + "\n"


def write_scene(scene, path: str | Path) -> Path:
    """Write ``scene`` to the TOML file ``path`` and its ground motion beside it (module docstring).

    :func:`pounding.io.scene.load_scene` of ``path`` gives a scene equal to ``scene``
    (:func:`scene_differences` is empty). Its folder is made when missing. Returns ``path``.

    Raises
    ------
    NotImplementedError
        When an element type has no :meth:`~pounding.elements.base.PlanarElement.to_table`.
    """
    path = Path(path)
    table, records = scene_table(scene, path.stem)
    path.parent.mkdir(parents=True, exist_ok=True)  # as write_results makes its folder
    for name, data in records.items():
        with open(path.parent / name, "w") as fh:
            fh.write("# time [s], ground acceleration [m/s2], written by pounding\n")
            fh.writelines(f"{t!r} {a!r}\n" for t, a in data.tolist())
    path.write_text(to_toml(table))
    return path


# --------------------------------------------------------------------------- comparison
#: fields that name where a thing came from, not what it is
_PROVENANCE = {"source", "name"}


def scene_differences(a, b, *, ulps: int = ULPS) -> list[str]:
    """The fields where two scenes differ (empty: equal), as key paths (``buildings[1].elements[0].direction``).

    Numbers compare within ``ulps`` roundings of the field's largest magnitude (module docstring);
    everything else exactly. The scene's ``source`` and a ground motion's ``name`` and ``source``
    (where a record was read from) are not compared; building names are.
    """
    out: list[str] = []
    _compare(a, b, "scene", ulps, out)
    return out


def _compare(a: Any, b: Any, where: str, ulps: int, out: list[str]) -> None:
    if isinstance(a, (np.ndarray, float, np.floating)) or isinstance(b, (np.ndarray, float, np.floating)):
        x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        finite = np.concatenate([x.ravel(), y.ravel()])
        scale = float(np.max(np.abs(finite[np.isfinite(finite)]), initial=0.0))  # NaN marks padding, not a size
        if x.shape != y.shape or not np.allclose(x, y, rtol=0.0, atol=ulps * np.finfo(float).eps * scale, equal_nan=True):
            out.append(where)
        return
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        if len(a) != len(b):
            out.append(where)
            return
        for i, (x, y) in enumerate(zip(a, b)):
            _compare(x, y, f"{where}[{i}]", ulps, out)
        return
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            out.append(where)
            return
        for k in a:
            _compare(a[k], b[k], f"{where}.{k}", ulps, out)
        return
    if type(a) is not type(b):
        out.append(where)
        return
    if is_dataclass(a):
        provenance = _PROVENANCE if where.endswith(("ground_motion", "first", "second")) or where == "scene" else set()
        for f in fields(a):
            if f.name not in provenance and not (where == "scene" and f.name == "source"):
                _compare(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}", ulps, out)
        # attributes set beside the fields (an element's first_storey, set by the framework): part of what it is
        # (not provenance, nor values cached on first use: a record's dt)
        extra_a, extra_b = ({k: v for k, v in vars(x).items() if k not in {f.name for f in fields(x)} and k not in provenance
                             and not isinstance(getattr(type(x), k, None), cached_property)} for x in (a, b))
        if extra_a or extra_b:
            _compare(extra_a, extra_b, where, ulps, out)
        return
    if hasattr(a, "__dict__") and not isinstance(a, type):
        _compare(vars(a), vars(b), where, ulps, out)
        return
    if a != b:
        out.append(where)
