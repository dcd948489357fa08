"""The small things users read: grammar, peaks that are always there, plan symbols, plotted components."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from pounding.framework.post.run import run
from pounding.io.scene import load_scene, parse_scene
from pounding.words import plural

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper"


def test_plural():
    assert [plural(n, "storey") for n in (0, 1, 2)] == ["0 storeys", "1 storey", "2 storeys"]
    assert plural(1, "impact") == "1 impact"


def test_info_of_a_one_storey_building_says_storey(tmp_path):
    from pounding.io.scene_doc import template_text

    text = template_text().replace("storey_heights = [3.2, 3.2]", "storey_heights = [3.2]")
    path = tmp_path / "s.toml"
    path.write_text(text)
    out = subprocess.run([sys.executable, "-m", "pounding", "info", str(path)], capture_output=True, text=True, check=True).stdout
    assert "Building 'right': 1 storey, 3 DOF" in out


@pytest.mark.parametrize("every", [1, 3])
def test_slab_peaks_are_always_filled_and_survive_the_run_folder(every, tmp_path):
    """Result.slab_peaks holds the peak |u|, |v|, |phi| of every slab over the continuous trajectory: with every step
    in the output they are the extremes of the histories' interpolant (pounding.framework.engine.peaks, the same code on the
    same numbers: to the bit) and bound the step-end maxima; with every 3rd step kept they bound the output's maxima; a run
    folder gives them back unchanged. (The kernel sums each slab's modal rows in its own order, the histories by a
    matrix product: the two differ by rounding, a few ulps; 1e-14 of the peak is allowed.)"""
    from pounding.io.results import load_result, write_results

    scene = load_scene(PAPER / "pair_gap_0.03.toml").with_analysis(duration=3.0, output_every=every)
    result = run(scene)
    assert result.slab_peaks is not None and result.slab_peaks.shape == (8, 3)
    from_output = np.vstack([np.abs(result.cm(n)).max(axis=0) for n in result.names])
    if every == 1:
        from pounding.framework.engine.peaks import slab_peaks

        assert np.array_equal(result.slab_peaks, slab_peaks(result))
        # the step-end values enter both as matrix products over the same numbers, perhaps blocked differently by
        # the BLAS for the two array shapes: a few ulps apart, hence 1e-14
        assert np.all(result.slab_peaks >= from_output * (1 - 1e-14))
    else:
        assert np.all(result.slab_peaks >= from_output * (1 - 1e-14))
    write_results(result, tmp_path / "o", (PAPER / "pair_gap_0.03.toml").read_text())
    _, back = load_result(tmp_path / "o")
    assert np.array_equal(back.slab_peaks, result.slab_peaks)
    assert np.array_equal(back.peaks("high"), result.peaks("high"))


def test_plan_draws_walls_and_frames_differently():
    """A wall (outline with panels) is drawn as a filled bar, a frame as a line with a marker per column."""
    from matplotlib.figure import Figure

    from pounding.io.plots import _draw_element_plan
    from pounding.io.scene_doc import template_text

    scene = parse_scene(tomllib.loads(template_text("shear_wall")))
    frame = load_scene(PAPER / "pair_gap_0.03.toml").buildings[0].elements[0]
    ax = Figure().add_subplot()
    assert _draw_element_plan(ax, scene.buildings[0].elements[0], "b") == "wall"
    assert len(ax.patches) == 1 and not ax.lines
    assert _draw_element_plan(ax, frame, "r") == "frame"
    line, columns = ax.lines
    assert len(columns.get_xdata()) == len(frame.columns)


@pytest.mark.parametrize("angle, components", [(0.0, ("x",)), (180.0, ("x",)), (90.0, ("y",)), (30.0, ("x", "y"))])
def test_displacement_plots_show_the_components_of_the_shaking(angle, components):
    from types import SimpleNamespace

    from pounding.io.plots import shaking_components

    assert shaking_components(SimpleNamespace(ground_motion={"angle": angle})) == components


def test_gap_plot_keeps_its_note_and_legend_off_the_curves(tmp_path, monkeypatch):
    """The note and the legend sit outside the axes (right of them), so no curve is hidden."""
    from pounding.io import plots

    result = run(load_scene(PAPER / "pair_gap_0.03.toml").with_analysis(duration=3.0))
    figures = []
    monkeypatch.setattr(plots, "_save", lambda fig, path: figures.append(fig) or Path(path))
    plots.plot_gap_histories(result, tmp_path / "g.png")
    fig = figures[0]
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend()
    assert "impacts" in legend.get_title().get_text()
    assert legend.get_window_extent().x0 >= ax.get_window_extent().x1
    assert not ax.texts
