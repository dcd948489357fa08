"""The paper's pair with yielding storeys, with pounding (gap 0.03 m) and without contact.

Usage: ``python examples/inelastic_pair/run_example.py OUT`` writes OUT/pounding and
OUT/no_contact (as `pounding run` does), their plots (OUT/pounding/plots, the no-contact run as
the reference: hysteresis loops, spring profiles, ...) and prints the table of README.md: per
building and storey, the worst line's peak drift ratio, ductility demand and residual drift ratio
with and without pounding.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from pounding import load_scene, run
from pounding.io.results import write_results
from pounding.framework.post.energy_account import energy_balance

HERE = Path(__file__).resolve().parent


def storey_table(result) -> dict[str, np.ndarray]:
    """Per building: (storeys, 3) = worst line's peak drift ratio [%], ductility, |residual drift ratio| [%]."""
    out = {}
    for name, sp in result.springs.items():
        n = int(sp["storey"].max())
        t = np.zeros((n, 3))
        for s in range(n):
            sel = sp["storey"] == s + 1
            t[s, 0] = 100.0 * np.max(sp["peak"][sel] / sp["height"][sel])
            t[s, 1] = np.max(sp["peak"][sel] / sp["yield_deformation"][sel])
            t[s, 2] = 100.0 * np.max(np.abs(sp["deformation"][-1, sel]) / sp["height"][sel])
        out[name] = t
    return out


def main(out: Path) -> None:
    runs = {}
    for key, scene_file in (("pounding", "pair_yielding_gap_0.03.toml"), ("no_contact", "pair_yielding_no_contact.toml")):
        path = HERE / scene_file
        result = run(load_scene(path))
        write_results(result, out / key, path.read_text(), scene_path=path)
        runs[key] = result
    try:
        from pounding.io.plots import plot_all

        plot_all(load_scene(HERE / "pair_yielding_gap_0.03.toml"), runs["pounding"], out / "pounding" / "plots",
                 reference=runs["no_contact"])
    except ImportError as exc:  # matplotlib is in the 'viz' extra
        print(f"plots skipped: {exc}")
    pounded, free = storey_table(runs["pounding"]), storey_table(runs["no_contact"])
    r = runs["pounding"]
    print(f"{r.n_impacts} impacts; energy balance error {energy_balance(r)['relative_error']:.1e} of the input")
    print("| building | storey | peak drift ratio [%] no contact / pounding | ductility no contact / pounding "
          "| residual drift ratio [%] no contact / pounding |")
    print("|---|---|---|---|---|")
    for name in pounded:
        for s in range(pounded[name].shape[0]):
            a, b = free[name][s], pounded[name][s]
            print(f"| {name} | {s + 1} | {a[0]:.3f} / {b[0]:.3f} | {a[1]:.2f} / {b[1]:.2f} | {a[2]:.3f} / {b[2]:.3f} |")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "inelastic_pair_output"))
