"""The integrator a scene gets when it names none (pounding.framework.engine.integrator_choice).

Elastic buildings with impulse contact get ``exact`` (modal closed form, as a modal linear time
history in ETABS or SAP2000); a yielding building or a force contact law gets Newmark's average
acceleration; a named integrator is kept. The run reports what it used, and ``pounding info``
says when the integrator was chosen.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pounding.cli import main
from pounding.framework.engine.integrator_choice import chosen_integrator
from pounding.io.scene import load_scene
from scenes_for_tests import scene, side_by_side

ROOT = Path(__file__).resolve().parents[1]
YIELDING = ROOT / "examples" / "inelastic_pair" / "pair_yielding_gap_0.03.toml"


def _unnamed(s):
    return s.with_analysis(integrator=None, integrator_params={})


def test_elastic_buildings_with_impulses_get_exact():
    assert chosen_integrator(_unnamed(scene(side_by_side(0.05)))) == "exact"


def test_elastic_buildings_without_contact_get_exact():
    assert chosen_integrator(_unnamed(scene(side_by_side(0.05))).with_analysis(contact="none", contact_params={})) == "exact"


def test_a_force_contact_law_gets_newmark():
    s = _unnamed(scene(side_by_side(0.05))).with_analysis(contact="penalty", contact_params={"stiffness": 1e9})
    assert chosen_integrator(s) == "newmark"


def test_a_force_law_on_one_pair_or_wall_beside_impulses_gets_newmark():
    """The pairs a force law serves are stepped by it whatever [analysis] contact is: a [[contact]]
    table's or a wall's force law gets the force laws' integrator."""
    from dataclasses import replace

    from pounding.framework.model.scene import ContactRule, Wall

    s = _unnamed(scene(side_by_side(0.05)))
    names = [b.name for b in s.buildings]
    rule = ContactRule((names[0], names[1]), "kelvin", {"stiffness": 1e9})
    wall = Wall(name="kerb", face=np.array([[-0.05, -1.0], [-0.05, 11.0]]), top=4.0, law="kelvin", params={})
    assert chosen_integrator(replace(s, contacts=(rule,))) == "newmark"
    assert chosen_integrator(replace(s, walls=(wall,))) == "newmark"
    assert chosen_integrator(replace(s, contacts=(rule,)).with_analysis(contact="none", contact_params={})) == "exact"  # nothing watched


def test_a_yielding_building_gets_newmark():
    assert chosen_integrator(_unnamed(load_scene(str(YIELDING)))) == "newmark"


def test_a_named_integrator_is_kept():
    s = scene(side_by_side(0.05)).with_analysis(integrator="hht", integrator_params={"alpha": -0.05})
    assert chosen_integrator(s) == "hht"


def test_a_scene_file_without_an_integrator_leaves_the_choice_to_the_run(tmp_path):
    text = (ROOT / "examples" / "paper" / "pair_gap_0.03.toml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("integrator")]
    f = tmp_path / "pair.toml"
    f.write_text("\n".join(lines))
    s = load_scene(str(f))
    assert s.analysis.integrator is None and chosen_integrator(s) == "exact"


def test_check_names_the_chosen_integrator(tmp_path, capsys):
    text = (ROOT / "examples" / "paper" / "pair_gap_0.03.toml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("integrator")]
    f = tmp_path / "pair.toml"
    f.write_text("\n".join(lines))
    assert main(["check", str(f)]) in (0, None)
    assert "integrator exact (chosen for the scene)" in capsys.readouterr().out
