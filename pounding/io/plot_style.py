"""The figures' common look: size in dots per inch, colours, markers, and how a figure is made and saved.

matplotlib is imported inside :func:`_figure` only, so that importing the plotting modules costs nothing
until a figure is drawn.
"""

from __future__ import annotations

from pathlib import Path


DPI = 120
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"]
MARKERS = ["o", "s", "^", "v", "D", "P", "X", "<", ">", "*"]


def _figure(w: float, h: float):
    from matplotlib.figure import Figure

    return Figure(figsize=(w, h), dpi=DPI, layout="constrained")


def _save(fig, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI, format="png")
    return path
