"""What engineers read of yielding buildings: summary.json and response.npz (README, result files)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.framework.post.inelastic_run import run_inelastic
from pounding.io.results import load_result, write_results
from pounding.io.scene import parse_scene

from strategies import to_toml
from test_inelastic_pounding import pair_data
from pounding.framework.post.energy_account import energy_balance

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """The pair 1 m apart (nothing touches) with contact on, written as `pounding run` writes it."""
    data = pair_data(1.0, duration=4.0)
    scene = parse_scene(data)
    result = run(scene)
    out = tmp_path_factory.mktemp("run") / "out"
    write_results(result, out, to_toml(data))
    return scene, result, out


def test_summary_reports_the_contact_free_stepping_s_drift_ductility_residual_and_energy(written):
    """Per yielding spring line and storey, summary.json's peak drift ratio, ductility demand,
    residual drift and hysteretic energy are those :func:`run_inelastic` computes with its own
    compiled stepping for the same buildings without contact: to 1e-9 relative (the two runs
    agree to 1e-15 of the peak; the ratios add a few roundings)."""
    scene, result, out = written
    summ = json.loads((out / "summary.json").read_text())
    free = run_inelastic(scene.with_analysis(contact="none"))
    for b in free.buildings:
        lines = summ["buildings"][b.name]["yielding_springs"]
        assert sorted(line["element"] for line in lines) == sorted(set(b.springs.element.tolist()))
        for line in lines:
            sel = np.flatnonzero(b.springs.element == line["element"])
            sel = sel[np.argsort(b.springs.storey[sel])]
            assert line["storeys"] == b.springs.storey[sel].tolist()
            for key, ref in (("peak_drift_ratio", b.drift_ratio), ("ductility", b.ductility), ("residual_drift", b.residual),
                             ("residual_drift_ratio", b.residual_drift_ratio), ("hysteretic_energy", b.hysteretic)):
                np.testing.assert_allclose(line[key], ref[sel], rtol=1e-9, atol=1e-9 * np.abs(ref).max(), err_msg=key)
        assert max(max(line["ductility"]) for line in lines) > 2.0  # the springs yield


def test_response_npz_holds_the_spring_histories_and_the_yielding_lines_carry_their_own_shear(written):
    """response.npz: ``B_spring_deformation`` and ``B_spring_force`` (nt, ns) equal the contact-free
    stepping's histories (1e-12 of their peaks), and ``B_element_shear`` of a yielding line is its
    springs' force, storey by storey (the same numbers, not the elastic k0 u)."""
    scene, result, out = written
    free = run_inelastic(scene.with_analysis(contact="none"))
    with np.load(out / "response.npz") as npz:
        for b in free.buildings:
            d, r = npz[f"{b.name}_spring_deformation"], npz[f"{b.name}_spring_force"]
            assert np.abs(d - b.deformation).max() <= 1e-12 * np.abs(b.deformation).max()
            assert np.abs(r - b.force).max() <= 1e-12 * np.abs(b.force).max()
            shear = npz[f"{b.name}_element_shear"]
            for s, (j, f) in enumerate(zip(b.springs.element, b.springs.storey)):
                np.testing.assert_array_equal(shear[:, j, f - 1], r[:, s])
            # elastic shear k0 u differs once the springs yield: the outputs are not the initial model's
            assert np.abs(r - b.springs.k0 * d).max() > 0.1 * np.abs(r).max()


def test_a_run_folder_reloads_its_springs_and_energy(written):
    """load_result (what `pounding plot` reads) gives back the springs' histories and the
    hysteretic energy the run wrote, so the energy audit of a reloaded run still closes."""
    scene, result, out = written
    _, loaded = load_result(out)
    for name, sp in result.springs.items():
        for key in ("deformation", "force", "dissipated", "peak"):
            np.testing.assert_array_equal(loaded.springs[name][key], sp[key])
        assert loaded.energy[name]["hysteretic"] == result.energy[name]["hysteretic"]
    assert energy_balance(loaded)["error"] == pytest.approx(energy_balance(result)["error"], abs=1e3 * EPS * energy_balance(result)["input"])


