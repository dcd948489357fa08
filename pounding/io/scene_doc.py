"""The scene reference page and the starting scene, generated from the schemas so they cannot drift.

:func:`reference_markdown` writes ``docs/scene-reference.md`` from

* the core schemas (:mod:`pounding.io.scene_schema`): the top level,
  ``[ground_motion]``, ``[analysis]``, ``[[building]]`` and its ``damping``;
* every registered element plugin's ``schema`` (nested tables such as a
  frame's sections included);
* every registered integrator and contact law: their keyword-only
  ``__init__`` parameters, documented in the class docstring's numpydoc
  *Parameters* section (type, ``[units]`` in the text), unless the class
  declares a ``schema`` of its own.

Each key's row gives its type, units, default (or *required*), accepted
range, an example and the description. :func:`undocumented` lists the keys
that lack a description (or numbers that lack units);
``tests/test_scene_reference.py`` fails on any, and when the checked-in page
differs from a fresh one (``python -m pounding.io.scene_doc`` rewrites it).

:func:`template_text` is the commented starting scene that ``pounding
template`` prints: the core keys with their descriptions, and the element
tables an element plugin gives as its schema's ``examples`` (elements on the
12 m x 8 m template slab with corners (0, 0) and (12, 8)).
"""

from __future__ import annotations

import inspect
import json
import math
import re
from pathlib import Path
from typing import Any, Mapping

#: Where the reference page lives in the source tree.
REFERENCE_PATH = Path(__file__).resolve().parents[2] / "docs" / "scene-reference.md"


# =============================================================================
# Plugin parameters as schemas
# =============================================================================


def plugin_schema(cls) -> dict:
    """The table schema of a plugin's parameters: its own ``schema``, or derived from ``__init__`` and its docstring."""
    own = getattr(cls, "schema", None)
    if isinstance(own, Mapping) and "properties" in own:
        return dict(own)
    docs = numpydoc_parameters(inspect.getdoc(cls) or "")
    sig = inspect.signature(cls.__init__)
    props = {}
    for name, par in sig.parameters.items():
        if par.kind is not inspect.Parameter.KEYWORD_ONLY:
            continue
        kind, text = docs.get(name, ("", ""))
        prop: dict[str, Any] = _type_from_doc(kind)
        if text:
            prop["description"] = text
            unit = UNIT_IN_TEXT.search(text)
            if unit:
                prop["units"] = unit.group(1)
            elif prop.get("type") in ("number", "integer"):
                prop["units"] = "-"
        if par.default is not inspect.Parameter.empty and par.default is not None:
            prop["default"] = par.default
        props[name] = prop
    return {"type": "object", "properties": props, "description": _first_paragraph(inspect.getdoc(cls) or "")}


_UNIT = r"(?:m|s|N|kg|Pa|rad|deg|g|J|Hz|mm|kN|MN|GPa|MPa)"
#: A unit in square brackets inside a parameter's description: [m], [N/m], [kg m^2], [N s/m], [N/m^1.5], [N/m^n].
UNIT_IN_TEXT = re.compile(rf"\[({_UNIT}(?:[ /*^]?(?:{_UNIT}|\d+(?:\.\d+)?|n))*)\]")


def numpydoc_parameters(doc: str) -> dict[str, tuple[str, str]]:
    """``{name: (type text, description)}`` from the *Parameters* section of a (dedented) numpydoc docstring."""
    lines = doc.splitlines()
    out: dict[str, tuple[str, str]] = {}
    heads = [i for i in range(len(lines) - 1) if lines[i].strip() and set(lines[i + 1].strip()) == {"-"}]
    starts = [i for i in heads if lines[i].strip() == "Parameters"]
    if not starts:
        return out
    start = starts[0] + 2
    end = next((i for i in heads if i > starts[0]), len(lines))
    name = None
    for line in lines[start:end]:
        if line.strip() and not line.startswith((" ", "\t")):
            head, _, kind = line.partition(":")
            name = head.strip()
            out[name] = (kind.strip(), "")
        elif line.strip() and name:
            kind, text = out[name]
            out[name] = (kind, (text + " " + line.strip()).strip())
    return out


