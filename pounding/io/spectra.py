"""Response spectra as files: CSV table, JSON document and a PNG figure.

Columns of ``spectrum.csv`` (one row per period, SI units and g):

``period_s``; per component ``<name>_psa_g`` and ``<name>_sd_m``; for a pair
``rotd50_psa_g``, ``rotd100_psa_g``, ``rotd50_sd_m``, ``rotd100_sd_m``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pounding.framework.post.intensity import Spectra
from pounding.framework.model.units import G

__all__ = ["spectra_table", "spectra_dict", "write_spectra_csv", "plot_spectra"]


def spectra_table(sp: Spectra) -> dict[str, np.ndarray]:
    """Column name -> values (nT,), in the order of the CSV file."""
    cols = {"period_s": sp.periods}
    labels = _labels(sp)
    for j, name in enumerate(labels):
        cols[f"{name}_psa_g"] = sp.psa[:, j] / G
        cols[f"{name}_sd_m"] = sp.sd[:, j]
    if sp.rotd50_psa is not None:
        cols["rotd50_psa_g"] = sp.rotd50_psa / G
        cols["rotd100_psa_g"] = sp.rotd100_psa / G
        cols["rotd50_sd_m"] = sp.rotd50_sd
        cols["rotd100_sd_m"] = sp.rotd100_sd
    return cols


def _labels(sp: Spectra) -> list[str]:
    """Component labels safe as column names; 'component1'/'component2' when two names coincide."""
    names = [n.replace(",", "_").replace(" ", "_") or f"component{j + 1}" for j, n in enumerate(sp.names)]
    if len(set(names)) != len(names):
        names = [f"component{j + 1}" for j in range(len(names))]
    return names


def spectra_dict(sp: Spectra, motion_name: str, building_periods: dict[str, list[float]] | None = None) -> dict:
    """The ``--json`` document: damping, components (PGA), periods, the table and the buildings' periods."""
    return {
        "ground_motion": motion_name,
        "damping_ratio": sp.zeta,
        "components": [{"name": n, "pga_g": float(p / G)} for n, p in zip(_labels(sp), sp.pga)],
        "spectra": {k: [float(x) for x in v] for k, v in spectra_table(sp).items()},
        "building_periods_s": building_periods or {},
    }


def write_spectra_csv(sp: Spectra, path) -> Path:
    path = Path(path)
    cols = spectra_table(sp)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(cols))
        for i in range(sp.periods.size):
            w.writerow([repr(float(v[i])) for v in cols.values()])
    return path


def plot_spectra(sp: Spectra, path, title: str = "", building_periods: dict[str, list[float]] | None = None) -> Path:
    """PSA [g] and SD [m] against the period (log axes), each component and RotD50/RotD100, periods marked."""
    from matplotlib.figure import Figure

    path = Path(path)
    fig = Figure(figsize=(10, 4.5), dpi=120, layout="constrained")
    axes = fig.subplots(1, 2)
    labels = _labels(sp)
    for ax, what, unit, scale in ((axes[0], "psa", "[g]", 1.0 / G), (axes[1], "sd", "[m]", 1.0)):
        data = sp.psa if what == "psa" else sp.sd
        for j, name in enumerate(labels):
            ax.loglog(sp.periods, data[:, j] * scale, lw=1.0, label=name)
        if sp.rotd50_psa is not None:
            r50 = sp.rotd50_psa if what == "psa" else sp.rotd50_sd
            r100 = sp.rotd100_psa if what == "psa" else sp.rotd100_sd
            ax.loglog(sp.periods, r50 * scale, "k-", lw=1.8, label="RotD50")
            ax.loglog(sp.periods, r100 * scale, "k--", lw=1.4, label="RotD100")
        styles = ["-.", ":", (0, (5, 2, 1, 2))]
        for b, (bname, periods) in enumerate((building_periods or {}).items()):
            for i, T in enumerate(periods):
                ax.axvline(T, color=f"C{(b + 4) % 10}", ls=styles[b % len(styles)], lw=0.9,
                           label=f"{bname} T{i + 1}-T{len(periods)}" if i == 0 else None)
        ax.set_xlabel("period T [s]")
        ax.set_ylabel(("pseudo-spectral acceleration PSA " if what == "psa" else "spectral displacement SD ") + unit)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(title or f"{100 * sp.zeta:g} %-damped response spectra")
    fig.savefig(path, format="png")
    return path
