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
(:mod:`pounding.compiler.prebuilt`): where the module has it for the call's argument types, calls run the
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
import importlib.util
import os
from pounding.compiler.cache import PACKAGE_ROOT, cache_dir, cache_key, compiled_modules, enabled  # noqa: F401 - the set-up's public names

#: the package's root folder (``pounding/``)

_KERNELS: list["Kernel"] = []
_interpreted = [0]  # depth of interpreted() blocks (scene loading: single-threaded)
_loading = [0]  # inside Kernel._first_call
_load_time = [0.0]
_compile_outside = [0.0]  # compile time not inside a first call (a second signature)
_active = False
_compile_time = [0.0]
_first_compile_hooks: list = []



class Kernel:
    """A compiled function, compiled on first use.

    Calling it calls the numba dispatcher (compiled once per argument types, cached
    on disk); ``py_func`` is the plain Python function. Inside :func:`interpreted`,
    calls run ``py_func`` instead and compile nothing (one-off geometry at scene load).
    """

    #: numba types a compiled function passed as an argument by the function itself
    #: (:func:`pounding.compiler.prebuilt.dispatch_print`)
    typed_by_identity = True

    def __init__(self, func, borrowed=False, fingerprinted=False):
        self.py_func = func
        self.borrowed = borrowed  #: compiled without reference counts (:func:`njit`)
        self.fingerprinted = fingerprinted  #: calls dispatched by their arguments' fingerprint (:func:`njit`)
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
            options = {"_nrt": False} if self.borrowed else {}
            self._dispatcher = numba.njit(cache=True, **options)(self.py_func)
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
        (:mod:`pounding.compiler.prebuilt`; its entry checks each call's argument types), else numba's dispatcher,
        compiled or loaded from the cache for these arguments' types before the first call runs it.
        Timed apart (:func:`load_seconds`)."""
        import time

        t0 = time.perf_counter()
        from pounding.compiler import prebuilt

        exports = prebuilt.lookup(self)
        _load_time[0] += time.perf_counter() - t0
        if exports:
            self._call = _Prebuilt(self, exports)
            return self._call
        self._call = self._jit(args)
        return self._call

    def _jit(self, args):
        """numba's dispatcher, with the machine code for these arguments' types compiled or loaded
        (:class:`_Entries`: later calls of the same argument types run that code directly)."""
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
        # numba's own dispatch types arrays, scalars and named bundles fast enough (an array-only
        # call: 0.2 us, against 2 us for a fingerprint); a plain tuple of laws and arrays it types in
        # Python, element by element (70 us): a function whose first call passes one, or one declared
        # ``fingerprinted``, keeps its machine code by fingerprint for every later call
        slow = self.fingerprinted or any(map(_typed_slowly, args))
        return _Entries(d) if hasattr(d, "overloads") and slow else d

    def __repr__(self) -> str:
        return f"<compiled function {self.__module__}.{self.__name__}>"

    def __getstate__(self) -> dict:
        # numba's cache pickles a compiled function by value when one defined outside an importable
        # module (a test's, a script's) names this one: what its calls run (the machine code kept
        # per fingerprint, the extension's entries) is this process's and is found again on a call
        state = dict(self.__dict__)
        state["_call"] = None
        return state


def _fix_identity(dispatcher, func) -> None:
    """Give a dispatcher the same identity in every process: its module, name and source file's digest.

    A compiled function that takes another as an argument (the link stepping takes the laws'
    ``update`` functions, :mod:`pounding.framework.engine.links`) is cached under its arguments' types, and
    numba's type of a compiled function names it by the dispatcher's uuid, which numba draws at
    random in each process: the cached code would never be found again, and every process would
    compile the stepping afresh (seconds). With this identity the same function is the same type
    in every process, and a law whose source file changed is another type (compiled afresh)."""
    import hashlib
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


def _typed_slowly(a) -> bool:
    """Whether numba types the argument ``a`` slowly at every call: a plain tuple (its elements one by
    one, in Python), a law tuple or a compiled function (through its first-class function typing)."""
    return type(a) is tuple or getattr(type(a), "typed_by_identity", False)


class _Entries:
    """numba's dispatcher, with the machine code it ran for each argument fingerprint kept by that
    fingerprint (:func:`pounding.compiler.prebuilt.dispatch_print`), for a function whose calls pass a
    plain tuple, a law tuple or a compiled function (:func:`_typed_slowly`), or one declared
    ``fingerprinted`` (:func:`njit`).

    numba's dispatcher types every argument at every call to choose the machine code, and types a
    plain tuple element by element in Python: a call of the contact solve with its
    arguments' tuple (the laws' kernels, seven arrays) spent 70 us there against 2 us in the code
    itself. The fingerprint says the same as numba's types (an array's dtype, dimensions, layout,
    mutability and alignment; a bundle's class and fields; a law tuple or a compiled function by
    identity, held so that its identity is not reused) for a few microseconds, so a call whose
    fingerprint ran before runs the same machine code directly (numba's ``overloads``, the entry
    its dispatcher would pick); any other call, or one whose arguments have no fingerprint, goes
    through the dispatcher, which compiles what it lacks."""

    __slots__ = ("dispatcher", "entries")

    def __init__(self, dispatcher):
        self.dispatcher, self.entries = dispatcher, {}

    def __call__(self, *args):
        from pounding.compiler.prebuilt import dispatch_print

        key = dispatch_print(args)
        f = self.entries.get(key) if key is not None else None
        if f is not None:
            return f(*args)
        out = self.dispatcher(*args)
        if key is not None:
            f = self._entry(args)
            if f is not None:
                self.entries[key] = f
        return out

    def _entry(self, args):
        """The machine code the dispatcher holds for exactly these arguments' numba types, or None."""
        from numba import typeof

        try:
            compiled = self.dispatcher.overloads.get(tuple(typeof(a) for a in args))
        except Exception:  # noqa: BLE001 - an argument numba types only by value: no direct entry
            return None
        return None if compiled is None else compiled.entry_point


