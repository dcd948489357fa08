"""The run's result files: a contract people script against (README, "Result files")."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.io.results import IMPACT_COLUMNS
from pounding.io.scene import load_scene
from pounding.framework.post.energy_account import energy_balance

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper"


@pytest.fixture(scope="module")
def far_run(tmp_path_factory):
    """`pounding run` on the paper pair at 0.5 m (no pounding), first 4 s."""
    out = tmp_path_factory.mktemp("run") / "far"
    proc = subprocess.run(
        [sys.executable, "-m", "pounding", "run", str(PAPER / "pair_gap_0.5.toml"), "--out", str(out), "--duration", "4", "--quiet"],
        capture_output=True, text=True,
    )
    assert proc.returncode == 0, proc.stderr
    return out


def test_response_arrays_have_the_documented_shapes(far_run):
    """t (nt,), B_cm (nt, storeys, 3), B_vertices (nt, storeys, vertices, 2) for both buildings."""
    data = np.load(far_run / "response.npz")
    nt = len(data["t"])
    assert nt == 801 and data["t"][1] == pytest.approx(0.005)
    assert data["low_cm"].shape == (nt, 3, 3) and data["high_cm"].shape == (nt, 5, 3)
    assert data["low_vertices"].shape == (nt, 3, 4, 2) and data["high_vertices"].shape == (nt, 5, 4, 2)


def test_vertex_displacements_are_the_rigid_motion_of_the_slab(far_run):
    """A vertex P of a slab with centre c moves by (u - phi (P_y - c_y), v + phi (P_x - c_x)): the
    structural model's small-rotation motion, as the drifts and the VTK files take it."""
    data = np.load(far_run / "response.npz")
    scene = load_scene(PAPER / "pair_gap_0.5.toml")
    slab = scene.building("low").slabs[2]
    cm, vx = data["low_cm"][:, 2], data["low_vertices"][:, 2]
    for k, P in enumerate(slab.vertices):
        r = P - slab.centre
        assert np.allclose(vx[:, k, 0], cm[:, 0] - cm[:, 2] * r[1], rtol=0, atol=1e-15)
        assert np.allclose(vx[:, k, 1], cm[:, 1] + cm[:, 2] * r[0], rtol=0, atol=1e-15)


def test_summary_has_the_documented_keys_and_peaks(far_run):
    """summary.json: steps, runtime_s, integrator, dt, periods and peak |u|, |v|, |phi| per storey: the peaks
    over the continuous trajectory (pounding.framework.engine.peaks), the run folder's slab peaks to the bit (the same
    numbers written twice), never below the maxima of the step-end histories (the step ends are points of the
    trajectory)."""
    from pounding.io.results import load_result

    s = json.loads((far_run / "summary.json").read_text())
    data = np.load(far_run / "response.npz")
    assert s["steps"] == 800 and s["dt"] == 0.005 and s["integrator"]["name"] == "hht" and s["runtime_s"] > 0
    low = s["buildings"]["low"]
    assert len(low["periods"]) == 9
    _, back = load_result(far_run)
    assert low["peak_u"] == back.peaks("low")[:, 0].tolist() and low["peak_phi"] == back.peaks("low")[:, 2].tolist()
    assert np.all(np.array(low["peak_u"]) >= np.abs(data["low_cm"][:, :, 0]).max(axis=0))
    assert np.all(np.array(low["peak_phi"]) >= np.abs(data["low_cm"][:, :, 2]).max(axis=0))
    assert s["peaks_over"].startswith("continuous trajectory")
    assert s["n_impacts"] == 0 and s["impacts_per_storey"] == {}


def test_impact_log_is_header_only_without_contact(far_run):
    rows = list(csv.reader(open(far_run / "impacts.csv")))
    assert rows == [IMPACT_COLUMNS]


def test_impact_log_rows_match_the_result(tmp_path):
    """With pounding, impacts.csv has one row per impact with the documented columns."""
    scene = load_scene(PAPER / "pair_gap_0.03.toml").with_analysis(duration=3.0)
    from pounding.io.results import write_results

    result = run(scene)
    write_results(result, tmp_path / "near")
    rows = list(csv.DictReader(open(tmp_path / "near" / "impacts.csv")))
    assert len(rows) == result.n_impacts > 0
    assert [float(r["time [s]"]) for r in rows] == [i.time for i in result.impacts]
    assert {r["storey"] for r in rows} == {"3"}  # only the lower building's top can reach the other
    s = json.loads((tmp_path / "near" / "summary.json").read_text())
    assert s["n_impacts"] == result.n_impacts and s["impacts_per_storey"] == {"3": result.n_impacts}


