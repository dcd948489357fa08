"""``pounding sweep``: a grid of analyses of one scene on Dask, summarised in one table and two plots."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pounding.commands.cluster_options import add_cluster_options, check_cluster_options
from pounding.errors import InputError
from pounding.words import plural


def add_parser(sub) -> None:
    p = sub.add_parser(
        "sweep",
        help="parameter study: gaps, PGA scales, records, incidence angles, restitution, integrators",
        description=(
            "Run a grid of analyses of a scene (the Cartesian product of the lists given; the scene's own value for a "
            "parameter not given) and write one table, OUT/sweep.csv (a row appended as each run completes, rewritten "
            "in run order at the end) and OUT/sweep.parquet (with pyarrow), with per run the parameters, the number of "
            "impacts, impacts per storey, peak responses of both buildings, the largest impulse and the energy lost, and "
            "whether the analysis window holds the record's strong motion; OUT/sweep.json (what the records were scaled to, "
            "with the period of a spectral target); "
            "plus OUT/impacts_vs_gap.png and OUT/drift_vs_gap.png. A failing run is reported in its row. Runs execute "
            "on a local Dask cluster of worker processes (one per core) unless --scheduler or --serial is given. "
            "Lists: 0,0.01,0.05 or a range a:b:n (n values from a to b), or both, comma-separated."
        ),
    )
    p.add_argument("scene", type=Path, help="scene file (TOML)")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: the scene's name + '_sweep', beside it)")
    p.add_argument("--overwrite", action="store_true", help="write into --out even if it holds files pounding did not write (they are kept)")
    p.add_argument("--gaps", default=None, metavar="LIST", help="clear distances at rest along --direction [m]; the second building is moved")
    p.add_argument("--direction", default=None, metavar="x|y|ANGLE", help="direction of the gap (default: the normal of the facing edges)")
    p.add_argument("--pga-scale", default=None, metavar="LIST", help="factors on the scene's ground motion (after its pga/scale)")
    from pounding.commands.choices import RECORD_SETS

    p.add_argument("--records", type=Path, default=None, metavar="FOLDER|SET",
                   help="run every .AT2 file of FOLDER in place of the scene's record (a two-component scene: every "
                        "horizontal pair of FOLDER, NGA-West2 files paired by their RSN number, verticals left out), or "
                        f"every pair of a record set ({', '.join(RECORD_SETS)}: the 22 far-field pairs of FEMA P695); "
                        "scaled as the scene says")
    p.add_argument("--angles", default=None, metavar="LIST",
                   help="incidence angles of the ground motion (its first component) [deg], e.g. 0:180:13; adds each run's "
                        "minimum gap for no contact, reports the governing angle and plots OUT/gap_vs_angle.png")
    p.add_argument("--min-gap", action="store_true", help="add each run's minimum gap for no contact (one more run without contact)")
    p.add_argument("--restitution", default=None, metavar="LIST", help="coefficients of restitution in [0, 1]")
    from pounding.commands.choices import integrators

    p.add_argument("--integrator", default=None, metavar="NAMES",
                   help=f"integrator names, comma-separated ({integrators()}, or a plugin's name; default parameters)")
    p.add_argument("--dt", type=float, default=None, help="override the scene's time step [s]")
    p.add_argument("--duration", type=float, default=None,
                   help="override the scene's duration [s]; records whose strong motion (95 %% Arias intensity) or peak "
                        "comes later are named in a warning and marked in sweep.csv (window_cut)")
    p.add_argument("--keep", action="store_true", help="also write every run's result folder (OUT/runs/run_NNNN)")
    add_cluster_options(p)
    p.add_argument("--no-plots", action="store_true", help="do not draw the plots")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.set_defaults(func=cmd_sweep)


def cmd_sweep(args: argparse.Namespace) -> int:
    from pounding.framework.studies.sweep import parse_values, run_sweep

    check_cluster_options(args)
    gaps = parse_values(args.gaps, "--gaps", minimum=0.0) if args.gaps is not None else None
    scales = parse_values(args.pga_scale, "--pga-scale") if args.pga_scale is not None else None
    if scales and any(s <= 0 for s in scales):
        raise InputError(f"expected factors > 0, got {scales}", field="--pga-scale")
    rest = parse_values(args.restitution, "--restitution", minimum=0.0, maximum=1.0) if args.restitution is not None else None
    integrators = [s.strip() for s in args.integrator.split(",") if s.strip()] if args.integrator is not None else None
    angles = parse_values(args.angles, "--angles") if args.angles is not None else None
    if integrators is not None and not integrators:
        raise InputError("expected integrator names", field="--integrator")
    overrides = {k: getattr(args, k) for k in ("dt", "duration") if getattr(args, k) is not None}
    out = args.out or args.scene.with_name(args.scene.stem + "_sweep")

    def progress(done, total, row):
        if args.quiet:
            return
        what = plural(row["n_impacts"], "impact") if row["status"] == "ok" else f"ERROR {row['error']}"
        gap = "-" if row["gap"] is None else f"{row['gap']:.4g} m"
        angle = "" if row.get("angle") is None else f"angle {row['angle']:g} deg, "
        print(f"[{done}/{total}] run {row['run']}: gap {gap}, pga x{row['pga_scale']:g}, {row['record']}, {angle}"
              f"k {row['restitution']}, {row['integrator']}: {what} ({row['runtime_s']:.2f} s)", file=sys.stderr, flush=True)

    from pounding.io.outputs import check_target

    check_target(out, overwrite=args.overwrite)
    res = run_sweep(args.scene, out, gaps=gaps, pga_scales=scales, records=args.records, restitutions=rest, integrators=integrators,
                    direction=args.direction, overrides=overrides, keep=args.keep, workers=args.workers, scheduler=args.scheduler,
                    serial=args.serial, plots=not args.no_plots, progress=progress, angles=angles,
                    min_gap=True if args.min_gap else None)
    from pounding.framework.studies.fragility_inputs import describe_measure

    where = "serial" if not res.workers else f"{res.workers} Dask worker(s)"
    print(f"scaling of the records: {describe_measure(res.intensity)}" + ("; then times each --pga-scale" if scales else ""))
    cut = [c.record for c in res.window if c.cut]
    if cut:
        print(f"window: {len(cut)} of {len(res.window)} records cut short ({', '.join(cut)}): see window_cut in {res.csv}")
    print(f"{plural(len(res.rows), 'run')} ({len(res.failed)} failed) on {where} in {res.runtime_s:.1f} s")
    print(f"table: {res.csv}" + (f", {res.parquet}" if res.parquet else " (no Parquet: pyarrow missing)"))
    if angles:
        from pounding.framework.studies.sweep import governing_angles

        for key, (angle, gap) in governing_angles(res.rows).items():
            what = ", ".join(f"{k} {v}" for k, v in zip(("gap", "pga_scale", "record", "restitution", "integrator"), key) if v is not None)
            print(f"governing angle {angle:g} deg (minimum gap {gap:.4f} m)" + (f" for {what}" if what else ""))
    if res.plots:
        print("plots: " + ", ".join(str(p) for p in res.plots))
    if args.keep:
        print(f"run results: {out / 'runs'}/")
    return 0