def _type_from_doc(kind: str) -> dict:
    """A schema fragment from a numpydoc type: ``float, default 1`` -> number; ``{"a", "b"}`` -> enum."""
    kind = kind.strip()
    if kind.startswith("{"):
        values = kind[1 : kind.index("}")].split(",")
        return {"enum": [json.loads(v.strip().replace("'", '"')) for v in values if v.strip()]}
    kind = kind.split(",")[0].strip()
    if not kind:
        return {}
    return {"type": {"float": "number", "int": "integer", "str": "string", "bool": "boolean"}.get(kind, "string")}


def _first_paragraph(doc: str) -> str:
    return doc.strip().split("\n\n")[0].replace("\n", " ") if doc else ""


# =============================================================================
# Walking schemas
# =============================================================================


def table_properties(schema: Mapping) -> dict[str, dict]:
    """The keys of a table schema with their schemas, through oneOf / anyOf branches (first definition wins)."""
    out: dict[str, dict] = {}
    if not isinstance(schema, Mapping):
        return out
    for key, sub in schema.get("properties", {}).items():
        out.setdefault(key, sub)
    for word in ("oneOf", "anyOf", "allOf"):
        for branch in schema.get(word, ()):
            for key, sub in table_properties(branch).items():
                out.setdefault(key, sub)
    return out


def nested_tables(schema: Mapping) -> dict[str, dict]:
    """Keys of a property schema that is itself a table (or a list of tables): ``{sub-key: schema}``."""
    props = table_properties(schema)
    if props:
        return props
    for word in ("oneOf", "anyOf"):
        for branch in schema.get(word, ()):
            if branch.get("type") == "array":
                props = nested_tables(branch.get("items", {}))
                if props:
                    return props
    return {}


def _is_number(schema: Mapping) -> bool:
    if schema.get("type") in ("number", "integer"):
        return True
    if schema.get("type") == "array":
        return _is_number(schema.get("items", {}))
    return any(_is_number(b) for b in schema.get("oneOf", ()))


def undocumented(schema: Mapping, where: str, *, skip: tuple[str, ...] = ()) -> list[str]:
    """Key paths under ``where`` without a description, or numbers without units (nested tables included)."""
    out = []
    for key, sub in table_properties(schema).items():
        if key in skip:
            continue
        path = f"{where}.{key}"
        if not sub.get("description"):
            out.append(f"{path}: no description")
        elif _is_number(sub) and not sub.get("units"):
            out.append(f"{path}: a number without units")
        out += undocumented(_nested_owner(sub), path)
    return out


def _nested_owner(sub: Mapping) -> Mapping:
    """The table schema whose keys ``sub`` nests (itself, a branch, or a list's items)."""
    if table_properties(sub):
        return sub
    return {"properties": nested_tables(sub)}


def all_undocumented() -> list[str]:
    """Every undocumented key of the core and of every registered plugin."""
    from pounding.framework.model.registry import CONTACT_LAWS, ELEMENTS, INTEGRATORS

    from pounding.io.scene_schema import ANALYSIS, BUILDING, CONTACT, LINK, WALL, ground_motion_schema, SCENE

    out = undocumented(SCENE, "(top level)", skip=("analysis", "building", "ground_motion", "contact", "link", "wall"))
    out += undocumented(LINK, "link")
    out += undocumented(ground_motion_schema(), "ground_motion")
    out += undocumented(ANALYSIS, "analysis")
    out += undocumented(CONTACT, "contact")
    out += undocumented(WALL, "wall")
    out += undocumented(BUILDING, "building")
    for name in ELEMENTS.names():
        out += undocumented(ELEMENTS.get(name).schema, f"element {name!r}")
    for registry in (INTEGRATORS, CONTACT_LAWS):
        for name in registry.names():
            out += undocumented(plugin_schema(registry.get(name)), f"{registry.kind} {name!r}")
    return out


# =============================================================================
# TOML values
# =============================================================================


