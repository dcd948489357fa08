"""Read a scene file (TOML) into a validated, immutable :class:`~pounding.framework.model.Scene`.

Checks run in three layers, each stopping at the first problem with one
message naming the file, the key path (``building[0].element[2].columns``)
and what was expected:

1. TOML syntax (``tomllib``) and non-finite numbers (TOML allows nan/inf);
2. structure and types against a JSON schema (``jsonschema``), including each
   element plugin's own schema;
3. meaning: polygon validity, one value per storey, mass and inertia, elements
   standing on their slabs, slabs overlapping at rest, plugin names and
   parameters, the ground-motion record.
"""

from __future__ import annotations

import inspect
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from pounding.errors import InputError
from pounding.framework.model import Analysis, Building, Damping, Scene, Slab

LENGTH_TOL = 1e-6  # [m] tolerance for "on the slab" and "same elevation"


def _path(parts) -> str:
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


# --------------------------------------------------------------------------- structure
@dataclass(frozen=True)
class Problem:
    """One thing wrong with the scene's structure, at a key path (a list of keys and 0-based indices)."""

    path: tuple
    message: str
    unknown: bool = False  # an unknown key or name: reported before every other problem

    def error(self) -> InputError:
        return InputError(self.message, field=_path(self.path) or "(top level)")


def unknown_key_message(key: str, known, what: str = "key") -> str:
    """``unknown key 'colums' (did you mean 'columns'?)``, or the accepted keys when none is close."""
    import difflib

    known = sorted(str(k) for k in known)
    close = difflib.get_close_matches(str(key), known, n=1, cutoff=0.6)
    if close:
        return f"unknown {what} {key!r} (did you mean {close[0]!r}?)"
    listing = "accepted keys" if what == "key" else "known"
    return f"unknown {what} {key!r}; {listing}: {', '.join(known) or 'none'}"


def schema_problems(instance: Any, schema: Mapping, prefix: list | tuple = ()) -> list[Problem]:
    """Every schema violation of ``instance``, in words (never raw JSON-schema text).

    Unknown keys are found through ``oneOf`` branches too: a key is unknown
    when no branch that describes that table knows it (``{ E, b, hh }`` against
    the two section forms gives "unknown key 'hh' (did you mean 'h'?)").
    """
    from jsonschema import Draft202012Validator

    prefix = tuple(prefix)
    out = []
    for err in Draft202012Validator(schema).iter_errors(instance):
        unknown = _unknown_keys(err)
        if unknown:
            out += [Problem(prefix + path, unknown_key_message(key, known), True) for path, key, known in unknown]
        else:
            out.append(_problem(err, prefix))
    return out


def _problem(err, prefix: tuple) -> Problem:
    """One schema error in words; a failed choice (oneOf) is described by the branch closest to the value."""
    here = tuple(err.absolute_path)
    if err.validator == "oneOf" and err.context and _choice_keys(err.schema) is None:
        branches: dict[int, list] = {}
        for e in err.context:
            branches.setdefault(e.relative_schema_path[0], []).append(e)
        fitting = [errs for errs in branches.values() if all(_fits_type(e, here) for e in errs)]
        if fitting:
            # the closest branch: no keys of another form, then the fewest errors
            errs = min(fitting, key=lambda es: (any(e.validator == "additionalProperties" for e in es), len(es)))
            return _problem(min(errs, key=lambda e: (e.validator != "required", len(e.absolute_path))), prefix)
    return Problem(prefix + here, _describe(err))


def _fits_type(err, here: tuple) -> bool:
    """False for a branch's error that only says the value has another type (a list given where a table goes)."""
    if tuple(err.absolute_path) != here:
        return True
    if err.validator == "type":
        return False
    if err.validator in ("oneOf", "anyOf") and err.context:
        return any(_fits_type(e, here) for e in err.context)
    return True


def _choice_keys(schema) -> list[str] | None:
    """The keys of an exclusive choice ``oneOf: [{required: [a], not: ...}, {required: [b], ...}]``, else None."""
    branches = schema.get("oneOf", []) if isinstance(schema, Mapping) else []
    if branches and all("not" in b and len(b.get("required", ())) == 1 for b in branches):
        return [b["required"][0] for b in branches]
    return None


