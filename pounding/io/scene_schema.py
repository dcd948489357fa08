"""JSON schema of the scene file's structure (types, required keys, ranges), and its documentation.

Element tables are checked against the schema their plugin declares; meaning
(polygons, lengths per storey, elements on their slabs, mechanisms) is checked
in :mod:`pounding.io.scene` after this.

Every key carries its documentation in the schema itself, read by the
reference page generator (:mod:`pounding.io.scene_doc`, ``docs/scene-reference.md``):
``description`` (what it is), ``units`` (a keyword of our own; validators
ignore it), ``default`` and ``examples`` (TOML values). A key added without a
description, or a number without units, fails ``tests/test_scene_reference.py``.
"""

from __future__ import annotations

from typing import Any


def number(description: str, units: str, *, example: Any = None, default: Any = None, **limits) -> dict:
    """A documented number schema; ``limits`` are JSON-schema bounds (minimum, exclusiveMinimum, ...)."""
    out: dict[str, Any] = {"type": "number", "units": units, "description": description, **limits}
    if default is not None:
        out["default"] = default
    if example is not None:
        out["examples"] = [example]
    return out


def positive(description: str, units: str, *, example: Any = None, default: Any = None) -> dict:
    return number(description, units, example=example, default=default, exclusiveMinimum=0)


POS = {"type": "number", "exclusiveMinimum": 0}
POINT = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2, "units": "m"}
POLYGON = {"type": "array", "items": POINT, "minItems": 3, "units": "m"}


def pos_or_list(item=POS, **doc):
    """One value for every storey or a list of one per storey (documentation keywords in ``doc``)."""
    return {"oneOf": [item, {"type": "array", "items": item, "minItems": 1}], **doc}


DAMPING = {
    "type": "object",
    "additionalProperties": False,
    "description": "Classical damping of the building (default: Rayleigh, 5 % at modes 1 and 3).",
    "properties": {
        "type": {
            "enum": ["rayleigh", "modal", "stiffness"],
            "default": "rayleigh",
            "description": "rayleigh: C = a0 M + a1 K with `ratio` at two `modes` or `periods`; modal: `ratio` for every mode "
            "(one value, or a list of one per mode); stiffness: C = a1 K with `ratio` at one mode.",
            "examples": ["rayleigh"],
        },
        "ratio": pos_or_list(
            {"type": "number", "minimum": 0, "exclusiveMaximum": 1},
            units="-", default=0.05, description="Damping ratio (fraction of critical, 0.05 = 5 %).", examples=[0.05],
        ),
        "modes": {
            "type": "array", "items": {"type": "integer", "minimum": 1}, "minItems": 1, "maxItems": 2, "units": "-",
            "default": [1, 3], "description": "Mode numbers (1-based) where `ratio` is met: two for rayleigh, one for stiffness.",
            "examples": [[1, 3]],
        },
        "periods": {
            "type": "array", "items": POS, "minItems": 2, "maxItems": 2, "units": "s",
            "description": "Rayleigh only, instead of `modes`: the two periods where `ratio` is met.", "examples": [[0.5, 0.1]],
        },
    },
}

P_DELTA = {
    "type": "object",
    "additionalProperties": False,
    "description": "P-Delta from gravity loads (off unless this table is given): a linear storey geometric stiffness "
    "-P/h on the storey drift at the load centre and -I_P/h on its twist (docs/modelling.md, P-Delta)",
    "properties": {
        "load_factor": {
            "type": "number",
            "minimum": 0,
            "default": 1.0,
            "units": "-",
            "examples": [1.0],
            "description": "Gravity load of each floor = load_factor x g x its slab mass.",
        },
        "loads": {
            "type": "array",
            "items": {"type": "number", "minimum": 0},
            "minItems": 1,
            "units": "N",
            "examples": [[1.2e6, 1.2e6, 0.9e6]],
            "description": "Gravity load of each floor, bottom first (replaces load_factor); spread over the slab like its mass.",
        },
    },
}

