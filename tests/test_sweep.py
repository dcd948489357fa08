"""Parameter sweeps (`pounding sweep`): the grid, the table, Dask scheduling and failures."""

from __future__ import annotations

import csv
import json
import os
import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from pounding.errors import InputError
from pounding.framework.post.run import run
from pounding.framework.model.placement import with_gap
from pounding.framework.studies.sweep import build_cases, parse_values, read_table, run_sweep
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
ELCENTRO = ROOT / "pounding" / "io" / "data" / "elcentro_1940_ns.at2"
SHORT = {"duration": 2.0}
# The runs are short on purpose (El Centro's strong motion lasts to 25.5 s): the window's warning is
# tested in tests/test_study_window.py, and said here for every study.
pytestmark = pytest.mark.filterwarnings("ignore::pounding.framework.studies.window.WindowWarning")
GAPS = [0.0, 0.02, 0.05, 0.1]


def comparable(rows):
    """Rows without the wall-clock column."""
    return [{k: v for k, v in r.items() if k != "runtime_s"} for r in rows]


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """A records folder: El Centro as an AT2 file, and a broken AT2 whose header promises more values than it holds."""
    folder = tmp_path_factory.mktemp("records")
    shutil.copy(ELCENTRO, folder / "elcentro_copy.AT2")
    lines = ELCENTRO.read_text().splitlines()
    (folder / "broken.at2").write_text("\n".join(lines[:4] + lines[4:20]) + "\n")
    return folder


@pytest.fixture(scope="module")
def serial_sweep(tmp_path_factory, records):
    out = tmp_path_factory.mktemp("serial")
    return run_sweep(PAPER, out, gaps=GAPS, records=records, restitutions=[0.5], overrides=SHORT, serial=True)


# --------------------------------------------------------------------------- the grid
def test_values_and_ranges():
    assert parse_values("0,0.01,0.05", "--gaps") == [0.0, 0.01, 0.05]
    assert parse_values("0:0.5:6", "--gaps") == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
    assert parse_values("0.3, 0:1:3", "--gaps") == [0.3, 0.0, 0.5, 1.0]
    for bad in ("a", "0:1", "0:1:0", ""):
        with pytest.raises(InputError):
            parse_values(bad, "--gaps")
    with pytest.raises(InputError, match=r"\[0, 1\]"):
        parse_values("1.5", "--restitution", minimum=0.0, maximum=1.0)
    cases = build_cases(gaps=[0.0, 0.1], pga_scales=[1.0, 2.0], integrators=["hht", "newmark"])
    assert len(cases) == 8 and [c.run for c in cases] == list(range(8))
    assert (cases[0].gap, cases[1].gap, cases[2].pga_scale) == (0.0, 0.1, 2.0)


# --------------------------------------------------------------------------- the table
def test_rows_match_single_runs(serial_sweep):
    """Each row holds what a run of the scene at that gap gives."""
    scene = load_scene(PAPER).with_analysis(**SHORT)
    rows = [r for r in serial_sweep.rows if r["record"] == "elcentro_copy"]
    assert [r["gap"] for r in rows] == GAPS
    for r in rows[1:3]:
        res = run(with_gap(scene, r["gap"]))
        assert r["n_impacts"] == res.n_impacts and r["status"] == "ok" and r["restitution"] == 0.5 and r["integrator"] == "hht"
        assert r["low_peak_u"] == res.peaks("low")[:, 0].max() and r["high_peak_phi"] == res.peaks("high")[:, 2].max()
        assert r["energy_loss"] == sum(i.energy_loss for i in res.impacts)
        assert sum(r[f"impacts_storey_{s}"] for s in (1, 2, 3)) == r["n_impacts"]
    assert rows[0]["n_impacts"] > rows[-1]["n_impacts"]


def test_a_failing_run_is_reported_and_the_sweep_goes_on(serial_sweep):
    rows = serial_sweep.rows
    assert len(rows) == 2 * len(GAPS)
    bad = [r for r in rows if r["record"] == "broken"]
    good = [r for r in rows if r["record"] == "elcentro_copy"]
    assert all(r["status"] == "error" and "NPTS" in r["error"] and r["n_impacts"] is None for r in bad)
    assert all(r["status"] == "ok" and r["error"] is None for r in good)
    assert serial_sweep.failed == bad


def test_csv_parquet_and_plots_are_written(serial_sweep):
    rows = read_table(serial_sweep.csv)
    assert comparable(rows) == comparable(serial_sweep.rows)
    header = next(csv.reader(open(serial_sweep.csv)))
    for col in ("run", "gap [m]", "pga_scale [-]", "record", "restitution [-]", "integrator", "status", "error", "n_impacts",
                "impacts_storey_1", "impacts_storey_3", "low_peak_u [m]", "high_peak_phi [rad]", "high_peak_drift_ratio_cm [-]",
                "max_impulse [N s]", "energy_loss [J]", "runtime_s"):
        assert col in header
    import pyarrow.parquet as pq

    parquet = pq.read_table(serial_sweep.parquet)
    assert parquet.schema.field("gap").metadata == {b"units": b"m"}
    table = parquet.to_pylist()
    assert comparable(table) == comparable(serial_sweep.rows)
    assert [p.name for p in serial_sweep.plots] == ["impacts_vs_gap.png", "drift_vs_gap.png"]
    assert all(p.stat().st_size > 1000 for p in serial_sweep.plots)


