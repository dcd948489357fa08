"""The install-time warm-up: compile (or load) the numerical core for the common runs.

It sits above the engine because its tasks run the engine (a whole run of the paper pair);
the compiler set-up it fills (:mod:`pounding.compiler`) sits below everything it compiles.
``python -m pounding.warmup --warm --if-needed`` is what ``make demo`` and ``make test`` run.
"""

from __future__ import annotations

import os
from pathlib import Path

from pounding.compiler import PACKAGE_ROOT, cache_dir, enabled


#: The warm-up tasks (see :func:`_warm_task`), in the two groups ``--jobs 2`` runs side by side (one
#: process each), so that the largest compiled entry points (the stretch with the crossing locator,
#: the held stretch, the free stretch, the force laws' stretch and the yielding springs' stepping)
#: compile two at a time. ``--jobs 1`` runs them all in order.
WARM_GROUPS = (("kernel", "force", "links"), ("shared", "free", "yielding"))
WARM_TASKS = tuple(t for g in WARM_GROUPS for t in g)


def _paper_scene():
    """The packaged paper pair at a gap of 0.03 m (``pounding demo``'s pounding scene)."""
    from importlib.resources import files

    from pounding.io.scene import load_scene

    return load_scene(str(files("pounding.io") / "data" / "paper" / "pair_gap_0.03.toml"))


def _yielding_scene():
    """The paper pair with yielding (bilinear) storey springs, gap 0.03 m (examples/inelastic_pair)."""
    from importlib.resources import files

    from pounding.io.scene import load_scene

    return load_scene(str(files("pounding.io") / "data" / "inelastic" / "pair_yielding_gap_0.03.toml"))


def _linked_scene():
    """The packaged paper pair with two linear viscous dampers between the roof of ``low`` and the
    slab of ``high`` at its level (examples/linked_pair/pair_viscous.toml's links)."""
    import tomllib
    from importlib.resources import files

    from pounding.io.scene import parse_scene

    path = files("pounding.io") / "data" / "paper" / "pair_gap_0.03.toml"
    data = tomllib.loads(path.read_text())
    law = {"name": "viscous", "coefficient": 7.5e5, "exponent": 1.0}
    data["link"] = [{"name": f"damper-{i}", "between": ["low", "high"], "storeys": [3, 3], "points": [[14.9, y], [15.13, y]], "law": law}
                    for i, y in enumerate((2.0, 8.0))]
    return parse_scene(data, source=Path(str(path)))


