"""`pounding plot DIR` and `pounding render DIR`: pictures of a finished run.

matplotlib, vtk and pyvista are imported only inside the command functions.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pounding.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plots of a run folder (PNG)", description="Displacement histories of the facing slab corners (with --reference overlaid, as the paper's Fig. 3), the impact timeline, the clear distance of every common storey over time, and the energy balance.")
    p.add_argument("run", type=Path, help="a folder written by `pounding run`")
    p.add_argument("--reference", type=Path, default=None, help="a second run folder (e.g. without pounding) to overlay")
    p.add_argument("--out", type=Path, default=None, help="where to write the PNGs (default: RUN/plots)")
    p.add_argument("--overwrite", action="store_true", help="write into --out even if it holds files pounding did not write (they are kept)")
    p.add_argument(
        "--point", action="append", default=None, metavar="BUILDING:STOREY:VERTEX[:x|y]",
        help="a slab vertex whose displacement history to plot (storey 1-based, vertex 0-based as in impacts.csv, "
        "component x by default); repeat for more (default: the lower building's corners facing the other)",
    )
    p.add_argument(
        "--spring", action="append", default=None, metavar="BUILDING:ELEMENT:STOREY",
        help="a yielding storey spring whose hysteresis loop to draw (element 0-based as in summary.json's "
        "yielding_springs, storey 1-based); repeat for more (default: the most ductile spring of every building)",
    )
    p.add_argument("--spectra", action="store_true", help="also floor response spectra of every floor (floor_spectra.png, floor_spectra.csv): pseudo-acceleration [m/s2], 0.02-5 s, impacts included")
    p.add_argument("--spectra-damping", type=float, default=0.05, metavar="ZETA", help="damping ratio of the spectra's oscillators (default 0.05)")
    p.set_defaults(func=cmd_plot)

    r = sub.add_parser("render", help="3-D pictures and an animation of a run (off-screen)", description="PNG snapshots (plan and 3-D view, displacements magnified) and an animated GIF of the pounding window, rendered off-screen with pyvista. Needs an OpenGL library for off-screen use (Debian: libegl1 and libgl1-mesa-dri, or libosmesa6); without it this command says so and exits 2.")
    r.add_argument("run", type=Path, help="a folder written by `pounding run`")
    r.add_argument("--out", type=Path, default=None, help="where to write the pictures (default: RUN/render)")
    r.add_argument("--overwrite", action="store_true", help="write into --out even if it holds files pounding did not write (they are kept)")
    r.add_argument("--magnify", type=float, default=50.0, help="displacement magnification (default 50)")
    r.set_defaults(func=cmd_render)


def cmd_plot(args) -> int:
    from pounding.io.outputs import check_target, write_folder
    from pounding.io.plots import plot_all
    from pounding.io.results import load_result

    out = args.out or args.run / "plots"
    check_target(out, overwrite=args.overwrite)
    scene, result = load_result(args.run)
    reference = load_result(args.reference)[1] if args.reference else None
    if reference is not None:
        _check_reference(result, reference, args.reference)
    points = [parse_point(text, scene) for text in args.point] if args.point else None
    springs = [parse_spring(text, result) for text in args.spring] if args.spring else None
    if not 0 <= args.spectra_damping < 1:
        raise InputError(f"expected a damping ratio in [0, 1), got {args.spectra_damping}", field="--spectra-damping")

    def write(tmp):
        paths = plot_all(scene, result, tmp, reference=reference, points=points, springs=springs)
        if args.spectra:
            from pounding.io.profile_plots import write_floor_spectra

            paths += write_floor_spectra(result, tmp, zeta=args.spectra_damping)
        return paths

    paths = write_folder(out, "plot", write)
    print("\n".join(str(p) for p in paths))
    return 0


def _check_reference(result, reference, where) -> None:
    """InputError on ``--reference`` unless its run has the same buildings, each with the same storeys
    (the plots overlay it building by building, storey by storey)."""
    mine = {s.name: s.n_storeys for s in result.systems}
    theirs = {s.name: s.n_storeys for s in reference.systems}
    if mine != theirs:
        show = lambda d: ", ".join(f"{k!r} ({v} storeys)" for k, v in d.items())  # noqa: E731
        raise InputError(f"{where}: expected a run of the same buildings to overlay ({show(mine)}), got {show(theirs)}",
                         field="--reference")


def cmd_render(args) -> int:
    if not args.magnify > 0:
        raise InputError(f"expected a positive magnification, got {args.magnify}", field="--magnify")
    from pounding.io.render import RenderUnavailable, render
    from pounding.io.results import load_result

    from pounding.io.outputs import check_target, write_folder

    out = args.out or args.run / "render"
    check_target(out, overwrite=args.overwrite)
    scene, result = load_result(args.run)
    try:
        paths = write_folder(out, "render", lambda tmp: render(result, tmp, magnify=args.magnify, scene=scene))
    except RenderUnavailable as exc:
        raise InputError(str(exc)) from None
    print("\n".join(str(p) for p in paths))
    return 0


def parse_spring(text: str, result) -> tuple:
    """'low:0:2' -> (building, element, storey), checked against the run's yielding springs."""
    parts = text.split(":")
    if len(parts) != 3 or not (parts[1].isdigit() and parts[2].isdigit()):
        raise InputError(f"expected BUILDING:ELEMENT:STOREY (element 0-based, storey 1-based), got {text!r}", field="--spring")
    name, element, storey = parts[0], int(parts[1]), int(parts[2])
    if name not in result.springs:
        known = ", ".join(result.springs) or "none"
        raise InputError(f"no yielding springs in building {name!r}; buildings with yielding springs: {known}", field="--spring")
    sp = result.springs[name]
    if not np.any((sp["element"] == element) & (sp["storey"] == storey)):
        have = sorted({int(e) for e in sp["element"]})
        raise InputError(f"building {name!r} has no yielding spring at element {element}, storey {storey} "
                         f"(yielding elements: {have})", field="--spring")
    return name, element, storey


def parse_point(text: str, scene) -> tuple:
    """'low:3:1' or 'low:3:1:y' -> (building, storey, vertex, component), checked against the scene."""
    parts = text.split(":")
    if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3] not in ("x", "y")):
        raise InputError(f"expected BUILDING:STOREY:VERTEX[:x|y], got {text!r}", field="--point")
    name, storey, vertex = parts[0], parts[1], parts[2]
    names = [b.name for b in scene.buildings]
    if name not in names:
        raise InputError(f"unknown building {name!r}; known: {', '.join(names)}", field="--point")
    b = scene.building(name)
    if not (storey.isdigit() and 1 <= int(storey) <= b.n_storeys):
        raise InputError(f"storey must be 1..{b.n_storeys} for {name!r}, got {storey!r}", field="--point")
    k = len(b.slabs[int(storey) - 1].vertices)
    if not (vertex.isdigit() and int(vertex) < k):
        raise InputError(f"vertex must be 0..{k - 1} for that slab, got {vertex!r}", field="--point")
    return (name, int(storey), int(vertex), parts[3] if len(parts) == 4 else "x")
