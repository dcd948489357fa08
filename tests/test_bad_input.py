"""Bad input: one clear message naming the file, the field and what was expected; exit code 2; no output.

Each case mutates a valid two-building scene in one way. The expected field is
the TOML key path (0-based indices) the message must name.
"""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from pounding.errors import InputError
from pounding.io.scene import load_scene

BASE = """
[ground_motion]
record = "elcentro"
pga = 0.32

[analysis]
dt = 0.01
duration = 1.0
integrator = "newmark"
contact = "impulse"
restitution = 0.5

[[building]]
name = "A"
storey_heights = [3.0, 3.0]
slab = [[0, 0], [10, 0], [10, 8], [0, 8]]
mass = 80000.0
  [[building.element]]
  type = "frame"
  start = [0, 0]
  angle = 0
  columns = [0, 5, 10]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }
  [[building.element]]
  type = "frame"
  start = [0, 8]
  angle = 0
  columns = [0, 5, 10]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }
  [[building.element]]
  type = "shear_wall"
  start = [0, 0]
  end = [0, 8]
  thickness = 0.2
  E = 30e9
  nu = 0.2
  [[building.element]]
  type = "shear_wall"
  start = [10, 0]
  end = [10, 8]
  thickness = 0.2
  E = 30e9
  nu = 0.2

[[building]]
name = "B"
storey_heights = [3.0]
slab = [[10.1, 0], [20, 0], [20, 8], [10.1, 8]]
mass_per_area = 800.0
  [[building.element]]
  type = "shear_wall"
  start = [10.1, 0]
  end = [20, 0]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [10.1, 8]
  end = [20, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [15, 0]
  end = [15, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
"""

