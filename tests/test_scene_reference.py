"""The scene format documented from the code: the reference page, the template, `pounding check`.

docs/scene-reference.md is generated from the schemas of the core and of the
plugins that ship with pounding; these tests fail when it differs from a fresh
one, or when a key (in a schema, a plugin's parameters or the ground-motion
reader) has no description or a number no units. Regenerate with
``python -m pounding.io.scene_doc``.
"""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from pounding.io import scene_doc
from pounding.io.scene import load_scene, parse_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper"


def pounding(*args, check=True):
    proc = subprocess.run([sys.executable, "-m", "pounding", *map(str, args)], capture_output=True, text=True)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def test_checked_in_reference_page_matches_the_schemas():
    """The page in docs/ is what the generator writes from today's schemas (no hand edits, no drift)."""
    assert scene_doc.REFERENCE_PATH.read_text() == scene_doc.reference_markdown(), (
        "docs/scene-reference.md is out of date: run `python -m pounding.io.scene_doc`"
    )


def test_every_key_of_the_core_and_of_every_registered_plugin_is_documented():
    """Every key has a description, every number its units: core tables, elements, integrator and contact-law parameters."""
    assert scene_doc.all_undocumented() == []


def test_a_key_added_without_documentation_fails(monkeypatch):
    """A new [analysis] key with only a type: listed as undocumented, and the page no longer matches."""
    from pounding.io import scene_schema

    monkeypatch.setitem(scene_schema.ANALYSIS["properties"], "new_option", {"type": "number"})
    assert "analysis.new_option: no description" in scene_doc.all_undocumented()
    assert scene_doc.REFERENCE_PATH.read_text() != scene_doc.reference_markdown()
    monkeypatch.setitem(scene_schema.ANALYSIS["properties"], "new_option", {"type": "number", "description": "A new option."})
    assert "analysis.new_option: a number without units" in scene_doc.all_undocumented()


def test_a_ground_motion_key_the_reader_accepts_must_be_documented(monkeypatch):
    """A key added to the ground-motion reader (records.KEYS) is accepted in scenes at once and flagged here until described."""
    from pounding.io import records

    monkeypatch.setattr(records, "KEYS", records.KEYS + ("new_key",))
    assert "ground_motion.new_key: no description" in scene_doc.all_undocumented()


def test_plugin_parameters_come_from_the_signature_and_the_docstring():
    """An integrator's keyword-only parameters with their numpydoc text; one without text is flagged."""
    from pounding.solvers.base import Integrator

    class Documented(Integrator):
        """A test scheme.

        Parameters
        ----------
        alpha : float, default 0.1
            A weight [s], in [0, 1].
        mode : {"a", "b"}
            A choice.
        """

        name = "documented"

        def __init__(self, *, alpha=0.1, mode="a", hidden=2):
            pass

        def step(self, *args):  # pragma: no cover - never stepped
            raise NotImplementedError

    schema = scene_doc.plugin_schema(Documented)
    assert schema["properties"]["alpha"] == {"type": "number", "description": "A weight [s], in [0, 1].", "units": "s", "default": 0.1}
    assert schema["properties"]["mode"]["enum"] == ["a", "b"]
    assert scene_doc.undocumented(schema, "x") == ["x.hidden: no description"]


@pytest.mark.parametrize("element", ["frame", "shear_wall"])
def test_template_loads_as_printed_and_is_plausible(element, tmp_path):
    """`pounding template [--element TYPE]` prints a scene that load_scene accepts, with no plausibility warning."""
    from pounding.framework.post import plausibility

    path = tmp_path / "scene.toml"
    path.write_text(pounding("template", "--element", element).stdout)
    scene = load_scene(path)
    assert [b.name for b in scene.buildings] == ["left", "right"]
    assert all(e.name == element for b in scene.buildings for e in b.elements)
    assert plausibility.findings(scene) == []


def test_template_of_an_unknown_element_type_suggests_the_closest():
    proc = pounding("template", "--element", "shear_wal", check=False)
    assert proc.returncode == 2 and "did you mean 'shear_wall'?" in proc.stderr


def test_check_prints_what_it_understood_with_units(tmp_path):
    """`pounding check` on the paper scene: exit 0, the masses [t], mass per area [kg/m2], the first period as
    the modal analysis gives it (to the 4 digits printed), the gap at rest, and that nothing was run."""
    from pounding.framework.model.assembly import assemble

    proc = pounding("check", PAPER / "pair_gap_0.03.toml")
    out = proc.stdout
    scene = load_scene(PAPER / "pair_gap_0.03.toml")
    for b in scene.buildings:
        assert f"T1 = {assemble(b).periods[0]:.4g}" in out
    for text in ("mass [t]", "[kg/m2]", "PGA 0.32 g", "dt 0.005 s", "smallest clear distance at rest 0.03 m", "nothing was run", "storey"):
        assert text in out
    assert not (PAPER / "pair_gap_0.03_out").exists()


def test_check_of_a_bad_scene_is_one_line_and_exit_2(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text((PAPER / "pair_gap_0.03.toml").read_text().replace("columns = [0.0, 5.0, 10.0, 15.0]", "colums = [0.0, 5.0, 10.0, 15.0]", 1))
    proc = pounding("check", path, check=False)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [f"pounding: error: {path}: building[0].element[0].colums: unknown key 'colums' (did you mean 'columns'?)"]


def test_reference_command_prints_the_page_with_installed_plugins():
    out = pounding("reference").stdout
    assert out.startswith("# Scene file reference") and "### Element `frame`" in out


def test_toml_values_read_back_as_written():
    """The page's and the template's TOML writer: every example value parses back to itself."""
    for value in (30e9, 0.005, 900.0, -0.05, 1e-4, 3, "x", [1, 2], [[0.0, 0.0], [1.5, 2.0]], {"E": 30e9, "b": 0.4}, True):
        assert tomllib.loads(f"v = {scene_doc.toml_value(value)}")["v"] == value


def test_with_gap_sets_the_clear_distance_at_rest():
    """Scene.with_gap(g, direction) moves the second building so that the clear distance along the direction is g."""
    from pounding.framework.model.placement import rest_gap

    scene = load_scene(PAPER / "pair_gap_0.03.toml")
    for g in (0.0, 0.1, 0.75):
        moved = scene.with_gap(g, "x")
        assert rest_gap(moved, "x")[0] == pytest.approx(g, abs=1e-12)
        assert np.allclose(moved.buildings[0].slabs[0].vertices, scene.buildings[0].slabs[0].vertices)


def test_parse_scene_takes_the_silence_list():
    text = (PAPER / "pair_gap_0.03.toml").read_text().replace("restitution = 0.5", 'restitution = 0.5\nsilence = ["period", "mass_per_area"]')
    assert parse_scene(tomllib.loads(text)).analysis.silence == ("period", "mass_per_area")
