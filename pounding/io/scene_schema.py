"""JSON schema of the scene file's structure (types, required keys, ranges).

Element tables are checked against the schema their plugin declares; meaning
(polygons, lengths per storey, elements on their slabs, mechanisms) is checked
in :mod:`pounding.io.scene` after this.
"""

from __future__ import annotations

POS = {"type": "number", "exclusiveMinimum": 0}
POINT = {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 2}
POLYGON = {"type": "array", "items": POINT, "minItems": 3}


def pos_or_list(item=POS):
    return {"oneOf": [item, {"type": "array", "items": item, "minItems": 1}]}


DAMPING = {
    "type": "object",
    "additionalProperties": False,
    "properties": {
        "type": {"enum": ["rayleigh", "modal", "stiffness"]},
        "ratio": pos_or_list({"type": "number", "minimum": 0, "exclusiveMaximum": 1}),
        "modes": {"type": "array", "items": {"type": "integer", "minimum": 1}, "minItems": 1, "maxItems": 2},
        "periods": {"type": "array", "items": POS, "minItems": 2, "maxItems": 2},
    },
}

P_DELTA = {
    "type": "object",
    "additionalProperties": False,
    "description": "P-Delta from gravity loads (off unless this table is given): a linear storey geometric stiffness "
    "-P/h on the storey drift at the load centre and -I_P/h on its twist (README, P-Delta)",
    "properties": {
        "load_factor": {
            "type": "number",
            "minimum": 0,
            "default": 1.0,
            "description": "gravity load of each floor = load_factor x g x its slab mass [-]",
        },
        "loads": {
            "type": "array",
            "items": {"type": "number", "minimum": 0},
            "minItems": 1,
            "description": "gravity load of each floor [N], bottom first (replaces load_factor); spread over the slab like its mass",
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
            "description": "hertz: elastic Hertz contact F = stiffness x delta^1.5 with the impact's effective mass and approach "
            "velocity; duration: a half-sine pulse of the given duration carrying the impulse",
        },
        "stiffness": {
            "type": "number",
            "exclusiveMinimum": 0,
            "default": 2.75e9,
            "description": "Hertz contact stiffness [N/m^1.5] (default: concrete slabs, Jankowski 2005)",
        },
        "duration": {"type": "number", "exclusiveMinimum": 0, "default": 0.005, "description": "contact duration [s] (model = duration)"},
    },
}

BUILDING = {
    "type": "object",
    "required": ["name", "storey_heights"],
    "additionalProperties": False,
    "properties": {
        "name": {"type": "string", "pattern": r"^[A-Za-z_][A-Za-z0-9_\-]*$"},
        "storey_heights": {"type": "array", "items": POS, "minItems": 1},
        "slab": POLYGON,
        "slabs": {"type": "array", "items": POLYGON, "minItems": 1},
        "mass": pos_or_list(),
        "mass_per_area": pos_or_list(),
        "centre_of_mass": {"type": "array", "items": POINT, "minItems": 1},
        "polar_inertia": {"type": "array", "items": POS, "minItems": 1},
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
                        "description": "factor on the element's condensed lateral stiffness [-] (cracked sections, like an ETABS "
                        "property modifier applied to every member's E: e.g. 0.7); any element type",
                    }
                },
            },
            "minItems": 1,
        },
        "p_delta": P_DELTA,
    },
}

NAMED_PLUGIN = {
    "oneOf": [
        {"type": "string"},
        {"type": "object", "required": ["name"], "properties": {"name": {"type": "string"}}},
    ]
}

ANALYSIS = {
    "type": "object",
    "additionalProperties": False,
    "properties": {
        "integrator": NAMED_PLUGIN,
        "dt": POS,
        "duration": POS,
        "contact": NAMED_PLUGIN,
        "restitution": {"type": "number", "minimum": 0, "maximum": 1},
        "output_every": {"type": "integer", "minimum": 1},
        "energy_tolerance": {"type": "number", "exclusiveMinimum": 0},
        "impact_force": IMPACT_FORCE,
    },
}

SCENE = {
    "type": "object",
    "required": ["building"],
    "additionalProperties": False,
    "properties": {
        "title": {"type": "string"},
        "building": {"type": "array", "items": BUILDING, "minItems": 1},
        "ground_motion": {"type": "object"},
        "analysis": ANALYSIS,
    },
}