# (id, old text, new text, field the message must name, words it must contain)
CASES = [
    ("misspelled key", 'storey_heights = [3.0, 3.0]', 'storey_height = [3.0, 3.0]', "building[0]", "storey_heights"),
    ("unknown key", 'mass = 80000.0', 'mass = 80000.0\ncolour = "red"', "building[0]", "colour"),
    ("wrong type", 'mass = 80000.0', 'mass = "heavy"', "building[0].mass", "expected"),
    ("nan", 'mass = 80000.0', 'mass = nan', "building[0].mass", "finite"),
    ("inf", 'pga = 0.32', 'pga = inf', "ground_motion.pga", "finite"),
    ("zero mass", 'mass = 80000.0', 'mass = 0.0', "building[0].mass", "expected"),
    ("negative mass", 'mass = 80000.0', 'mass = -5.0', "building[0].mass", "expected"),
    ("mass list length", 'mass = 80000.0', 'mass = [80000.0, 80000.0, 80000.0]', "building[0].mass", "2"),
    ("negative height", 'storey_heights = [3.0, 3.0]', 'storey_heights = [3.0, -3.0]', "building[0].storey_heights[1]", "expected"),
    ("zero storey height: a slab on the one below", 'storey_heights = [3.0, 3.0]', 'storey_heights = [3.0, 0.0]', "building[0].storey_heights[1]", "expected"),
    ("storeys overlap at different levels", 'storey_heights = [3.0]\nslab = [[10.1, 0]', 'storey_heights = [3.5]\nslab = [[9.5, 0]', "building[1].slab", "different levels"),
    ("self-intersecting slab", 'slab = [[0, 0], [10, 0], [10, 8], [0, 8]]', 'slab = [[0, 0], [10, 8], [10, 0], [0, 8]]', "building[0].slab", "simple"),
    ("repeated vertex", 'slab = [[0, 0], [10, 0], [10, 8], [0, 8]]', 'slab = [[0, 0], [10, 0], [10, 0], [10, 8], [0, 8]]', "building[0].slab", "simple"),
    ("degenerate slab", 'slab = [[0, 0], [10, 0], [10, 8], [0, 8]]', 'slab = [[0, 0], [5, 0], [10, 0]]', "building[0].slab", "simple"),
    ("slabs overlap at rest", 'slab = [[10.1, 0], [20, 0], [20, 8], [10.1, 8]]', 'slab = [[9.5, 0], [20, 0], [20, 8], [9.5, 8]]', "building[1]", "overlap"),
    ("element off its slab", 'start = [0, 8]\n  angle = 0', 'start = [0, 9]\n  angle = 0', "building[0].element[1]", "outside the slab"),
    ("mechanism", 'start = [15, 0]\n  end = [15, 8]', 'start = [12, 0]\n  end = [18, 0]', "building[1]", "mechanism"),
    ("unknown element", 'type = "frame"\n  start = [0, 0]', 'type = "truss"\n  start = [0, 0]', "building[0].element[0].type", "known:"),
    ("unknown integrator", 'integrator = "newmark"', 'integrator = "rk4"', "analysis.integrator", "known:"),
    ("unknown contact law", 'contact = "impulse"', 'contact = "glue"', "analysis.contact", "known:"),
    ("bad integrator parameter", 'integrator = "newmark"', 'integrator = { name = "hht", alfa = -0.1 }', "analysis.integrator", "alfa"),
    ("hht alpha out of range", 'integrator = "newmark"', 'integrator = { name = "hht", alpha = -0.5 }', "analysis.integrator", "alpha"),
    ("restitution above 1", 'restitution = 0.5', 'restitution = 1.5', "analysis.restitution", "expected"),
    ("zero dt", 'dt = 0.01', 'dt = 0.0', "analysis.dt", "expected"),
    ("dt longer than duration", 'dt = 0.01', 'dt = 2.0', "analysis.dt", "duration"),
    ("angle and end", 'start = [0, 0]\n  angle = 0\n  columns', 'start = [0, 0]\n  angle = 0\n  end = [10, 0]\n  columns', "building[0].element[0]", "either angle or end"),
    ("G and nu", 'E = 30e9\n  G = 12e9\n  [[building.element]]\n  type = "shear_wall"\n  start = [10.1, 8]', 'E = 30e9\n  G = 12e9\n  nu = 0.2\n  [[building.element]]\n  type = "shear_wall"\n  start = [10.1, 8]', "building[1].element[0]", "either G or nu"),
    ("missing record", 'record = "elcentro"', 'record = "no_such_file.at2"', "ground_motion.record", "no_such_file"),
    ("negative pga", 'pga = 0.32', 'pga = -0.3', "ground_motion.pga", ""),
    ("column positions not increasing", 'columns = [0, 5, 10]\n  column = { E = 30e9, b = 0.4, h = 0.4 }\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', 'columns = [0, 10, 5]\n  column = { E = 30e9, b = 0.4, h = 0.4 }\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', "building[0].element[0].columns", "increasing"),
    ("section list length", 'column = { E = 30e9, b = 0.4, h = 0.4 }\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', 'column = [{ E = 30e9, b = 0.4, h = 0.4 }]\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', "building[0].element[0].column", "list of 2"),
    ("section missing a property", 'column = { E = 30e9, b = 0.4, h = 0.4 }\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', 'column = { E = 30e9, b = 0.4 }\n  beam = { E = 30e9, b = 0.3, h = 0.5 }\n  [[building.element]]\n  type = "frame"\n  start = [0, 8]', "building[0].element[0].column", ""),
    ("duplicate building name", 'name = "B"', 'name = "A"', "building[1].name", "twice"),
    ("no buildings", None, 'title = "empty"', "(top level)", "building"),
    ("not TOML", None, 'this is = = not toml', "", "TOML"),
    # [[contact]]: the law of one pair of buildings, and laws named "module:Class"
    ("[[contact]] unknown building", 'contact = "impulse"\nrestitution = 0.5', 'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "C"]\nlaw = "penalty"',
     "contact[0].between[1]", "no building is named 'C'; the buildings: 'A', 'B'"),
    ("[[contact]] same building twice", 'contact = "impulse"\nrestitution = 0.5', 'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "A"]\nlaw = "penalty"',
     "contact[0].between", "expected two different buildings"),
    ("[[contact]] unknown law", 'contact = "impulse"\nrestitution = 0.5', 'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = "penalti"',
     "contact[0].law", "unknown contact law 'penalti' (did you mean 'penalty'?)"),
    ("[[contact]] law parameter", 'contact = "impulse"\nrestitution = 0.5',
     'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = { name = "penalty", stifness = 1e9 }',
     "contact[0].law.stifness", "unknown key 'stifness' (did you mean 'stiffness'?)"),
    ("[[contact]] impulse law beside forces, by halving", 'contact = "impulse"\nrestitution = 0.5',
     'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = { name = "impulse", locate = "halving" }',
     "contact[0].law", 'takes locate = "crossing"'),
    ("[[contact]] impulse law with another tolerance", 'contact = "impulse"\nrestitution = 0.5',
     'contact = "impulse"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = { tolerance = 0.001 }',
     "contact[0].law", "tolerance must be as [analysis] contact gives it"),
    ("[[contact]] force law beside the paper's locator", 'contact = "impulse"\nrestitution = 0.5',
     'contact = { name = "impulse", locate = "halving" }\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = "penalty"',
     "contact[0].law", 'takes locate = "crossing"'),
    ("module:Class no module", 'contact = "impulse"', 'contact = "no_such_module:Hertz"',
     "analysis.contact", "cannot import module 'no_such_module'"),
    ("module:Class no class", 'contact = "impulse"', 'contact = "pounding.contact.penalty:Hertz"',
     "analysis.contact", "module 'pounding.contact.penalty' has no 'Hertz'"),
    ("module:Class not a law", 'contact = "impulse"', 'contact = "pounding.contact.penalty:no_tension_restitution"',
     "analysis.contact", "is a function, not a subclass of ContactLaw"),
    ("module:Class malformed", 'contact = "impulse"', 'contact = "pounding.contact:penalty:Penalty"',
     "analysis.contact", "expected a contact law name or 'module:Class'"),
    ("module:Class in [[contact]]", 'contact = "impulse"\nrestitution = 0.5',
     'contact = "penalty"\nrestitution = 0.5\n\n[[contact]]\nbetween = ["A", "B"]\nlaw = { name = "no_such_module:Hertz", stiffness = 1e9 }',
     "contact[0].law.name", "cannot import module 'no_such_module'"),
    # the modifier scales the modal stiffness and not the law's: a yielding element would carry two stiffnesses
    ("stiffness_modifier on a yielding element", 'type = "shear_wall"\n  start = [10.1, 0]\n  end = [20, 0]\n  thickness = 0.2\n  E = 30e9\n  G = 12e9',
     'type = "storey_springs"\n  start = [10.1, 0]\n  end = [20, 0]\n  stiffness = 4e8\n  yield_force = 1e6\n  stiffness_modifier = 0.7',
     "building[1].element[0].stiffness_modifier", "a yielding element takes no stiffness_modifier"),
]


