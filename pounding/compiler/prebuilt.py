"""Loading the compiled core's extension module built at install (:mod:`pounding.aot` builds it).

At run time a compiled function's first call looks for its export (:func:`lookup`). A call whose
arguments have a fingerprint the module was built for runs the export; any other call (another
scene's types, a function the warm-up did not call) goes to numba as before. The fingerprint check
is what makes this safe: the module's argument conversion checks only an array's item size, so a
call with the wrong layout would read wrong memory.

Who uses it: ``POUNDING_AOT=1`` turns it on, ``0`` off. Unset, the ``pounding`` commands that run
one scene (``run``, ``gap``, ``check``, ``demo``, ...) use it (:func:`prefer`): their process is short
and its start is what the user waits for. Unset, a program that imports pounding, and ``pounding sweep`` /
``pounding fragility``, keep numba's dispatch (see :func:`enabled`).
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np

from pounding.compiler.cache import EXTENSION_MANIFEST as _MANIFEST
from pounding.compiler.cache import EXTENSION_MODULE as MODULE  # name of the extension module

#: the manifest's format (a build of another format is not loaded)
FORMAT = 2
_state: dict = {}  # "module": the imported module or None, "exports": {kernel: {fingerprint: export name}}
_bundles: dict = {}  # id -> (bundle, its key)
_tokens: dict = {}  # a bundle's full print -> its number


# --------------------------------------------------------------------------- fingerprints
def _array_print(a: np.ndarray) -> tuple:
    # numba's array type: dtype (byte order included), ndim, layout (C before F, as numba.typeof),
    # mutability, alignment
    fl = a.flags
    return ("a", a.dtype, a.ndim, "C" if fl.c_contiguous else "F" if fl.f_contiguous else "A", fl.writeable, fl.aligned)


def fingerprint(x) -> tuple | str | None:
    """A hashable description of an argument's numba type, computed without numba; None for a kind
    the module does not take (such a call goes to numba). Types are matched exactly: a subclass
    (a masked array, an IntEnum) is left to numba, which types it apart."""
    t = type(x)
    if t is np.ndarray:
        return _array_print(x)
    if t is bool or t is np.bool_:
        return "b"
    if t is int:
        return _int_print(x)
    if t is float:
        return "f"
    if isinstance(x, np.generic) and t in (np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32, np.uint64,
                                           np.float32, np.float64):
        return ("n", np.dtype(t))
    if x is None:
        return "none"
    if isinstance(x, tuple) and hasattr(t, "_fields"):  # a named bundle (pounding.framework.engine.bundles)
        parts = tuple(fingerprint(v) for v in x)
        return None if any(p is None for p in parts) else (t.__module__ + "." + t.__qualname__ + str(tuple(t._fields)), parts)
    if t is tuple:
        parts = tuple(fingerprint(v) for v in x)
        return None if any(p is None for p in parts) else ("t", parts)
    return None


def _int_print(x):
    # numba types a Python int as int64 (uint64 beyond): the module takes int64 only
    return "i" if -(2**63) <= x < 2**63 else None


def _scalar(kind):
    return lambda x: kind


# the kinds passed most often, by exact type (a call checks every argument: keep it short)
_FAST = {np.ndarray: _array_print, float: _scalar("f"), int: _int_print, bool: _scalar("b"), np.bool_: _scalar("b"),
         type(None): _scalar("none")}


def _is_bundle_print(p) -> bool:
    return isinstance(p, tuple) and len(p) == 2 and isinstance(p[0], str) and "." in p[0] and p[0] != "n"


def _token(p):
    """A bundle's print as a short key: ("B", n), n numbering the distinct prints of this process.
    (Hashing the whole print, some dozen arrays' worth, at every call cost more than the check.)"""
    return ("B", _tokens.setdefault(p, len(_tokens)))


def _bundle(x):
    # a bundle is built once and passed to hundreds of calls: its key is kept with it (by identity,
    # the bundle held so that its id is not reused). This relies on the package's rule for bundles
    # (pounding.framework.engine.bundles): their arrays are filled in place, never reshaped, re-typed or
    # re-flagged; a bundle with other arrays is a new bundle.
    hit = _bundles.get(id(x))
    if hit is not None and hit[0] is x:
        return hit[1]
    p = fingerprint(x)
    key = None if p is None else _token(p)
    if len(_bundles) > 256:
        _bundles.clear()
    _bundles[id(x)] = (x, key)
    return key


def _one(x):
    f = _FAST.get(type(x))
    if f is not None:
        return f(x)
    if isinstance(x, tuple) and hasattr(type(x), "_fields"):
        return _bundle(x)
    return fingerprint(x)


def call_print(args: tuple) -> tuple | None:
    """The key of a call's arguments: their :func:`fingerprint`, each named bundle's as a short
    token (:func:`call_key` of the recorded prints gives the same); None if any argument is of a
    kind the module does not take."""
    out = tuple(map(_one, args))
    return None if None in out else out


def dispatch_print(args: tuple) -> tuple | None:
    """:func:`call_print` for numba's dispatch (:class:`pounding.compiler._Entries`): also a tuple of
    the laws' kernels (:class:`pounding.compiler.unroll.LawTuple`) and a compiled function, by identity
    (each held for the process, so that its identity is not reused: a run's laws and compiled
    functions are a handful, and a law tuple is one per set of kernels), inside plain tuples too;
    None if any argument is of another kind."""
    out = tuple(map(_dispatched, args))
    return None if None in out else out


_held: dict = {}  # id -> an object fingerprinted by identity (dispatch_print)


def _dispatched(x):
    f = _FAST.get(type(x))
    if f is not None:
        return f(x)
    t = type(x)
    if t is tuple:
        parts = tuple(map(_dispatched, x))
        return None if None in parts else ("t", parts)
    if isinstance(x, tuple) and hasattr(t, "_fields"):
        return _bundle(x)
    if _by_identity(t):
        _held.setdefault(id(x), x)
        return ("id", id(x))
    return fingerprint(x)


def _by_identity(t) -> bool:
    """Whether numba types a value of type t by the value itself: a law tuple or a compiled function
    (their classes say so, ``typed_by_identity``: this module imports nothing of the compiler's), or
    numba's own dispatcher."""
    return getattr(t, "typed_by_identity", False) or t.__name__ == "CPUDispatcher"


def call_key(prints: tuple) -> tuple:
    """:func:`call_print`'s key for the arguments' full fingerprints (as recorded at build)."""
    return tuple(_token(p) if _is_bundle_print(p) else p for p in prints)


def _to_json(p):
    if isinstance(p, np.dtype):  # record dtypes too (the impact log): their fields, not '|V88'
        return {"dtype": np.lib.format.dtype_to_descr(p)}
    return [_to_json(v) for v in p] if isinstance(p, tuple) else p


def _descr(d):
    # JSON made the fields' tuples (name, format[, shape]) lists; numpy reads a field only as a tuple
    if isinstance(d, list):
        return [(f[0], _descr(f[1]), *(tuple(r) for r in f[2:])) for f in d]
    return d


def _from_json(p):
    if isinstance(p, dict):
        return np.lib.format.descr_to_dtype(_descr(p["dtype"]))
    return tuple(_from_json(v) for v in p) if isinstance(p, list) else p


# --------------------------------------------------------------------------- where
def folder() -> Path | None:
    """The module's folder for this version of the compiled modules (None: no writable cache);
    ``POUNDING_AOT_DIR`` names another (tests, benchmarks)."""
    from pounding.compiler.cache import cache_dir, cache_key

    if os.environ.get("POUNDING_AOT_DIR"):
        return Path(os.environ["POUNDING_AOT_DIR"])
    base = cache_dir()
    if base is None:
        return None
    return Path(base).parent / ("aot-" + cache_key())


_prefer = [False]  # the default when POUNDING_AOT is unset (prefer(): the pounding commands of one scene)


def prefer(on: bool) -> None:
    """Use the module by default in this process (``POUNDING_AOT``, when set, wins). The ``pounding``
    commands that run one scene call it: their process is short and its start is what the user
    waits for."""
    _prefer[0] = bool(on)


def enabled() -> bool:
    """Whether runs use the module: ``POUNDING_AOT=1`` or ``0`` when set, else :func:`prefer`'s choice,
    and compiled code is on. By default a program that imports pounding keeps numba's dispatch: a
    long process of many runs loads numba's cache once, and numba's checks of a call's argument
    types, in C, cost ~1 us less a call than :func:`call_print` (5-10 % of an in-process solve of the
    paper pair, benchmarks/results/compile.json)."""
    from pounding.compiler.cache import enabled as jit_enabled

    env = os.environ.get("POUNDING_AOT")
    on = _prefer[0] if env is None else env not in ("0", "")
    return on and jit_enabled()


def environment() -> dict:
    """What a module is valid for: the compiled source (its key), the manifest's format, the Python
    ABI, the numpy, numba and llvmlite it was built with (numba's code, numpy's C API) and the
    processor (it is compiled for this one). Read without importing numba or llvmlite."""
    import importlib.metadata as md
    import platform

    from pounding.compiler.cache import cache_key

    versions = {}
    for name in ("numpy", "numba", "llvmlite"):
        try:
            versions[name] = md.version(name)
        except md.PackageNotFoundError:  # pragma: no cover - an install without metadata
            versions[name] = None
    return {"format": FORMAT, "key": cache_key(), "python": sys.implementation.cache_tag, **versions,
            "machine": platform.machine(), "cpu": _cpu()}


def _cpu() -> str:
    """The processor's model and feature flags (Linux: /proc/cpuinfo's first entry), else platform's."""
    import hashlib
    import platform

    try:
        with open("/proc/cpuinfo") as fh:
            first = fh.read().split("\n\n", 1)[0]
        keep = [ln for ln in first.splitlines() if ln.split(":")[0].strip() in ("vendor_id", "model name", "flags", "Features", "CPU part")]
        return hashlib.sha1("\n".join(keep).encode()).hexdigest()[:16]
    except OSError:
        return platform.processor() or platform.machine()


def _module_file(where: Path) -> Path:
    import importlib.machinery

    return where / (MODULE + importlib.machinery.EXTENSION_SUFFIXES[0])


def _manifest(where: Path) -> dict | None:
    """The folder's manifest when it is valid for this process (:func:`environment`), else None."""
    try:
        m = json.loads((where / _MANIFEST).read_text())
    except (OSError, ValueError):
        return None
    return m if isinstance(m, dict) and m.get("environment") == environment() and _module_file(where).exists() else None


def _load():
    """Import the module and its manifest once per process (None when absent, invalid here, broken,
    or turned off: the runs then use numba)."""
    if "module" in _state:
        return _state["module"]
    _state["module"], _state["exports"] = None, {}
    where = folder() if enabled() else None
    if where is None:
        return None
    try:
        manifest = _manifest(where)
        if manifest is None:
            return None
        import importlib.util

        spec = importlib.util.spec_from_file_location(MODULE, str(_module_file(where)))
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        if getattr(module, "build_id", lambda: None)() != manifest["build"]:  # a manifest of another build
            return None
        exports: dict = {}
        for row in manifest["exports"]:
            exports.setdefault(row["kernel"], {})[call_key(_from_json(row["fingerprint"]))] = getattr(module, row["export"])
    except Exception:  # noqa: BLE001 - any broken build (a half-written manifest, a foreign file): numba as before
        return None
    _state["module"], _state["exports"] = module, exports
    return module


def lookup(kernel) -> dict | None:
    """The exports of a compiled function, {argument fingerprint: function}, or None."""
    if _load() is None:
        return None
    return _state["exports"].get(f"{kernel.__module__}.{kernel.__qualname__}")


