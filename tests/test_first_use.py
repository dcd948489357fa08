"""What a new user meets first: the template's comments and choices, and a unit slip named as one.

Each test states one behaviour a user relies on; the numbers come from the scene's own stiffness.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from pounding.errors import InputError
from pounding.framework.engine.integrator_choice import chosen_integrator
from pounding.framework.model.registry import ELEMENTS
from pounding.framework.model.stiffness_scale import STIFF_RATIO
from pounding.io.scene import parse_scene
from pounding.io.scene_doc import first_clause, template_text

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"

#: words a sentence does not end on: a comment ending on one was cut
DANGLING = {"the", "a", "an", "of", "to", "in", "on", "at", "by", "for", "from", "with", "and", "or", "as", "is", "/"}


@pytest.mark.parametrize("element", ELEMENTS.builtin_names())
def test_template_comments_are_whole_clauses(element):
    """Every comment line of the template has balanced parentheses and does not end on an article,
    a preposition or an operator (a description cut mid-phrase did: "shaking of the [deg]")."""
    for line in template_text(element).splitlines():
        text = line.strip()
        if not text.startswith("# ") or "=" in text.split(" ", 2)[1]:
            continue  # not a comment, or a commented-out key
        body = re.sub(r"\s*\[[^\]]*\]$", "", text[2:]).rstrip(".,;:")  # the units at the end are not words
        assert body.count("(") == body.count(")"), line
        assert body.split()[-1].lower() not in DANGLING, line


def test_first_clause_keeps_asides_and_stops_outside_them():
    """A clause ends at ". ", ": " or "; " outside parentheses; an aside in parentheses is kept whole."""
    text = "Direction of the (first) component, from x (90 = along y; 180 = back); a second acts at +90."
    assert first_clause(text) == "Direction of the (first) component, from x (90 = along y; 180 = back)"
    assert first_clause("Poisson's ratio, G = E / (2 (1 + nu)).") == "Poisson's ratio, G = E / (2 (1 + nu))"


@pytest.mark.parametrize("element", ELEMENTS.builtin_names())
def test_template_of_every_builtin_element_passes_check(element, tmp_path, capsys):
    """`pounding template --element NAME` prints a scene that `pounding check` accepts as printed, with
    no plausibility warning: its elements stand on their slab and the buildings resist x, y and torsion
    (the help says: save it, edit it, then check)."""
    from pounding.cli import main

    path = tmp_path / "t.toml"
    path.write_text(template_text(element))
    assert main(["check", str(path)]) == 0
    assert "0 plausibility warnings" in capsys.readouterr().out


@pytest.mark.parametrize("element", ELEMENTS.builtin_names())
def test_template_leaves_integrator_and_step_to_the_defaults(element):
    """The template names no integrator and no time step, so a run of it gets what
    integrator_choice picks for its buildings and contact law (and the step chosen from its modes)."""
    data = tomllib.loads(template_text(element))
    assert "integrator" not in data["analysis"] and "dt" not in data["analysis"]
    scene = parse_scene(data)
    assert scene.analysis.integrator is None
    assert chosen_integrator(scene) in ("exact", "newmark")


def _in_mm(text: str) -> str:
    """The paper scene with the first frame's column and beam sections typed in mm."""
    old = "column = { E = 30e9, b = 0.50, h = 0.50 }\n  beam = { E = 30e9, b = 0.30, h = 0.55 }"
    assert old in text
    return text.replace(old, "column = { E = 30e9, b = 500, h = 500 }\n  beam = { E = 30e9, b = 300, h = 550 }", 1)


def test_sections_in_mm_are_named_as_a_unit_slip_not_a_mechanism():
    """Sections in mm make that frame ~1e12 times too stiff (I ~ b h^3), so the building's smallest eigenvalue
    is lost to rounding beside it; the error names the element and the units, not a mechanism."""
    with pytest.raises(InputError) as err:
        parse_scene(tomllib.loads(_in_mm(PAPER.read_text())))
    message = str(err.value)
    assert "element[0]" in message and "mm" in message
    assert "nothing resists" not in message
    ratio = float(re.search(r"is ([0-9.e+]+)x the median", message).group(1))
    assert ratio > STIFF_RATIO


def test_a_real_mechanism_is_still_called_one():
    """A building with no element along y (its y-frames removed) is a mechanism, whatever the units."""
    data = tomllib.loads(PAPER.read_text())
    low = data["building"][0]
    low["element"] = [e for e in low["element"] if e.get("angle", 0.0) == 0.0]
    with pytest.raises(InputError, match="mechanism: nothing resists y translation"):
        parse_scene(data)
