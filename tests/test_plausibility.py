"""Plausibility warnings: valid scenes with unlikely numbers are flagged with the number and the likely cause,
each can be silenced by name, and realistic scenes are not flagged."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from pounding.framework.post import plausibility
from pounding.io.scene import parse_scene
from pounding.io.scene_doc import template_text

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper"


def scene_of(text: str):
    return parse_scene(tomllib.loads(text))


def names(found) -> list[str]:
    return [f.check for f in found]


@pytest.mark.parametrize("path", sorted(PAPER.glob("*.toml")), ids=lambda p: p.name)
def test_the_paper_scenes_are_plausible(path):
    assert plausibility.findings(parse_scene(tomllib.loads(path.read_text()))) == []


def test_the_check_names_are_those_the_scene_accepts():
    from pounding.io.scene_schema import PLAUSIBILITY_CHECKS

    assert plausibility.NAMES == PLAUSIBILITY_CHECKS


def test_mass_in_tonnes_is_flagged_with_the_number_and_the_cause():
    """900 kg/m2 typed as 0.9 (tonnes): the mass per area and the period per storey (~sqrt(1000) = 32x too short) both warn."""
    found = plausibility.findings(scene_of(template_text().replace("mass_per_area = 900.0", "mass_per_area = 0.9")))
    assert set(names(found)) == {"mass_per_area", "period"}
    text = " ".join(str(f) for f in found)
    assert "0.9 kg/m2" in text and "tonnes" in text and "[silence with: mass_per_area]" in text


def test_a_pga_in_gal_typed_as_g_is_flagged_with_what_it_means():
    """392 cm/s2 (0.4 g) typed as `pga = 392` is beyond any recorded peak (about 4.4 g): one warning, the
    number in g and m/s2 and both readings in g: the number as cm/s2 (392 / 100 / 9.80665 = 0.3997 g) and a
    record in cm/s2 read as m/s2 (392 g / 100 = 3.92 g); the template's 0.3 g is not flagged."""
    assert "pga" not in names(plausibility.findings(scene_of(template_text())))
    found = plausibility.findings(scene_of(template_text().replace("pga = 0.3", "pga = 392")))
    assert names(found) == ["pga"]
    assert "392 g" in str(found[0]) and "= 0.4 g" in str(found[0]) and "= 3.92 g" in str(found[0])
    assert "[silence with: pga]" in str(found[0])


def test_each_check_is_silenced_by_name_in_the_scene_or_the_call():
    text = template_text().replace("mass_per_area = 900.0", "mass_per_area = 0.9")
    assert names(plausibility.findings(scene_of(text), silence=("mass_per_area",))) == ["period", "period"]
    silenced = text.replace("# silence = []", 'silence = ["mass_per_area", "period"]')
    assert plausibility.findings(scene_of(silenced)) == []


def test_storey_stiffness_of_columns_between_rigid_beams_is_12_EI_over_h_cubed():
    """Columns fixed-fixed between floors (beams 1e6 times stiffer in bending, columns 1e5 times stiffer axially than
    the real ones, so the frame neither rocks nor bends as a whole): each storey's stiffness is n 12 E I / h^3.
    The neglected flexibilities add relative errors of the order of those ratios, <= 1e-5; 1e-4 is asserted."""
    E, I40, I45 = 30e9, 0.4**4 / 12, 0.45**4 / 12
    text = template_text().replace("beam = { E = 30e9,", "beam = { E = 30e15,")
    for size, I in (("0.4, h = 0.4", I40), ("0.45, h = 0.45", I45)):
        text = text.replace(f"column = {{ E = 30e9, b = {size} }}", f"column = {{ E = 30e9, A = 1.6e4, I = {I!r} }}")
    left = scene_of(text).buildings[0]
    # along x: two frames of 3 columns (the first 0.45 m square, the second 0.4 m), storeys 3.2 m high
    expected = 3 * 12 * E * (I45 + I40) / 3.2**3
    assert plausibility.storey_stiffness(left, (1.0, 0.0)) == pytest.approx([expected] * 3, rel=1e-4)


def test_a_soft_first_storey_is_flagged():
    """First-storey columns 0.25 m instead of 0.4/0.45 m: stiffness ~ (0.25/0.4)^4 = 15 % of the storey above, along x and y."""
    text, right = template_text().split('name = "right"')
    for size in ("0.4, h = 0.4", "0.45, h = 0.45"):
        text = text.replace(f"column = {{ E = 30e9, b = {size} }}",
                            f"column = [{{ E = 30e9, b = 0.25, h = 0.25 }}, {{ E = 30e9, b = {size} }}, {{ E = 30e9, b = {size} }}]")
    found = plausibility.findings(scene_of(text + 'name = "right"' + right))
    assert names(found) == ["soft_storey", "soft_storey"]
    assert "storey 1 along x" in found[0].message and "storey 1 along y" in found[1].message