def _warm_task(name: str) -> None:
    """Compile (or load) what one warm-up task needs, in this process.

    The two processes of ``--jobs 2`` share the work without compiling the same function twice:
    numba caches every compiled function on its own, and a process that needs a function
    another has already cached loads it, but compiles it itself when the other is still at it.
    ``kernel``: the polygon geometry (the signed gap and the contact points of two polygons,
    which everything else calls), then tells the other process (``POUNDING_WARM_SENTINEL``),
    then the gap of a slab pair and a whole run of the paper pair with pounding. ``shared``: the
    Newton impulses (no geometry), then, once the geometry is cached, what that run needs later,
    called from Python with the argument types the compiled code passes: the touching features
    of a pair and of several pairs, the held stretch (a call over no steps), the selection of a held
    pair's touching points and the one-off maps and impact search
    of ``exact`` (the default integrator of elastic scenes). ``free``: the
    contact-free stretch (the same scene with contact ``none``) and the gap study on its result
    (the compiled translation of two polygons to contact). ``force``: the same scene with a
    force law (``kelvin``), whose stretches stop at the contact tolerance rather than at a crossing,
    and the law's compiled force and point solve; then with ``penalty`` (its compiled solve). ``yielding``: the paper pair with yielding storey springs, with
    pounding and without (the springs' compiled stepping, with the bilinear law), their held
    stretch and held step (calls over no steps and no held pair) and the impact search with
    their step inside it. ``links``: the paper pair joined
    by two linear viscous dampers (links between buildings: the links' stepping with the viscous
    law, with pounding). Measured in
    ``benchmarks/bench_compile.py``."""
    import warnings

    import numpy as np

    from pounding.framework.engine.driver import Driver

    from pounding.framework.post.run import run

    warnings.simplefilter("ignore")
    scene = _paper_scene()
    sentinel = os.environ.get("POUNDING_WARM_SENTINEL")
    if name == "kernel":
        from pounding.contact.geometry import contact_points, signed_gap

        square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        signed_gap(square, square + 2.0)
        contact_points(square, square + np.array([1.0, 0.0]), 1e-4)
        if sentinel:
            Path(sentinel).touch()
        driver = Driver(scene)
        driver.model.pair_gap(np.zeros(driver.model.n), 0)
        run(scene)
    elif name == "shared":
        from pounding.contact.base import newton_impulses

        import time

        newton_impulses(np.eye(2), np.ones(2), 0.5)
        waited = 0.0
        while sentinel and not Path(sentinel).exists() and waited < 900.0:  # the geometry, compiled by `kernel`
            time.sleep(0.1)
            waited += 0.1
        driver = Driver(scene)
        model = driver.model
        q = np.zeros(model.n)
        model.features(q, 0, driver.tol)
        touching = model.touching(q, np.arange(len(model.pairs), dtype=np.int64), driver.tol, True)
        driver.advance_held(0, 0)
        from pounding.framework.engine.held import rows_where

        rows_where(np.ascontiguousarray(touching.gap <= driver.touch), np.ascontiguousarray(touching.W))  # a held Python step's plastic stop
        # the default integrator of elastic scenes (exact): its compiled maps, the transition the
        # crossing locator builds at every located impact and the work integrals of the energy audit
        # (grid step and partial steps; the packaged paper scene names HHT)
        from pounding.solvers.exact import Exact

        Exact().partial_transition(model.omega, model.zeta, 1e-3)
        Exact().work_maps(model.omega, model.zeta, 1e-3)
        # and its impact search, compiled whole (pounding.framework.engine.event_search), as the driver calls it
        search = Driver(scene.with_analysis(integrator="exact", integrator_params={}))
        search.locate(0.0, search.dt, [0], search.trial(search.z, 0.0, search.dt))
    elif name == "free":
        free = scene.with_analysis(contact="none", contact_params={})
        from pounding.framework.studies.gap import gap_from_result

        gap_from_result(free, run(free), full=False)  # a gap study's (and fragility's) translation to contact
    elif name == "force":
        run(scene.with_analysis(contact="kelvin", contact_params={}, duration=5.0))
        run(scene.with_analysis(contact="penalty", contact_params={}, duration=5.0))  # its compiled active-set solve
    elif name == "links":
        run(_linked_scene().with_analysis(duration=5.0))
    elif name == "yielding":
        yielding = _yielding_scene()
        run(yielding.with_analysis(duration=5.0))
        driver = Driver(yielding)
        driver.advance_held(0, 0)  # the held stretch with the springs (a call over no steps)
        driver.held_trial(driver.z, 0.0, driver.dt)  # the held step's fixed point, as the Python step calls it
        # the impact search compiled whole with the links' own step inside (event_search.locate)
        driver.locate(0.0, driver.dt, [0], driver.trial(driver.z, 0.0, driver.dt))
        run(yielding.with_analysis(contact="none", contact_params={}, duration=1.0))
        # the links and a force law's contact solved together (spring_core.contact_fixed_point), with
        # the point laws' solve and the penalty law's
        for law in ("kelvin", "penalty"):
            run(yielding.with_analysis(contact=law, contact_params={}, duration=5.0))
    else:
        raise ValueError(f"unknown warm-up task {name!r}; expected one of {WARM_TASKS}")


