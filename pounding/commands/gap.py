"""``pounding gap``: the smallest separation at which the slabs never touch, checked, beside the code estimates."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from pounding.words import plural



def add_parser(sub) -> None:
    p = sub.add_parser(
        "gap",
        help="minimum separation gap that avoids pounding, with ABS/SRSS/DDC estimates",
        description=(
            "Find the smallest clear distance between the facing slab edges (at rest, along the direction) at which no "
            "pair of slabs ever touches (nor a slab the other building's facade between two of its floors) under the scene's ground motion, from one run without contact (rotations "
            "included, any polygon). The second building of the scene is the one moved. With three or more buildings "
            "(a row or block), the same for every adjacent pair (slabs at a common level, or a slab between two floors of "
            "the other building against its facade, facing each other with no building between), each pair measured and checked as if it stood alone, from one run. Reports the governing storey, "
            "instant and corner, checks the answer with two full runs at 0.99x (impacts expected) and 1.01x (none), and "
            "prints the building-code estimates ABS, SRSS and DDC from the same run. Exit code 1 if the check fails."
        ),
    )
    p.add_argument("scene", type=Path, help="scene file (TOML) with two or more buildings")
    p.add_argument("--direction", default=None, metavar="x|y|ANGLE",
                   help="direction of the gap (degrees from x for ANGLE; oriented from the first building towards the second). "
                        "Default: the normal of the facing edges (shortest segment between the slabs at rest)")
    p.add_argument("--json", action="store_true", help="print JSON instead of text")
    p.add_argument("--no-check", action="store_true", help="skip the two verification runs")
    p.add_argument("--history", type=Path, default=None, metavar="CSV",
                   help="also write the clear distance along the direction at every common storey and slab-facade site over time (scene as given) to CSV")
    p.add_argument("--angles", default=None, metavar="LIST",
                   help="vary the incidence angle of the ground motion (its first component) [deg], e.g. 0:180:19; "
                        "reports the angle that needs the largest gap and plots the gap against the angle")
    p.add_argument("--plot", type=Path, default=None, metavar="PNG",
                   help="with --angles: where to draw the gap against the angle (default: SCENE_gap_vs_angle.png beside the scene)")
    p.add_argument("--dt", type=float, default=None, help="override the scene's time step [s]")
    p.add_argument("--duration", type=float, default=None, help="override the scene's duration [s]")
    p.set_defaults(func=cmd_gap)


def cmd_gap(args: argparse.Namespace) -> int:
    from pounding.framework.model.placement import direction_vector
    from pounding.framework.studies.gap import minimum_gap, verify_gap
    from pounding.io.scene import load_scene

    direction = direction_vector(args.direction)
    scene = load_scene(args.scene)
    from pounding.commands.time_options import time_overrides

    overrides = time_overrides(args)
    if overrides:
        scene = scene.with_analysis(**overrides)
    if args.angles is not None:
        if args.history is not None:
            from pounding.errors import InputError

            raise InputError("--history writes one run's clearances; with --angles there is one run per angle", field="--history")
        return _angle_study(args, scene, direction)
    if len(scene.buildings) == 1 and scene.walls:  # no pair: only the clearances to the walls
        return _walls_only(args, scene)
    if len(scene.buildings) > 2:
        return _row(args, scene, direction)
    report = minimum_gap(scene, direction)
    if args.history is not None:
        write_history(report, args.history)
    if not args.no_check:
        verify_gap(scene, report)
    if args.json:
        json.dump(report.to_dict(), sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(format_report(report))
        _print_walls(report.walls)
        for b in report.bumpers:  # the study measures the bare slabs (gap.bumper_gaps)
            print(f"bumper on {b['on']} storey {b['storey']}: the gaps above are between the bare slabs; "
                  f"the {b['thickness']:g} m layer stays untouched at a gap of {b['gap']:.4f} m")
    if report.check is not None and not report.check.ok:
        print("pounding: warning: the check runs disagree with the minimum gap (see 'check')", file=sys.stderr)
        return 1
    return 0


def _print_walls(clearances: list) -> None:
    from pounding.framework.studies.wall_gap import format_walls

    if clearances:
        print(format_walls(clearances))


def _walls_only(args, scene) -> int:
    """One building and its walls: the clearance it needs to each (exit 0 whatever it has: a report)."""
    from pounding.framework.studies.wall_gap import wall_gaps

    clearances = wall_gaps(scene)
    if args.json:
        json.dump({"walls": [c.to_dict() for c in clearances]}, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        _print_walls(clearances)
    return 0


def _row(args, scene, direction) -> int:
    """Three or more buildings: the required gap of every adjacent pair, each checked alone."""
    from pounding.errors import InputError
    from pounding.framework.model.placement import pair_scene, pair_sites
    from pounding.framework.studies.gap import minimum_gaps, verify_gap

    for opt in ("angles", "history"):
        if getattr(args, opt) is not None:
            raise InputError(f"--{opt} needs a scene of two buildings (this one has {len(scene.buildings)})", field=f"--{opt}")
    row = minimum_gaps(scene, direction)
    names = [b.name for b in scene.buildings]
    partial = []  # pairs facing at some of their sites only: alone they would meet at the others too
    for r in row.reports:
        a, b = (scene.buildings[names.index(n)] for n in r.buildings)
        if len(r.required) < len(pair_sites(a, b)):
            partial.append(r.buildings)
        elif not args.no_check:
            verify_gap(pair_scene(scene, names.index(a.name), names.index(b.name)), r)
    if args.json:
        json.dump(row.to_dict(), sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(f"{len(scene.buildings)} buildings, {plural(len(row.reports), 'adjacent pair')} (each measured and checked as if alone):")
        _print_walls(row.walls)
        for r in row.reports:
            print(format_report(r))
            if r.buildings in partial:
                print(f"  faces {r.buildings[1]!r} at storeys {', '.join(str(fa) for fa, _, _, _ in r.required)} only (a building "
                      "between them below): required gap over those storeys, not checked by runs of the pair alone")
        for a, b in row.screened:
            print(f"{a!r} and {b!r}: not adjacent (a building stands between them wherever they could meet): no gap reported")
    if any(r.check is not None and not r.check.ok for r in row.reports):
        print("pounding: warning: the check runs disagree with the minimum gap of a pair (see 'check')", file=sys.stderr)
        return 1
    return 0


def _angle_study(args, scene, direction) -> int:
    """``--angles``: the minimum gap at every incidence angle, the governing one checked and plotted."""
    import os

    from pounding.framework.studies.gap import verify_gap
    from pounding.framework.studies.incidence import gap_against_angle, plot_gap_against_angle
    from pounding.framework.studies.sweep import parse_values

    angles = parse_values(args.angles, "--angles")
    study = gap_against_angle(scene, angles, direction)
    g = study.governing
    report = study.reports[g]
    if not args.no_check:
        verify_gap(scene.with_ground_motion(scene.ground_motion.with_angle(study.governing_angle)), report)
    plot = args.plot or args.scene.with_name(args.scene.stem + "_gap_vs_angle.png")
    tmp = plot.with_name(f".{plot.name}.tmp-{os.getpid()}")
    try:
        plot_gap_against_angle(study, tmp)
        os.replace(tmp, plot)
    except ImportError:
        plot = None
    finally:
        if tmp.exists():
            tmp.unlink()
    if args.json:
        out = study.to_dict()
        out["plot"] = None if plot is None else str(plot)
        json.dump(out, sys.stdout, indent=1)
        sys.stdout.write("\n")
    else:
        print(f"minimum gap against the incidence angle of the ground motion ({scene.ground_motion.name}):")
        print(f"  {'angle [deg]':>11} {'gap [m]':>9}")
        for a, x in zip(study.angles, study.gaps):
            print(f"  {a:>11g} {x:>9.4f}" + ("  <- governing" if a == study.governing_angle else ""))
        print(f"governing angle {study.governing_angle:g} deg:")
        print(format_report(report))
        print(f"plot: {plot}" if plot else "no plot (matplotlib missing)")
    if report.check is not None and not report.check.ok:
        print("pounding: warning: the check runs disagree with the minimum gap (see 'check')", file=sys.stderr)
        return 1
    return 0


def write_history(report, path: Path) -> Path:
    """t and the clear distance along the direction per common storey or slab-facade site [m] (negative: overlapping; empty: never facing)."""
    import csv
    import math

    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time"] + [_column(report, k) for k in range(len(report.required))])
        for t, row in zip(report.t, report.clearance):
            w.writerow([repr(float(t))] + [repr(float(c)) if math.isfinite(c) else "" for c in row])
    return path


def _column(report, k: int) -> str:
    """History column of row k of ``report.required``: a common storey, or a slab against a facade."""
    fa = report.required[k][0]
    F = report.facades[k] if k < len(report.facades) else None
    if F is None:
        return f"clearance_storey_{fa}"
    return f"clearance_{F['striking']}_slab_{F['slab_storey']}_{F['struck']}_facade_storey_{F['struck_storey']}"


def _facade_words(F: dict) -> str:
    return (f"slab {F['slab_storey']} of {F['striking']!r} (z = {F['height']:.3f} m) against the facade of {F['struck']!r} "
            f"in its storey {F['struck_storey']} (eta = {F['eta']:.3f})")


def format_report(r) -> str:
    a, b = r.buildings
    dx, dy = r.direction
    lines = [f"gap between {a!r} and {b!r} along ({dx:.4g}, {dy:.4g}) ({b!r} moved)"]
    lines.append(f"  clear distance at rest in the scene: {r.current_gap:.4f} m")
    lines.append(f"  minimum gap (no slabs ever touch):  {r.min_gap:.4f} m")
    where = f"storey {r.storey}" if r.facade is None else _facade_words(r.facade)
    lines.append(
        f"  governing: {where} at t = {r.time:.3f} s, corner {r.vertex} of {r.striking!r} against edge {r.edge} of "
        f"{r.struck!r} at ({r.point[0]:.3f}, {r.point[1]:.3f})"
    )
    facades = r.facades or [None] * len(r.required)
    per = ", ".join(f"{fa}: {g:.4f} m" for (fa, _, g, _), F in zip(r.required, facades) if g is not None and F is None)
    if per:
        lines.append(f"  required per storey: {per}")
    for (_, _, g, _), F in zip(r.required, facades):
        if F is not None and g is not None:
            lines.append(f"  required, {_facade_words(F)}: {g:.4f} m")
    if r.check is not None:
        c = r.check
        verdict = "OK" if c.ok else "FAILED"
        lines.append(
            f"  check: {c.factors[0]:g}x = {c.gaps[0]:.4f} m -> {plural(c.n_impacts[0], 'impact')}; "
            f"{c.factors[1]:g}x = {c.gaps[1]:.4f} m -> {plural(c.n_impacts[1], 'impact')}  {verdict}"
        )
    lines.append(
        f"  code estimates at {where} from the peak displacements along the direction of the facing points "
        f"({a}: {r.peaks[0]:.4f} m, {b}: {r.peaks[1]:.4f} m)"
    )
    lines.append(f"    {'rule':<6} {'gap [m]':>9} {'/ minimum':>10}")
    for name, val in (("ABS", r.abs), ("SRSS", r.srss), ("DDC", r.ddc)):
        ratio = f"{val / r.min_gap:>10.2f}" if r.min_gap > 0 else f"{'-':>10}"
        lines.append(f"    {name:<6} {val:>9.4f} {ratio}")
    lines.append(
        f"    DDC = sqrt(ua^2 + ub^2 - 2 rho ua ub) with T {a} = {r.periods[0]:.3f} s (zeta {r.damping[0]:.3f}), T {b} = {r.periods[1]:.3f} s "
        f"(zeta {r.damping[1]:.3f}): each building's mode with the largest effective mass along the direction; "
        f"rho = {r.rho:.3f}, their CQC correlation (Der Kiureghian 1981)"
    )
    return "\n".join(lines)
