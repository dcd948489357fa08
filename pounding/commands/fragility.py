"""``pounding fragility``: the probability of pounding against the gap and the intensity, over a record set, on Dask."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from pounding.commands.cluster_options import add_cluster_options, check_cluster_options


def add_parser(sub) -> None:
    p = sub.add_parser(
        "fragility",
        help="probability of pounding against gap and intensity over a record set",
        description=(
            "Scale every record of SET to every intensity level and run the scene once without contact: before their first "
            "impact the buildings move as if contact were off, so the run's required gap answers 'pounding or not' for every "
            "gap at once. Writes OUT/runs.csv (one row per record and level, appended as runs finish), OUT/fragility.csv "
            "(P(pounding) per gap and level, and the lognormal fragility per gap fitted by maximum likelihood over the levels, "
            "with Wald bounds), OUT/target_gap.csv (the gap for each target probability per level beside the mean ABS, SRSS "
            "and DDC estimates), OUT/study.json (the intensity measure with the period it used, and each record against the analysis "
            "window: a record whose strong motion comes after --duration is named in a warning), plots, and with --consequences runs with contact for the drift (and, for yielding storeys, ductility) amplification. A rerun with the "
            "same OUT resumes: finished runs are read back, failed ones run again. Runs execute on a local Dask cluster "
            "unless --scheduler or --serial is given."
        ),
    )
    p.add_argument("scene", type=Path, help="scene file (TOML) with two buildings")
    from pounding.commands.choices import RECORD_SETS, intensity_measures

    p.add_argument("--records", type=Path, default=None, metavar="SET",
                   help="a folder of .AT2 records, each shaken along the scene's angle, or a named set of record pairs "
                        f"({', '.join(RECORD_SETS)}: the 22 far-field pairs of FEMA P695, turned to the scene's angle); "
                        "default: the scene's own record")
    p.add_argument("--im", default="pga", metavar="IM", help="intensity measure the records are scaled to: " + intensity_measures().replace("%", "%%") + "; default pga; printed, and written to OUT/study.json with the period used")
    p.add_argument("--levels", required=True, metavar="LIST", help="intensity levels in the measure's unit: 0.1,0.2 or a range a:b:n")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: the scene's name + '_fragility', beside it)")
    p.add_argument("--gaps", default=None, metavar="LIST", help="gap grid of fragility.csv [m] (default: 0 to the largest required gap, round step)")
    p.add_argument("--target", default="0.1", metavar="LIST", help="target probabilities of pounding for target_gap.csv (default 0.1)")
    p.add_argument("--plot-gaps", default=None, metavar="LIST", help="gaps [m] whose fragility curves are drawn (default: three from the data)")
    p.add_argument("--consequences", default=None, metavar="GAPS",
                   help="also run every record and level with contact at these gaps [m]: drift (and ductility) amplification per level")
    p.add_argument("--direction", default=None, metavar="x|y|ANGLE", help="direction of the gap (default: the normal of the facing edges)")
    p.add_argument("--dt", type=float, default=None, help="override the scene's time step [s]")
    p.add_argument("--duration", type=float, default=None,
                   help="override the scene's duration [s]; records whose strong motion (95 %% Arias intensity) or peak "
                        "comes later are named in a warning and marked in runs.csv (window_cut)")
    add_cluster_options(p)
    p.add_argument("--no-plots", action="store_true", help="do not draw the plots")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_fragility)


def cmd_fragility(args: argparse.Namespace) -> int:
    from pounding.framework.studies.fragility import run_fragility
    from pounding.framework.studies.sweep import parse_values

    check_cluster_options(args)
    levels = parse_values(args.levels, "--levels")
    gaps = parse_values(args.gaps, "--gaps", minimum=0.0) if args.gaps is not None else None
    targets = parse_values(args.target, "--target", minimum=0.0, maximum=1.0)
    plot_gaps = parse_values(args.plot_gaps, "--plot-gaps", minimum=0.0) if args.plot_gaps is not None else None
    cons = parse_values(args.consequences, "--consequences", minimum=0.0) if args.consequences is not None else None
    overrides = {k: getattr(args, k) for k in ("dt", "duration") if getattr(args, k) is not None}
    out = args.out or args.scene.with_name(args.scene.stem + "_fragility")

    bar = None
    if not args.quiet:
        from tqdm import tqdm

        def progress(done, total, row):
            nonlocal bar
            if bar is None:
                bar = tqdm(total=total, unit="run", file=sys.stderr, desc="fragility")
            bar.update(1)
            if row.get("status") != "ok":
                bar.write(f"run {row.get('record')} @ {row.get('level')}: {row.get('error')}", file=sys.stderr)
    else:
        progress = None
    try:
        res = run_fragility(args.scene, out, records=args.records, im=args.im, levels=levels, gaps=gaps, direction=args.direction,
                            overrides=overrides, targets=targets, plot_gaps=plot_gaps, consequence_gaps=cons, serial=args.serial,
                            workers=args.workers, scheduler=args.scheduler, plots=not args.no_plots, progress=progress)
    finally:
        if bar is not None:
            bar.close()
    from pounding.framework.studies.fragility_inputs import describe_measure

    where = "serial" if not res.workers else f"{res.workers} Dask worker(s)"
    print(f"intensity measure: {describe_measure(res.measure)}")
    cut = [c.record for c in res.window if c.cut]
    if cut:
        print(f"window: {len(cut)} of {len(res.window)} records cut short ({', '.join(cut)}): see window_cut in {res.files['runs']}")
    print(f"{res.n_run} runs on {where} in {res.runtime_s:.1f} s ({res.n_resumed} read back from {res.files['runs']}); "
          f"{len(res.failed)} failed")
    print(format_target(res.target))
    print("tables: " + ", ".join(str(p) for k, p in res.files.items() if k != "study"))
    if res.plots:
        print("plots: " + ", ".join(str(p) for p in res.plots))
    return 0


def format_target(rows: list[dict]) -> str:
    """The gap for each target probability per level, beside the code estimates (a text table)."""
    lines = [f"  {'level':>8} {'P':>5} {'n':>4} {'gap [m]':>9} {'lognormal':>9} {'ABS':>8} {'SRSS':>8} {'DDC':>8}   P(pounding) at ABS/SRSS/DDC"]
    f = (lambda v: f"{v:>9.4f}" if v is not None and math.isfinite(v) else f"{'-':>9}")
    for r in rows:
        lines.append(f"  {r['level']:>8g} {r['p_target']:>5g} {r['n_runs']:>4d} {f(r['gap_m'])} {f(r['gap_lognormal_m'])} "
                     f"{r['abs_mean_m']:>8.4f} {r['srss_mean_m']:>8.4f} {r['ddc_mean_m']:>8.4f}   "
                     f"{r['p_at_abs']:.2f}/{r['p_at_srss']:.2f}/{r['p_at_ddc']:.2f}")
    return "gap for the target probability of pounding per level (code estimates: mean over the records)\n" + "\n".join(lines)