def _marker() -> Path | None:
    """The file that records a finished warm-up of this version of the compiled modules."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "pounding-warmed.json"
    folder = cache_dir()
    return None if folder is None else Path(folder) / "warmed.json"


def warm(jobs: int | None = None, *, if_needed: bool = False, quiet: bool = False) -> dict:
    """Fill the compiler cache for the common runs, in ``jobs`` processes at once (default: up to 2).

    Also writes the package's Python bytecode (``compileall``), which an editable install or an
    environment with ``PYTHONDONTWRITEBYTECODE`` never writes: every process would otherwise compile
    the package's ~50 modules from source (~0.15 s). After it, the first ``pounding run`` of a scene
    with pounding loads machine code instead of compiling it (~30 s on 2 cores).

    Parameters
    ----------
    jobs : int, optional
        Processes compiling at once (default ``min(2, cpu count)``); 1 compiles in this process.
    if_needed : bool
        Return at once when this version of the compiled modules was already warmed.
    quiet : bool
        Print nothing.

    Returns
    -------
    dict
        ``wall_s`` [s], ``jobs``, ``tasks`` (task name -> wall time [s] of its process),
        ``skipped`` (True when ``if_needed`` found the cache warm), and after a warm-up
        ``pruned``: the cache folders of earlier versions it removed and the bytes freed
        (:func:`pounding.compiler.cache.prune_stale`; none with ``NUMBA_CACHE_DIR`` set).
    """
    import compileall
    import json
    import subprocess
    import sys
    import time

    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    marker = _marker() if enabled() else None
    if if_needed and (marker is None or marker.exists()):
        return {"skipped": True, "wall_s": 0.0, "jobs": 0, "tasks": {}}
    t0 = time.perf_counter()
    compileall.compile_dir(str(PACKAGE_ROOT), quiet=1)  # bytecode; a read-only install is left as it is
    if marker is None:  # no numba, or NUMBA_DISABLE_JIT: nothing to compile
        return {"skipped": False, "wall_s": time.perf_counter() - t0, "jobs": 0, "tasks": {}}
    jobs = max(1, min(len(WARM_GROUPS), jobs or min(2, os.cpu_count() or 1)))
    say(f"pounding: compiling the numerical core for the first runs ({jobs} process{'es' if jobs > 1 else ''}; once per version of the code, a few minutes of CPU) ...")
    groups: list[list[str]] = [list(g) for g in WARM_GROUPS] if jobs > 1 else [list(WARM_TASKS)]
    times: dict[str, float] = {}
    import tempfile

    procs = {}
    scratch = tempfile.TemporaryDirectory(prefix="pounding-warm-")
    env = dict(os.environ, POUNDING_WARM_SENTINEL=str(Path(scratch.name) / "geometry-compiled"))
    for group in groups:
        cmd = [sys.executable, "-m", "pounding.warmup", "--task", ",".join(group)]
        procs[",".join(group)] = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    failed = []
    while procs:
        for name, proc in list(procs.items()):
            if proc.poll() is None:
                continue
            times[name] = time.perf_counter() - t0
            if proc.returncode != 0:
                failed.append(f"{name}: {proc.stderr.read().strip()[-600:]}")
                for other in procs.values():  # a worker may be waiting for the failed one
                    if other is not proc and other.poll() is None:
                        other.terminate()
            proc.stderr.close()
            del procs[name]
        time.sleep(0.05)
    scratch.cleanup()
    wall = time.perf_counter() - t0
    if failed:
        raise RuntimeError("pounding: compiling the numerical core failed\n" + "\n".join(failed))
    info = {"skipped": False, "wall_s": wall, "jobs": jobs, "tasks": times}
    try:
        marker.write_text(json.dumps(info) + "\n")
    except OSError:  # pragma: no cover - a read-only cache: the runs compile as they go
        pass
    say(f"pounding: compiled in {wall:.1f} s")
    if not os.environ.get("NUMBA_CACHE_DIR"):  # (a cache folder the user chose is theirs)
        from pounding.compiler.cache import prune_stale

        removed, freed = prune_stale()
        info["pruned"] = {"folders": removed, "bytes": freed}
        if removed:
            say(f"pounding: removed {removed} cache folder{'s' if removed > 1 else ''} of earlier versions ({freed / 1e6:.0f} MB)")
    return info


def _main(argv=None) -> int:
    import argparse
    import json

    ap = argparse.ArgumentParser(prog="python -m pounding.warmup", description="Fill the compiler cache (run once after installing).")
    ap.add_argument("--warm", action="store_true", help="compile the numerical core for the common runs")
    ap.add_argument("--jobs", type=int, default=None, help="processes compiling at once (default: up to 2)")
    ap.add_argument("--if-needed", action="store_true", help="do nothing when this version was already compiled")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--json", action="store_true", help="print the timings as JSON")
    ap.add_argument("--task", help=argparse.SUPPRESS)  # internal: one worker's tasks, comma-separated
    args = ap.parse_args(argv)
    if args.task:
        for name in args.task.split(","):
            _warm_task(name)
        return 0
    if not args.warm:
        ap.print_help()
        return 2
    info = warm(args.jobs, if_needed=args.if_needed, quiet=args.quiet)
    if args.json:
        print(json.dumps(info))
    return 0


if __name__ == "__main__":
    # run the package's own module (not this __main__ copy), whose state the compiled functions share
    from pounding.warmup import _main as _package_main

    raise SystemExit(_package_main())
