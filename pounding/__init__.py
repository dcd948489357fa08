"""pounding: seismic response and slab pounding of adjacent non-symmetric buildings (a pair, a row or a block).

The Python API (docs/python.md):

>>> import pounding                                                      # doctest: +SKIP
>>> scene = pounding.load_scene("examples/paper/pair_gap_0.03.toml")     # doctest: +SKIP
>>> scene = scene.with_gap(0.05).with_analysis(duration=10.0)            # doctest: +SKIP
>>> result = pounding.run(scene)                                         # doctest: +SKIP
>>> pounding.storey_peaks(result)            # pandas DataFrame, units in the names   # doctest: +SKIP
>>> pounding.impact_table(result)            # one row per impact                     # doctest: +SKIP
>>> pounding.contact_table(result)           # contacts.csv: episodes of force laws and impacts alike  # doctest: +SKIP
>>> pounding.histories(result)               # xarray Dataset, time x building x storey x dof   # doctest: +SKIP
>>> pounding.write_results(result, "out")    # the files `pounding run` writes; `pounding plot out` draws them   # doctest: +SKIP
>>> pounding.write_scene(scene, "mine.toml") # loads back equal                      # doctest: +SKIP

Heavy modules (vtk, pyvista, matplotlib, pandas, xarray) are never imported from here.
"""

from pounding.errors import InputError


def __getattr__(name):
    # The version is read from the installed metadata only when asked (--version): reading it
    # costs tens of milliseconds that every other command would pay at start-up.
    if name == "__version__":
        from pounding.version import package_version

        return package_version()
    raise AttributeError(name)


__all__ = ["InputError", "__version__", "load_scene", "assemble", "run", "storey_peaks", "impact_table", "contact_table", "histories",
           "write_results", "load_result", "write_scene", "minimum_gap", "sweep", "fragility", "export_opensees"]


def _forward(func, options: dict, skip: tuple, name: str):
    """``func``, once every key of ``options`` is one of its parameters (less ``skip``, those given by
    position): a misspelt option is a TypeError naming the closest one (as the command line does)."""
    import inspect

    from pounding.framework.model.scene import check_keywords

    check_keywords(options, [p for p in inspect.signature(func).parameters if p not in skip], name)
    return func


def load_scene(path):
    """Read and validate a scene file (TOML); see :func:`pounding.io.scene.load_scene`."""
    from pounding.io.scene import load_scene as _load

    return _load(path)


def assemble(building):
    """Assemble one building (mass, stiffness, damping, modes); see :func:`pounding.framework.model.assembly.assemble`."""
    from pounding.framework.model.assembly import assemble as _assemble

    return _assemble(building)


def run(scene, **options):
    """Run the time-history analysis; see :func:`pounding.framework.post.run.run` (options: ``progress``).

    A misspelt option raises :class:`~pounding.framework.model.scene.KeywordError` (a TypeError) with the closest name.
    """
    from pounding.framework.post.run import run as _run

    return _forward(_run, options, ("scene",), "pounding.run")(scene, **options)


def storey_peaks(result):
    """Per-storey peaks as a pandas DataFrame; see :func:`pounding.io.frames.storey_peaks`."""
    from pounding.io.frames import storey_peaks as _peaks

    return _peaks(result)


def impact_table(result):
    """The impacts as a pandas DataFrame; see :func:`pounding.io.frames.impact_table`."""
    from pounding.io.frames import impact_table as _impacts

    return _impacts(result)


def contact_table(result):
    """The contacts (force laws' episodes and impacts alike, contacts.csv's rows) as a pandas DataFrame;
    see :func:`pounding.io.frames.contact_table`."""
    from pounding.io.frames import contact_table as _contacts

    return _contacts(result)


def histories(result):
    """The histories as an xarray Dataset; see :func:`pounding.io.frames.histories`."""
    from pounding.io.frames import histories as _histories

    return _histories(result)


def write_results(result, out, **options):
    """Write a run folder (response.npz, summary.json, impacts.csv, scene.toml...); see :func:`pounding.io.results.write_results`."""
    from pounding.io.results import write_results as _write

    return _forward(_write, options, ("result", "out"), "pounding.write_results")(result, out, **options)


def load_result(folder):
    """(scene, result) of a run folder; see :func:`pounding.io.results.load_result`."""
    from pounding.io.results import load_result as _load

    return _load(folder)


def write_scene(scene, path):
    """Write a scene file that loads back the same scene; see :func:`pounding.io.scene_writer.write_scene`."""
    from pounding.io.scene_writer import write_scene as _write

    return _write(scene, path)


def minimum_gap(scene, direction=None, **options):
    """The smallest clear distance at rest at which no slabs of the scene's two buildings touch, with the
    code estimates (``pounding gap``); see :func:`pounding.framework.studies.gap.minimum_gap` (options: ``progress``)."""
    from pounding.framework.studies.gap import minimum_gap as _gap

    return _forward(_gap, options, ("scene", "direction"), "pounding.minimum_gap")(scene, direction, **options)


def sweep(scene_path, out, **options):
    """A grid of runs of one scene file, its table and plots written into ``out`` (``pounding sweep``); see
    :func:`pounding.framework.studies.sweep.run_sweep` (options: ``gaps``, ``pga_scales``, ``records``,
    ``restitutions``, ``integrators``, ``angles``, ``serial``, ``workers``, ...)."""
    from pounding.framework.studies.sweep import run_sweep as _sweep

    return _forward(_sweep, options, ("scene_path", "out"), "pounding.sweep")(scene_path, out, **options)


def fragility(scene_path, out, **options):
    """A pounding-fragility study of one scene file over records and intensity levels, written into ``out``
    (``pounding fragility``); see :func:`pounding.framework.studies.fragility.run_fragility` (options: ``records``,
    ``levels``, ``im``, ``gaps``, ``targets``, ``consequence_gaps``, ``serial``, ``workers``, ...)."""
    from pounding.framework.studies.fragility import run_fragility as _fragility

    return _forward(_fragility, options, ("scene_path", "out"), "pounding.fragility")(scene_path, out, **options)


def export_opensees(scene, path, **options):
    """Write the scene as an OpenSeesPy script (``pounding export opensees``); returns the notes on what
    OpenSees does not get; see :func:`pounding.peer.export.write_script`."""
    from pounding.peer.export import write_script as _write

    return _forward(_write, options, ("scene", "out"), "pounding.export_opensees")(scene, path, **options)
