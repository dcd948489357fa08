"""pounding: seismic response and slab pounding of adjacent non-symmetric buildings (a pair, a row or a block).

The public Python API is small:

>>> from pounding import load_scene, assemble, run      # doctest: +SKIP
>>> scene = load_scene("examples/paper/pair_gap_0.03.toml")  # doctest: +SKIP
>>> result = run(scene)                                 # doctest: +SKIP

Heavy modules (vtk, pyvista, matplotlib) are never imported from here.
"""

from pounding.errors import InputError


def __getattr__(name):
    # The version is read from the installed metadata only when asked (--version): reading it
    # costs tens of milliseconds that every other command would pay at start-up.
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("pounding")
        except PackageNotFoundError:  # running from a source tree that is not installed
            return "0.0.0+src"
    raise AttributeError(name)

__all__ = ["InputError", "__version__", "load_scene", "assemble", "run"]


def load_scene(path):
    """Read and validate a scene file (TOML); see :func:`pounding.io.scene.load_scene`."""
    from pounding.io.scene import load_scene as _load

    return _load(path)


def assemble(building):
    """Assemble one building; see :func:`pounding.framework.model.assembly.assemble`."""
    from pounding.framework.model.assembly import assemble as _assemble

    return _assemble(building)


def run(scene, **options):
    """Run the time-history analysis; see :func:`pounding.framework.post.run.run`."""
    from pounding.framework.post.run import run as _run

    return _run(scene, **options)
