"""The compiler set-up: numba, loaded only when compiled code first runs.

Every compiled function of the package is declared with :func:`njit`. It returns a
:class:`Kernel`, a light handle on the plain Python function: numba is imported,
and the function compiled (or its machine code loaded from the cache), only when
the function is first called. So importing the package, loading a scene and
``pounding info`` import no numba and load no machine code, and a run loads only
the functions it calls. A compiled function that calls another finds the handle
in its module's globals; numba types it as the dispatcher behind it
(:func:`_register_typeof`), so calls between compiled functions stay compiled
calls.

Without numba, or with ``NUMBA_DISABLE_JIT=1``, :func:`njit` returns the
function itself (``func.py_func is func``): the same arithmetic runs as plain
Python over numpy arrays.

A function's first call first looks for it in the extension module built at install
(:mod:`pounding.aot`): where the module has it for the call's argument types, calls run the
module's machine code, and numba is not imported at all; any other call goes to numba.

The cache
---------
numba keys a cached function on its own source file only: a change in a function
it calls from another module would leave it stale. The cache folder is therefore
keyed on the source of every module that declares compiled functions, found by
scanning the package for ``@njit`` (:func:`compiled_modules`), not by a hand-kept
list. ``NUMBA_CACHE_DIR``, when set, is numba's and is left alone.

Timing
------
:func:`compile_seconds` is the wall time this process has spent compiling (numba's
``numba:compile`` events, cache loads excluded); :func:`load_seconds` the time spent making
compiled functions ready (compiling or loading each from the cache before its first call); :func:`on_first_compile` registers a
callback run once, just before the first compilation (the command line prints that it
is compiling).
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import re
from pathlib import Path

#: the package's root folder (``pounding/``)
PACKAGE_ROOT = Path(__file__).resolve().parent

_KERNELS: list["Kernel"] = []
_interpreted = [0]  # depth of interpreted() blocks (scene loading: single-threaded)
_loading = [0]  # inside Kernel._first_call
_load_time = [0.0]
_compile_outside = [0.0]  # compile time not inside a first call (a second signature)
_active = False
_compile_time = [0.0]
_first_compile_hooks: list = []


def enabled() -> bool:
    """Whether compiled code is used: numba is installed and ``NUMBA_DISABLE_JIT`` is not set.

    Decided without importing numba."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return False
    return importlib.util.find_spec("numba") is not None


class Kernel:
    """A compiled function, compiled on first use.

    Calling it calls the numba dispatcher (compiled once per argument types, cached
    on disk); ``py_func`` is the plain Python function. Inside :func:`interpreted`,
    calls run ``py_func`` instead and compile nothing (one-off geometry at scene load).
    """

    def __init__(self, func):
        self.py_func = func
        self._dispatcher = None
        self._call = None  # what a call runs: the numba dispatcher, or the built extension's entry (pounding.aot)
        self.__name__ = func.__name__
        self.__qualname__ = func.__qualname__
        self.__doc__ = func.__doc__
        self.__module__ = func.__module__
        self.__wrapped__ = func
        _KERNELS.append(self)

    @property
    def dispatcher(self):
        """The numba dispatcher (created, with numba imported, on first access)."""
        if self._dispatcher is None:
            import numba

            activate()
            self._dispatcher = numba.njit(cache=True)(self.py_func)
            _fix_identity(self._dispatcher, self.py_func)
        return self._dispatcher

    @property
    def signatures(self) -> list:
        """The argument types compiled or loaded so far in this process (empty before first use)."""
        return [] if self._dispatcher is None else list(self._dispatcher.signatures)

    def __call__(self, *args):
        # the driver calls compiled functions hundreds of times a run: keep this path short
        if _interpreted[0]:
            return self.py_func(*args)
        c = self._call
        if c is None:
            c = self._first_call(args)
        return c(*args)

    def _first_call(self, args):
        """What calls run from now on: the extension built at install when it has this function
        (:mod:`pounding.aot`; its entry checks each call's argument types), else numba's dispatcher,
        compiled or loaded from the cache for these arguments' types before the first call runs it.
        Timed apart (:func:`load_seconds`)."""
        import time

        t0 = time.perf_counter()
        from pounding import aot

        exports = aot.lookup(self)
        _load_time[0] += time.perf_counter() - t0
        if exports:
            self._call = _Prebuilt(self, exports)
            return self._call
        self._call = self._jit(args)
        return self._call

    def _jit(self, args):
        """numba's dispatcher, with the machine code for these arguments' types compiled or loaded."""
        import time

        t0 = time.perf_counter()
        d = self.dispatcher
        if hasattr(d, "compile"):  # not with NUMBA_DISABLE_JIT
            from numba import typeof

            _loading[0] += 1
            try:
                d.compile(tuple(typeof(a) for a in args))
            except Exception:  # noqa: BLE001 - the call itself reports a typing error, with numba's message
                pass
            finally:
                _loading[0] -= 1
        _load_time[0] += time.perf_counter() - t0
        return d

    def __repr__(self) -> str:
        return f"<compiled function {self.__module__}.{self.__name__}>"


