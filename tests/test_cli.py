"""The command line: every command has --help, runs stay light, pictures work from a run folder."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper"
HEAVY = ("vtk", "pyvista", "matplotlib", "pandas", "xarray")


def pounding(*args, check=True):
    proc = subprocess.run([sys.executable, "-m", "pounding", *map(str, args)], capture_output=True, text=True)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


@pytest.mark.parametrize("command", ["info", "run", "demo", "plot", "render", "gap", "sweep", "template", "check", "reference", "export"])
def test_every_command_explains_its_options(command):
    proc = pounding(command, "--help")
    assert "usage: pounding " + command in proc.stdout
    assert "--help" in proc.stdout


def test_version():
    assert pounding("--version").stdout.startswith("pounding ")


@pytest.mark.parametrize(
    "argv",
    [
        ["info", str(PAPER / "pair_gap_0.03.toml")],
        ["run", str(PAPER / "pair_gap_0.03.toml"), "--duration", "2", "--quiet", "--out", "{tmp}/o"],
    ],
    ids=["info", "run"],
)
def test_info_and_run_import_no_drawing_library(argv, tmp_path):
    """Start-up stays light: without --vtk neither vtk, pyvista nor matplotlib is imported."""
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code = (
        "import sys; from pounding.cli import main; rc = main(%r); "
        "heavy = [m for m in sys.modules if m.split('.')[0] in %r]; print('HEAVY', heavy); sys.exit(rc)" % (argv, HEAVY)
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "HEAVY []" in proc.stdout


@pytest.fixture(scope="module")
def run_dirs(tmp_path_factory):
    base = tmp_path_factory.mktemp("cli")
    pounding("run", PAPER / "pair_gap_0.03.toml", "--out", base / "near", "--duration", "4", "--quiet")
    pounding("run", PAPER / "pair_gap_0.5.toml", "--out", base / "far", "--duration", "4", "--quiet")
    return base


def test_run_prints_a_human_summary(tmp_path):
    out = pounding("run", PAPER / "pair_gap_0.03.toml", "--out", tmp_path / "o", "--duration", "3").stdout
    assert "impacts:" in out and "storey 3" in out and "peak |u|" in out and str(tmp_path / "o") in out


def test_load_result_rebuilds_the_run(run_dirs):
    """A run folder holds everything to rebuild the Result: same physical histories and impacts."""
    import numpy as np

    from pounding.io.results import load_result

    scene, result = load_result(run_dirs / "near")
    data = np.load(run_dirs / "near" / "response.npz")
    assert np.allclose(result.cm("low"), data["low_cm"], rtol=0, atol=1e-15)
    summary = json.loads((run_dirs / "near" / "summary.json").read_text())
    assert result.n_impacts == summary["n_impacts"] > 0


def test_plot_writes_pngs_from_a_run_folder(run_dirs):
    out = pounding("plot", run_dirs / "near", "--reference", run_dirs / "far").stdout.split()
    assert len(out) >= 4
    for p in out:
        assert Path(p).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_takes_chosen_points(run_dirs, tmp_path):
    """--point BUILDING:STOREY:VERTEX[:x|y] chooses the histories; a bad point is a clear error."""
    out = pounding("plot", run_dirs / "near", "--point", "high:5:2:y", "--point", "low:1:0", "--out", tmp_path / "p").stdout
    assert (tmp_path / "p" / "displacement_histories.png").is_file() and "displacement_histories.png" in out
    bad = pounding("plot", run_dirs / "near", "--point", "low:4:0", check=False)
    assert bad.returncode == 2 and "storey must be 1..3" in bad.stderr


def test_plot_of_a_folder_that_is_not_a_run_is_a_clear_error(tmp_path):
    proc = pounding("plot", tmp_path, check=False)
    assert proc.returncode == 2 and "not a run folder" in proc.stderr and "Traceback" not in proc.stderr


def test_run_with_vtk_writes_a_paraview_series(tmp_path):
    """`pounding run --vtk --vtk-every 40` over 3 s at dt 0.005: the .pvd lists every 40th step
    (t = 0, 0.2, ..., 3.0: 16 frames) plus one frame at each distinct impact instant, every file present."""
    import csv
    import xml.etree.ElementTree as ET

    out = tmp_path / "o"
    pounding("run", PAPER / "pair_gap_0.03.toml", "--out", out, "--duration", "3", "--vtk", "--vtk-every", "40", "--quiet")
    pvd = out / "vtk" / "pounding.pvd"
    sets = list(ET.parse(pvd).getroot().iter("DataSet"))
    times = sorted(float(d.get("timestep")) for d in sets)
    impact_times = {float(r["time [s]"]) for r in csv.DictReader(open(out / "impacts.csv"))}
    grid = {round(0.2 * k, 12) for k in range(16)}
    assert impact_times, "the scene pounds within 3 s"
    assert len(times) == len(grid | impact_times)
    assert all(any(abs(t - g) < 1e-12 for t in times) for g in grid)
    assert all(any(abs(t - i) < 1e-12 for t in times) for i in impact_times)
    assert all((pvd.parent / d.get("file")).is_file() for d in sets)


def test_run_of_a_folder_is_a_clear_error_and_writes_nothing(tmp_path):
    """`pounding run .` names the folder and what was expected (a scene file), exit 2, no output folder."""
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", "."], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 2 and "it is a folder" in proc.stderr and "Traceback" not in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_plot_with_a_reference_of_other_buildings_is_a_clear_error(run_dirs, tmp_path):
    """--reference must be a run of the same buildings (the plots overlay it storey by storey): another
    scene's run is named with both sets of buildings, exit 2, and no plot folder is written."""
    from pounding.io.scene_doc import template_text

    scene = tmp_path / "t.toml"
    scene.write_text(template_text())
    pounding("run", scene, "--out", tmp_path / "other", "--duration", "0.5", "--quiet")
    proc = pounding("plot", run_dirs / "near", "--reference", tmp_path / "other", "--out", tmp_path / "p", check=False)
    assert proc.returncode == 2 and "--reference" in proc.stderr and "'left' (3 storeys)" in proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "p").exists()


def test_an_analysis_that_diverges_is_one_line_and_exit_1(tmp_path, monkeypatch, capsys):
    """An iteration of the analysis that does not converge (FloatingPointError from the engine) is reported
    in one line with the engine's own message, exit code 1 (not bad input), without a traceback."""
    import pounding.cli as cli

    def diverges(*args, **kwargs):
        raise FloatingPointError("building 'low': the links' Newton iteration did not converge (try a smaller dt)")

    monkeypatch.setattr(cli, "analyse", diverges)
    assert cli.main(["run", str(PAPER / "pair_gap_0.03.toml"), "--out", str(tmp_path / "o"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0 and "did not converge" in err and err.startswith("pounding: error:")


def test_an_unknown_option_is_reported_with_the_commands_own_usage():
    """`pounding gap SCENE --bogus`: exit 2 with gap's usage line (what gap takes), not the top-level one."""
    proc = pounding("gap", PAPER / "pair_gap_0.03.toml", "--bogus", check=False)
    assert proc.returncode == 2 and proc.stderr.startswith("usage: pounding gap ") and "unrecognized arguments: --bogus" in proc.stderr


def test_an_unknown_option_before_the_command_is_reported_with_the_top_level_usage():
    """`pounding --bogus run SCENE`: the option was given to pounding itself, whose usage says what it takes."""
    proc = pounding("--bogus", "run", PAPER / "pair_gap_0.03.toml", check=False)
    assert proc.returncode == 2 and proc.stderr.startswith("usage: pounding [-h]") and "unrecognized arguments: --bogus" in proc.stderr
