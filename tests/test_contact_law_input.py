"""Bad parameters of the force laws (kelvin, hertz, hertzdamp, jankowski): one InputError naming the
field and what was expected, from the class, from a scene file (the field under analysis.contact),
and from the command line (one line, exit code 2, no output)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from pounding.errors import InputError
from pounding.framework.model.registry import CONTACT_LAWS
from pounding.io.scene import load_scene
from test_bad_input import BASE

#: (law, parameter, bad value, words of the message)
CASES = [
    *[(law, "stiffness", value, "positive contact stiffness")
      for law in ("kelvin", "hertz", "hertzdamp", "jankowski") for value in (0.0, -1e9, float("inf"))],
    *[(law, "exponent", value, "(0, 3]") for law in ("hertz", "hertzdamp") for value in (0.0, -1.5, 3.5)],
    *[(law, "restitution", 0.0, "(0, 1]") for law in ("hertzdamp", "jankowski")],
    *[(law, "restitution", value, "[0, 1]") for law in ("kelvin", "hertz", "hertzdamp", "jankowski") for value in (-0.1, 1.5)],
    ("kelvin", "tension", 1.0, "true or false"),
    ("hertzdamp", "damping", "hunt_crossley", "'ye'"),
]


def case_id(case) -> str:
    return f"{case[0]}-{case[1]}={case[2]}"


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_a_bad_parameter_names_its_field(case):
    """Building the law raises one InputError whose field is the parameter and whose text says what was expected."""
    name, key, value, words = case
    with pytest.raises(InputError) as exc:
        CONTACT_LAWS.get(name)(**{key: value})
    assert exc.value.field == key
    assert words in exc.value.message


def test_lankarani_nikravesh_takes_a_plastic_restitution():
    """Only the calibrations that divide by e refuse e = 0: Lankarani and Nikravesh's 3 (1 - e^2) / 4 gives 3/4, Kelvin's xi 1."""
    assert CONTACT_LAWS.get("hertzdamp")(restitution=0.0, damping="lankarani_nikravesh").damping_ratio == 0.75
    assert CONTACT_LAWS.get("kelvin")(restitution=0.0).damping_ratio == 1.0


@pytest.mark.parametrize("law, text, field", [
    ("hertz", 'contact = { name = "hertz", stiffness = -2.75e9 }', "analysis.contact.stiffness"),
    ("hertzdamp", 'contact = { name = "hertzdamp", exponent = 4.0 }', "analysis.contact.exponent"),
    ("jankowski", 'contact = { name = "jankowski", restitution = 0.0 }', "analysis.contact.restitution"),
])
def test_a_scene_with_a_bad_law_parameter_fails_on_the_command_line_with_exit_code_2(tmp_path, law, text, field):
    """`pounding run` on a scene whose law has a bad parameter: one line on stderr naming the file and
    analysis.contact.<parameter>, no traceback, exit code 2, no output folder; load_scene raises the same."""
    scene = tmp_path / "scene.toml"
    scene.write_text(BASE.replace('contact = "impulse"', text, 1))
    with pytest.raises(InputError) as exc:
        load_scene(scene)
    assert field in str(exc.value) and str(scene) in str(exc.value)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(scene), "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert field in proc.stderr
    assert not out.exists()


def test_the_entry_points_are_the_registrys_built_ins():
    """pyproject.toml registers under pounding.contact exactly the laws the registry finds from a source
    tree (its built-ins), each pointing at the same class, and every one passes the contract check."""
    import tomllib
    from pathlib import Path

    project = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())
    declared = project["project"]["entry-points"]["pounding.contact"]
    assert declared == CONTACT_LAWS._builtins
    for name in ("kelvin", "hertz", "hertzdamp", "jankowski"):
        assert CONTACT_LAWS.get(name).name == name