IMPACT_FORCE = {
    "type": "object",
    "additionalProperties": False,
    "description": "contact-duration model that turns each impact's impulse into an equivalent peak force (impacts.csv, "
    "summary.json); it does not change the analysis",
    "properties": {
        "model": {
            "enum": ["hertz", "duration"],
            "default": "hertz",
            "examples": ["hertz"],
            "description": "hertz: elastic Hertz contact F = stiffness x delta^1.5 with the impact's effective mass and approach "
            "velocity; duration: a half-sine pulse of the given duration carrying the impulse",
        },
        "stiffness": {
            "type": "number",
            "exclusiveMinimum": 0,
            "default": 2.75e9,
            "units": "N/m^1.5",
            "examples": [2.75e9],
            "description": "Hertz contact stiffness (default: concrete slabs, Jankowski 2005).",
        },
        "duration": {"type": "number", "exclusiveMinimum": 0, "default": 0.005, "units": "s", "examples": [0.005],
                     "description": "Contact duration (model = duration)."},
    },
}

BUILDING = {
    "type": "object",
    "required": ["name", "storey_heights"],
    "additionalProperties": False,
    "description": "One building (`[[building]]`, repeated): storeys, slabs, masses, damping and its planar elements.",
    "properties": {
        "name": {
            "type": "string", "pattern": r"^[A-Za-z_][A-Za-z0-9_\-]*$",
            "description": "Unique name: letters, digits, _ and -, not starting with a digit (used in files: `NAME_cm` in response.npz).",
            "examples": ["low"],
        },
        "storey_heights": {
            "type": "array", "items": POS, "minItems": 1, "units": "m",
            "description": "Height of every storey, bottom first; their number is the number of storeys.",
            "examples": [[3.2, 3.2, 3.2]],
        },
        "slab": {
            **POLYGON,
            "description": "Plan polygon of every slab, vertices [x, y] in order (either turn; stored counter-clockwise). "
            "Any simple polygon, convex or not. Give `slab` or `slabs`.",
            "examples": [[[0.0, 0.0], [15.0, 0.0], [15.0, 10.0], [0.0, 10.0]]],
        },
        "slabs": {
            "type": "array", "items": POLYGON, "minItems": 1, "units": "m",
            "description": "One plan polygon per storey, bottom first (setbacks); instead of `slab`.",
            "examples": [[[[0, 0], [15, 0], [15, 10], [0, 10]], [[0, 0], [10, 0], [10, 10], [0, 10]]]],
        },
        "mass": pos_or_list(
            units="kg", description="Mass of every slab: one value or one per storey. Give `mass` or `mass_per_area`.",
            examples=[135000.0],
        ),
        "mass_per_area": pos_or_list(
            units="kg/m2",
            description="Mass per unit plan area of every slab (kg, not tonnes: 300-2000 is usual; a value far "
            "outside gets a plausibility warning): one value or one per storey.",
            examples=[900.0],
        ),
        "centre_of_mass": {
            "type": "array", "items": POINT, "minItems": 1, "units": "m",
            "description": "Centre of mass [x, y] of every slab, one per storey (default: the polygon's centroid).",
            "examples": [[[7.5, 5.2], [7.5, 5.2], [7.5, 5.0]]],
        },
        "polar_inertia": {
            "type": "array", "items": POS, "minItems": 1, "units": "kg m2",
            "description": "Mass moment of inertia of every slab about the vertical axis through its centre of mass, one "
            "per storey (default: a uniform lamina, m Ip / A, moved to the centre of mass).",
            "examples": [[3.66e6, 3.66e6, 3.66e6]],
        },
        "damping": DAMPING,
        "element": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["type"],
                "properties": {
                    "stiffness_modifier": {
                        "type": "number",
                        "exclusiveMinimum": 0,
                        "maximum": 10,
                        "default": 1.0,
                        "units": "-",
                        "description": "Factor on the element's condensed lateral stiffness (cracked sections, like an ETABS "
                        "property modifier applied to every member's E: e.g. 0.7); any element type that does not yield (a yielding "
                        "element's law carries its own stiffness).",
                        "examples": [0.7],
                    },
                    "first_storey": {
                        "type": "integer",
                        "minimum": 1,
                        "default": 1,
                        "units": "-",
                        "description": "The building's storey where the element begins: it stands on floor first_storey - 1 "
                        "(1: on the ground) and spans `storeys` storeys from there (`storeys` omitted: every storey above); "
                        "a base-isolated building's superstructure starts at 2, over its isolators in storey 1; any element type.",
                        "examples": [2],
                    },
                },
            },
            "minItems": 1,
            "description": "The planar elements (`[[building.element]]`, repeated); `type` picks the plugin, whose keys "
            "are listed under *Elements*; every element also takes `stiffness_modifier` and `first_storey`.",
        },
        "p_delta": P_DELTA,
    },
}