def test_an_element_in_the_wrong_units_is_flagged():
    """One frame's E typed 1e4 times too large (MPa taken as kPa, say): its stiffness is ~1e4 times the median."""
    text = template_text().replace("column = { E = 30e9, b = 0.45, h = 0.45 }", "column = { E = 30e13, b = 0.45, h = 0.45 }", 1)
    text = text.replace("beam = { E = 30e9, b = 0.3, h = 0.55 }", "beam = { E = 30e13, b = 0.3, h = 0.55 }", 1)
    found = plausibility.findings(scene_of(text))
    assert names(found) == ["stiff_element"]
    assert "element[0] (frame)" in found[0].message


def test_run_and_check_print_warnings_on_stderr_and_silence_them(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(template_text().replace("mass_per_area = 900.0", "mass_per_area = 0.9"))
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr.count("pounding: warning:") == 4
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path), "--silence", "period", "--silence", "mass_per_area"],
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "warning" not in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(tmp_path / "o"), "--duration", "0.1",
                           "--silence", "mass_per_area", "--quiet"], capture_output=True, text=True)
    assert proc.returncode == 0 and proc.stderr.count("pounding: warning:") == 2 and "period" in proc.stderr


LINES = (([0.0, 0.0], [12.0, 0.0]), ([0.0, 8.0], [12.0, 8.0]), ([0.0, 0.0], [0.0, 8.0]), ([12.0, 0.0], [12.0, 8.0]))


def _isolated_building(isolators: dict, damping: str) -> str:
    """A two-storey building on the four edges of its slab: storey 1 four lines of storey springs (the isolators,
    ``isolators`` their keys), storey 2 four lines standing on the base slab (``first_storey = 2``)."""
    keys = "\n".join(f"{k} = {v}" for k, v in isolators.items())
    iso = "".join(f"[[building.element]]\ntype = \"storey_springs\"\nstart = {a}\nend = {b}\nstoreys = 1\n{keys}\n" for a, b in LINES)
    top = "".join(f"[[building.element]]\ntype = \"storey_springs\"\nfirst_storey = 2\nstart = {a}\nend = {b}\nstiffness = 2.0e8\n"
                  for a, b in LINES)
    return f'''
[[building]]
name = "isolated"
storey_heights = [1.0, 3.2]
mass = [150000.0, 135000.0]
slab = [[0.0, 0.0], [12.0, 0.0], [12.0, 8.0], [0.0, 8.0]]
damping = {damping}
{iso}{top}
[ground_motion]
record = "elcentro"
'''


LEAD_RUBBER = {"stiffness": 4.0e7, "yield_force": 2.0e5, "hardening": 0.1}


def test_damping_on_yielding_isolators_is_flagged():
    """Rayleigh damping (5 %) set on the model with the isolators at their initial stiffness keeps acting while they
    yield: flagged once, naming the building and the isolator lines (elements 0 to 3, as the scene's element[i])."""
    found = plausibility.findings(scene_of(_isolated_building(LEAD_RUBBER, '{ type = "rayleigh", ratio = 0.05, modes = [1, 2] }')))
    assert names(found) == ["isolation_damping"]
    assert "'isolated'" in found[0].message and "element[0, 1, 2, 3]" in found[0].message


def test_undamped_modally_damped_or_linear_isolators_are_not_flagged():
    """No damping, per-mode ratios (the remedy: the user chose the damped modes), or isolators that do not yield
    (plain springs, or the linear `elastic` law: their initial stiffness is the one they keep) give no warning."""
    rayleigh = '{ type = "rayleigh", ratio = 0.05, modes = [1, 2] }'
    quiet = [_isolated_building(LEAD_RUBBER, '{ type = "rayleigh", ratio = 0.0, modes = [1, 2] }'),
             _isolated_building(LEAD_RUBBER, '{ type = "modal", ratio = [0.0, 0.0, 0.0, 0.05, 0.05, 0.05] }'),
             _isolated_building({"stiffness": 4.0e7}, rayleigh),
             _isolated_building({"hysteresis": '{ name = "elastic", stiffness = 4.0e7 }'}, rayleigh)]
    for text in quiet:
        assert "isolation_damping" not in names(plausibility.findings(scene_of(text)))
