"""The row of five under El Centro, with and without pounding: runs, plots and the table of peaks.

    python examples/row/run_row.py [OUT_DIR]

Runs row.toml (impulse contact) and row_no_contact.toml (contact off) with `pounding run`,
draws the plots of the pounding run with the other overlaid (`pounding plot --reference`),
and prints a Markdown table per building: peak displacement along x at the top and peak
inter-storey drift ratio (worst corner, over all storeys) without and with pounding, and the
largest ratio with / without over its storeys of the drift and of the storey shear.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from pounding.cli import main as pounding

HERE = Path(__file__).resolve().parent


def table(out: Path) -> str:
    """Markdown: per building, peaks without and with pounding, and the largest amplification over its storeys."""
    runs = {k: json.loads((out / k / "summary.json").read_text()) for k in ("no_pounding", "pounding")}
    rows = ["| building | storeys | T1 [s] | top u without / with [mm] | peak drift without / with [%] "
            "| largest drift ratio with/without (storey) | largest storey-shear ratio (storey) |",
            "|---|---:|---:|---:|---:|---:|---:|"]

    def worst(a, b):
        r = [y / x for x, y in zip(a, b)]
        k = max(range(len(r)), key=r.__getitem__)
        return f"{r[k]:.2f} ({k + 1})"

    for name, b in runs["pounding"]["buildings"].items():
        a = runs["no_pounding"]["buildings"][name]
        u0, u1 = 1e3 * a["peak_u"][-1], 1e3 * b["peak_u"][-1]
        d0, d1 = 100 * max(a["peak_drift_ratio_corner"]), 100 * max(b["peak_drift_ratio_corner"])
        rows.append(f"| {name} | {len(b['peak_u'])} | {b['periods'][0]:.3f} | {u0:.1f} / {u1:.1f} | {d0:.3f} / {d1:.3f} "
                    f"| {worst(a['peak_drift_ratio_corner'], b['peak_drift_ratio_corner'])} "
                    f"| {worst(a['peak_storey_shear'], b['peak_storey_shear'])} |")
    s = runs["pounding"]
    rows.append("")
    rows.append(f"{s['n_impacts']} impacts, {s['impact_energy_loss'] / 1e3:.1f} kJ lost in impacts; impacts per storey: {s['impacts_per_storey']}")
    return "\n".join(rows)


def main(out: Path) -> None:
    for stem, key in (("row_no_contact", "no_pounding"), ("row", "pounding")):
        t0 = time.perf_counter()
        pounding(["run", str(HERE / f"{stem}.toml"), "--out", str(out / key), "--overwrite", "--quiet"])
        print(f"{key}: `pounding run` {time.perf_counter() - t0:.2f} s wall")
    pounding(["plot", str(out / "pounding"), "--reference", str(out / "no_pounding"), "--out", str(out / "plots"), "--overwrite"])
    print(table(out))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("row_output"))
