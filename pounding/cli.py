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


# --------------------------------------------------------------------------- info
def cmd_info(args: argparse.Namespace) -> int:
    from pounding.framework.assembly import assemble
    from pounding.framework.modal import modal_summary
    from pounding.io.scene import load_scene

    scene = load_scene(args.scene)
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
    lines = [f"Building {name!r}: {s['storeys']} storeys, {3 * s['storeys']} DOF"]
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
    from pounding import __version__

    p = argparse.ArgumentParser(
        prog="pounding",
        description="Earthquake response of two adjacent non-symmetric buildings and the pounding between their slabs.",
    )
    p.add_argument("--version", action="version", version=f"pounding {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    info = sub.add_parser("info", help="modal summary of every building in a scene", description="Print per building: storey masses, centres of mass and rigidity, eccentricities, periods, damping ratios and modal participation.")
    info.add_argument("scene", type=Path, help="scene file (TOML)")
    info.add_argument("--json", action="store_true", help="print JSON instead of tables")
    info.add_argument("--modes", type=int, default=None, metavar="N", help="show only the first N modes (default: all)")
    info.set_defaults(func=cmd_info)

    for extra in _EXTRA_COMMANDS:
        extra(sub)
    return p


_EXTRA_COMMANDS: list = []


def command(fn):
    """Register a function that adds a sub-command to the parser."""
    _EXTRA_COMMANDS.append(fn)
    return fn


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        print(f"pounding: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("pounding: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
