"""The compiled core as an extension module built at install: no compiler, no numba, at run time.

numba's cache makes a second process skip compilation, but not numba itself: importing it and
loading each cached function's machine code costs a warm ``pounding run`` of the paper pair
~0.5 s over its work (each function carries its own copy of the polygon geometry it calls;
benchmarks/README.md). Built ahead of time (numba's ``pycc``) the same functions are one shared
library with the geometry once, 1.9 MB, and load with the process like any extension: the
whole ``pounding run`` takes 0.40 s against 0.86 s (``benchmarks/bench_compile.py``), with the
same numbers bit for bit (``tests/test_aot.py``).

How
---
:func:`build` runs the warm-up tasks in this process (:func:`pounding.compiler._warm_task`; they load
from numba's cache after the install-time warm-up) and records, for every compiled function called
from Python, the *fingerprint* of its arguments (:func:`fingerprint`: array dtype, dimensions,
layout, writability and alignment, scalar kinds, the structure of the bundles) with the numba signature it
was compiled for. Each (function, fingerprint) becomes one export of the module ``pounding_core``,
written with a manifest into ``aot-<key>`` beside numba's cache folder, ``<key>`` the digest of
the compiled modules' source (:func:`pounding.compiler.cache_key`). The manifest names what the
module is valid for (:func:`environment`: that key, the Python ABI, the numpy, numba and llvmlite
versions, the processor) and the build it belongs to; a module is loaded only where all of them
match, so an edited source, an upgraded library or another machine never runs an old module.

At run time a compiled function's first call looks for its export (:func:`lookup`). A call whose
arguments have a fingerprint the module was built for runs the export; any other call (another
scene's types, a function the warm-up did not call) goes to numba as before. The fingerprint check
is what makes this safe: the module's argument conversion checks only an array's item size, so a
call with the wrong layout would read wrong memory.

Who uses it: ``POUNDING_AOT=1`` turns it on, ``0`` off. Unset, the ``pounding`` commands that run
one scene (``run``, ``gap``, ``check``, ``demo``, ...) use it (:func:`prefer`): their process is short
and its start is what the user waits for. Unset, a program that imports pounding, and ``pounding sweep`` /
``pounding fragility``, keep numba's dispatch (see :func:`enabled`).

Building needs a C compiler (``pycc`` compiles a small C wrapper); without one :func:`build` says
so in one line and the runs use numba's cache as before.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np

#: name of the extension module
MODULE = "pounding_core"
#: the manifest's format (a build of another format is not loaded)
FORMAT = 2
_MANIFEST = "manifest.json"
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
    if isinstance(x, tuple) and hasattr(t, "_fields"):  # a named bundle (pounding.framework.bundles)
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
    # (pounding.framework.bundles): their arrays are filled in place, never reshaped, re-typed or
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
    from pounding.compiler import cache_dir, cache_key

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
    from pounding.compiler import enabled as jit_enabled

    env = os.environ.get("POUNDING_AOT")
    on = _prefer[0] if env is None else env not in ("0", "")
    return on and jit_enabled()


def environment() -> dict:
    """What a module is valid for: the compiled source (its key), the manifest's format, the Python
    ABI, the numpy, numba and llvmlite it was built with (numba's code, numpy's C API) and the
    processor (it is compiled for this one). Read without importing numba or llvmlite."""
    import importlib.metadata as md
    import platform

    from pounding.compiler import cache_key

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


# --------------------------------------------------------------------------- build
def _ours(where: Path) -> bool:
    """Whether a folder holds only what a build writes (it may then be replaced)."""
    return all(f.name == _MANIFEST or f.name.startswith(MODULE + ".") for f in where.iterdir())


def _export_name(kernel, fp) -> str:
    # named by what it is, not by build order: a manifest and a module of two builds cannot pair
    # one function's fingerprint with another's entry
    import hashlib

    text = f"{kernel.__module__}.{kernel.__qualname__}|" + json.dumps(_to_json(fp))
    return f"{kernel.__name__}_{hashlib.sha1(text.encode()).hexdigest()[:16]}"


def _constant(value: str):
    """A function returning ``value`` (numba compiles a closure's variable as a constant)."""
    def build_id():
        return value

    return build_id


def _no_module(say, why: str) -> None:
    say(f"pounding: no extension module built ({why}); runs use numba's cache")


def build(*, quiet: bool = False, out: Path | None = None, job=None) -> Path | None:
    """Build the module for the warm-up's calls into :func:`folder` (or ``out``): the folder, or None
    with one line on stderr when it cannot be built here (no C compiler, a folder holding other
    files, any failure); nothing is left behind then. Runs the warm-up tasks in this process first
    (or ``job()``, whose calls are then the module's)."""
    import shutil
    import tempfile
    import time
    import uuid

    from pounding import compiler

    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    target = out or folder()
    if target is None or not compiler.enabled():
        return None
    target = Path(target)
    if target.exists() and (not target.is_dir() or not _ours(target)):
        _no_module(say, f"{target} holds other files; it is left as it is")
        return None
    t0 = time.perf_counter()
    tmp = Path(tempfile.mkdtemp(prefix="pounding-aot-"))
    staged = None
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from numba.pycc import CC
            from numba.pycc.platform import external_compiler_works

            if not external_compiler_works():
                _no_module(say, "no working C compiler, which numba's pycc needs")
                return None
            _state.update(module=None, exports={})  # record numba's own signatures, whatever is built already
            calls = record(job or (lambda: [compiler._warm_task(name) for name in compiler.WARM_TASKS]))
            cc = CC(MODULE)
            cc.output_dir = str(tmp)
            # for this machine's processor, as numba's JIT compiles (built here at install, used here:
            # the manifest's environment names the processor)
            from llvmlite import binding as llvm

            cc.target_cpu = llvm.get_host_cpu_name()
            build_id = uuid.uuid4().hex
            cc.export("build_id", "unicode_type()")(_constant(build_id))
            rows = []
            for kernel, fp, sig in calls:
                name = _export_name(kernel, fp)
                cc.export(name, sig)(kernel.py_func)
                rows.append({"kernel": f"{kernel.__module__}.{kernel.__qualname__}", "export": name,
                             "fingerprint": _to_json(fp), "signature": str(sig)})
            say(f"pounding: building the compiled core as an extension module ({len(rows)} entry points) ...")
            cc.compile()
        manifest = {"environment": environment(), "build": build_id, "exports": rows, "seconds": time.perf_counter() - t0}
        (tmp / _MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n")
        staged = target.with_name(f"{target.name}.{os.getpid()}.tmp")
        shutil.copytree(tmp, staged)
        os.chmod(staged, 0o755)  # (mkdtemp's folder is private)
        if target.exists():  # an earlier build (only our files, checked above): replaced whole
            old = target.with_name(f"{target.name}.{os.getpid()}.old")
            os.replace(target, old)
            os.replace(staged, target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(staged, target)
        staged = None
    except Exception as exc:  # noqa: BLE001 - a build that fails leaves numba's cache to serve the runs
        text = str(exc).strip().splitlines()
        _no_module(say, f"{type(exc).__name__}: {text[-1][:200] if text else ''}")
        return None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        if staged is not None:
            shutil.rmtree(staged, ignore_errors=True)
    _state.clear()
    say(f"pounding: extension module built in {time.perf_counter() - t0:.1f} s")
    return target


def record(job) -> list:
    """Run ``job()`` with every call of a compiled function from Python recorded: the list of
    (kernel, argument fingerprint, numba signature), one row per distinct fingerprint."""
    from pounding import compiler

    seen: dict = {}
    original = compiler.Kernel.__call__

    def recording(self, *args):
        out = original(self, *args)
        fp = tuple(fingerprint(a) for a in args)
        if None not in fp and (self, fp) not in seen and self._dispatcher is not None:
            from numba import typeof

            types = tuple(typeof(a) for a in args)
            sig = next((s for s in self._dispatcher.signatures if tuple(s) == types), None)
            if sig is not None:
                seen[(self, fp)] = self._dispatcher.overloads[sig].signature
        return out

    compiler.Kernel.__call__ = recording
    try:
        job()
    finally:
        compiler.Kernel.__call__ = original
    return [(k, fp, sig) for (k, fp), sig in seen.items()]


def _main(argv=None) -> int:
    import argparse

    ap = argparse.ArgumentParser(prog="python -m pounding.aot", description="Build the compiled core as an extension (after the warm-up).")
    ap.add_argument("--if-needed", action="store_true", help="do nothing when this version is built")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    where = folder()
    if args.if_needed and where is not None and _manifest(where) is not None:
        return 0
    build(quiet=args.quiet)
    return 0  # not building is not an error: the runs use numba's cache


if __name__ == "__main__":
    from pounding.aot import _main as _package_main

    raise SystemExit(_package_main())
