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
        return self._dispatcher

    @property
    def signatures(self) -> list:
        """The argument types compiled or loaded so far in this process (empty before first use)."""
        return [] if self._dispatcher is None else list(self._dispatcher.signatures)

    def __call__(self, *args):
        # the driver calls compiled functions hundreds of times a run: keep this path short
        if _interpreted[0]:
            return self.py_func(*args)
        d = self._dispatcher
        if d is None:
            d = self._first_call(args)
        return d(*args)

    def _first_call(self, args):
        """Compile, or load from the cache, the machine code for these arguments' types before the
        first call runs it, timed apart (:func:`load_seconds`)."""
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
    """Source files of the package that declare compiled functions (a line ``@njit``), sorted."""
    pattern = re.compile(rb"^@njit\b", re.MULTILINE)
    out = []
    for path in sorted(PACKAGE_ROOT.rglob("*.py")):
        if "__pycache__" in path.parts:  # generated modules live in the cache itself: keying on them would move it
            continue
        try:
            if pattern.search(path.read_bytes()):
                out.append(path)
        except OSError:  # pragma: no cover - unreadable file
            continue
    return out


def cache_key() -> str:
    """Digest of the source of every compiled module (:func:`compiled_modules`)."""
    digest = hashlib.sha1()
    for path in compiled_modules():
        digest.update(str(path.relative_to(PACKAGE_ROOT)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:12]


def cache_dir() -> str | None:
    """numba's cache folder for this exact version of the compiled modules (None: numba's default).

    Folders of earlier versions stay behind (a few MB each); delete ``pounding/__pycache__/numba-*``
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
