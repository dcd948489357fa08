"""The structure of a scene file checked in words: every problem found, reported in one voice.

:func:`scene_problems` collects every structural problem of a parsed scene
(JSON schemas of the core and of each element plugin, plugin names and
parameters, the keys of ``[ground_motion]``) as :class:`Problem` objects, in
the order they are reported: unknown keys and names first, with the closest
known one (``unknown key 'colums' (did you mean 'columns'?)``, difflib), then
the rest; within each, in the order of the file. Messages never show raw
JSON-schema text. :mod:`pounding.io.scene` raises the first one.
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass
from typing import Any, Mapping

from pounding.errors import InputError


def _path(parts) -> str:
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


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


def framework_element_keys() -> frozenset:
    """Keys every element table takes besides its plugin's own (``type``, ``stiffness_modifier``):
    read from the element items of the scene schema, so a key added there is excluded here too."""
    from pounding.io.scene_schema import BUILDING

    return frozenset(["type", *BUILDING["properties"]["element"]["items"].get("properties", {})])


def _element_problems(data: Mapping) -> list[Problem]:
    from pounding.framework.model.registry import ELEMENTS

    framework_keys = framework_element_keys()
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
            body = {key: val for key, val in table.items() if key not in framework_keys}
            out += schema_problems(body, ELEMENTS.get(table["type"]).schema, where)
    return out


def _plugin_problems(data: Mapping) -> list[Problem]:
    """Unknown plugin names and parameters in [analysis] and the [[contact]] tables (their values
    are checked by the plugin; a ``module:Class`` is imported and checked when the scene is built)."""
    from pounding.framework.model.registry import CONTACT_LAWS, INTEGRATORS

    if not isinstance(data, Mapping):
        return []
    places = []
    analysis = data.get("analysis")
    if isinstance(analysis, Mapping):
        places += [(("analysis", key), analysis.get(key), registry) for key, registry in (("integrator", INTEGRATORS), ("contact", CONTACT_LAWS))]
    contacts = data.get("contact")
    for i, table in enumerate(contacts if isinstance(contacts, list) else ()):
        if isinstance(table, Mapping):
            places.append((("contact", i, "law"), table.get("law"), CONTACT_LAWS))
    from pounding.framework.model.registry import HYSTERESIS

    links = data.get("link")
    for i, table in enumerate(links if isinstance(links, list) else ()):
        if isinstance(table, Mapping) and isinstance(table.get("law"), Mapping):
            # its parameters: the law's own, and a yielding law's stiffness, yield_force, hardening (checked on building it)
            places.append((("link", i, "law"), {"name": table["law"].get("name")}, HYSTERESIS))
    walls = data.get("wall")
    for i, table in enumerate(walls if isinstance(walls, list) else ()):
        if isinstance(table, Mapping) and "contact" in table:
            value = table["contact"]
            if isinstance(value, Mapping) and "name" not in value:  # [analysis] contact's law, its parameters
                default = analysis.get("contact", "impulse") if isinstance(analysis, Mapping) else "impulse"
                name = default if isinstance(default, str) else default.get("name") if isinstance(default, Mapping) else None
                value = {"name": name, **value} if isinstance(name, str) else None
            places.append((("wall", i, "contact"), value, CONTACT_LAWS))
    out = []
    for at, value, registry in places:
        name = value if isinstance(value, str) else value.get("name") if isinstance(value, Mapping) else None
        if not isinstance(name, str) or ":" in name:
            continue
        where = at if isinstance(value, str) else at + ("name",)
        if name not in registry:
            out.append(Problem(where, unknown_key_message(name, registry.names(), registry.kind), True))
            continue
        if isinstance(value, Mapping):
            accepted = ["name"] + plugin_parameters(registry.get(name))
            for param in value:
                if param not in accepted:
                    out.append(Problem(at + (param,), unknown_key_message(param, accepted), True))
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
    return " or ".join(forms) or "see docs/scene-reference.md"
