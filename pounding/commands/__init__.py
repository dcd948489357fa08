"""Sub-commands that live in their own modules.

Each module listed in :data:`MODULES` defines ``add_parser(sub)``, which adds its
sub-parser to the ``pounding`` command line and sets ``func`` (a callable
taking the parsed arguments and returning an exit code). Modules are imported
only to build the parser; their heavy imports stay inside ``func``.
"""

MODULES = (
    "pounding.commands.scene",
    "pounding.commands.gap",
    "pounding.commands.sweep",
    "pounding.commands.draw",
    "pounding.commands.spectrum",
    "pounding.commands.fragility",
    "pounding.commands.export",
)