NAMED_PLUGIN = {
    "oneOf": [
        {"type": "string"},
        {"type": "object", "required": ["name"], "properties": {"name": {"type": "string", "description": "The plugin's registered name; the other keys are its parameters."}}},
    ]
}

#: Names of the plausibility checks that ``[analysis] silence`` and ``--silence`` accept.
PLAUSIBILITY_CHECKS = ("mass_per_area", "period", "soft_storey", "stiff_element", "isolation_damping", "pga", "no_common_level")

ANALYSIS = {
    "type": "object",
    "additionalProperties": False,
    "description": "Time integration, contact and output options.",
    "properties": {
        "integrator": {
            **NAMED_PLUGIN,
            "description": "Time integrator: a name, or a table `{ name = ..., parameter = ... }` (see *Integrators*). "
                           "Default: `exact` when every building is elastic, no link joins slabs and every pair's contact is "
                           "by impulses (or none), else `newmark` (average acceleration); see docs/accuracy.md.",
            "examples": [{"name": "hht", "alpha": -0.05}],
        },
        "dt": positive("Time step (default: chosen for accuracy, the largest divisor of the record's sample interval "
                       "with 32 steps per shortest period among the modes with at least 1 % effective mass, 8 for `exact`; "
                       "see docs/accuracy.md).", "s", example=0.005),
        "duration": positive("Length of the analysis (default: the record's; beyond it the ground is at rest).", "s", example=20.0),
        "contact": {
            **NAMED_PLUGIN, "default": "impulse",
            "description": "Contact law of every slab pair: a name, or a table `{ name = ..., parameter = ... }` (see "
                           "*Contact laws*). The name may also be `\"module:Class\"`: a law that is not installed, imported from "
                           "`module` (on the Python path, or a `module.py` beside the scene file). `[[contact]]` tables give "
                           "single pairs of buildings laws of their own.",
            "examples": ["impulse", {"name": "my_laws:Hertz", "stiffness": 2.75e9}],
        },
        "restitution": number(
            "Coefficient of restitution of the contact law (shorthand for its `restitution` parameter).", "-",
            example=0.5, minimum=0, maximum=1,
        ),
        "output_every": {
            "type": "integer", "minimum": 1, "units": "-", "default": 1,
            "description": "Keep every N-th step in response.npz (peaks still cover every step).", "examples": [2],
        },
        "energy_tolerance": number(
            "Relative energy-balance error above which a run warns and summary.json says `ok: false`.", "-",
            example=0.02, default=0.02, exclusiveMinimum=0,
        ),
        "impact_force": IMPACT_FORCE,
        "silence": {
            "type": "array", "items": {"enum": list(PLAUSIBILITY_CHECKS)}, "uniqueItems": True, "default": [],
            "description": "Plausibility warnings not to show, by name: " + ", ".join(f"`{c}`" for c in PLAUSIBILITY_CHECKS)
            + " (see *Plausibility warnings*). Also `--silence NAME` on the command line.",
            "examples": [["mass_per_area"]],
        },
    },
}