def toml_value(value: Any) -> str:
    """A value written as TOML (inline tables and arrays)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isfinite(value) and value == int(value) and abs(value) < 1e6:
            return f"{value:.1f}"
        if math.isfinite(value) and abs(value) >= 1e6:
            exp = int(math.floor(math.log10(abs(value)) / 3) * 3)  # engineering notation: 30e9, not 3e+10
            return f"{value / 10**exp:.6g}e{exp}"
        text = f"{value:.6g}"
        return text if any(c in text for c in ".e") else text + ".0"
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")


# =============================================================================
# Rows of the reference page
# =============================================================================


def type_text(schema: Mapping) -> str:
    """The type of a key in words."""
    if "enum" in schema:
        return "string"
    t = schema.get("type")
    if t == "array":
        items = schema.get("items", {})
        n = (schema.get("minItems"), schema.get("maxItems"))
        if n[0] == n[1] == 2 and items.get("type") == "number" and schema.get("units") == "m":
            return "point [x, y]"
        if n[0] == n[1] and items.get("type") in ("number", "integer"):
            return f"list of {n[0]} {items['type']}s"
        if items.get("type") == "array" and items.get("items", {}).get("type") == "number":
            return "points [[x, y], ...]"
        if items.get("type") == "array":
            return "list of polygons"
        inner = type_text(items) if items else "value"
        return f"list of {inner}s" if not inner.endswith(("]", ")")) else f"list of {inner}"
    if t == "object":
        return "table"
    if t in ("number", "integer", "string", "boolean"):
        return t
    if "oneOf" in schema:
        forms = []
        for b in schema["oneOf"]:
            if "required" in b and "type" not in b:
                continue
            forms.append("{ " + ", ".join(b["required"]) + " }" if b.get("type") == "object" and b.get("required") and "properties" in b and len(b) > 2 else type_text(b))
        if len(forms) == 2 and forms[1] == f"list of {forms[0]}s":
            return f"{forms[0]} or list of {forms[0]}s"
        return " or ".join(f for f in forms if f) or "table"
    if "properties" in schema:
        return "table"
    return "value"


def range_text(schema: Mapping) -> str:
    """Accepted values: bounds, choices, list lengths."""
    if "enum" in schema:
        return "one of " + ", ".join(f"`{toml_value(v)}`" for v in schema["enum"])
    s = schema
    if s.get("type") == "array" and isinstance(s.get("items"), Mapping) and "enum" in s["items"]:
        return "each one of " + ", ".join(f"`{toml_value(v)}`" for v in s["items"]["enum"])
    for b in s.get("oneOf", ()):
        if b.get("type") in ("number", "integer"):
            s = b
            break
    if s.get("type") == "array" and s.get("items", {}).get("type") in ("number", "integer"):
        s = s["items"]
    parts = []
    for word, sym in (("exclusiveMinimum", ">"), ("minimum", ">="), ("exclusiveMaximum", "<"), ("maximum", "<=")):
        if word in s:
            parts.append(f"{sym} {s[word]:g}")
    if schema.get("type") == "array":
        lo, hi = schema.get("minItems"), schema.get("maxItems")
        if lo and lo > 1 and lo != hi and "points" not in type_text(schema):
            parts.append(f">= {lo} items")
        elif lo and lo > 2 and "points" in type_text(schema):
            parts.append(f">= {lo} points")
    if "pattern" in schema:
        parts.append(f"matches `{schema['pattern']}`")
    return ", ".join(parts)


def _cell(text: str) -> str:
    return str(text).replace("``", "`").replace("|", "\\|").replace("\n", " ")


def key_rows(schema: Mapping, *, prefix: str = "", required: tuple = (), expand: bool = True) -> list[str]:
    """Markdown table rows, one per key (nested table keys as ``key.sub``)."""
    rows = []
    required = tuple(schema.get("required", ())) + tuple(required)
    for key, sub in table_properties(schema).items():
        name = f"{prefix}{key}"
        if "default" in sub:
            default = f"`{toml_value(sub['default'])}`"
        else:
            default = "**required**" if key in required else ""
        value = sub["examples"][0] if sub.get("examples") else sub.get("default")
        example = f"`{key} = {toml_value(value)}`" if value is not None else ""
        rows.append(
            f"| `{name}` | {_cell(type_text(sub))} | {_cell(sub.get('units', ''))} | {default} | {_cell(range_text(sub))} | "
            f"{example} | {_cell(sub.get('description', '**undocumented**'))} |"
        )
        nested = nested_tables(sub)
        if expand and nested and set(nested) != {"name"} and key != "element":
            owner = _nested_owner(sub)
            rows += key_rows({"properties": owner.get("properties", nested)}, prefix=f"{name}.")
    return rows


HEADER = "| key | type | units | default | accepted | example | description |\n|---|---|---|---|---|---|---|"


def table_section(title: str, schema: Mapping, intro: str = "", required: tuple = (), expand: bool = True) -> str:
    text = f"## {title}\n\n"
    if intro or schema.get("description"):
        text += (intro or schema["description"]) + "\n\n"
    return text + HEADER + "\n" + "\n".join(key_rows(schema, required=required, expand=expand)) + "\n"


def reference_markdown(*, installed: bool = False) -> str:
    """The whole reference page (deterministic: plugins in name order).

    Parameters
    ----------
    installed : bool
        Also document the plugins other installed packages register (``pounding reference``);
        by default only those that ship with pounding (the checked-in page).
    """
    from pounding.framework.model.registry import CONTACT_LAWS, ELEMENTS, INTEGRATORS
    from pounding.io.scene_schema import ANALYSIS, BUILDING, CONTACT, DAMPING, LINK, SCENE, WALL, ground_motion_schema

    parts = [
        "# Scene file reference\n\n"
        "<!-- Generated by `python -m pounding.io.scene_doc` from the schemas of the core and of every registered "
        "plugin; do not edit by hand (tests/test_scene_reference.py fails when it differs). -->\n\n"
        "A scene is a TOML file. Units are SI throughout (m, kg, s, N, Pa) except where the *units* column says "
        "otherwise (degrees, g). Lists marked *one per storey* take one value for every storey or a list with one "
        "value per storey, bottom first. `pounding template` prints a commented starting scene; "
        "`pounding check SCENE` validates one without running it and prints what it understood, with units.\n\n"
        "Contents: [top level](#top-level), [[ground_motion]](#ground_motion), [[analysis]](#analysis), "
        "[[[contact]]](#contact), [[[link]]](#link), [[[wall]]](#wall), "
        "[[[building]]](#building), [damping](#buildingdamping), [elements](#elements), [integrators](#integrators), "
        "[contact laws](#contact-laws), [plausibility warnings](#plausibility-warnings), [a whole scene](#a-whole-scene).\n",
        table_section("Top level", {"properties": {k: v for k, v in SCENE["properties"].items()}, "required": SCENE["required"]},
                      "The keys and tables at the top of the file.", expand=False),
        table_section("[ground_motion]", ground_motion_schema()),
        table_section("[analysis]", ANALYSIS),
        table_section("[[contact]]", CONTACT) + "\n" + CONTACT_EXAMPLE,
        table_section("[[link]]", LINK) + "\n" + LINK_EXAMPLE,
        table_section("[[wall]]", WALL) + "\n" + WALL_EXAMPLE,
        table_section("[[building]]", {**BUILDING, "properties": {k: v for k, v in BUILDING["properties"].items() if k != "damping"}}),
        table_section("[building.damping]", DAMPING, "An inline table inside `[[building]]`, e.g. "
                      "`damping = { type = \"rayleigh\", ratio = 0.05, modes = [1, 3] }`. " + DAMPING["description"]),
        "## Elements\n\nEach `[[building.element]]` table has `type = \"NAME\"` and the keys of that element type. "
        "Element types are plugins (entry-point group `pounding.elements`); the types registered here, after "
        "the keys every type takes.\n",
        "#" + table_section("Keys of every element", BUILDING["properties"]["element"]["items"],
                            "Taken by the framework, whatever the `type`. An element with `first_storey = s` stands on floor "
                            "s - 1 and spans storeys s to s + `storeys` - 1 (`storeys` omitted: every storey up to the top); "
                            "first_storey + storeys - 1 may not exceed the building's storeys."),
    ]
    def names(registry):
        return registry.names() if installed else registry.builtin_names()

    for name in names(ELEMENTS):
        cls = ELEMENTS.get(name)
        schema = cls.schema
        text = table_section(f"Element `{name}`", schema, schema.get("description", "") or _first_paragraph(inspect.getdoc(cls) or ""))
        choice = _exclusive_choices(schema)
        if choice:
            text += "\n" + choice + "\n"
        if schema.get("examples"):
            text += "\nExample:\n\n```toml\n[[building.element]]\ntype = " + json.dumps(name) + "\n" + "".join(
                f"{k} = {toml_value(v)}\n" for k, v in schema["examples"][0].items()) + "```\n"
        parts.append("#" + text)
    for title, registry, key in (("Integrators", INTEGRATORS, "integrator"), ("Contact laws", CONTACT_LAWS, "contact")):
        parts.append(
            f"## {title}\n\n`[analysis] {key} = \"NAME\"`, or with parameters "
            f"`{key} = {{ name = \"NAME\", parameter = value }}`. Plugins (entry-point group `{registry.group}`); registered here:\n"
        )
        for name in names(registry):
            schema = plugin_schema(registry.get(name))
            if schema["properties"]:
                parts.append("#" + table_section(f"{registry.kind.capitalize()} `{name}`", schema))
            else:
                parts.append(f"### {registry.kind.capitalize()} `{name}`\n\n{schema.get('description', '')} No parameters.\n")
        if registry is CONTACT_LAWS:
            parts.append(OWN_LAW)
    parts.append(plausibility_section())
    parts.append("## A whole scene\n\nThe output of `pounding template` (loads as it is; "
                 "`pounding template --element shear_wall` gives walls instead of frames):\n\n```toml\n" + template_text() + "```\n")
    return "\n".join(parts)


#: the [[contact]] section's example
CONTACT_EXAMPLE = """Example: three buildings in a row, the pairs of `A` and `B` with the default law, those of `B` and the
retaining wall `wall` with a stiffer spring of their own:

