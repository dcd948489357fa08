"""`pounding plot DIR` and `pounding render DIR`: pictures of a finished run.

matplotlib, vtk and pyvista are imported only inside the command functions.
"""

from __future__ import annotations

from pathlib import Path

from pounding.errors import InputError


def add_parser(sub) -> None:
    p = sub.add_parser("plot", help="plots of a run folder (PNG)", description="Displacement histories of the facing slab corners (with --reference overlaid, as the paper's Fig. 3), the impact timeline, the clear distance of every common storey over time, and the energy balance.")
    p.add_argument("run", type=Path, help="a folder written by `pounding run`")
    p.add_argument("--reference", type=Path, default=None, help="a second run folder (e.g. without pounding) to overlay")
    p.add_argument("--out", type=Path, default=None, help="where to write the PNGs (default: RUN/plots)")
    p.set_defaults(func=cmd_plot)

    r = sub.add_parser("render", help="3-D pictures and an animation of a run (off-screen)", description="PNG snapshots (plan and 3-D view, displacements magnified) and an animated GIF of the pounding window, rendered off-screen with pyvista. Needs an OpenGL library for off-screen use (Debian: libegl1 and libgl1-mesa-dri, or libosmesa6); without it this command says so and exits 2.")
    r.add_argument("run", type=Path, help="a folder written by `pounding run`")
    r.add_argument("--out", type=Path, default=None, help="where to write the pictures (default: RUN/render)")
    r.add_argument("--magnify", type=float, default=50.0, help="displacement magnification (default 50)")
    r.set_defaults(func=cmd_render)


def cmd_plot(args) -> int:
    from pounding.io.plots import plot_all
    from pounding.io.results import load_result

    scene, result = load_result(args.run)
    reference = load_result(args.reference)[1] if args.reference else None
    paths = plot_all(scene, result, args.out or args.run / "plots", reference=reference)
    print("\n".join(str(p) for p in paths))
    return 0


def cmd_render(args) -> int:
    if not args.magnify > 0:
        raise InputError(f"expected a positive magnification, got {args.magnify}", field="--magnify")
    from pounding.io.render import RenderUnavailable, render
    from pounding.io.results import load_result

    scene, result = load_result(args.run)
    try:
        paths = render(result, args.out or args.run / "render", magnify=args.magnify, scene=scene)
    except RenderUnavailable as exc:
        raise InputError(str(exc)) from None
    print("\n".join(str(p) for p in paths))
    return 0
