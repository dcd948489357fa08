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
:func:`build` runs the warm-up tasks in this process (:func:`pounding.warmup._warm_task`; they load
from numba's cache after the install-time warm-up) and records, for every compiled function called
from Python, the *fingerprint* of its arguments (:func:`fingerprint`: array dtype, dimensions,
layout, writability and alignment, scalar kinds, the structure of the bundles) with the numba signature it
was compiled for. Each (function, fingerprint) becomes one export of the module ``pounding_core``,
written with a manifest into ``aot-<key>`` beside numba's cache folder, ``<key>`` the digest of
the compiled modules' source (:func:`pounding.compiler.cache_key`). The manifest names what the
module is valid for (:func:`environment`: that key, the Python ABI, the numpy, numba and llvmlite
versions, the processor) and the build it belongs to; a module is loaded only where all of them
match, so an edited source, an upgraded library or another machine never runs an old module.

At run time a compiled function's first call loads its export through :mod:`pounding.compiler.prebuilt`,
which says when the module is used and why a call's fingerprint makes that safe.

Building needs a C compiler (``pycc`` compiles a small C wrapper); without one :func:`build` says
so in one line and the runs use numba's cache as before.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path


from pounding import compiler, warmup
from pounding.compiler.prebuilt import MODULE, _MANIFEST, _manifest, _state, _to_json, environment, fingerprint, folder


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
            calls = record(job or (lambda: [warmup._warm_task(name) for name in warmup.WARM_TASKS]))
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