#: Documentation of the ``[ground_motion]`` keys (read by :func:`pounding.io.ground_motion.load_record`,
#: which checks their values). Keys the reader accepts but this table lacks are added undocumented by
#: :func:`ground_motion_schema`, so a scene never fails here for a new key, and the reference test does.
GROUND_MOTION_KEYS = {
    "record": {
        "type": "string",
        "description": "One component (or `components` for two): \"elcentro\" (the packaged El Centro 1940 NS record: 1560 samples at "
        "0.02 s, PGA 0.3188 g) or the path of a record file, relative to the scene file. Without a [ground_motion] "
        "table the scene runs El Centro as recorded, along x.",
        "examples": ["records/RSN6_IMPVALL.I_I-ELC180.AT2"],
    },
    "format": {
        "enum": ["auto", "at2", "single_column", "two_columns"], "default": "auto",
        "description": "Record file layout: PEER .AT2; one acceleration per line (needs `dt`); `time, acceleration` "
        "per line. auto: .AT2 by extension, otherwise by the number of values on the first data line.",
        "examples": ["single_column"],
    },
    "dt": positive("Sample interval of a single-column record (rejected for the others: their times come from the file).", "s", example=0.01),
    "units": {
        "enum": ["g", "m/s2", "m/s^2", "cm/s2", "cm/s^2"], "default": "g",
        "description": "Units of the record's accelerations. AT2 files state their own; if given it must agree.",
        "examples": ["cm/s2"],
    },
    "pga": positive("Scale the record so that its peak |acceleration| is this (or `scale`, not both).", "g", example=0.32),
    "scale": positive("Multiply the record by this factor (or `pga`, not both).", "-", example=1.5),
    "angle": number("Plan direction of shaking of the (first) component, counter-clockwise from the global x axis "
                    "(90 = along y); a second component acts at angle + 90.", "deg", example=30.0, default=0.0),
    "components": {
        "type": ["array", "string"],
        "description": "Two orthogonal horizontal components instead of `record`: a list of two record paths, or of two "
        "tables `{ record = ..., format = ..., units = ..., dt = ..., baseline = ... }` (each may have its own format, "
        "units and dt), or a member of a record set (`\"fema-p695:farfield/N\"`). They are put on one time base (the finer "
        "dt, linear interpolation; the shorter padded with zeros after its end).",
        "examples": [["RSN1111_KOBE_NIS000.AT2", "RSN1111_KOBE_NIS090.AT2"]],
    },
    "baseline": {
        "enum": ["none", "mean", "linear", "quadratic", "cubic"],
        "description": "Baseline correction: remove a least-squares polynomial of this order from each acceleration "
        "record (default: none, the record as given).",
        "examples": ["linear"],
    },
    "intensity": {
        "enum": ["pga", "sa", "geomean", "rotd50", "rotd100"],
        "description": "Intensity measure to scale to (with `target`): peak ground acceleration, 5 %-damped "
        "pseudo-spectral acceleration Sa(T) of the first component, geometric mean of the two components' Sa(T), "
        "RotD50 or RotD100 Sa(T) (Boore 2010).",
        "examples": ["rotd50"],
    },
    "target": positive("Value of `intensity` the motion is scaled to (one factor for both components).", "g", example=0.6),
    "period": positive("Period of spectral intensity measures (default: the first period of the taller building).", "s",
                       example=1.2),
}


def ground_motion_schema() -> dict:
    """Schema of ``[ground_motion]``: the documented keys plus any key the reader accepts (undocumented).

    The reader may document its keys itself, as ``pounding.io.ground_motion.SPEC_SCHEMA``
    (``{key: schema with description, units, examples}``); those take precedence.
    """
    from pounding.io import ground_motion, records

    props = {**GROUND_MOTION_KEYS, **getattr(ground_motion, "SPEC_SCHEMA", {})}
    for key in records.KEYS:
        props.setdefault(key, {})
    return {
        "type": "object",
        "additionalProperties": False,
        "description": "The ground motion applied to every building: one horizontal component (`record`) or two "
        "(`components`), scaled by `pga`, `scale` or an `intensity` target (default: El Centro 1940 NS as recorded, along x).",
        "properties": props,
    }