def _fix_identity(dispatcher, func) -> None:
    """Give a dispatcher the same identity in every process: its module, name and source file's digest.

    A compiled function that takes another as an argument (the link stepping takes the laws'
    ``update`` functions, :mod:`pounding.framework.links`) is cached under its arguments' types, and
    numba's type of a compiled function names it by the dispatcher's uuid, which numba draws at
    random in each process: the cached code would never be found again, and every process would
    compile the stepping afresh (seconds). With this identity the same function is the same type
    in every process, and a law whose source file changed is another type (compiled afresh)."""
    import sys

    module = sys.modules.get(func.__module__)
    path = getattr(module, "__file__", None)
    try:
        with open(path, "rb") as fh:
            digest = hashlib.sha1(fh.read()).hexdigest()
    except (OSError, TypeError):  # no source file (a function made at run time): numba's own uuid
        return
    try:
        dispatcher._set_uuid(f"pounding:{func.__module__}.{func.__qualname__}:{digest}")
    except (AttributeError, AssertionError):  # another numba, or an identity set already: numba's own
        return


class _Prebuilt:
    """A compiled function's entries in the extension built at install (:mod:`pounding.aot`): a call
    whose argument fingerprint the extension was built for runs its entry; any other goes to numba."""

    __slots__ = ("kernel", "exports", "fallback", "call_print")

    def __init__(self, kernel, exports):
        from pounding.aot import call_print

        self.kernel, self.exports, self.fallback, self.call_print = kernel, exports, None, call_print

    def __call__(self, *args):
        f = self.exports.get(self.call_print(args))
        if f is not None:
            return f(*args)
        if self.fallback is None:
            self.fallback = self.kernel._jit(args)
        return self.fallback(*args)


def njit(func):
    """Declare ``func`` compiled (numba ``njit(cache=True)``, no fastmath): a :class:`Kernel`,
    or ``func`` itself (with ``func.py_func = func``) when compiled code is not used."""
    if not enabled():
        func.py_func = func
        return func
    return Kernel(func)


@contextlib.contextmanager
def interpreted():
    """Run compiled functions called in this block (and the functions they call) as plain Python.

    For one-off calls from Python where compiling would cost seconds and running
    interpreted costs microseconds (the rest gaps of a scene's slabs at load)."""
    _interpreted[0] += 1
    try:
        yield
    finally:
        _interpreted[0] -= 1


def kernels() -> list[Kernel]:
    """Every compiled function declared so far (by the modules imported so far)."""
    return list(_KERNELS)


def compiled_modules() -> list[Path]:
    """Source files of the package that declare compiled functions (a line ``@njit``), sorted.

    Files under ``__pycache__`` are not the package's source: the cache folder lives there, and a
    file in it must never move the key that names it (the next process would compile everything
    again, into a new folder)."""
    pattern = re.compile(rb"^@njit\b", re.MULTILINE)
    out = []
    for path in _sources():  # (not under __pycache__: generated modules live in the cache itself, keying on them would move it)
        try:
            if pattern.search(path.read_bytes()):
                out.append(path)
        except OSError:  # pragma: no cover - unreadable file
            continue
    return out


def cache_key() -> str:
    """Digest of the source of every compiled module (:func:`compiled_modules`). Kept while no source
    file of the package changes (size and modification time): scanning and reading them all costs
    ~20 ms, and a process asks several times (numba's folder, the extension module's)."""
    stamp = _source_stamp()
    hit = _key.get(PACKAGE_ROOT)
    if hit is not None and hit[0] == stamp:
        return hit[1]
    digest = hashlib.sha1()
    for path in compiled_modules():
        digest.update(str(path.relative_to(PACKAGE_ROOT)).encode())
        digest.update(path.read_bytes())
    key = digest.hexdigest()[:12]
    _key[PACKAGE_ROOT] = (stamp, key)
    return key


_key: dict = {}  # package root -> (source stamp, key)


def _sources() -> list[Path]:
    """The package's Python files, sorted, not descending into ``__pycache__`` (numba's cache
    folders hold thousands of files)."""
    out = []
    for folder, dirs, files in os.walk(PACKAGE_ROOT):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        out.extend(Path(folder) / f for f in files if f.endswith(".py"))
    return sorted(out)


def _source_stamp() -> tuple:
    return tuple((str(p), st.st_size, st.st_mtime_ns) for p in _sources() for st in (p.stat(),))


def cache_dir() -> str | None:
    """numba's cache folder for this exact version of the compiled modules (None: numba's default).

    Folders of earlier versions stay behind (a few MB each, and the extension modules' ``aot-*``
    beside them); delete ``pounding/__pycache__/numba-*`` and ``aot-*``
    to reclaim them."""
    try:
        key = cache_key()
    except OSError:  # pragma: no cover - a frozen or zipped install
        return None
    for base in (PACKAGE_ROOT / "__pycache__", Path.home() / ".cache" / "pounding"):
        folder = base / ("numba-" + key)
        try:
            folder.mkdir(parents=True, exist_ok=True)
            if os.access(folder, os.W_OK):
                return str(folder)
        except OSError:
            continue
    return None