```toml
[analysis]
contact = { name = "penalty", stiffness = 1e9, restitution = 0.5 }

[[contact]]
between = ["wall", "B"]
law = { name = "penalty", stiffness = 5e9, restitution = 0.3 }
```
"""

#: the [[link]] section's example
LINK_EXAMPLE = """Example: a linear viscous damper between the top slab of `low` (storey 3) and the slab of `high` at the
same level, across a 0.03 m gap, and a bilinear steel link between floors 2 and 3 of `high`:

```toml
[[link]]
name = "damper-1"
between = ["low", "high"]
storeys = [3, 3]
points = [[15.0, 5.0], [15.03, 5.0]]
law = { name = "viscous", coefficient = 2.0e6, exponent = 1.0 }

[[link]]
between = ["high", "high"]
storeys = [2, 3]
points = [[20.0, 5.0], [22.0, 5.0]]
law = { name = "bilinear", stiffness = 5.0e7, yield_force = 2.0e5, hardening = 0.02 }
```

Its deformation, force and dissipated energy are in response.npz (`link_<name>_deformation`, `_force`,
`_dissipated`), its peaks in summary.json (`links`), and the work it does on each building is that building's
`links` term in the energy account.
"""

#: the [[wall]] section's example
WALL_EXAMPLE = """A moat wall 0.25 m from the base slab of a base-isolated building (slab 1 at 1.0 m), with a law of its own:

```toml
[analysis]
contact = { name = "kelvin", stiffness = 2.0e9, restitution = 0.7 }

[[wall]]
name = "moat"
face = [[-0.25, -1.0], [-0.25, 9.0]]
top = 1.0
contact = { name = "kelvin", stiffness = 1.0e9, restitution = 0.5 }
```
"""

#: the contact-laws section's note on laws that are not installed
OWN_LAW = """### A law of your own

A contact law is one class written from `pounding.contact.base.ContactLaw` (its docstring states the whole
contract): an impulse law (`kind = "impulse"`) implements `impulses(W, b)`; a force law (`kind = "force"`)
implements `forces(contact)`, given one `ContactState` per step with the points' gaps and rates without contact
forces, their compliances to the forces, and the contact's history (its pair, when it began, its closing speed
then) and the share of one contact each point stands for (1/2 at each end of a face, fixed at rest). Register it
under the entry-point group `pounding.contact`, or name it `"module:Class"` in the scene: the
module is imported from the Python path or from a `module.py` beside the scene file. Every call of `forces` is a
trial; a law that declares `keeps_state = True` is given each point's identity (`contact.point`: the pair, the
striking slab and its vertex) and, once a step is accepted, the engine calls its `commit(contact, forces)` with the
state and forces it accepted, so it may keep a state of its own point by point, as an OpenSees material commits its
state: a plastic set, for one. `opensees_material` (optional) names
the law's OpenSees material, so that `pounding export opensees` writes its contact elements. A force law that runs
beside yielding storeys or links is asked for its forces once per pass of the step's solve; written as a
compiled function of the end gaps and rates (`forces_solver`, optional: see the base class), that whole solve
runs compiled. For a Hertz contact in `my_laws.py` next to the scene:

