"""``pounding export FORMAT SCENE``: write the scene's model for another program (today: an OpenSeesPy script)."""

from __future__ import annotations

from pathlib import Path

#: export formats: name -> (module, function(scene, out) -> notes, default file suffix)
FORMATS = {"opensees": ("pounding.peer.export", "write_script", "_opensees.py")}


def add_parser(sub) -> None:
    p = sub.add_parser(
        "export",
        help="write a scene's model for another program (opensees: an OpenSeesPy script)",
        description=(
            "Write the scene's model in another program's terms. 'opensees' writes an OpenSeesPy script of the same "
            "model (rigid diaphragms, frames and walls as planar structures, storey springs as links with Steel01 or "
            "BoucWen, each building's Rayleigh damping, the ground motion as UniformExcitation, contact as zeroLength "
            "elements with the material of the force law: ViscoelasticGap, Hertzdamp, JankowskiImpact, ElasticPPGap; "
            "retaining walls as fixed nodes with such elements to the slabs' edges; links between slabs as zeroLength "
            "elements with their law's material); running it prints the periods and writes the floors' displacement histories. "
            "What OpenSees cannot represent is printed as warnings and written at the top of the script. "
            "See docs/opensees-export.md."
        ),
    )
    p.add_argument("format", metavar="FORMAT", help=f"export format: {', '.join(FORMATS)}")
    p.add_argument("scene", type=Path, help="scene file (TOML)")
    p.add_argument("--out", type=Path, default=None,
                   help="file to write (default: the scene's name without .toml + '_opensees.py', beside it)")
    p.set_defaults(func=cmd_export)


def cmd_export(args) -> int:
    import importlib
    import warnings

    from pounding.errors import AnalysisWarning, InputError
    from pounding.io.scene import load_scene
    from pounding.io.scene_structure import unknown_key_message

    if args.format not in FORMATS:
        raise InputError(unknown_key_message(args.format, FORMATS, what="export format"), field="FORMAT")
    module, function, suffix = FORMATS[args.format]
    scene = load_scene(args.scene)
    out = args.out or args.scene.with_name(args.scene.stem + suffix)
    if not out.parent.is_dir():
        raise InputError("the folder to write into does not exist", field="--out", file=str(out.parent))
    notes = getattr(importlib.import_module(module), function)(scene, out)
    for note in notes:
        warnings.warn(note, AnalysisWarning, stacklevel=1)
    print(f"wrote {out} (run it with: python {out})")
    return 0
