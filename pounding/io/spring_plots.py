"""Figures of yielding storey springs (PNG): hysteresis loops and drift profiles.

* ``hysteresis_loops.png`` - storey shear against storey drift of chosen springs (default: the
  spring of largest ductility demand in every building), with a ``reference`` run (e.g. the same
  scene without pounding) dashed grey;
* ``spring_profiles.png`` - per building (one row each), per yielding line, over the storeys:
  peak drift ratio, ductility demand and residual drift ratio, the reference dashed;
* ``link_loops.png`` - force against deformation of every link between slabs (`[[link]]`).

matplotlib is imported by the figure helpers of :mod:`pounding.io.plots` only.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from pounding.io.plot_style import COLOURS, _figure, _save


def spring_index(sp: dict, element: int, storey: int) -> int:
    """Index of the spring of ``element`` (0-based) at ``storey`` (1-based) in a run's spring record."""
    hit = np.flatnonzero((sp["element"] == element) & (sp["storey"] == storey))
    if len(hit) == 0:
        raise KeyError((element, storey))
    return int(hit[0])


def default_springs(result) -> list[tuple[str, int, int]]:
    """(building, element, storey) of the spring with the largest ductility demand in every building."""
    out = []
    for name, sp in result.springs.items():
        # a link with no yield deformation (a damper, a linear spring) has no ductility: its peak deformation ranks it
        finite = np.isfinite(sp["yield_deformation"])
        demand = sp["peak"] / sp["yield_deformation"] if finite.any() else sp["peak"]
        s = int(np.argmax(np.where(finite, demand, -np.inf) if finite.any() else demand))
        out.append((name, int(sp["element"][s]), int(sp["storey"][s])))
    return out


def plot_hysteresis(result, path, *, springs: Sequence | None = None, reference=None) -> Path:
    """Force-deformation loops of ``springs`` [(building, element 0-based, storey 1-based)]."""
    chosen = list(springs) if springs else default_springs(result)
    fig = _figure(4.0 * len(chosen), 3.4)
    axes = fig.subplots(1, len(chosen), squeeze=False)[0]
    for ax, (name, element, storey) in zip(axes, chosen):
        sp = result.springs[name]
        s = spring_index(sp, element, storey)
        if reference is not None and name in reference.springs:
            rs = reference.springs[name]
            r = spring_index(rs, element, storey)
            ax.plot(rs["deformation"][:, r] * 1e3, rs["force"][:, r] * 1e-3, "--", color="0.55", lw=0.8, label="reference")
        ax.plot(sp["deformation"][:, s] * 1e3, sp["force"][:, s] * 1e-3, "-", color=COLOURS[0], lw=0.9, label="this run")
        uy = sp["yield_deformation"][s]
        demand = f"ductility {sp['peak'][s] / uy:.1f}" if np.isfinite(uy) else f"peak {sp['peak'][s] * 1e3:.1f} mm"
        ax.set_title(f"{name}, element {element}, storey {storey} ({demand})", fontsize=9)
        ax.set_xlabel("storey drift along the line [mm]")
        ax.set_ylabel("storey shear [kN]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return _save(fig, path)


def _lines(sp: dict) -> dict[int, np.ndarray]:
    """Spring indices of every yielding line, storeys bottom first."""
    out = {}
    for j in sorted({int(e) for e in sp["element"]}):
        sel = np.flatnonzero(sp["element"] == j)
        out[j] = sel[np.argsort(sp["storey"][sel])]
    return out


PANELS = (
    ("peak drift ratio [%]", lambda sp, sel: 100.0 * sp["peak"][sel] / sp["height"][sel]),
    # NaN (not drawn) for a link with no yield deformation
    ("ductility demand [-]", lambda sp, sel: np.where(np.isfinite(sp["yield_deformation"][sel]),
                                                      sp["peak"][sel] / sp["yield_deformation"][sel], np.nan)),
    ("residual drift ratio [%]", lambda sp, sel: 100.0 * sp["deformation"][-1, sel] / sp["height"][sel]),
)


def plot_spring_profiles(result, path, *, reference=None) -> Path:
    """Peak drift ratio, ductility and residual drift ratio per yielding line over height."""
    names = list(result.springs)
    fig = _figure(3.2 * len(PANELS), 2.8 * len(names))
    axes = fig.subplots(len(names), len(PANELS), squeeze=False)
    for r, name in enumerate(names):
        sp = result.springs[name]
        ref = reference.springs.get(name) if reference is not None else None
        for c, (label, value) in enumerate(PANELS):
            ax = axes[r, c]
            for k, (j, sel) in enumerate(_lines(sp).items()):
                colour = COLOURS[k % len(COLOURS)]
                ax.plot(value(sp, sel), sp["storey"][sel], "-o", color=colour, ms=3, label=f"element {j}")
                if ref is not None:
                    rsel = _lines(ref).get(j)
                    if rsel is not None:
                        ax.plot(value(ref, rsel), ref["storey"][rsel], "--", color=colour, lw=0.8, alpha=0.7)
            ax.set_xlabel(label)
            ax.set_ylabel(f"{name}: storey")
            ax.set_yticks(np.unique(sp["storey"]))
            ax.grid(alpha=0.3)
            if c == 0:
                ax.legend(fontsize=6)
    fig.suptitle("yielding storey springs" + (" (dashed: reference run)" if reference is not None else ""), fontsize=10)
    return _save(fig, path)


def plot_link_loops(result, path, *, reference=None) -> Path:
    """``link_loops.png``: force against deformation of every link between slabs (one panel each),
    titled by its place and peaks; a ``reference`` run's loop of the same link dashed grey."""
    names = list(result.links)
    fig = _figure(4.0 * len(names), 3.4)
    axes = fig.subplots(1, len(names), squeeze=False)[0]
    for ax, name in zip(axes, names):
        rec = result.links[name]
        ref = reference.links.get(name) if reference is not None else None
        if ref is not None:
            ax.plot(ref["deformation"] * 1e3, ref["force"] * 1e-3, "--", color="0.55", lw=0.8, label="reference")
        ax.plot(rec["deformation"] * 1e3, rec["force"] * 1e-3, "-", color=COLOURS[0], lw=0.9, label="this run")
        (a, b), (sa, sb) = rec["between"], rec["storeys"]
        ax.set_title(f"{name}: {a} {sa} - {b} {sb} (stroke {float(rec['peak']) * 1e3:.1f} mm, "
                     f"{float(rec['energy_dissipated']) * 1e-3:.3g} kJ)", fontsize=9)
        ax.set_xlabel("link deformation [mm]")
        ax.set_ylabel("link force [kN]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return _save(fig, path)