def write(tmp_path: Path, old, new) -> Path:
    text = new if old is None else BASE.replace(old, new, 1)
    assert old is None or text != BASE, "the case does not change the scene"
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_base_scene_is_valid(tmp_path):
    """The scene every case starts from loads without error (so each case tests only its own defect)."""
    scene = load_scene(write(tmp_path, None, BASE))
    assert [b.name for b in scene.buildings] == ["A", "B"]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_malformed_scene_names_file_and_field(tmp_path, case):
    """load_scene raises one InputError whose text names the file, the key path and what was wrong."""
    _, old, new, field, words = case
    path = write(tmp_path, old, new)
    with pytest.raises(InputError) as exc:
        load_scene(path)
    text = str(exc.value)
    assert str(path) in text
    assert field in text
    assert words.lower() in text.lower()


CLI_CONTACT_CASES = ("[[contact]] unknown building", "module:Class no module")


@pytest.mark.parametrize("case", [c for c in CASES if c[0] in CLI_CONTACT_CASES], ids=CLI_CONTACT_CASES)
def test_cli_reports_a_bad_contact_law_in_one_line_with_exit_code_2(tmp_path, case):
    """A [[contact]] table or a "module:Class" that cannot serve: one line naming the file, the field
    and what was expected, exit code 2, no output folder."""
    _, old, new, field, words = case
    path = write(tmp_path, old, new)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert str(path) in proc.stderr and field in proc.stderr and words in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize("command", ["info", "run"])
def test_cli_reports_bad_input_in_one_line_with_exit_code_2_and_no_output(tmp_path, command):
    """The command line prints one line on stderr, no traceback, exits 2, and writes no output folder."""
    path = write(tmp_path, 'mass = 80000.0', 'mass = -5.0')
    out = tmp_path / "out"
    args = [sys.executable, "-m", "pounding", command, str(path)] + (["--out", str(out)] if command == "run" else [])
    proc = subprocess.run(args, capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "building[0].mass" in proc.stderr
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["scene.toml"]


def test_coincident_buildings_are_rejected(tmp_path):
    """Two identical buildings at the same place: their slabs have zero clear distance yet lie on top of each other."""
    first = BASE[: BASE.index("[[building]]\nname = \"B\"")]
    a_block = first[first.index("[[building]]"):]
    path = tmp_path / "scene.toml"
    path.write_text(first + a_block.replace('name = "A"', 'name = "A2"'))
    with pytest.raises(InputError, match="on top of each other"):
        load_scene(path)


def test_base_scene_toml_is_what_the_cases_edit():
    """Guard: the base text parses as TOML (a broken base would make every case pass for the wrong reason)."""
    tomllib.loads(BASE)
