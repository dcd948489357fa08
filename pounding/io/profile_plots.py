"""Profiles over height of the response quantities of practice, and floor response spectra (PNG, CSV).

* ``response_profiles.png`` - per building (one row each), over the storeys:
  peak drift ratio at the centre of mass and at the worst corner, peak storey
  shear, peak overturning moment, peak absolute floor acceleration (smooth
  part; the impacts' equivalent half-sine spikes as separate markers); with a
  ``reference`` run (e.g. the same scene without pounding) overlaid dashed grey.
* ``floor_spectra.png`` and ``floor_spectra.csv`` (on request) - pseudo-
  acceleration spectra of every floor, x and y, impacts included
  (:mod:`pounding.framework.post.spectra`).

matplotlib is imported by the figure helpers of :mod:`pounding.io.plots` only.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pounding.io.plot_style import COLOURS, _figure, _save


def _peaks(result) -> dict[str, dict]:
    from pounding.framework.post.response import building_response, impact_forces, peaks

    _, tau = impact_forces(result)
    return {name: peaks(building_response(result, name, tau)) for name in result.names}


PANELS = (
    ("peak_drift_ratio_cm", "drift ratio [%]", 100.0),
    ("peak_storey_shear", "storey shear, no damping [MN]", 1e-6),
    ("peak_overturning_moment", "overturning moment, no damping [MN m]", 1e-6),
    ("peak_floor_acceleration", "floor acceleration [m/s$^2$]", 1.0),
)


def plot_response_profiles(result, path, *, reference=None) -> Path:
    """Peak response over height, one row per building; ``reference`` overlaid dashed grey."""
    ours = _peaks(result)
    ref = _peaks(reference) if reference is not None else None
    fig = _figure(3.0 * len(PANELS), 2.8 * len(result.names))
    axes = fig.subplots(len(result.names), len(PANELS), squeeze=False)
    for r, name in enumerate(result.names):
        p = ours[name]
        storeys = np.arange(1, len(p["peak_drift_ratio_cm"]) + 1)
        for c, (key, label, scale) in enumerate(PANELS):
            ax = axes[r, c]
            ax.plot(np.asarray(p[key]) * scale, storeys, "-o", color=COLOURS[0], ms=4, label="with pounding" if ref else name)
            if key == "peak_drift_ratio_cm":
                ax.plot(np.asarray(p["peak_drift_ratio_corner"]) * scale, storeys, "-s", color=COLOURS[1], ms=4, label="worst corner")
            if key == "peak_floor_acceleration":
                spikes = np.asarray(p["peak_floor_acceleration_impact"])
                hit = spikes > 1e-9 * max(spikes.max(), 1e-300)  # other floors see rounding only (M is diagonal)
                if hit.any():
                    ax.plot(spikes[hit], storeys[hit], "x", color=COLOURS[1], ms=7, label="impact (half-sine)")
            if ref is not None and name in ref:
                q = ref[name]
                ax.plot(np.asarray(q[key]) * scale, storeys, "--", color="0.55", lw=1.0, label="reference")
                if key == "peak_drift_ratio_cm":
                    ax.plot(np.asarray(q["peak_drift_ratio_corner"]) * scale, storeys, ":", color="0.55", lw=1.0, label="reference corner")
            ax.set_yticks(storeys)
            ax.set_xlim(left=0)
            ax.grid(alpha=0.3)
            if r == len(result.names) - 1:
                ax.set_xlabel(label)
            if c == 0:
                ax.set_ylabel(f"{name}: storey")
            if r == 0 and c in (0, len(PANELS) - 1):
                ax.legend(fontsize=7, loc="best", framealpha=0.8)
    fig.suptitle("peak response over height" + (" (dashed: reference run)" if ref else ""), fontsize=10)
    return _save(fig, path)


def default_periods() -> np.ndarray:
    """0.02 to 5 s, 120 periods evenly spaced in log [s]."""
    return np.geomspace(0.02, 5.0, 120)


def write_floor_spectra(result, out_dir, *, periods=None, zeta: float = 0.05) -> list[Path]:
    """floor_spectra.csv (units in the header) and floor_spectra.png of every building and floor."""
    from pounding.framework.post.spectra import floor_spectra

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    periods = default_periods() if periods is None else np.asarray(periods, dtype=float)
    spectra = {name: floor_spectra(result, name, periods, zeta) for name in result.names}
    header, cols = ["period [s]"], [periods]
    for name, sa in spectra.items():
        for f in range(sa.shape[1]):
            for d, axis in enumerate("xy"):
                header.append(f"{name} storey {f + 1} {axis} [m/s2]")
                cols.append(sa[:, f, d])
    csv_path = out / "floor_spectra.csv"
    with open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(np.column_stack(cols).tolist())
    fig = _figure(9.0, 3.0 * len(spectra))
    axes = fig.subplots(len(spectra), 2, squeeze=False)
    for r, (name, sa) in enumerate(spectra.items()):
        for d, axis in enumerate("xy"):
            ax = axes[r, d]
            for f in range(sa.shape[1]):
                ax.plot(periods, sa[:, f, d], color=COLOURS[f % len(COLOURS)], lw=1.0, label=f"storey {f + 1}")
            ax.set_xscale("log")
            ax.set_title(f"{name}, {axis}", fontsize=9)
            ax.grid(alpha=0.3, which="both")
            ax.set_xlabel("period [s]")
            ax.set_ylabel("pseudo-acceleration [m/s$^2$]")
        axes[r, 1].legend(fontsize=7)
    fig.suptitle(f"floor response spectra, {100 * zeta:g} % damping, impacts included", fontsize=10)
    return [csv_path, _save(fig, out / "floor_spectra.png")]