CONTACT = {
    "type": "object",
    "additionalProperties": False,
    "required": ["between"],
    "description": "The contact law of the slab pairs between two buildings (`[[contact]]`, repeated: one table per "
    "pair of buildings), instead of `[analysis] contact`: a retaining wall and a slab, a stiff and a soft facade; "
    "and a rubber bumper between them (`bumper`). It gives `law`, `bumper` or both. "
    "Laws that act by forces solved with the step (`kelvin`, `hertzdamp`, `penalty`, and plugins of that kind) may "
    "differ from pair to pair, also beside an impulse law that strikes the other pairs (which then locates its impacts "
    "by `crossing`, the default); one impulse law serves every pair that takes impulses: `[analysis] contact`'s, "
    "whose restitution a table may change (`law = { restitution = 0.8 }`), or beside a force law there the first "
    "impulse law a table names (`law = { name = \"impulse\", restitution = 0.6 }`; without a name a table keeps the "
    "force law), whose restitution the others may change.",
    "properties": {
        "between": {
            "type": "array", "items": {"type": "string"}, "minItems": 2, "maxItems": 2,
            "description": "The names of the two buildings (either order).", "examples": [["wall", "B"]],
        },
        "law": {
            "oneOf": [NAMED_PLUGIN["oneOf"][0], {k: v for k, v in NAMED_PLUGIN["oneOf"][1].items() if k != "required"}],
            "description": "Their contact law, as `[analysis] contact`: a name or `\"module:Class\"`, or a table "
            "`{ name = ..., parameter = ... }`; a table without a name is `[analysis] contact`'s law with parameters "
            "of its own (`{ restitution = 0.8 }`: the impulse law with the pair's own restitution).",
            "examples": [{"name": "penalty", "stiffness": 5e8}, {"restitution": 0.8}],
        },
        "bumper": {
            "type": "object",
            "additionalProperties": False,
            "required": ["on", "storeys", "thickness", "law"],
            "description": "A rubber layer on one building's facing faces at some storeys (docs/modelling.md): the gap "
            "shrinks by its thickness t; the layer follows its own law on its compression delta until delta reaches "
            "`compressible` t, beyond which the slabs' law (`law`, else `[analysis] contact`) acts on delta - "
            "`compressible` t as well, in parallel with the layer. Both laws must act by forces (a layer compresses).",
            "properties": {
                "on": {"type": "string", "description": "The building that carries the layer (one of `between`).",
                       "examples": ["low"]},
                "storeys": {"type": "array", "items": {"type": "integer", "minimum": 1}, "minItems": 1, "units": "-",
                            "description": "The storeys (1-based) of `on` whose slab carries the layer; each has a slab "
                            "of the other building at its level.", "examples": [[3]]},
                "thickness": positive("The layer's thickness t, less than the rest gap.", "m", example=0.02),
                "compressible": number("The fraction of t the layer compresses before the slabs' law acts too, in (0, 1] "
                                       "(from the rubber's strain limit).", "-", example=0.8, default=1.0,
                                       exclusiveMinimum=0, maximum=1),
                "law": {
                    **NAMED_PLUGIN,
                    "description": "The layer's own contact law: `rubber` (Hertz-type with Hunt-Crossley damping; "
                    "`stiffness` required) or any law that acts by forces.",
                    "examples": [{"name": "rubber", "stiffness": 5.0e7, "exponent": 1.5, "restitution": 0.5}],
                },
            },
        },
    },
}