def activate() -> None:
    """Import numba and set it up (cache folder, typing of :class:`Kernel`, compile-time listener).

    Called by the first compiled call; idempotent."""
    global _active
    if _active:
        return
    import numba
    from numba.core import event

    if not os.environ.get("NUMBA_CACHE_DIR"):
        folder = cache_dir()
        if folder is not None:
            numba.config.CACHE_DIR = folder
    _register_typeof()
    event.register("numba:compile", _compile_listener())
    _active = True


def _register_typeof() -> None:
    from numba.extending import typeof_impl

    @typeof_impl.register(Kernel)
    def _typeof_kernel(val, c):
        # a compiled function calling another: type the handle as the dispatcher behind it
        return typeof_impl(val.dispatcher, c)


def _compile_listener():
    """numba event listener: wall time of outermost compilations (nested ones run inside them)."""
    import time

    from numba.core import event

    class CompileTimer(event.Listener):
        depth = 0
        start = 0.0

        def on_start(self, ev):
            if self.depth == 0:
                hooks = list(_first_compile_hooks)
                _first_compile_hooks.clear()
                for hook in hooks:
                    hook()
                self.start = time.perf_counter()
            self.depth += 1

        def on_end(self, ev):
            self.depth -= 1
            if self.depth == 0:
                _compile_time[0] += time.perf_counter() - self.start
                if not _loading[0]:
                    _compile_outside[0] += time.perf_counter() - self.start

    return CompileTimer()


def compile_seconds() -> float:
    """Wall time [s] this process has spent compiling (cache loads excluded)."""
    return _compile_time[0]


def load_seconds() -> float:
    """Wall time [s] this process has spent making compiled functions ready: the first call of
    each (compile or cache load) and any later compilation. Time that is not the solve."""
    return _load_time[0] + _compile_outside[0]


def on_first_compile(callback) -> None:
    """Run ``callback()`` once, just before this process first compiles (not on cache loads)."""
    _first_compile_hooks.append(callback)


# --------------------------------------------------------------------------- warm-up at install
#: The warm-up tasks (see :func:`_warm_task`). ``--jobs 2`` runs the first in one process and the
#: rest in a second one, so that the two largest compiled entry points (the free stretch and the
#: held stretch) compile side by side.
WARM_TASKS = ("kernel", "shared", "free")


def _paper_scene():
    """The packaged paper pair at a gap of 0.03 m (``pounding demo``'s pounding scene)."""
    from importlib.resources import files

    from pounding.io.scene import load_scene

    return load_scene(str(files("pounding.io") / "data" / "paper" / "pair_gap_0.03.toml"))


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
    contact-free stretch (the same scene with contact ``none``). Measured in
    ``benchmarks/bench_compile.py``."""
    import warnings

    import numpy as np

    from pounding.framework.analysis import Driver, run

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
        _, gap, W, _, _ = model.touching(q, np.arange(len(model.pairs), dtype=np.int64), driver.tol, True)
        driver.advance_held(0, 0)
        from pounding.framework.held import rows_where

        rows_where(np.ascontiguousarray(gap <= driver.touch), np.ascontiguousarray(W))  # a held Python step's plastic stop
        # the default integrator of elastic scenes (exact): its compiled one-off maps, which the
        # crossing locator builds at every located impact (the packaged paper scene names HHT)
        from pounding.solvers.exact import Exact

        Exact().partial_transition(model.omega, model.zeta, 1e-3)
        Exact().partial_work_maps(model.omega, model.zeta, 1e-3)
        # and its impact search, compiled whole (pounding.framework.event_search), as the driver calls it
        search = Driver(scene.with_analysis(integrator="exact", integrator_params={}))
        search.locate(0.0, search.dt, [0], search.trial(search.z, 0.0, search.dt))
    elif name == "free":
        run(scene.with_analysis(contact="none"))
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
        ``skipped`` (True when ``if_needed`` found the cache warm).
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
    jobs = max(1, min(len(WARM_TASKS), jobs or min(2, os.cpu_count() or 1)))
    say(f"pounding: compiling the numerical core for the first runs ({jobs} process{'es' if jobs > 1 else ''}; once per version of the code, about 40 s of CPU) ...")
    groups: list[list[str]] = [[WARM_TASKS[0]], list(WARM_TASKS[1:])] if jobs > 1 else [list(WARM_TASKS)]
    times: dict[str, float] = {}
    import tempfile

    procs = {}
    scratch = tempfile.TemporaryDirectory(prefix="pounding-warm-")
    env = dict(os.environ, POUNDING_WARM_SENTINEL=str(Path(scratch.name) / "geometry-compiled"))
    for group in groups:
        cmd = [sys.executable, "-m", "pounding.compiler", "--task", ",".join(group)]
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
    return info


def _main(argv=None) -> int:
    import argparse
    import json

    ap = argparse.ArgumentParser(prog="python -m pounding.compiler", description="Fill the compiler cache (run once after installing).")
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
    from pounding.compiler import _main as _package_main

    raise SystemExit(_package_main())
