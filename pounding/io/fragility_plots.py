"""Plots of a pounding-fragility study (matplotlib, imported only here)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["plot_fragility"]


def _choose_gaps(runs: list[dict], levels: list[float], grid: list[float]) -> list[float]:
    """Three gaps worth a curve: the median required gap at the lowest, middle and highest level, on the grid."""
    out = []
    for lv in (levels[0], levels[len(levels) // 2], levels[-1]):
        r = [x["required_gap_m"] for x in runs if x.get("status") == "ok" and x["level"] == lv]
        if r:
            g = float(np.median(r))
            out.append(min(grid, key=lambda v: abs(v - g)) if grid else g)
    return sorted(set(out))


def plot_fragility(out, runs: list[dict], fragility: list[dict], target: list[dict], levels: list[float], im_label: str, *,
                   plot_gaps=None, confidence: float = 0.95) -> list[Path]:
    """``p_vs_gap.png`` (P(pounding) against the gap, one curve per level, target gaps marked) and
    ``fragility_curves.png`` (P(pounding) against the intensity for chosen gaps: observed fractions and fitted lognormal curves).

    Returns the paths written (none without matplotlib or without successful runs).
    """
    try:
        from matplotlib.figure import Figure
    except ImportError:
        return []
    from pounding.framework.post.lognormal import fit_lognormal
    from pounding.framework.post.lognormal import pounding_probability

    ok = [r for r in runs if r.get("status") == "ok"]
    levels = [lv for lv in levels if any(r["level"] == lv for r in ok)]
    if not levels:
        return []
    out = Path(out)
    paths = []

    fig = Figure(figsize=(7.5, 4.8), dpi=120, layout="constrained")
    ax = fig.add_subplot()
    r_all = [r["required_gap_m"] for r in ok]
    top = 1.05 * max(r_all)
    g = np.linspace(0.0, top, 600)
    colours = [f"C{i % 10}" for i in range(len(levels))]
    for lv, col in zip(levels, colours):
        r = np.array([x["required_gap_m"] for x in ok if x["level"] == lv])
        ax.step(g, pounding_probability(r, g), where="post", color=col, label=f"{lv:g} (n = {r.size})")
        for t in target:
            if t["level"] == lv and t["gap_m"] is not None and math.isfinite(t["gap_m"]):
                ax.plot([t["gap_m"]], [t["p_target"]], marker="o", color=col, markersize=4)
    ax.set_xlabel("gap at rest [m]")
    ax.set_ylabel("P(pounding)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title("Probability of pounding against the gap (dots: gap for the target probability)")
    ax.grid(True, alpha=0.3)
    ax.legend(title=im_label, fontsize=8)
    paths.append(out / "p_vs_gap.png")
    fig.savefig(paths[-1], format="png")

    grid = sorted({row["gap_m"] for row in fragility})
    chosen = list(plot_gaps) if plot_gaps else _choose_gaps(ok, levels, grid)
    fig = Figure(figsize=(7.5, 4.8), dpi=120, layout="constrained")
    ax = fig.add_subplot()
    x = np.array(levels, dtype=float)
    xs = np.linspace(0.0, 1.15 * x.max(), 400)[1:]
    for i, gap in enumerate(chosen):
        col = f"C{i % 10}"
        n = np.array([sum(1 for r in ok if r["level"] == lv) for lv in levels], dtype=float)
        z = np.array([sum(1 for r in ok if r["level"] == lv and r["required_gap_m"] >= gap) for lv in levels], dtype=float)
        ax.plot(x, z / n, linestyle="none", marker="o", color=col)
        fit = fit_lognormal(x, n, z, level=confidence)
        if fit.status == "ok":
            ax.plot(xs, fit.probability(xs), color=col,
                    label=f"gap {gap:g} m: median {fit.median:.3g} [{fit.median_lo:.3g}, {fit.median_hi:.3g}], beta {fit.beta:.2f}")
        else:
            ax.plot([], [], color=col, marker="o", label=f"gap {gap:g} m: no fit ({fit.status})")
    ax.set_xlabel(im_label)
    ax.set_ylabel("P(pounding)")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title(f"Pounding fragility (dots: fraction of records; lines: lognormal MLE, {100 * confidence:g} % bounds on the median)")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    paths.append(out / "fragility_curves.png")
    fig.savefig(paths[-1], format="png")
    return paths
