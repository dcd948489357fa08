"""Figures (matplotlib, Agg) and off-screen renders (pyvista; skipped where no OpenGL context can be made)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from pounding.framework.post.energy_account import energy_balance

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

pytest.importorskip("matplotlib")


@pytest.fixture(scope="module")
def runs():
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene

    scene = load_scene(PAPER).with_analysis(duration=3.0)
    result = run(scene)
    reference = run(scene.with_analysis(contact="none", contact_params={}))
    assert result.impacts and not reference.impacts
    return scene, result, reference


def assert_png(path: Path, min_bytes: int = 8000, min_size=(300, 200)):
    from PIL import Image

    path = Path(path)
    assert path.is_file(), path
    data = path.read_bytes()
    assert data[:8] == PNG_MAGIC, f"{path} is not a PNG"
    assert len(data) >= min_bytes, f"{path} is only {len(data)} bytes"
    with Image.open(path) as im:
        im.verify()
    with Image.open(path) as im:
        assert im.size[0] >= min_size[0] and im.size[1] >= min_size[1]
        # not a blank canvas
        arr = np.asarray(im.convert("L"))
        assert arr.std() > 5


def test_plot_all_writes_valid_pngs(runs, tmp_path):
    from pounding.io.plots import plot_all

    scene, result, reference = runs
    paths = plot_all(scene, result, tmp_path / "figs", reference=reference)
    names = {p.name for p in paths}
    assert {"displacement_histories.png", "impact_timeline.png", "gap_histories.png", "energy_balance.png", "plan.png"} <= names
    for p in paths:
        assert p.parent == tmp_path / "figs"
        assert_png(p)


def test_plot_all_without_impacts_or_scene(runs, tmp_path):
    from pounding.io.plots import plot_all

    _, _, reference = runs  # contact "none": no pairs, no impacts
    for p in plot_all(None, reference, tmp_path):
        assert_png(p, min_bytes=4000)


def test_plot_corner_history(runs, tmp_path):
    from pounding.io.plots import plot_corner_history

    _, result, reference = runs
    p = plot_corner_history(result, "low", 3, 1, reference, path=tmp_path / "corner.png")
    assert p == tmp_path / "corner.png"
    assert_png(p)
    assert_png(plot_corner_history(result, 1, 5, 0, path=tmp_path / "c2.png", component="y"))


def test_default_points_are_the_facing_corners_of_the_lower_building(runs):
    from pounding.io.plots import default_points, lower_building

    _, result, reference = runs
    assert result.names[lower_building(result)] == "low"
    pts = default_points(result)
    assert default_points(reference) == pts  # a run without contact keeps no pairs: found from the levels
    # "low" spans x in [0, 15]; its corners at x = 15 (vertices 1 and 2) face "high"
    assert pts == [("low", s, v, "x") for s in (3, 2, 1) for v in (1, 2)]
    for _, s, v, _ in pts:
        assert result.systems[0].slabs[s - 1].vertices[v][0] == pytest.approx(15.0)


def test_energy_histories_end_at_the_run_totals(runs):
    from pounding.io.plots import energy_histories

    scene, result, _ = runs
    h = energy_histories(result, scene)
    bal = energy_balance(result)
    assert h["kinetic_plus_strain"][-1] == pytest.approx(bal["kinetic_plus_strain"], rel=1e-9)
    assert h["impact_loss"][-1] == pytest.approx(bal["impact_loss"], rel=1e-12)
    assert h["impact_loss"][0] == 0.0 and np.all(np.diff(h["impact_loss"]) >= 0)
    # trapezoidal rule on the output grid: close to the run's own accumulation
    assert h["input"][-1] == pytest.approx(bal["input"], rel=0.05)
    assert h["damping"][-1] == pytest.approx(bal["damping"], rel=0.05)


def test_gap_history_starts_at_the_rest_gap_and_touches_at_impacts(runs):
    from pounding.io.vtk import pair_gaps

    _, result, _ = runs
    g = pair_gaps(result)
    assert g.shape == (len(result.t), len(result.pairs))
    np.testing.assert_allclose(g[0], [p[4] for p in result.pairs], atol=1e-12)
    for imp in result.impacts:
        k = int(np.argmin(np.abs(result.t - imp.time)))
        assert g[k, imp.pair] < 0.01  # within an output step of touching


# ----------------------------------------------------------------------------- render


def _render_or_skip(*args, **kwargs):
    from pounding.io.render import RenderUnavailable, render

    try:
        return render(*args, **kwargs)
    except RenderUnavailable as exc:
        pytest.skip(f"off-screen rendering unavailable here: {exc}")


def test_render_result(runs, tmp_path):
    scene, result, _ = runs
    paths = _render_or_skip(result, tmp_path / "r", scene=scene, magnify=50, window_size=(480, 320), gif_size=(320, 220), max_frames=4)
    names = [p.name for p in paths]
    assert names == ["render_plan.png", "render_3d.png", "render_pounding.gif"]
    for p in paths[:2]:
        assert_png(p, min_bytes=3000, min_size=(480, 320))
    gif = paths[2].read_bytes()
    assert gif[:6] in (b"GIF89a", b"GIF87a") and len(gif) > 5000
    import imageio.v3 as iio

    frames = iio.imread(paths[2], index=None)
    assert 2 <= len(frames) <= 4


def test_render_run_directory(runs, tmp_path):
    from pounding.io.render import load_run

    _, result, _ = runs
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    shutil.copy(PAPER, run_dir / "scene.toml")
    arrays = {"t": result.t}
    for n in result.names:
        arrays[f"{n}_cm"] = result.cm(n)
        arrays[f"{n}_vertices"] = result.vertices(n)
    np.savez(run_dir / "response.npz", **arrays)
    scene, motion = load_run(run_dir)
    assert motion.names == result.names
    np.testing.assert_array_equal(motion.cm[1], result.cm("high"))
    assert [p[:4] for p in motion.pairs] == [p[:4] for p in result.pairs]
    paths = _render_or_skip(run_dir, tmp_path / "r2", window_size=(400, 300), gif_size=(240, 180), max_frames=3)
    assert all(p.is_file() and p.stat().st_size > 2000 for p in paths)


def test_render_unavailable_is_a_runtime_error():
    from pounding.io.render import RenderUnavailable

    assert issubclass(RenderUnavailable, RuntimeError)


def test_render_unavailable_names_the_missing_library(monkeypatch, tmp_path, runs):
    import pounding.io.render as rd

    monkeypatch.setattr(rd, "_backend", None)
    monkeypatch.setattr(rd, "_failure", None)
    monkeypatch.setattr(rd, "_probe", lambda window, timeout=120.0: (False, "exit code -11"))
    monkeypatch.setattr(rd.ctypes.util, "find_library", lambda name: None)
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    _, result, _ = runs
    with pytest.raises(rd.RenderUnavailable) as err:
        rd.render(result, tmp_path)
    msg = str(err.value)
    assert "\n" not in msg
    assert "libEGL.so.1" in msg and "libegl1" in msg and "libosmesa6" in msg and "xvfb" in msg
    assert not any(tmp_path.iterdir())


def test_render_draws_walls_standing_still_and_links_moving_with_their_slabs(tmp_path):
    """With a scene of walls and links (tests/test_vtk.py's walled linked pair), the 3-D scene the renders draw
    holds the wall's face at z = 0 and z = top, exactly, at every frame, and the link's ends at their slabs'
    magnified rigid motion at the frame shown, (u - phi (y - y_c), v + phi (x - x_c)) from the run's own
    history (8 eps of the coordinates); the pictures are written."""
    import pyvista as pv

    from pounding.framework.post.run import run
    from pounding.io.render import _Scene3D
    from pounding.io.scene import parse_scene
    from pounding.io.vtk import Drawing, Motion
    from test_vtk import _walled_linked_pair

    scene = parse_scene(_walled_linked_pair())
    result = run(scene)
    motion = Motion.from_result(result, scene)
    sc = _Scene3D(pv, Drawing.build(scene, motion.names), motion, 50.0, scene)
    wall, link = scene.walls[0], scene.links[0]
    k = len(result.t) // 2
    sc.update(k)
    assert {tuple(p) for p in np.asarray(sc.walls.points)} == {(x, y, z) for z in (0.0, wall.top) for x, y in wall.face}
    for end, ((x, y), name, s) in enumerate(zip(link.points, link.between, link.storeys)):
        slab = scene.building(name).slabs[s - 1]
        u, v, phi = result.cm(name)[k, s - 1]
        moved = (x + 50.0 * (u - phi * (y - slab.centre[1])), y + 50.0 * (v + phi * (x - slab.centre[0])), slab.elevation)
        np.testing.assert_allclose(sc.links.points[end], moved, rtol=0, atol=8 * np.finfo(float).eps * 20.05)
    paths = _render_or_skip(result, tmp_path / "r", scene=scene, window_size=(400, 300), gif_size=(240, 180), max_frames=3)
    assert [p.name for p in paths] == ["render_plan.png", "render_3d.png", "render_pounding.gif"]
    for p in paths[:2]:
        assert_png(p, min_bytes=3000, min_size=(400, 300))


def test_the_pounding_window_spans_every_laws_contacts():
    """The window runs from the first contact's start to the last one's end, impacts and force laws'
    episodes alike, with its key instant at the start of the contact with the largest impulse."""
    pytest.importorskip("vtkmodules")
    from types import SimpleNamespace as NS

    from pounding.io.render import pounding_window

    t = np.arange(0.0, 10.0 + 1e-9, 0.01)
    impact = NS(time=2.0, impulse=1.0e3)
    episodes = [NS(start=2.0, end=2.0, impulse=1.0e3), NS(start=5.0, end=5.3, impulse=4.0e4), NS(start=7.5, end=7.6, impulse=2.0e3)]
    motion = NS(t=t, impacts=[impact], episodes=episodes, pairs=[], cm=[], tolerance=1e-4)
    first, last, key = pounding_window(motion, margin=0.5)
    assert (t[first], t[last], t[key]) == pytest.approx((1.5, 8.1, 5.0))