def _unknown_keys(err) -> list[tuple[tuple, str, list]]:
    """(path of the key, key, keys known there) for every key no schema at its table accepts."""
    known: dict[tuple, set] = {}
    extra: dict[tuple, list] = {}
    stack = [err]
    while stack:
        e = stack.pop()
        stack.extend(e.context or ())
        path = tuple(e.absolute_path)
        if isinstance(e.instance, Mapping):
            known.setdefault(path, set()).update(_table_keys(e.schema))
        if e.validator == "additionalProperties" and isinstance(e.instance, Mapping):
            props = e.schema.get("properties", {})
            extra.setdefault(path, []).extend(k for k in e.instance if k not in props)
    out = []
    for path, keys in extra.items():
        for key in dict.fromkeys(keys):
            if key not in known.get(path, ()):
                out.append((path + (key,), key, known.get(path, set())))
    return out


def _table_keys(schema) -> set:
    """Keys a table schema accepts, through its oneOf / anyOf / allOf branches."""
    if not isinstance(schema, Mapping):
        return set()
    keys = set(schema.get("properties", ()))
    for word in ("oneOf", "anyOf", "allOf"):
        for branch in schema.get(word, ()):
            keys |= _table_keys(branch)
    return keys


def document_order(data: Any, path: tuple) -> tuple:
    """Sort key of a key path in the order its keys appear in the file (a missing key after its table's keys)."""
    key, node = [], data
    for p in path:
        if isinstance(node, Mapping):
            keys = list(node)
            key.append(keys.index(p) if p in keys else len(keys))
            node = node.get(p)
        elif isinstance(node, list) and isinstance(p, int):
            key.append(p)
            node = node[p] if p < len(node) else None
        else:
            key.append(0)
            node = None
    return tuple(key)


def scene_problems(data: Mapping) -> list[Problem]:
    """Every structural problem of a parsed scene, the order they are reported in.

    Unknown keys and names first (a misspelt key is often why a required one
    is missing), then the rest; within each, in the order of the file (the
    first building first). Covers the top level, ``[analysis]`` and its plugin
    parameters, ``[ground_motion]`` (keys; its values are checked on reading
    the record), every building and every element table (against its
    plugin's schema).
    """
    from pounding.io.scene_schema import scene_schema

    problems = _finite_problems(data, ())
    schema = scene_schema()
    gm = schema["properties"]["ground_motion"]
    # the record reader checks the values of [ground_motion]; here only its keys
    schema["properties"]["ground_motion"] = {**gm, "properties": {k: {} for k in gm["properties"]}}
    problems += schema_problems(data, schema)
    problems += _element_problems(data)
    problems += _plugin_problems(data)
    return sorted(problems, key=lambda p: (not p.unknown, document_order(data, p.path)))


