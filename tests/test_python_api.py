"""The Python API as a documented surface: docs/python.md's session runs, results as data, scenes written back.

Each test states the relation it checks: the documented example runs as written; a scene written
to TOML loads back equal (every example and test scene); the DataFrame and Dataset hold the same
numbers as the Result under summary.json's names; the drift of a first storey is its floor's
displacement over its height; misspelt keywords are named with the closest one; a run folder
written from Python is a complete run folder (it loads back and plots).
"""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import pounding
from pounding.io.scene import load_scene, parse_scene
from pounding.io.scene_writer import scene_differences, write_scene

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "python.md"
SCENE_FILES = sorted([*ROOT.glob("examples/**/*.toml"), *ROOT.glob("benchmarks/scenes/*.toml"),
                      *ROOT.glob("pounding/io/data/**/*.toml")])
SCENE_FILES = [p for p in SCENE_FILES if p.name != "pyproject.toml"]


def _python_blocks(text: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """docs/python.md's first example, run as written in a folder holding the repository's examples/."""
    folder = tmp_path_factory.mktemp("doc")
    shutil.copytree(ROOT / "examples" / "paper", folder / "examples" / "paper", ignore=shutil.ignore_patterns("*_out", "output"))
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        namespace: dict = {}
        exec(compile(_python_blocks(DOC.read_text())[0], str(DOC), "exec"), namespace)
    finally:
        os.chdir(cwd)
    return folder, namespace


def test_the_documented_session_runs_and_pounds(session):
    """The example runs as written; at a 0.05 m gap under 0.4 g the paper pair pounds (impacts > 0), and its
    scene file loads back as the scene it wrote."""
    folder, ns = session
    assert len(ns["impacts"]) == ns["result"].n_impacts > 0
    assert scene_differences(ns["scene"], ns["again"]) == []


def test_a_run_folder_written_from_python_plots(session):
    """write_results without a scene text still writes scene.toml (the run's scene written back), so
    load_result rebuilds the same histories and `pounding plot` draws it (exit 0)."""
    folder, ns = session
    scene, result = pounding.load_result(folder / "my_run")
    assert scene_differences(scene, ns["scene"]) == []
    for name in result.names:
        np.testing.assert_array_equal(result.cm(name), ns["result"].cm(name))
    pytest.importorskip("matplotlib")
    from pounding.cli import main

    assert main(["plot", str(folder / "my_run")]) == 0
    assert any((folder / "my_run" / "plots").glob("*.png"))


def test_storey_peaks_hold_summary_json_under_its_names(session):
    """Every per-storey peak of summary.json is a column `name [unit]` with the same numbers (one set of names)."""
    from pounding.io.frames import PEAK_UNITS
    from pounding.io.results import summary

    _, ns = session
    result, peaks = ns["result"], ns["peaks"]
    s = summary(result)
    for name, b in s["buildings"].items():
        n = len(b["peak_u"])
        per_storey = [k for k, v in b.items() if isinstance(v, list) and len(v) == n and all(isinstance(x, float) for x in v)]
        assert set(per_storey) <= set(PEAK_UNITS), set(per_storey) - set(PEAK_UNITS)  # a new peak needs its unit
        for k in per_storey:
            np.testing.assert_array_equal(peaks.loc[name][f"{k} [{PEAK_UNITS[k]}]"].to_numpy(), b[k])


def test_histories_first_storey_drift_is_the_floor_displacement_over_its_height(session):
    """At storey 1 the ground does not move, so the drift ratio at the centre of mass is |(u, v)| / h1 (closed
    form, to rounding: one hypot and one division, 4 eps), and the Dataset's displacement is Result.cm."""
    _, ns = session
    ds, result, scene = ns["ds"], ns["result"], ns["scene"]
    for b in scene.buildings:
        disp = ds["displacement"].sel(building=b.name).values[:, : b.n_storeys]
        np.testing.assert_array_equal(disp, result.cm(b.name))
        expected = np.hypot(disp[:, 0, 0], disp[:, 0, 1]) / b.storey_heights[0]
        got = ds["drift_ratio_cm"].sel(building=b.name, storey=1).values
        np.testing.assert_allclose(got, expected, rtol=4 * np.finfo(float).eps, atol=0)
        assert np.isnan(ds["displacement"].sel(building=b.name).values[:, b.n_storeys:]).all()
    assert ds["time"].attrs["units"] == "s" and "damping" in ds["storey_shear"].attrs["description"]


def test_write_scene_makes_its_folder(tmp_path):
    """write_scene into a folder that does not exist yet makes it, as write_results does, and the scene loads back."""
    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    path = write_scene(scene, tmp_path / "new" / "deeper" / "scene.toml")
    assert scene_differences(scene, load_scene(path)) == []


@pytest.mark.parametrize("path", SCENE_FILES, ids=[str(p.relative_to(ROOT)) for p in SCENE_FILES])
def test_every_example_scene_round_trips(path, tmp_path):
    """write_scene then load_scene gives the same scene: every number within 8 roundings of its field's largest
    (element directions come back through an angle: cos/sin of atan2), everything else exactly."""
    scene = load_scene(path)
    again = load_scene(write_scene(scene, tmp_path / "scene.toml"))
    assert scene_differences(scene, again) == []


def _test_scene_dicts():
    from inelastic_scenes import eccentric_building, single
    from scenes_for_tests import pointed_pair, side_by_side

    return {
        "side_by_side": side_by_side(0.05, storeys=(2, 3)),
        "pointed_pair": pointed_pair(),
        "yielding_bouc_wen": single(eccentric_building(hysteresis={"name": "bouc_wen", "n": 2.0, "beta": 0.5, "gamma": 0.5})),
    }


@pytest.mark.parametrize("name", ["side_by_side", "pointed_pair", "yielding_bouc_wen"])
def test_every_test_scene_round_trips(name, tmp_path):
    """The scenes the tests build in code (frames, an L-shaped point, yielding Bouc-Wen springs) round-trip too."""
    scene = parse_scene(_test_scene_dicts()[name])
    again = load_scene(write_scene(scene, tmp_path / "scene.toml"))
    assert scene_differences(scene, again) == []


def test_a_changed_scene_round_trips_with_its_changes(tmp_path):
    """What Python changed is what is written: a moved building, new options, a rotated two-component motion."""
    from pounding.io.motion_pair import GroundMotionPair

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    gm = scene.ground_motion
    pair = GroundMotionPair(gm, gm.scaled(0.5), angle=30.0)
    changed = (scene.with_gap(0.07).with_analysis(dt=0.004, duration=7.5, contact="penalty", contact_params={"stiffness": 2e9})
               .with_ground_motion(pair))
    again = load_scene(write_scene(changed, tmp_path / "changed.toml"))
    assert scene_differences(changed, again) == []
    assert scene_differences(scene, again) != []  # the comparison sees the changes


def test_the_comparison_sees_a_small_change():
    """scene_differences is not vacuous: a slab mass off by 1e-9 relative is reported, by its key path."""
    from dataclasses import replace

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    b = scene.buildings[0]
    slabs = (replace(b.slabs[0], mass=b.slabs[0].mass * (1 + 1e-9)),) + b.slabs[1:]
    other = replace(scene, buildings=(replace(b, slabs=slabs),) + scene.buildings[1:])
    assert scene_differences(scene, other) == ["scene.buildings[0].slabs[0].mass"]


def test_misspelt_keywords_say_did_you_mean():
    """A misspelt option is a TypeError naming the closest accepted one, as the command line does."""
    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    with pytest.raises(TypeError, match=r"unknown keyword 'duraton' \(did you mean 'duration'\?\)"):
        scene.with_analysis(duraton=10.0)
    with pytest.raises(TypeError, match=r"unknown keyword 'progres' \(did you mean 'progress'\?\)"):
        pounding.run(scene, progres=None)
    with pytest.raises(TypeError, match=r"did you mean 'scene_text'"):
        pounding.write_results(None, "nowhere", scene_txt="")


@pytest.mark.parametrize("option, value", [("duration", 0), ("duration", -1.0), ("dt", -0.01), ("dt", float("nan")),
                                           ("output_every", 0), ("output_every", 1.5), ("energy_tolerance", 0.0)])
def test_analysis_options_from_python_are_checked_as_the_scene_file_checks_them(option, value):
    """`with_analysis` refuses what the scene file's schema refuses: an InputError naming analysis.OPTION
    and what was expected (a zero duration ran the whole record, a negative dt failed inside the integrator)."""
    from pounding.errors import InputError

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    with pytest.raises(InputError, match=rf"^analysis\.{option}: expected a positive"):
        scene.with_analysis(**{option: value})


def test_shifting_a_building_that_does_not_exist_names_the_buildings():
    from pounding.errors import InputError

    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml")
    with pytest.raises(InputError, match=r"no building 'C'; expected one of 'low', 'high'"):
        scene.with_building_shifted("C", (1.0, 0.0))


def test_sweep_drift_column_is_summary_json_drift(session):
    """One name, one definition: sweep.csv's B_peak_drift_ratio_cm is the largest of summary.json's per-storey
    peak_drift_ratio_cm (the same rows over the same continuous trajectory: equal to rounding, 4 eps)."""
    from pounding.framework.studies.sweep import _measures
    from pounding.io.results import summary

    _, ns = session
    result, scene = ns["result"], ns["scene"]
    row, s = _measures(result, scene, []), summary(result)
    for b in scene.buildings:
        expected = max(s["buildings"][b.name]["peak_drift_ratio_cm"])
        assert row[f"{b.name}_peak_drift_ratio_cm"] == pytest.approx(expected, rel=4 * np.finfo(float).eps)


def test_the_studies_and_the_export_are_in_the_public_api(tmp_path):
    """What the command line does is in the Python API: pounding.minimum_gap is `pounding gap`'s answer (the
    study's own function), pounding.sweep writes sweep.csv with one row per gap, pounding.export_opensees writes
    the script and returns its notes; a misspelt option names the closest one."""
    from pounding.framework.studies.gap import minimum_gap

    path = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
    scene = load_scene(path).with_analysis(duration=4.0)
    assert pounding.minimum_gap(scene).min_gap == minimum_gap(scene).min_gap > 0.0
    swept = pounding.sweep(path, tmp_path / "sweep", gaps=[0.5, 0.4], overrides={"duration": 0.3}, serial=True, plots=False)
    assert [r["gap"] for r in swept.rows] == [0.5, 0.4] and (tmp_path / "sweep" / "sweep.csv").is_file()
    notes = pounding.export_opensees(scene, tmp_path / "model.py")
    assert (tmp_path / "model.py").is_file() and isinstance(notes, list)
    with pytest.raises(TypeError, match=r"did you mean 'gaps'"):
        pounding.sweep(path, tmp_path / "other", gapz=[0.5])


def test_contact_table_is_contacts_csv_as_a_dataframe(tmp_path):
    """pounding.contact_table(result) is contacts.csv read back: the same columns and rows (buildings by name,
    each impact with its equivalent peak force)."""
    pd = pytest.importorskip("pandas")
    result = pounding.run(load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=4.0))
    table = pounding.contact_table(result)
    pounding.write_results(result, tmp_path / "run")
    written = pd.read_csv(tmp_path / "run" / "contacts.csv")
    assert list(table.columns) == list(written.columns) and len(table) == len(written) == len(result.impacts) > 0
    assert set(table["building_a"]) <= {"low", "high"} and (table["peak_force [N]"] > 0).all()
    assert (table["impulse [N s]"].to_numpy() == written["impulse [N s]"].to_numpy()).all()  # (the csv holds each float exactly)