def test_the_csv_grows_as_runs_complete_and_survives_an_interruption(tmp_path):
    seen = []

    def progress(done, total, row):
        with open(tmp_path / "sweep.csv") as fh:
            seen.append(len(fh.read().splitlines()) - 1)
        if done == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(PAPER, tmp_path, gaps=[0.0, 0.05, 0.1, 0.2, 0.3], overrides=SHORT, serial=True, progress=progress)
    assert seen == [1, 2, 3]
    rows = read_table(tmp_path / "sweep.csv")
    assert [r["run"] for r in rows] == [0, 1, 2] and all(r["status"] == "ok" for r in rows)


def test_keep_writes_each_runs_results(tmp_path):
    res = run_sweep(PAPER, tmp_path, gaps=[0.05], pga_scales=[0.5, 1.0], overrides=SHORT, serial=True, keep=True, plots=False)
    for r in res.rows:
        folder = tmp_path / "runs" / f"run_{r['run']:04d}"
        summary = json.loads((folder / "summary.json").read_text())
        assert summary["n_impacts"] == r["n_impacts"] and (folder / "response.npz").exists()
        assert json.loads((folder / "case.json").read_text())["pga_scale"] == r["pga_scale"]
    assert res.rows[0]["n_impacts"] <= res.rows[1]["n_impacts"]


# --------------------------------------------------------------------------- Dask
def test_parallel_sweeps_equal_the_serial_one(tmp_path, serial_sweep, records):
    """1 and 2 local worker processes give the serial table (failed runs included), row for row."""
    for n in (1, 2):
        res = run_sweep(PAPER, tmp_path / f"w{n}", gaps=GAPS, records=records, restitutions=[0.5], overrides=SHORT, workers=n, plots=False)
        assert res.workers == n
        assert comparable(res.rows) == comparable(serial_sweep.rows)
        assert comparable(read_table(res.csv)) == comparable(serial_sweep.rows)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def dask_cluster(tmp_path):
    """A dask.distributed scheduler and two workers, each its own process on localhost; always terminated."""
    pytest.importorskip("distributed")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    procs = []
    log = open(tmp_path / "dask.log", "w")
    try:
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", str(port),
                                       "--no-dashboard"], stdout=log, stderr=subprocess.STDOUT, env=env))
        for i in range(2):
            procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1", "--no-nanny",
                                           "--no-dashboard", "--name", f"w{i}", "--host", "127.0.0.1"],
                                          stdout=log, stderr=subprocess.STDOUT, env=env))
        from dask.distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
        yield address
    finally:
        # workers first: a worker whose scheduler is gone keeps trying to reconnect
        for p in procs[1:] + procs[:1]:
            p.terminate()
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait(timeout=5)
        log.close()


def test_sweep_on_an_existing_scheduler(dask_cluster, tmp_path):
    """`pounding sweep --scheduler ADDRESS` runs on a separately started scheduler with two workers."""
    out = tmp_path / "remote"
    proc = subprocess.run([sys.executable, "-m", "pounding", "sweep", str(PAPER), "--out", str(out), "--gaps", "0,0.05,0.1",
                           "--duration", "2", "--scheduler", dask_cluster, "--quiet", "--no-plots"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "2 Dask worker(s)" in proc.stdout
    rows = read_table(out / "sweep.csv")
    serial = run_sweep(PAPER, tmp_path / "serial", gaps=[0.0, 0.05, 0.1], overrides=SHORT, serial=True, plots=False)
    assert comparable(rows) == comparable(serial.rows)


# --------------------------------------------------------------------------- command line
@pytest.mark.parametrize("extra, field", [
    (["--gaps", "-0.1"], "--gaps"),
    (["--restitution", "2"], "--restitution"),
    (["--records", "no/such/folder"], "--records"),
    (["--integrator", "nosuch"], "--integrator"),
    (["--gaps", "0.1", "--direction", "y"], "--direction"),
])
def test_bad_sweep_input_exits_2(tmp_path, capsys, extra, field):
    from pounding.cli import main

    code = main(["sweep", str(PAPER), "--out", str(tmp_path / "o"), "--serial", *extra])
    err = capsys.readouterr()
    assert code == 2 and field in err.err and err.out == ""
    assert not (tmp_path / "o").exists()  # nothing is written before the inputs are checked


def test_a_relative_out_folder_lists_every_file_it_wrote(tmp_path, monkeypatch):
    """With --out given relative to the working folder, the manifest lists the table, sweep.json, the Parquet copy
    and the plots by their names in the folder, so nothing there counts as foreign and a rerun is not refused."""
    from pounding.io.outputs import foreign, read_manifest

    monkeypatch.chdir(tmp_path)
    res = run_sweep(PAPER, Path("rel"), gaps=[0.05, 0.1], overrides={"duration": 0.5}, serial=True)
    assert foreign(Path("rel")) == [] and len(res.plots) == 2
    assert set(read_manifest(Path("rel"))["sweep"]) == {"sweep.csv", "sweep.json", "sweep.parquet", "impacts_vs_gap.png",
                                                         "drift_vs_gap.png"}
