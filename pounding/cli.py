"""Command line: parse, call the library, print, map errors to exit codes.

Exit codes: 0 success, 2 bad input (one line naming file, field, expectation),
1 an unexpected failure, 130 interrupted. Heavy modules (vtk, pyvista,
matplotlib) are imported only by the commands that draw.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from pounding.errors import InputError
from pounding.words import plural


# --------------------------------------------------------------------------- info
def cmd_info(args: argparse.Namespace) -> int:
    from pounding.framework.model.assembly import assemble
    from pounding.framework.model.modal import modal_summary
    from pounding.io.scene import load_scene

    from pounding.framework.post import plausibility

    scene = load_scene(args.scene)
    plausibility.warn(scene)
    summaries = {b.name: modal_summary(assemble(b), args.modes) for b in scene.buildings}
    if args.json:
        json.dump({"buildings": summaries}, sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    for name, s in summaries.items():
        print(format_info(name, s))
    return 0


def format_info(name: str, s: dict) -> str:
    """Human-readable modal summary of one building."""
    lines = [f"Building {name!r}: {plural(s['storeys'], 'storey')}, {3 * s['storeys']} DOF"]
    lines.append(f"  {'storey':>6} {'mass [t]':>10} {'J [t m2]':>12} {'CM x,y [m]':>18} {'CR x,y [m]':>18} {'e x,y [m]':>16}")
    for f in range(s["storeys"]):
        cm, cr, e = s["centre_of_mass"][f], s["centre_of_rigidity"][f], s["eccentricity"][f]
        lines.append(
            f"  {f + 1:>6} {s['mass'][f] / 1e3:>10.2f} {s['polar_inertia'][f] / 1e3:>12.1f} "
            f"{cm[0]:>8.3f},{cm[1]:>8.3f} {cr[0]:>8.3f},{cr[1]:>8.3f} {e[0]:>7.3f},{e[1]:>7.3f}"
        )
    lines.append(f"  {'mode':>6} {'T [s]':>9} {'f [Hz]':>9} {'zeta':>7} {'Mx %':>7} {'My %':>7} {'Mrz %':>7}")
    em = s["effective_mass_ratio"]
    for i, T in enumerate(s["periods"]):
        lines.append(
            f"  {i + 1:>6} {T:>9.4f} {s['frequencies'][i]:>9.3f} {s['damping_ratios'][i]:>7.4f} "
            f"{100 * em['x'][i]:>7.2f} {100 * em['y'][i]:>7.2f} {100 * em['rz'][i]:>7.2f}"
        )
    tot = s["effective_mass_ratio_sum"]
    lines.append(f"  {'sum':>6} {'':>9} {'':>9} {'':>7} {100 * tot['x']:>7.2f} {100 * tot['y']:>7.2f} {100 * tot['rz']:>7.2f}")
    return "\n".join(lines)


# --------------------------------------------------------------------------- parser
def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="pounding",
        description="Earthquake response of adjacent non-symmetric buildings (a pair, a row or a block) and the pounding between their slabs.",
    )
    p.add_argument("--version", action=_Version, nargs=0, help="show the version and exit")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    info = sub.add_parser("info", help="modal summary of every building in a scene", description="Print per building: storey masses, centres of mass and rigidity, eccentricities, periods, damping ratios and modal participation.")
    info.add_argument("scene", type=Path, help="scene file (TOML)")
    info.add_argument("--json", action="store_true", help="print JSON instead of tables")
    info.add_argument("--modes", type=int, default=None, metavar="N", help="show only the first N modes (default: all)")
    info.set_defaults(func=cmd_info)

    for extra in _EXTRA_COMMANDS:
        extra(sub)
    import importlib

    from pounding.commands import MODULES

    for name in MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name:
                raise
            continue  # a command module not written yet
        module.add_parser(sub)
    p.command_parsers = sub.choices  # {command: its parser}: main() reports an option error with the command's usage
    return p


class _Version(argparse.Action):
    """--version that reads the installed version only when asked."""

    def __call__(self, parser, namespace, values, option_string=None):
        import pounding

        print(f"pounding {pounding.__version__}")
        parser.exit()


_EXTRA_COMMANDS: list = []


def command(fn):
    """Register a function that adds a sub-command to the parser."""
    _EXTRA_COMMANDS.append(fn)
    return fn


#: commands that run many scenes in one process: numba's own dispatch (~10 % faster per run on
#: small scenes) pays for loading its cache once (pounding.aot)
MANY_RUNS = ("sweep", "fragility")


def console() -> None:
    """The ``pounding`` command (and ``python -m pounding``): :func:`main`, then the process ends
    without the interpreter's teardown.

    Everything the command writes is closed by then (results are published by a rename); what is
    left is releasing the loaded machine code of the compiled core and every module, which took
    0.21-0.25 s of a 1.2 s warm ``pounding run`` (measured with the file-writing work done).
    Standard streams and logging are flushed first; atexit handlers are run.
    """
    import atexit
    import logging
    import os

    code = main()
    # os._exit skips atexit: run its handlers here (worker pools a sweep started, logging); CPython's
    # own entry to them, stable since Python 3.0
    atexit._run_exitfuncs()
    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can reach it
            pass
    os._exit(code)


def main(argv: list[str] | None = None) -> int:
    import os
    import warnings

    # The matrices here are small (3N <= a few hundred): one BLAS thread is faster, and a
    # multi-threaded BLAS on a loaded machine was measured 1000x slower on a 300x300 Cholesky.
    # setdefault: a user's own setting wins. numpy is not imported yet at this point.
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")

    from pounding.errors import AnalysisWarning

    warnings.simplefilter("always", AnalysisWarning)
    warnings.showwarning = _show_warning
    parser = build_parser()
    args, extras = parser.parse_known_args(argv)
    if extras:  # argparse would report them with the top-level usage; the command's own says what it takes
        argv_list = list(sys.argv[1:] if argv is None else argv)
        command = getattr(args, "command", None)
        before = command in argv_list and argv_list.index(extras[0]) < argv_list.index(command)  # (an option of pounding itself)
        owner = parser if before else parser.command_parsers.get(command, parser)
        owner.error(f"unrecognized arguments: {' '.join(extras)}")
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    if args.command not in MANY_RUNS:
        # a command of one scene is a short process: the extension module built at install serves it
        # without numba (pounding.aot); a user's own POUNDING_AOT wins
        from pounding.compiler import prebuilt

        prebuilt.prefer(True)
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        print(f"pounding: error: {_as_option(exc)}", file=sys.stderr)
        return 2
    except FloatingPointError as exc:  # an iteration of the analysis diverged: said in one line, nothing written
        print(f"pounding: error: the analysis stopped: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("pounding: interrupted", file=sys.stderr)
        return 130


#: the arguments the studies name in their errors (their Python names), and the options that give them here
OPTION_OF = {"direction": "--direction"}


def _as_option(exc: InputError) -> InputError:
    """``exc`` with a study's argument named as the command line's option that gave it (an error about
    a file keeps its key path)."""
    if exc.file is None and exc.field in OPTION_OF:
        return InputError(exc.message, field=OPTION_OF[exc.field])
    return exc


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print(f"pounding: warning: {message}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())


# --------------------------------------------------------------------------- run
def _progress(quiet: bool):
    """A tqdm progress callback on stderr: shown after one second, only on a terminal."""
    if quiet or not sys.stderr.isatty():
        return None, None
    from tqdm import tqdm

    bar = tqdm(total=None, unit="step", delay=1.0, file=sys.stderr, leave=False)

    def update(k, n):
        bar.total = n
        bar.n = k
        bar.refresh()

    return update, bar


def analyse(scene_path: Path, out: Path, *, vtk: bool = False, vtk_every: int = 1, scale: float = 1.0, quiet: bool = False, overrides=None,
            overwrite: bool = False, silence=()):
    """Load, check plausibility, run and write one scene; returns (scene, result).

    The output folder is checked before the run (:func:`pounding.io.outputs.check_target`):
    a folder holding files pounding did not write is refused unless ``overwrite``.
    """
    from pounding.framework.post import plausibility
    from pounding.framework.post.run import run
    from pounding.framework.engine.yielding import check_springs
    from pounding.io.outputs import check_target
    from pounding.io.results import write_results
    from pounding.io.scene import load_scene

    scene = load_scene(scene_path)
    check_springs(scene)  # one hysteresis law per building: said before anything runs
    check_target(out, overwrite=overwrite)
    if overrides:
        scene = scene.with_analysis(**overrides)
    plausibility.warn(scene, silence)
    if not quiet:
        announce_compiling()
    update, bar = _progress(quiet)
    try:
        result = run(scene, progress=update)
    finally:
        if bar is not None:
            bar.close()

    def extra(folder: Path) -> None:
        if vtk:
            from pounding.io.vtk import write_vtk_series

            series = Path(VTK_SERIES)
            write_vtk_series(scene, result, folder / series.parent, every=vtk_every, scale=scale, name=series.stem)

    write_results(result, out, scene_path.read_text(), extra=extra, scene_path=scene_path, overwrite=overwrite)
    return scene, result


def announce_compiling() -> None:
    """Say on stderr, once and only if it happens, that the numerical core is being compiled."""
    from pounding import compiler

    compiler.on_first_compile(lambda: print("compiling the parts of the numerical core this kind of run needs (once: cached for the next runs; "
                                             "up to a few minutes on two cores; `python -m pounding.warmup --warm` does it ahead) ...",
                                             file=sys.stderr, flush=True))


def human_summary(result, out: Path) -> str:
    from collections import Counter

    lines = [f"{result.steps} steps of {result.dt:g} s with {result.integrator['name']} in {result.runtime_s * 1e3:.1f} ms (solver)"]
    tm = getattr(result, "timings", {})
    if tm.get("compile_s", 0.0) > 0.0:
        lines[0] += f"; compiling the core took {tm['compile_s']:.1f} s (first run only)"
    elif tm.get("load_and_compile_s"):
        lines[0] += f"; loading the compiled core {tm['load_and_compile_s'] * 1e3:.0f} ms"
    per = Counter(result.impact_storey(i) for i in result.impacts)
    if result.impacts:
        lines.append(f"{plural(len(result.impacts), 'impact')} (" + ", ".join(f"storey {s}: {n}" for s, n in sorted(per.items())) + ")")
        lines.append(f"energy lost in impacts: {sum(i.energy_loss for i in result.impacts) / 1e3:.2f} kJ")
    if result.contacts:  # a force law's contact episodes
        per = Counter(result.impact_storey(e) for e in result.contacts)
        lines.append(f"{plural(len(result.contacts), 'contact')} by forces (" + ", ".join(f"storey {s}: {n}" for s, n in sorted(per.items()))
                     + f"), largest force {max(e.peak_force for e in result.contacts) / 1e3:.4g} kN, "
                     f"energy dissipated {sum(e.energy_dissipated for e in result.contacts) / 1e3:.2f} kJ")
    if not result.impacts and not result.contacts:
        lines.append("no impacts")
    else:  # the count that converges with dt (chatter merged: pounding.framework.engine.chatter)
        from pounding.framework.engine.chatter import CONVERGES_WITH_DT, DEPENDS_ON_DT

        eps = result.contact_episodes()
        per = Counter(result.impact_storey(e) for e in eps)
        word = ("impact", "impacts") if not result.contacts else ("contact", "contacts") if not result.impacts else \
            ("impact or contact", "impacts or contacts")
        lines.append(f"{plural(len(eps), 'contact episode')} (" + ", ".join(f"storey {s}: {n}" for s, n in sorted(per.items()))
                     + f"; {plural(sum(e.strikes for e in eps), *word)} in them: a pair's chatter is one episode)")
        lines.append(f"converge as dt falls: {', '.join(CONVERGES_WITH_DT)}; not: {', '.join(DEPENDS_ON_DT)}")
    for name in result.names:
        pk = result.peaks(name)
        lines.append(f"{name}: peak |u| {pk[:, 0].max() * 1e3:.1f} mm, |v| {pk[:, 1].max() * 1e3:.1f} mm, |phi| {pk[:, 2].max() * 1e3:.3f} mrad (top storey {pk[-1, 0] * 1e3:.1f} mm in x)")
    for name, rec in getattr(result, "links", {}).items():  # links between slabs
        lines.append(f"link {name}: peak force {rec['peak_force'] * 1e-3:.4g} kN, stroke {rec['peak'] * 1e3:.1f} mm, "
                     f"dissipated {rec['energy_dissipated'] * 1e-3:.4g} kJ")
    lines.append(f"results in {out}/ (response.npz, summary.json, impacts.csv, contacts.csv)")
    return "\n".join(lines)


@command
def _add_run(sub):
    p = sub.add_parser(
        "run", help="time-history analysis of a scene",
        description="Integrate every building under the scene's ground motion, with pounding, and write response.npz, "
        "summary.json, impacts.csv (and modal.npz, scene.toml for `pounding plot` and `render`) into --out, through a "
        "temporary folder moved into place when complete. A folder holding files pounding did not write is refused "
        "unless --overwrite; a rerun replaces only the files the earlier run wrote, so plots and renders made from it "
        "stay. Plausibility warnings (unlikely masses, periods, storey or element stiffnesses) go to stderr.",
    )
    p.add_argument("scene", type=Path, help="scene file (TOML)")
    p.add_argument("--out", type=Path, default=None, help="output folder (default: the scene's name without .toml, beside it, + '_out')")
    p.add_argument("--overwrite", action="store_true",
                   help="write into --out even if it holds files pounding did not write (they are kept; only files of the same name are replaced)")
    p.add_argument("--vtk", action="store_true", help=f"also write a ParaView time series ({VTK_SERIES}, one .vtu per written step)")
    p.add_argument("--vtk-every", type=int, default=1, metavar="N", help="write every N-th output step to VTK (impact instants are always written)")
    p.add_argument("--scale", type=float, default=1.0, help="displacement scale of the VTK geometry (default: true scale)")
    p.add_argument("--dt", type=float, default=None, help="override the scene's time step [s]")
    p.add_argument("--duration", type=float, default=None, help="override the scene's duration [s]")
    from pounding.commands.choices import integrators

    p.add_argument("--integrator", default=None,
                   help=f"override the scene's integrator by name ({integrators()}, or a plugin's name; default parameters)")
    from pounding.commands.scene import add_silence

    add_silence(p)
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary")
    p.set_defaults(func=cmd_run)


#: The ParaView collection `run --vtk` writes, relative to the run folder (tests/test_cli.py checks it is the file written).
VTK_SERIES = "vtk/pounding.pvd"


def cmd_run(args) -> int:
    if args.vtk_every < 1:
        raise InputError(f"expected a positive integer, got {args.vtk_every}", field="--vtk-every")
    if args.scale <= 0:
        raise InputError(f"expected a positive scale, got {args.scale}", field="--scale")
    from pounding.commands.time_options import time_overrides

    overrides = time_overrides(args)
    if args.integrator:
        from pounding.framework.model.registry import INTEGRATORS

        INTEGRATORS.get(args.integrator, field="--integrator")
        overrides.update(integrator=args.integrator, integrator_params={})
    from pounding.commands.scene import silenced

    silence = silenced(args)
    if args.scene.is_dir():  # (".", "..", any folder: no scene file to name the results folder after)
        raise InputError(f"{args.scene}: cannot read the scene file: it is a folder; give a .toml scene file")
    out = args.out or args.scene.with_name(args.scene.stem + "_out")
    _, result = analyse(args.scene, out, vtk=args.vtk, vtk_every=args.vtk_every, scale=args.scale, quiet=args.quiet, overrides=overrides,
                        overwrite=args.overwrite, silence=silence)
    if not args.quiet:
        print(human_summary(result, out))
        for sub in ("plots", "render"):
            if (out / sub / ".pounding-manifest.json").is_file():
                print(f"note: {out / sub}/ was made from the earlier run and is kept; `pounding {sub[:-1] if sub == 'plots' else sub} {out}` redraws it")
    return 0


# --------------------------------------------------------------------------- demo
def paper_scene_paths() -> tuple[Path, Path]:
    """The packaged paper example: (gap 0.5 m, gap 0.03 m)."""
    from importlib.resources import files

    base = files("pounding.io") / "data" / "paper"
    return Path(str(base / "pair_gap_0.5.toml")), Path(str(base / "pair_gap_0.03.toml"))


def corner_tally(result) -> str:
    from collections import Counter

    tally = Counter((result.impact_storey(i), result.striking_building(i), i.vertex) for i in result.impacts)
    lines = [f"  {'storey':>6} {'striking':>10} {'vertex':>7} {'impacts':>8}"]
    for (storey, who, vertex), n in sorted(tally.items()):
        lines.append(f"  {storey:>6} {who:>10} {('face' if vertex < 0 else vertex):>7} {n:>8}")
    return "\n".join(lines)


@command
def _add_demo(sub):
    p = sub.add_parser("demo", help="run the built-in example (the paper's pair)", description="Run the paper's 3- and 5-storey pair under El Centro (0.32 g) at gaps 0.5 m (no pounding) and 0.03 m (pounding), print the impact tally per storey and corner, and save results and plots.")
    p.add_argument("--out", type=Path, default=Path("demo_output"), help="output folder (default: demo_output)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_demo)


def cmd_demo(args) -> int:
    from pounding.framework.post.run import run
    from pounding.io.results import write_results
    from pounding.io.scene import load_scene

    far, near = paper_scene_paths()
    out = args.out
    announce_compiling()
    results = {}
    for label, path in (("gap_0.5", far), ("gap_0.03", near)):
        scene = load_scene(path)
        results[label] = (scene, run(scene))
        write_results(results[label][1], out / label, path.read_text(), scene_path=path)
        print(f"== {scene_title(path)}")
        print(human_summary(results[label][1], out / label))
    print("impacts per storey and corner at gap 0.03 m:")
    print(corner_tally(results["gap_0.03"][1]))
    try:
        from pounding.io.plots import plot_all
    except ImportError as exc:  # matplotlib is in the 'viz' extra
        print(f"plots skipped: {exc}")
        return 0
    from pounding.io.outputs import write_folder

    scene, res = results["gap_0.03"]
    paths = write_folder(out / "plots", "plot", lambda tmp: plot_all(scene, res, tmp, reference=results["gap_0.5"][1]))
    print(f"plots: {', '.join(str(p) for p in paths)}")
    return 0


def scene_title(path: Path) -> str:
    import tomllib

    return tomllib.loads(path.read_text()).get("title", path.name)
