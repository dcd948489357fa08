"""Errors in one voice: an unknown key is named with the closest known one, before any "required" error,
the first offending place in the file first, in every section; never raw JSON-schema text."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from pounding.errors import InputError
from pounding.io.scene import load_scene
from pounding.io.scene_structure import scene_problems

ROOT = Path(__file__).resolve().parents[1]
PAPER = (ROOT / "examples" / "paper" / "pair_gap_0.03.toml").read_text()

# jsonschema's own wording, which must never reach the user
RAW = ("Additional properties", "is a required property", "is not valid under", "was unexpected", "is not of type", "does not match")


def error_of(tmp_path, text) -> str:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(InputError) as exc:
        load_scene(path)
    message = str(exc.value)
    assert not any(raw in message for raw in RAW), message
    return message.removeprefix(f"{path}: ")


# (id, old, new, count (0 = all), expected message after the file name)
CASES = [
    ("misspelt required key", "columns = [0.0, 5.0, 10.0, 15.0]", "colums = [0.0, 5.0, 10.0, 15.0]", 1,
     "building[0].element[0].colums: unknown key 'colums' (did you mean 'columns'?)"),
    ("[analysis]", "restitution = 0.5", "restitutoin = 0.5", 1,
     "analysis.restitutoin: unknown key 'restitutoin' (did you mean 'restitution'?)"),
    ("[ground_motion]", "pga = 0.32", "pag = 0.32", 1, "ground_motion.pag: unknown key 'pag' (did you mean 'pga'?)"),
    ("integrator parameter", 'integrator = { name = "hht", alpha = -0.05 }', 'integrator = { name = "hht", alpah = -0.05 }', 1,
     "analysis.integrator.alpah: unknown key 'alpah' (did you mean 'alpha'?)"),
    ("integrator name", 'integrator = { name = "hht", alpha = -0.05 }', 'integrator = "hhtt"', 1,
     "analysis.integrator: unknown integrator 'hhtt' (did you mean 'hht'?)"),
    ("contact law", 'contact = "impulse"', 'contact = "impuls"', 1, "analysis.contact: unknown contact law 'impuls' (did you mean 'impulse'?)"),
    ("element type", 'type = "frame"', 'type = "frme"', 1, "building[0].element[0].type: unknown element type 'frme' (did you mean 'frame'?)"),
    ("section key", "column = { E = 30e9, b = 0.50, h = 0.50 }", "column = { E = 30e9, b = 0.50, hh = 0.50 }", 1,
     "building[0].element[0].column.hh: unknown key 'hh' (did you mean 'h'?)"),
    ("section missing a key", "column = { E = 30e9, b = 0.50, h = 0.50 }", "column = { E = 30e9, b = 0.50 }", 1,
     "building[0].element[0].column: missing required key 'h'"),
    ("damping key", "mass_per_area = 900.0", 'mass_per_area = 900.0\ndamping = { typ = "modal" }', 1,
     "building[0].damping.typ: unknown key 'typ' (did you mean 'type'?)"),
    ("top-level key", "title =", "titel =", 1, "titel: unknown key 'titel' (did you mean 'title'?)"),
    ("building key", 'name = "high"', 'name = "high"\nmass_per_aera = 1.0', 1, "building[1].mass_per_aera: unknown key 'mass_per_aera' (did you mean 'mass_per_area'?)"),
    ("same typo in both buildings: the first building first", "storey_heights =", "storey_height =", 0,
     "building[0].storey_height: unknown key 'storey_height' (did you mean 'storey_heights'?)"),
    ("neither angle nor end", "angle = 0.0\n  columns", "columns", 1, "building[0].element[0]: give angle or end"),
    ("a value out of range in a list", "mass_per_area = 900.0", "mass_per_area = [900.0, 900.0, -1.0]", 1,
     "building[0].mass_per_area[2]: expected a number > 0, got -1.0"),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_one_voice(tmp_path, case):
    _, old, new, count, expected = case
    text = PAPER.replace(old, new) if count == 0 else PAPER.replace(old, new, count)
    assert text != PAPER
    assert error_of(tmp_path, text) == expected


def test_unknown_key_comes_before_a_required_key_missing_earlier_in_the_file(tmp_path):
    """building[0] lacks a required key; building[1] has a typo: the typo is reported (it is often the cause)."""
    text = PAPER.replace("storey_heights = [3.2, 3.2, 3.2]\n", "", 1).replace('name = "high"', 'name = "high"\ncolour = 1')
    assert error_of(tmp_path, text).startswith("building[1].colour: unknown key 'colour'")
    # once the typo is fixed, the missing key
    assert error_of(tmp_path, text.replace("colour = 1\n", "")) == "building[0]: missing required key 'storey_heights'"


def test_every_problem_is_collected_in_file_order():
    """scene_problems lists all structural problems: unknown keys first, each group in the order of the file."""
    text = PAPER.replace("pga = 0.32", "pag = 0.32").replace("storey_heights =", "storey_height =").replace("restitution = 0.5", "restitution = 2")
    problems = scene_problems(tomllib.loads(text))
    paths = [p.path for p in problems]
    assert paths[:3] == [("ground_motion", "pag"), ("building", 0, "storey_height"), ("building", 1, "storey_height")]
    assert all(p.unknown for p in problems[:3]) and not any(p.unknown for p in problems[3:])
    assert ("analysis", "restitution") in paths[3:]