class _Prebuilt:
    """A compiled function's entries in the extension built at install (:mod:`pounding.compiler.prebuilt`): a call
    whose argument fingerprint the extension was built for runs its entry; any other goes to numba."""

    __slots__ = ("kernel", "exports", "fallback", "call_print")

    def __init__(self, kernel, exports):
        from pounding.compiler.prebuilt import call_print

        self.kernel, self.exports, self.fallback, self.call_print = kernel, exports, None, call_print

    def __call__(self, *args):
        f = self.exports.get(self.call_print(args))
        if f is not None:
            return f(*args)
        if self.fallback is None:
            self.fallback = self.kernel._jit(args)
        return self.fallback(*args)


def njit(func=None, *, borrowed: bool = False, fingerprinted: bool = False):
    """Declare ``func`` compiled (numba ``njit(cache=True)``, no fastmath): a :class:`Kernel`,
    or ``func`` itself (with ``func.py_func = func``) when compiled code is not used.

    ``@njit(borrowed=True)``: a function that allocates no array and returns none, whose arrays
    are all its caller's (borrowed for the call), is compiled without numba's reference counts
    (numba's ``_nrt=False``). numba otherwise counts a reference, an atomic add through a call, on
    every array argument at entry and exit (every array of a bundle argument) and on every array
    read from a bundle: in the links' stepping those counts were 40 % of a yielding run's time
    (measured with perf). numba checks the promise when it compiles: without reference counts a
    function that allocates an array, or returns one that is not an argument, fails to type.

    ``@njit(fingerprinted=True)``: a function called with bundles of bundles built once for many
    calls (the compiled stretch, whose search bundle holds the step's and the held pairs' bundles)
    finds its machine code by its arguments' fingerprint (:class:`_Entries`; a bundle's by identity),
    not by numba's typing, which types the inner bundles in Python at every call: 13 us of the
    stretch's 28 us call from the driver, against 3.5 us. Not for a function given a new bundle at
    most calls (the held step's held set): its full fingerprint costs more than numba's typing."""
    if func is None:
        return lambda f: njit(f, borrowed=borrowed, fingerprinted=fingerprinted)
    if not enabled():
        func.py_func = func
        return func
    return Kernel(func, borrowed, fingerprinted)


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


def is_compiled(func) -> bool:
    """Whether ``func`` is a compiled function (declared with :func:`njit`), which compiled code can
    take as an argument, rather than a plain Python one."""
    return isinstance(func, Kernel)


def kernels() -> list[Kernel]:
    """Every compiled function declared so far (by the modules imported so far)."""
    return list(_KERNELS)



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
    for hook in _activation_hooks:
        hook()


#: what a module needs from numba itself before its compiled functions are typed (called once, when
#: numba is imported by :func:`activate`): a run served by the extension module built at install
#: never imports numba, so no module may import it at its own import
_activation_hooks: list = []


def on_activate(hook) -> None:
    """Call ``hook()`` when numba is set up (at once if it is already)."""
    _activation_hooks.append(hook)
    if _active:
        hook()


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