def _finite_problems(obj: Any, parts: tuple) -> list[Problem]:
    if isinstance(obj, float) and not math.isfinite(obj):
        return [Problem(parts, f"expected a finite number, got {obj}")]
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += _finite_problems(v, parts + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            out += _finite_problems(v, parts + (i,))
    return out


def _element_problems(data: Mapping) -> list[Problem]:
    from pounding.framework.registry import ELEMENTS

    out = []
    buildings = data.get("building") if isinstance(data, Mapping) else None
    for i, b in enumerate(buildings if isinstance(buildings, list) else ()):
        elements = b.get("element") if isinstance(b, Mapping) else None
        for k, table in enumerate(elements if isinstance(elements, list) else ()):
            if not isinstance(table, Mapping) or not isinstance(table.get("type"), str):
                continue  # the scene schema reports it
            where = ("building", i, "element", k)
            if table["type"] not in ELEMENTS:
                out.append(Problem(where + ("type",), unknown_key_message(table["type"], ELEMENTS.names(), "element type"), True))
                continue
            body = {key: val for key, val in table.items() if key != "type"}
            out += schema_problems(body, ELEMENTS.get(table["type"]).schema, where)
    return out


def _plugin_problems(data: Mapping) -> list[Problem]:
    """Unknown plugin names and parameters in [analysis] (their values are checked by the plugin)."""
    from pounding.framework.registry import CONTACT_LAWS, INTEGRATORS

    analysis = data.get("analysis") if isinstance(data, Mapping) else None
    if not isinstance(analysis, Mapping):
        return []
    out = []
    for key, registry in (("integrator", INTEGRATORS), ("contact", CONTACT_LAWS)):
        value = analysis.get(key)
        name = value if isinstance(value, str) else value.get("name") if isinstance(value, Mapping) else None
        if not isinstance(name, str):
            continue
        where = ("analysis", key) if isinstance(value, str) else ("analysis", key, "name")
        if name not in registry:
            out.append(Problem(where, unknown_key_message(name, registry.names(), registry.kind), True))
            continue
        if isinstance(value, Mapping):
            accepted = ["name"] + plugin_parameters(registry.get(name))
            for param in value:
                if param not in accepted:
                    out.append(Problem(("analysis", key, param), unknown_key_message(param, accepted), True))
    return out


def plugin_parameters(cls) -> list[str]:
    """The keyword-only parameters of a plugin class's ``__init__`` (its scene parameters)."""
    sig = inspect.signature(cls.__init__)
    return [p for p, par in sig.parameters.items() if par.kind is inspect.Parameter.KEYWORD_ONLY]


def _describe(err) -> str:
    """A schema error in words an engineer reads without knowing JSON schema."""
    v = err.validator
    if v == "required":
        missing = [k for k in err.validator_value if isinstance(err.instance, Mapping) and k not in err.instance]
        return f"missing required key {missing[0]!r}" if missing else err.message
    if v in ("exclusiveMinimum", "minimum", "maximum", "exclusiveMaximum", "type", "enum", "minItems", "maxItems", "pattern"):
        return f"expected {_expectation(err)}, got {err.instance!r}"
    if v == "uniqueItems":
        return f"expected each name once, got {err.instance!r}"
    if v == "oneOf":
        choice = _choice_keys(err.schema)
        if choice is not None and isinstance(err.instance, Mapping):
            given = [k for k in choice if k in err.instance]
            if len(given) > 1:
                return f"give either {' or '.join(given)}, not both"
            return f"give {' or '.join(choice)}"
        return f"expected {_forms(err.schema)}, got {err.instance!r}"
    if v == "additionalProperties":
        props = err.schema.get("properties", {})
        extra = [k for k in err.instance if k not in props]
        return f"{', '.join(map(repr, extra))} does not go with this form; its keys: {', '.join(sorted(props))}"
    return f"not accepted here: {err.instance!r}"


def _expectation(err) -> str:
    s, v = err.schema, err.validator
    if v == "exclusiveMinimum":
        return f"a number > {s['exclusiveMinimum']}"
    if v == "minimum":
        return f"a number >= {s['minimum']}"
    if v == "maximum":
        return f"a number <= {s['maximum']}"
    if v == "exclusiveMaximum":
        return f"a number < {s['exclusiveMaximum']}"
    if v == "type":
        return {"number": "a number", "integer": "an integer", "string": "a string", "array": "a list", "object": "a table"}.get(
            s["type"], s["type"]
        )
    if v == "enum":
        return "one of " + ", ".join(map(repr, s["enum"]))
    if v == "minItems":
        return f"at least {s['minItems']} items"
    if v == "maxItems":
        return f"at most {s['maxItems']} items"
    return f"a value matching {s.get('pattern')}"


def _forms(schema: Mapping) -> str:
    forms = []
    for sub in schema.get("oneOf", []):
        if "required" in sub:
            forms.append("{" + ", ".join(sub["required"]) + "}")
        elif "oneOf" in sub:
            forms.append(_forms(sub))
        elif "type" in sub:
            forms.append({"number": "a number", "array": "a list", "string": "a string", "object": "a table"}.get(sub["type"], sub["type"]))
    return " or ".join(forms) or "see the README"


# --------------------------------------------------------------------------- buildings
def _per_storey(table: Mapping, key: str, n: int, where: list) -> list:
    value = table[key]
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(f"expected one value or a list of {n} (one per storey), got {len(value)}", field=_path(where + [key]))
        return list(value)
    return [value] * n


def _slab_polygons(table: Mapping, n: int, where: list) -> list[np.ndarray]:
    from pounding.contact.geometry import ccw, is_simple

    if ("slab" in table) == ("slabs" in table):
        raise InputError("give exactly one of slab (one polygon for every storey) or slabs (one per storey)", field=_path(where + ["slab"]))
    if "slab" in table:
        polys, keys = [table["slab"]] * n, [["slab"]] * n
    else:
        if len(table["slabs"]) != n:
            raise InputError(f"expected {n} polygons (one per storey), got {len(table['slabs'])}", field=_path(where + ["slabs"]))
        polys, keys = table["slabs"], [["slabs", i] for i in range(n)]
    out = []
    for poly, key in zip(polys, keys):
        v = np.asarray(poly, dtype=float)
        ok, reason = is_simple(v)
        if not ok:
            raise InputError(f"the slab polygon is not a simple polygon: {reason}", field=_path(where + key))
        out.append(ccw(v))
    return out


def _damping(table: Mapping | None, where: list) -> Damping:
    if table is None:
        return Damping()
    kind = table.get("type", "rayleigh")
    ratio = table.get("ratio", 0.05)
    field = _path(where + ["damping"])
    if kind == "rayleigh":
        if isinstance(ratio, list):
            raise InputError("Rayleigh damping takes one ratio", field=field + ".ratio")
        if "periods" in table and "modes" in table:
            raise InputError("give modes or periods, not both", field=field)
        modes = tuple(table.get("modes", (1, 3)))
        if "periods" not in table and (len(modes) != 2 or modes[0] == modes[1]):
            raise InputError("Rayleigh damping needs two different modes, e.g. [1, 3]", field=field + ".modes")
        periods = tuple(float(p) for p in table["periods"]) if "periods" in table else None
        if periods is not None and periods[0] == periods[1]:
            raise InputError("Rayleigh damping needs two different periods", field=field + ".periods")
        return Damping("rayleigh", float(ratio), modes, periods)
    if kind == "modal":
        return Damping("modal", tuple(float(r) for r in ratio) if isinstance(ratio, list) else float(ratio), ())
    if isinstance(ratio, list):
        raise InputError("stiffness-proportional damping takes one ratio", field=field + ".ratio")
    modes = tuple(table.get("modes", (1,)))
    if len(modes) != 1:
        raise InputError("stiffness-proportional damping takes one mode, e.g. [1]", field=field + ".modes")
    return Damping("stiffness", float(ratio), modes)


def _building(table: Mapping, index: int) -> Building:
    from pounding.contact.geometry import polygon_properties
    from pounding.framework.registry import ELEMENTS

    where = ["building", index]
    heights = tuple(float(h) for h in table["storey_heights"])
    n = len(heights)
    polys = _slab_polygons(table, n, where)
    props = [polygon_properties(p) for p in polys]  # (area, centroid, polar moment about centroid)

    if ("mass" in table) == ("mass_per_area" in table):
        raise InputError("give exactly one of mass [kg] or mass_per_area [kg/m2]", field=_path(where + ["mass"]))
    if "mass" in table:
        masses = [float(m) for m in _per_storey(table, "mass", n, where)]
    else:
        masses = [float(m) * a for m, (a, _, _) in zip(_per_storey(table, "mass_per_area", n, where), props)]

    centres = [c for _, c, _ in props]
    if "centre_of_mass" in table:
        cm = table["centre_of_mass"]
        if len(cm) != n:
            raise InputError(f"expected {n} points (one per storey), got {len(cm)}", field=_path(where + ["centre_of_mass"]))
        centres = [np.asarray(c, dtype=float) for c in cm]
    if "polar_inertia" in table:
        J = table["polar_inertia"]
        if len(J) != n:
            raise InputError(f"expected {n} values (one per storey), got {len(J)}", field=_path(where + ["polar_inertia"]))
        inertia = [float(j) for j in J]
    else:
        # uniform lamina: m * Ip / A about the centroid, moved to the centre of mass by parallel axes
        inertia = [m * (ip / a + float(np.sum((c - c0) ** 2))) for m, (a, c0, ip), c in zip(masses, props, centres)]

    elevations = np.cumsum(heights)
    slabs = tuple(
        Slab(vertices=p, mass=m, centre=np.asarray(c, dtype=float), polar_inertia=j, elevation=float(z))
        for p, m, c, j, z in zip(polys, masses, centres, inertia, elevations)
    )

    elements = []
    for k, etable in enumerate(table.get("element", [])):
        ewhere = where + ["element", k]
        cls = ELEMENTS.get(etable["type"], field=_path(ewhere + ["type"]))
        body = {key: val for key, val in etable.items() if key != "type"}  # checked by scene_problems
        try:
            element = cls.from_table(body, storey_heights=heights)
        except InputError as exc:
            raise exc.located(field_prefix=_path(ewhere)) from None
        _check_on_slabs(element, slabs, ewhere)
        elements.append(element)
    if not elements:
        raise InputError(f"building {table['name']!r} has no elements: add frames or walls", field=_path(where + ["element"]))
    return Building(table["name"], heights, slabs, tuple(elements), _damping(table.get("damping"), where))


def distance_to_polygon(vertices: np.ndarray, p: np.ndarray) -> float:
    """Distance [m] from point p to a simple polygon (0 when p is inside or on it)."""
    a, b = vertices, np.roll(vertices, -1, axis=0)
    ab, ap = b - a, p - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    d = float(np.min(np.hypot(*(ap - t[:, None] * ab).T)))
    # crossing number: a ray from p towards +x crosses the boundary an odd number of times when inside
    crosses = ((a[:, 1] > p[1]) != (b[:, 1] > p[1])) & (p[0] < a[:, 0] + (p[1] - a[:, 1]) * ab[:, 0] / np.where(ab[:, 1] == 0, 1, ab[:, 1]))
    return 0.0 if np.count_nonzero(crosses) % 2 == 1 else d


def interior_point(vertices: np.ndarray) -> np.ndarray:
    """A point strictly inside a simple polygon (its centroid, unless that falls outside, as in
    an L's notch: then the centroid of an ear triangle that contains no other vertex)."""
    from pounding.contact.geometry import polygon_properties

    c = polygon_properties(vertices)[1]
    if _strictly_inside(vertices, c):
        return c
    k = len(vertices)
    for i in range(k):
        tri = vertices[[(i - 1) % k, i, (i + 1) % k]]
        p = tri.mean(axis=0)
        if _strictly_inside(vertices, p):
            return p
    return c


def _strictly_inside(vertices: np.ndarray, p: np.ndarray) -> bool:
    a, b = vertices, np.roll(vertices, -1, axis=0)
    ab, ap = b - a, p - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    on_boundary = np.min(np.hypot(*(ap - t[:, None] * ab).T)) <= LENGTH_TOL
    return not on_boundary and distance_to_polygon(vertices, p) == 0.0


def _check_on_slabs(element, slabs, where: list) -> None:
    a, b = element.plan_segment()
    for f in element.floors:
        slab = slabs[f - 1]
        for name, p in (("start", a), ("end", b)):
            if distance_to_polygon(slab.vertices, p) > LENGTH_TOL:
                raise InputError(
                    f"the element's {name} point ({p[0]:g}, {p[1]:g}) lies outside the slab of storey {f}",
                    field=_path(where),
                )


def _check_apart_at_rest(buildings: list[Building]) -> None:
    from pounding.contact.geometry import signed_gap

    for i, a in enumerate(buildings):
        for j in range(i + 1, len(buildings)):
            b = buildings[j]
            for fa, sa in enumerate(a.slabs):
                for fb, sb in enumerate(b.slabs):
                    if abs(sa.elevation - sb.elevation) < LENGTH_TOL:
                        g = signed_gap(sa.vertices, sb.vertices)
                        # a slab lying over another (even coincident) has its centroid inside the other
                        nested = distance_to_polygon(sb.vertices, interior_point(sa.vertices)) == 0.0 or distance_to_polygon(sa.vertices, interior_point(sb.vertices)) == 0.0
                        if nested and g >= -LENGTH_TOL:
                            raise InputError(
                                f"the slabs of {a.name!r} and {b.name!r} at storey {fa + 1} lie on top of each other at rest",
                                field=_path(["building", j, "slab"]),
                            )
                        if g < -LENGTH_TOL:
                            raise InputError(
                                f"the slabs of {a.name!r} and {b.name!r} at storey {fa + 1} overlap by {-g:.4g} m at rest",
                                field=_path(["building", j, "slab"]),
                            )


# --------------------------------------------------------------------------- analysis
def _plugin(value: Any, registry, field: str) -> tuple[str, dict]:
    if isinstance(value, str):
        name, params = value, {}
    else:
        params = dict(value)
        name = params.pop("name")
    cls = registry.get(name, field=field)
    _check_params(cls, params, field)
    return name, params


def _check_params(cls, params: dict, field: str) -> None:
    try:
        cls(**params)
    except TypeError:
        sig = inspect.signature(cls.__init__)
        accepted = [p for p in sig.parameters if p != "self" and sig.parameters[p].kind is inspect.Parameter.KEYWORD_ONLY]
        bad = [k for k in params if k not in accepted]
        raise InputError(
            f"unknown parameter(s) {', '.join(bad) or '?'} for {cls.name!r}; accepted: {', '.join(accepted) or 'none'}", field=field
        ) from None
    except InputError as exc:
        raise exc.located(field_prefix=field) from None


def _analysis(table: Mapping) -> Analysis:
    from pounding.framework.registry import CONTACT_LAWS, INTEGRATORS

    integrator, iparams = _plugin(table.get("integrator", "hht"), INTEGRATORS, "analysis.integrator")
    contact, cparams = _plugin(table.get("contact", "impulse"), CONTACT_LAWS, "analysis.contact")
    if "restitution" in table:
        cparams.setdefault("restitution", float(table["restitution"]))
        _check_params(CONTACT_LAWS.get(contact), cparams, "analysis.restitution")
    return Analysis(
        integrator=integrator,
        integrator_params=iparams,
        dt=table.get("dt"),
        duration=table.get("duration"),
        contact=contact,
        contact_params=cparams,
        output_every=int(table.get("output_every", 1)),
        energy_tolerance=float(table.get("energy_tolerance", 0.02)),
        silence=tuple(table.get("silence", ())),
    )


# --------------------------------------------------------------------------- entry point
def parse_scene(data: Mapping, *, source: Path | None = None) -> Scene:
    """Validate a parsed TOML document and build the Scene (errors carry no file; see load_scene)."""
    from pounding.io.ground_motion import load_record

    problems = scene_problems(data)
    if problems:
        raise problems[0].error()
    buildings = [_building(t, i) for i, t in enumerate(data["building"])]
    from pounding.framework.assembly import check_stable

    for i, b in enumerate(buildings):
        check_stable(b, field=f"building[{i}].element")
    names = [b.name for b in buildings]
    for i, nm in enumerate(names):
        if nm in names[:i]:
            raise InputError(f"building name {nm!r} is used twice", field=f"building[{i}].name")
    _check_apart_at_rest(buildings)
    base_dir = source.parent if source is not None else Path.cwd()
    gm = load_record(dict(data.get("ground_motion", {"record": "elcentro"})), base_dir=base_dir, file=str(source) if source else None)
    analysis = _analysis(data.get("analysis", {}))
    if analysis.dt is not None and analysis.duration is not None and analysis.dt > analysis.duration:
        raise InputError(f"dt ({analysis.dt} s) is longer than the duration ({analysis.duration} s)", field="analysis.dt")
    return Scene(tuple(buildings), gm, analysis, source)


def load_scene(path: str | Path) -> Scene:
    """Read, validate and build a scene from a TOML file.

    Raises
    ------
    InputError
        Naming the file, the key path and what was expected.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"cannot read the scene file: {exc.strerror}", file=str(path)) from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError:
        raise InputError("the scene file is not UTF-8 text", file=str(path)) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not valid TOML: {exc}", file=str(path)) from None
    try:
        return parse_scene(data, source=path)
    except InputError as exc:
        raise InputError(exc.message, file=exc.file or str(path), field=exc.field) from None