def test_pounding_plot_draws_hysteresis_loops_and_spring_profiles(written, tmp_path):
    """`pounding plot RUN --reference REF --spring B:E:S` writes hysteresis_loops.png and
    spring_profiles.png besides the other figures; a spring that is not in the run is one clear
    message naming --spring, exit 2, nothing written."""
    import subprocess
    import sys

    pytest.importorskip("matplotlib")
    scene, result, out = written
    name = result.names[0]
    sp = result.springs[name]
    spring = f"{name}:{int(sp['element'][0])}:{int(sp['storey'][0])}"
    plots = tmp_path / "plots"
    cmd = [sys.executable, "-m", "pounding", "plot", str(out), "--reference", str(out), "--out", str(plots), "--spring", spring]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    for png in ("hysteresis_loops.png", "spring_profiles.png"):
        assert (plots / png).stat().st_size > 10_000
    bad = tmp_path / "bad"
    proc = subprocess.run([sys.executable, "-m", "pounding", "plot", str(out), "--out", str(bad), "--spring", f"{name}:99:1"],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "--spring" in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    assert not bad.exists()


def test_drift_ratio_at_every_slab_corner_from_the_vertex_histories(written):
    """response.npz ``B_drift_ratio_corners`` (nt, storeys, corners): at corner k of storey s,
    |(vertex k displacement of slab s) - (that of slab s-1)| / h_s, read straight from B_vertices
    (the buildings' slabs have the same polygon at every storey, so vertex k of both floors is the
    same plan point; the ground does not move). Differences of O(1e-2) m: rounding 1e-16 m, so
    1e-12 of the peak. summary.json ``peak_drift_ratio_corners`` is its peak per storey and corner,
    and the worst corner is ``B_drift_ratio_corner``."""
    scene, _, out = written
    summ = json.loads((out / "summary.json").read_text())
    with np.load(out / "response.npz") as npz:
        for b in scene.buildings:
            verts = npz[f"{b.name}_vertices"]
            h = np.asarray(b.storey_heights)
            below = np.concatenate([np.zeros_like(verts[:, :1]), verts[:, :-1]], axis=1)
            corners = np.linalg.norm(verts - below, axis=-1) / h[None, :, None]
            got = npz[f"{b.name}_drift_ratio_corners"]
            assert got.shape == corners.shape == (len(npz["t"]), b.n_storeys, 4)
            peak = corners.max()
            assert np.abs(got - corners).max() <= 1e-12 * peak
            np.testing.assert_allclose(summ["buildings"][b.name]["peak_drift_ratio_corners"], corners.max(axis=0),
                                       rtol=0, atol=1e-12 * peak)
            np.testing.assert_array_equal(npz[f"{b.name}_drift_ratio_corner"], got.max(axis=2))


def test_vtk_cells_of_yielding_springs_carry_their_ductility(written, tmp_path):
    """The VTK series colours storey-spring cells by ductility demand: on every cell that draws the
    spring of element j in storey s, ``ductility_peak`` is that spring's peak |u| / u_y from the
    run (summary.json's ductility, the same numbers) and ``ductility`` at the last frame is the
    running peak of its recorded deformations over u_y; slabs carry NaN; ``element`` says which
    element a cell draws."""
    pytest.importorskip("vtkmodules")
    from pounding.io.vtk import read_pvd, write_vtk_series
    from test_vtk import read_vtu

    scene, result, out = written
    pvd = write_vtk_series(scene, result, tmp_path / "vtk", every=100, impact_times=())
    entries = read_pvd(pvd)
    _, _, _, cd, _ = read_vtu(entries[-1][1])
    k_last = int(round(entries[-1][0] / (result.t[1] - result.t[0])))
    summ = json.loads((out / "summary.json").read_text())
    assert np.all(np.isnan(cd["ductility"][cd["element_type"] == 0]))
    checked = 0
    for b_idx, b in enumerate(scene.buildings):
        sp = result.springs[b.name]
        for line in summ["buildings"][b.name]["yielding_springs"]:
            for s, mu in zip(line["storeys"], line["ductility"]):
                mine = np.flatnonzero((cd["building"] == b_idx) & (cd["element"] == line["element"]) & (cd["storey"] == s))
                assert len(mine) == 2  # the spring's zig-zag: two line cells
                spring = np.flatnonzero((sp["element"] == line["element"]) & (sp["storey"] == s))[0]
                running = np.abs(sp["deformation"][: k_last + 1, spring]).max() / sp["yield_deformation"][spring]
                np.testing.assert_allclose(cd["ductility_peak"][mine], mu, rtol=1e-12)
                np.testing.assert_allclose(cd["ductility"][mine], running, rtol=1e-12)
                checked += 1
    assert checked == sum(len(result.springs[b.name]["element"]) for b in scene.buildings)
