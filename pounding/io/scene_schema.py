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
        "element": {"type": "array", "items": {"type": "object", "required": ["type"]}, "minItems": 1},
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