```toml
[analysis]
contact = { name = "my_laws:Hertz", stiffness = 2.75e9 }
```

Every law's contacts are reported the same way: one row per contact episode in `contacts.csv` (start, end, the
pair's buildings and storeys, point, closing speed, peak force, peak penetration, impulse, energy dissipated),
with `n_contacts` and their totals in `summary.json`, and on the impact timeline.
"""


def _exclusive_choices(schema: Mapping) -> str:
    branches = schema.get("oneOf", ())
    keys = [b["required"][0] for b in branches if "not" in b and len(b.get("required", ())) == 1]
    return f"Give exactly one of {', '.join(f'`{k}`' for k in keys)}." if keys else ""


def plausibility_section() -> str:
    from pounding.framework.post.plausibility import CHECKS

    rows = "\n".join(f"| `{c.name}` | {_cell(c.condition)} | {_cell(c.cause)} |" for c in CHECKS)
    return (
        "## Plausibility warnings\n\n`pounding check` and `pounding run` warn (they do not stop) when a scene is valid "
        "but unlikely, with the number and the likely cause. Silence one by name with `[analysis] silence = [\"NAME\"]` "
        "or `--silence NAME`.\n\n| name | warns when | likely cause |\n|---|---|---|\n" + rows + "\n"
    )


# =============================================================================
# The starting scene
# =============================================================================

#: The template's slab (the element plugins' ``examples`` stand on it) and where the second building starts.
TEMPLATE_SLAB = [[0.0, 0.0], [12.0, 0.0], [12.0, 8.0], [0.0, 8.0]]
TEMPLATE_SHIFT = 12.05  # [m] along x: a 0.05 m gap


def _comment(schema: Mapping, key: str) -> str:
    """The template's comment above ``key``: the first clause of its description, with its units."""
    sub = table_properties(schema).get(key, {})
    units = sub.get("units")
    text = first_clause(sub.get("description", ""))
    return f"# {text}" + (f" [{units}]" if units and units != "-" else "")


def first_clause(text: str) -> str:
    """A description's first clause (up to ". ", ": " or "; " outside parentheses): a comment line that reads whole.

    A boundary inside parentheses does not end the clause, and an aside is never cut: "of the
    (first) component, counter-clockwise from x (90 = along y); a second ..." keeps both asides.
    """
    depth = 0
    for i, ch in enumerate(text):
        depth += (ch == "(") - (ch == ")")
        if depth == 0 and ch in ".:;" and text[i + 1:i + 2] in (" ", ""):
            return text[:i].strip()
    return text.strip()


def _element_tables(element: str) -> tuple[list[dict], bool]:
    """(example tables of an element type, whether they came from the plugin)."""
    from pounding.framework.model.registry import ELEMENTS

    schema = ELEMENTS.get(element, field="--element").schema
    if schema.get("examples"):
        return [dict(t) for t in schema["examples"]], True
    table = {}
    for key in schema.get("required", ()):
        sub = table_properties(schema).get(key, {})
        table[key] = sub["examples"][0] if sub.get("examples") else None
    return [table], False