def test_output_every_thins_the_arrays_only():
    """output_every = 4 keeps every 4th step of the same response."""
    scene = load_scene(PAPER / "pair_gap_0.5.toml").with_analysis(duration=2.0)
    full, thin = run(scene), run(scene.with_analysis(output_every=4))
    assert np.array_equal(thin.t, full.t[::4])
    assert np.allclose(thin.cm("high"), full.cm("high")[::4], rtol=0, atol=1e-15)


@pytest.mark.parametrize("gap, duration", [("0.5", 4.0), ("0.03", None)])
def test_compiled_kernel_and_python_path_agree(gap, duration):
    """The compiled stretches (free steps, and held steps in sustained contact) and the per-step
    Python path give the same response to 1e-12 of its peak, the same impacts, held episodes and
    energy terms (1e-12 of the input). Gap 0.03 m runs the whole record: 73 impacts, and pairs
    held in sustained contact nine times."""
    scene = load_scene(PAPER / f"pair_gap_{gap}.toml")
    if duration:
        scene = scene.with_analysis(duration=duration)
    a, b = run(scene), run(scene, use_kernel=False)
    assert a.n_impacts == b.n_impacts
    assert [i.time for i in a.impacts] == pytest.approx([i.time for i in b.impacts], abs=1e-12)
    ea, eb = energy_balance(a), energy_balance(b)
    for key in ("input", "damping", "contact_force_work", "impact_loss", "kinetic_plus_strain"):
        assert ea[key] == pytest.approx(eb[key], abs=1e-12 * ea["input"])
    for name in a.names:
        peak = np.abs(a.cm(name)).max()
        assert np.abs(a.cm(name) - b.cm(name)).max() <= 1e-12 * peak


def test_existing_output_survives_a_failed_run(tmp_path):
    """Results go to a temporary folder first: a run that fails leaves the previous results untouched."""
    from pounding.io.results import write_results

    out = tmp_path / "res"
    out.mkdir()
    (out / "keep.txt").write_text("old")
    result = run(load_scene(PAPER / "pair_gap_0.5.toml").with_analysis(duration=0.2))

    def boom(folder):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_results(result, out, extra=boom)
    assert [p.name for p in tmp_path.iterdir()] == ["res"]
    assert (out / "keep.txt").read_text() == "old"


def test_ctrl_c_leaves_no_half_written_folder(tmp_path):
    """SIGINT while the results are being written: exit code 130, no output folder, no temporary folder."""
    import signal
    import time

    out = tmp_path / "res"
    # Ctrl-C as a terminal sends it: Python turns SIGINT into KeyboardInterrupt only when the process
    # starts with the default action, which a test runner started in the background may have set to
    # "ignore" for its children
    proc = subprocess.Popen(
        [sys.executable, "-m", "pounding", "run", str(PAPER / "pair_gap_0.03.toml"), "--out", str(out), "--vtk", "--quiet"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if any(p.name.startswith(".res.tmp-") for p in tmp_path.iterdir()):
            break  # the writer has started: interrupt it mid-way
        time.sleep(0.01)
    assert proc.poll() is None, "the run ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_without_numba_the_same_numbers(tmp_path):
    """With numba switched off (NUMBA_DISABLE_JIT=1, as when it is not installed) every compiled
    function runs as plain Python over numpy arrays: the paper pair with pounding over its first
    3 s (impacts and held steps) gives the compiled run's response to 1e-12 of its peak."""
    import os
    import subprocess
    import sys

    scene = load_scene(PAPER / "pair_gap_0.03.toml").with_analysis(duration=3.0)
    a = run(scene)
    code = (
        "import numpy as np, sys\n"
        "from pounding.contact import geometry\n"
        "assert geometry.signed_gap.py_func is geometry.signed_gap, 'numba still compiling'\n"
        "from pounding.io.scene import load_scene\n"
        "from pounding.framework.post.run import run\n"
        f"r = run(load_scene({str(PAPER / 'pair_gap_0.03.toml')!r}).with_analysis(duration=3.0))\n"
        f"np.savez({str(tmp_path / 'b.npz')!r}, q=r.q, n=r.n_impacts)\n"
    )
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1"}
    subprocess.run([sys.executable, "-c", code], check=True, env=env, timeout=600)
    b = np.load(tmp_path / "b.npz")
    assert a.n_impacts == int(b["n"]) > 0
    assert np.abs(a.q - b["q"]).max() <= 1e-12 * np.abs(a.q).max()