LINK = {
    "type": "object",
    "additionalProperties": False,
    "required": ["between", "storeys", "points", "law"],
    "description": "A link between two slabs (`[[link]]`, repeated: one table per link): a damper, a spring or any "
    "hysteresis law acting between a point of one building's slab and a point of another's (or of another floor of "
    "the same building), along the line from the first point to the second at rest, as OpenSees' zeroLength element "
    "with a uniaxial material. Its deformation is the second point's displacement minus the first's along that line.",
    "properties": {
        "name": {"type": "string", "description": "The link's name in the outputs (default: `link-K`, K its 1-based "
                 "place among the `[[link]]` tables).", "examples": ["damper-1"]},
        "between": {
            "type": "array", "items": {"type": "string"}, "minItems": 2, "maxItems": 2,
            "description": "The names of the two buildings (a building named twice: two of its floors).",
            "examples": [["low", "high"]],
        },
        "storeys": {
            "type": "array", "items": {"type": "integer", "minimum": 1}, "minItems": 2, "maxItems": 2, "units": "-",
            "description": "The slab (storey, 1-based) of each building the link is attached to.", "examples": [[3, 3]],
        },
        "points": {
            "type": "array", "items": POINT, "minItems": 2, "maxItems": 2, "units": "m",
            "description": "The attachment points [x, y], each on its slab; they must differ (the line between them is "
            "the link's direction).", "examples": [[[15.0, 5.0], [15.03, 5.0]]],
        },
        "law": {
            "type": "object", "required": ["name"],
            "description": "The link's law: `{ name = ..., parameter = ... }`: `viscous` (coefficient, exponent), "
            "`maxwell` and `kelvin` (stiffness, coefficient, exponent), `elastic` (stiffness), or a hysteresis law "
            "(`bilinear`, `bouc_wen`, a plugin's) with `stiffness` [N/m], `yield_force` [N] and `hardening` [-] beside "
            "its own parameters.",
            "examples": [{"name": "viscous", "coefficient": 2.0e6, "exponent": 1.0}],
        },
    },
}

WALL = {
    "type": "object",
    "additionalProperties": False,
    "required": ["name", "face", "top"],
    "description": "A retaining wall fixed to the ground (`[[wall]]`, repeated: one table per wall), such as the moat "
    "wall around a base-isolated building: every slab at or below its top can strike its face, and the wall does not "
    "move. Its face may run between buildings, beside a storey or under a slab above its top, never through the plan of a "
    "storey that stands below its top. Impacts on it are in impacts.csv (the struck body is the wall) and in the struck "
    "building's energy account; `pounding gap` reports the clearance each building needs to it.",
    "properties": {
        "name": {"type": "string", "description": "The wall's name (the struck body in impacts.csv and contacts.csv).",
                 "examples": ["moat"]},
        "face": {"type": "array", "items": POINT, "minItems": 2, "units": "m",
                 "description": "Plan polyline of the wall's face (two points or more); a building stands on the side of "
                 "each segment where it is at rest.", "examples": [[[-0.25, -1.0], [-0.25, 11.0]]]},
        "top": positive("Height of the wall's top above the ground: the slabs at or below it can strike the wall.", "m", example=1.0),
        "contact": {
            "oneOf": [NAMED_PLUGIN["oneOf"][0], {k: v for k, v in NAMED_PLUGIN["oneOf"][1].items() if k != "required"}],
            "description": "Its contact law, as `[analysis] contact` (default: `[analysis] contact`). A force law, also "
            "beside an impulse law on the buildings' pairs (located by `crossing`, the default); or `[analysis] contact`'s "
            "impulse law, whose restitution the wall may change (`{ restitution = 0.8 }` without a name); or beside a "
            "force law there the impulse law by name (`{ name = \"impulse\", restitution = 0.6 }`).",
            "examples": [{"name": "kelvin", "stiffness": 1.0e9, "restitution": 0.5}],
        },
    },
}

SCENE = {
    "type": "object",
    "required": ["building"],
    "additionalProperties": False,
    "properties": {
        "title": {"type": "string", "description": "A title, shown by `pounding check` and in plots.", "examples": ["L-shaped 10 storeys beside 6 storeys"]},
        "building": {"type": "array", "items": BUILDING, "minItems": 1, "description": "The buildings (`[[building]]`), one table each."},
        "ground_motion": {"type": "object", "description": "See *[ground_motion]*."},
        "analysis": ANALYSIS,
        "contact": {"type": "array", "items": CONTACT, "description": "See *[[contact]]*."},
        "link": {"type": "array", "items": LINK, "description": "See *[[link]]*."},
        "wall": {"type": "array", "items": WALL, "description": "See *[[wall]]*."},
    },
}


def scene_schema() -> dict:
    """The whole scene's schema with ``[ground_motion]`` filled in (element tables are checked by their plugin's schema)."""
    return {**SCENE, "properties": {**SCENE["properties"], "ground_motion": ground_motion_schema()}}