def _shifted(table: dict, schema: Mapping, dx: float) -> dict:
    """An element table moved by dx along x: every key that is a plan point [m] is moved."""
    out = {}
    props = table_properties(schema)
    for key, value in table.items():
        sub = props.get(key, {})
        is_point = sub.get("type") == "array" and sub.get("minItems") == sub.get("maxItems") == 2 and sub.get("units") == "m"
        out[key] = [round(value[0] + dx, 6), value[1]] if is_point and isinstance(value, list) else value
    return out


def template_text(element: str = "frame") -> str:
    """A commented starting scene: two buildings of ``element`` tables, a gap of 0.05 m along x."""
    from pounding.framework.model.registry import ELEMENTS
    from pounding.io.scene_schema import ANALYSIS, BUILDING, DAMPING, ground_motion_schema

    tables, from_plugin = _element_tables(element)
    eschema = ELEMENTS.get(element).schema
    gm = ground_motion_schema()
    lines = [
        "# A starting scene for pounding: two buildings side by side along x, 0.05 m apart.",
        "# Units are SI (m, kg, s, N, Pa) except where a comment says otherwise.",
        "# Every key is described in docs/scene-reference.md; `pounding check FILE` validates",
        "# this file and prints what it understood, with units.",
        'title = "Two buildings, 3 and 2 storeys, 0.05 m apart"',
        "",
        "[ground_motion]",
        _comment(gm, "record"), 'record = "elcentro"',
        _comment(gm, "pga"), "pga = 0.3",
        _comment(gm, "angle"), "angle = 0.0",
        "",
        "[analysis]",
        "# The time integrator and the time step are left out: each run chooses them for accuracy",
        "# from the scene (`pounding check` prints the choice). To name them (docs/scene-reference.md):",
        '# integrator = "newmark"',
        "# dt = 0.005",
        _comment(ANALYSIS, "duration"), "duration = 15.0",
        "# contact law between the slabs: rigid impacts with restitution", 'contact = "impulse"',
        _comment(ANALYSIS, "restitution"), "restitution = 0.5",
        "# plausibility warnings not to show, by name: " + ", ".join(ANALYSIS["properties"]["silence"]["items"]["enum"]),
        "# silence = []",
    ]
    for name, heights, dx in (("left", [3.2, 3.2, 3.2], 0.0), ("right", [3.2, 3.2], TEMPLATE_SHIFT)):
        slab = [[round(x + dx, 6), y] for x, y in TEMPLATE_SLAB]
        lines += [
            "",
            "[[building]]",
            _comment(BUILDING, "name"), f'name = "{name}"',
            _comment(BUILDING, "storey_heights"), f"storey_heights = {toml_value(heights)}",
            _comment(BUILDING, "slab"), f"slab = {toml_value(slab)}",
            _comment(BUILDING, "mass_per_area"), "mass_per_area = 900.0",
            "# " + DAMPING["description"].rstrip("."),
            'damping = { type = "rayleigh", ratio = 0.05, modes = [1, 3] }',
        ]
        if not from_plugin:
            lines.append(f"# the element type {element!r} gives no example tables: this one is made of its keys' examples;")
            lines.append("# place it on the slab and add elements until the building resists x, y and torsion")
        element_keys = BUILDING["properties"]["element"]["items"]
        for k, table in enumerate(tables):
            lines += ["", "  [[building.element]]", f'  type = "{element}"']
            if k == 0:  # a framework key every element type takes, at its default
                lines += ["  " + _comment(element_keys, "first_storey"), "  # first_storey = 1"]
            for key, value in _shifted(table, eschema, dx).items():
                if k == 0:
                    lines.append("  " + _comment(eschema, key))
                lines.append(f"  {key} = {toml_value(value)}" if value is not None else f"  # {key} = TODO")
    return "\n".join(lines) + "\n"


def write_reference(path: Path = REFERENCE_PATH) -> Path:
    """Rewrite the checked-in reference page (the plugins that ship with pounding)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(reference_markdown())
    return path


if __name__ == "__main__":
    print(write_reference())
