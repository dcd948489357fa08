"""The declared interface to the compiled core: what is compiled, when, and its cache key.

Each test states one property of :mod:`pounding.compiler` and the driver's use of it.
Timings are measured in ``benchmarks/bench_compile.py``, never asserted here.
"""

from __future__ import annotations

import importlib
import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding import compiler, warmup
from pounding.compiler import cache
from pounding.compiler.unroll import kernel_tuple, unrolled_in

PAPER = Path(__file__).resolve().parents[1] / "examples" / "paper" / "pair_gap_0.03.toml"
COMPILED_PACKAGES = ("pounding.contact.geometry", "pounding.contact.base", "pounding.framework.engine.pairs",
                     "pounding.framework.engine.kernel", "pounding.framework.engine.held")

needs_numba = pytest.mark.skipif(not compiler.enabled(), reason="numba is not compiling here (missing or NUMBA_DISABLE_JIT)")


def _python(code: str, env: dict | None = None, timeout: float = 900) -> dict:
    """Run ``code`` in a fresh interpreter; it prints one JSON object, returned."""
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                         env={**os.environ, **(env or {})}, timeout=timeout)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_cache_key_covers_every_compiled_module():
    """numba keys a cached function on its own file only, so the cache folder is keyed on every
    module that declares compiled functions: every module holding a compiled function (after
    importing all of them) is among the scanned ``compiled_modules()``."""
    for name in COMPILED_PACKAGES:
        importlib.import_module(name)
    scanned = {str(p) for p in compiler.compiled_modules()}
    # only the package's own modules (a test's plugin law is not ours; the cache folder under
    # __pycache__ is not source)
    root = Path(compiler.PACKAGE_ROOT).resolve()
    declaring = {Path(sys.modules[k.__module__].__file__).resolve() for k in compiler.kernels()}
    declaring = {str(p) for p in declaring if root in p.parents and "__pycache__" not in p.parts}
    if compiler.enabled():
        assert declaring, "no compiled function declared"
    assert declaring <= scanned, sorted(declaring - scanned)


def test_cache_key_changes_with_a_compiled_module(tmp_path, monkeypatch):
    """The key is a digest of the compiled modules' source: editing one changes it."""
    root = tmp_path / "pkg"
    root.mkdir()
    (root / "a.py").write_text("@njit\ndef f(x):\n    return x\n")
    (root / "b.py").write_text("def g(x):\n    return x\n")
    monkeypatch.setattr(cache, "PACKAGE_ROOT", root)
    assert [p.name for p in cache.compiled_modules()] == ["a.py"]
    k0 = cache.cache_key()
    (root / "b.py").write_text("def g(x):\n    return 2 * x\n")
    assert cache.cache_key() == k0  # not a compiled module
    (root / "a.py").write_text("@njit\ndef f(x):\n    return 2 * x\n")
    assert cache.cache_key() != k0


def test_cache_key_ignores_files_written_into_the_cache(tmp_path, monkeypatch):
    """Files written into the cache folder (a .py among them) do not change the key: a run must not
    send the next process to a new, empty cache."""
    root = tmp_path / "pkg"
    root.mkdir()
    (root / "a.py").write_text("@njit\ndef f(x):\n    return x\n")
    monkeypatch.setattr(cache, "PACKAGE_ROOT", root)
    k0 = cache.cache_key()
    written = root / "__pycache__" / ("numba-" + k0) / "framework"
    written.mkdir(parents=True)
    (written / "stray.py").write_text("@njit\ndef stretch(x):\n    return x\n")
    assert cache.cache_key() == k0


def _cache_folder(base, name, files, age_s):
    """A cache folder ``base/name`` holding ``files`` (relative paths), last changed ``age_s`` ago."""
    import os
    import time

    folder = base / name
    for rel in files:
        path = folder / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b"x" * 100)
    stamp = time.time() - age_s
    for path in [folder, *folder.rglob("*")]:
        os.utime(path, (stamp, stamp))
    return folder


def test_only_the_caches_of_earlier_versions_that_the_package_wrote_are_stale(tmp_path):
    """A warm-up removes the cache folders of earlier versions of the compiled modules (about 80 MB
    each): numba's and the extension module's, named by another key, holding only what they write
    and idle for a while. The current version's folder, a folder holding anything else (a user's
    file), one changed recently (a process of the earlier version may still be running) and any
    other name are kept."""
    key, old = "0123456789ab", 3600.0
    keep = [
        _cache_folder(tmp_path, "numba-" + key, ["engine_1/f.nbi"], old),
        _cache_folder(tmp_path, "numba-bbbbbbbbbbbb", ["engine_1/f.nbi", "notes.txt"], old),
        _cache_folder(tmp_path, "numba-cccccccccccc", ["engine_1/f.nbi", "engine_1/f.nbc"], 10.0),
        _cache_folder(tmp_path, "numba-old", ["engine_1/f.nbi"], old),
        _cache_folder(tmp_path, "other-aaaaaaaaaaaa", ["engine_1/f.nbi"], old),
    ]
    stale = [
        _cache_folder(tmp_path, "aot-dddddddddddd", ["manifest.json", "pounding_core.cpython-311-x86_64-linux-gnu.so"], old),
        _cache_folder(tmp_path, "numba-aaaaaaaaaaaa", ["engine_1/f.nbi", "engine_1/f.nbc", "warmed.json"], old),
    ]
    assert cache.PRUNE_AFTER_S < old
    assert cache.stale_folders(tmp_path, key) == sorted(stale)
    assert all(folder.exists() for folder in keep + stale)  # finding them removes nothing


def test_pruning_removes_the_stale_folders_beside_the_package_only(tmp_path, monkeypatch):
    """:func:`~pounding.compiler.cache.prune_stale` removes exactly the stale folders beside the package
    (this install's earlier versions, a half-written numba file among them) and counts their bytes; the
    user's cache, shared by every install of the user, keeps its folders (other versions still in use)."""
    key = "0123456789ab"
    monkeypatch.setattr(cache, "cache_key", lambda: key)
    monkeypatch.setattr(cache, "cache_bases", lambda: (tmp_path / "package", tmp_path / "user"))
    current = _cache_folder(tmp_path / "package", "numba-" + key, ["engine_1/f.nbi"], 3600.0)
    old = _cache_folder(tmp_path / "package", "numba-aaaaaaaaaaaa", ["engine_1/f.nbi", "engine_1/f.nbc.tmp.1f2e"], 3600.0)
    old_aot = _cache_folder(tmp_path / "package", "aot-aaaaaaaaaaaa", ["manifest.json"], 3600.0)
    shared = _cache_folder(tmp_path / "user", "aot-bbbbbbbbbbbb", ["manifest.json"], 3600.0)
    assert cache.prune_stale() == (2, 300)
    assert current.exists() and shared.exists() and not old.exists() and not old_aot.exists()


def test_loading_a_scene_and_info_import_no_numba():
    """Loading a scene (with its rest-gap check) and assembling its buildings for ``pounding info``
    import no numba and compile nothing: the rest gaps run interpreted."""
    code = (
        "import sys, json\n"
        "from pounding.io.scene import load_scene\n"
        "from pounding.framework.model.assembly import assemble\n"
        "from pounding.framework.model.modal import modal_summary\n"
        f"s = load_scene({str(PAPER)!r})\n"
        "[modal_summary(assemble(b), 6) for b in s.buildings]\n"
        "print(json.dumps({'numba': 'numba' in sys.modules}))\n"
    )
    assert _python(code) == {"numba": False}


@needs_numba
def test_contact_off_loads_no_contact_code():
    """With contact "none" the run uses the free stretch only: no function of the geometry,
    the pair queries, the contact laws or the held stretch is compiled or loaded."""
    code = (
        "import json\n"
        "from pounding import compiler\n"
        "from pounding.io.scene import load_scene\n"
        "from pounding.framework.post.run import run\n"
        f"r = run(load_scene({str(PAPER)!r}).with_analysis(contact='none', contact_params={{}}, duration=2.0))\n"
        "print(json.dumps({k.__module__ + '.' + k.__name__: len(k.signatures) for k in compiler.kernels() if k.signatures}))\n"
    )
    used = _python(code)
    assert "pounding.framework.engine.kernel.advance_free" in used
    contact = [name for name in used if name.startswith(("pounding.contact.", "pounding.framework.engine.pairs", "pounding.framework.engine.held"))]
    assert contact == []


@needs_numba
def test_one_specialization_per_compiled_function():
    """Every call site gives a compiled function the same argument types, so a run compiles each
    function once: after the paper pair with pounding (impacts, located events, held pairs),
    with its named integrator and with ``exact`` (its one-off maps for the impact search, the
    split steps' energy and the true peaks), every dispatcher holds a single signature. A process
    that finds the package's cache filled compiles nothing: every function comes from the cache (a
    compiled function called from Python outside the cached entry points would compile each time).
    On the cache ``make test`` warmed that is the first process; on a cold cache the first fills
    it and a second one is asked. (Loaded or compiled, a dispatcher gains one signature per
    distinct argument typing, so the count is the same either way.)"""
    code = (
        "import json\n"
        "from pounding import compiler\n"
        "from numba.core import event\n"
        "seen = []\n"
        "class L(event.Listener):\n"
        "    def on_start(self, ev): seen.append(ev.data['dispatcher'].py_func.__name__)\n"
        "    def on_end(self, ev): pass\n"
        "event.register('numba:compile', L())\n"
        "from pounding.io.scene import load_scene\n"
        "from pounding.framework.post.run import run\n"
        f"run(load_scene({str(PAPER)!r}).with_analysis(integrator='exact', integrator_params={{}}, duration=3.0))\n"
        f"r = run(load_scene({str(PAPER)!r}).with_analysis(duration=3.0))\n"
        "sigs = {k.__module__ + '.' + k.__name__: [str(s) for s in k.signatures] for k in compiler.kernels() if k.signatures}\n"
        "print(json.dumps({'impacts': r.n_impacts, 'sigs': sigs, 'compiled': seen}))\n"
    )
    env = {"POUNDING_AOT": "0"}  # numba's dispatchers, not the extension module
    out = _python(code, env=env)
    assert out["impacts"] > 0
    assert "pounding.framework.engine.free_stretch.advance" in out["sigs"]
    many = {name: s for name, s in out["sigs"].items() if len(s) > 1}
    assert many == {}
    if out["compiled"]:  # a cold cache: this process filled it
        out = _python(code, env=env)
    assert out["compiled"] == []


def test_kernel_and_python_path_log_the_same_impact_records():
    """The kernel (kernel.impulses_at) and the driver's Python path apply the same Newton
    impulses and log the same :data:`IMPACT_DTYPE` records: the first 3 s of the paper pair,
    with the kernel and step by step in Python, give the same impacts. The paths differ in the
    rounding of W w^T products (numba against numpy, 1e-16 relative), so the agreement is to
    rounding (1e-12 of the peak)."""
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene

    scene = load_scene(PAPER).with_analysis(duration=3.0)
    a, b = run(scene), run(scene, use_kernel=False)
    assert a.n_impacts == b.n_impacts > 0
    for x, y in zip(a.impacts, b.impacts):
        assert (x.pair, x.striker, x.vertex) == (y.pair, y.striker, y.vertex)
        assert abs(x.time - y.time) <= 1e-12 * max(1.0, x.time)
        assert abs(x.impulse - y.impulse) <= 1e-12 * max(abs(i.impulse) for i in a.impacts)
    assert np.abs(a.q - b.q).max() <= 1e-12 * np.abs(a.q).max()


@needs_numba
def test_first_compilation_is_announced_and_timed(tmp_path):
    """A compilation (not a cache load) runs the registered first-compile callbacks once, before
    it starts, and adds its wall time to compile_seconds(): what the command line uses to say
    it is compiling and to report the compile time apart from the solve. (A fresh interpreter
    and an empty cache, so that the function is compiled, not loaded.)"""
    code = (
        "import json\n"
        "from pounding import compiler\n"
        "calls = []\n"
        "compiler.on_first_compile(lambda: calls.append(compiler.compile_seconds()))\n"
        "def plus_one(x):\n"
        "    return x + 1.0\n"
        "f = compiler.njit(plus_one)\n"
        "print(json.dumps({'values': [f(1.0), f(2.0)], 'calls': calls, 'seconds': compiler.compile_seconds()}))\n"
    )
    script = tmp_path / "plus_one.py"  # numba caches functions that have a source file
    script.write_text(code)
    out = _python(f"import runpy; runpy.run_path({str(script)!r}, run_name='__main__')", env={"NUMBA_CACHE_DIR": str(tmp_path / "numba")})
    assert out["values"] == [2.0, 3.0]
    assert out["calls"] == [0.0]  # once, before anything was compiled
    assert out["seconds"] > 0.0


def test_summary_separates_the_solve_from_loading_and_compiling(tmp_path):
    """summary.json keeps runtime_s as the solve and reports loading and compiling apart."""
    from pounding.framework.post.run import run
    from pounding.io.results import write_results
    from pounding.io.scene import load_scene

    r = run(load_scene(PAPER).with_analysis(duration=1.0))
    write_results(r, tmp_path / "out", PAPER.read_text(), scene_path=PAPER)
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["timings_s"]["solve"] == s["runtime_s"] == r.runtime_s
    assert s["timings_s"]["load_and_compile"] >= s["timings_s"]["compile"] >= 0.0


YIELDING = PAPER.parents[1] / "inelastic_pair" / "pair_yielding_gap_0.03.toml"
LINKED = PAPER.parents[1] / "linked_pair" / "pair_viscous.toml"


@needs_numba
def test_install_warm_up_covers_the_runs_with_one_specialization_each():
    """The install-time warm-up (``python -m pounding.warmup --warm``) prepares what the runs it is
    for call from Python (the paper pair with pounding, with contact off and with a force law, the
    paper pair with yielding storeys, without and with a force law, and the paper pair linked by viscous dampers) with the very signatures those runs use: each run gives
    every compiled function one signature, and every one of them is among the warm-up's. The
    warm-up's own calls from Python (the ``shared`` task, which compiles inner functions ahead for
    the other process) add no specialization that no run uses: a function the warm-up holds with
    more than one signature (the stretch's two stopping rules, crossing and contact tolerance) has
    each of them used by a run. (Fresh processes on the package's cache: once the cache is warm
    they load machine code and compile nothing. Which inner functions a second process then loads
    rather than compiles is shown by ``NUMBA_DEBUG_CACHE=1``, see benchmarks/README.md.)"""
    # a signature names the laws' compiled functions it takes by their address in the process: drop it
    sigs = ("import re\nprint(json.dumps({k.__module__ + '.' + k.__name__: sorted(re.sub(' at 0x[0-9a-f]+', '', str(s)) "
            "for s in k.signatures) for k in compiler.kernels() if k.signatures}))\n")
    env = {"POUNDING_AOT": "0"}  # numba's dispatchers, not the extension module
    warm_up = ("import json, warnings\nwarnings.simplefilter('ignore')\nfrom pounding import compiler, warmup\n"
               + "".join(f"warmup._warm_task({t!r})\n" for t in warmup.WARM_TASKS) + sigs)
    # on a cold cache the warm-up compiles the inner functions too, each with every signature its callers
    # give it, where a process on the warm cache loads them with their callers: the warm-up's own
    # signatures are those of a second process, as the runs' are (the first warms the cache)
    _python(warm_up, env=env)
    warmed = _python(warm_up, env=env)
    runs = {"impulse": (PAPER, "contact='impulse'"), "none": (PAPER, "contact='none', contact_params={}"),
            "kelvin": (PAPER, "contact='kelvin', contact_params={}, duration=5.0"), "yielding": (YIELDING, "duration=5.0"),
            "linked": (LINKED, "duration=5.0"),
            **{f"yielding {law}": (YIELDING, f"contact={law!r}, contact_params={{}}, duration=5.0") for law in ("kelvin", "penalty")}}
    used_by_some: dict[str, set] = {}
    for what, (scene, change) in runs.items():
        used = _python("import json, warnings\nwarnings.simplefilter('ignore')\nfrom pounding import compiler\n"
                       "from pounding.framework.post.run import run\nfrom pounding.io.scene import load_scene\n"
                       f"run(load_scene({str(scene)!r}).with_analysis({change}))\n" + sigs, env=env)
        assert {name: s for name, s in used.items() if len(s) != 1} == {}, what
        assert {name: s for name, s in used.items() if not set(s) <= set(warmed.get(name, ()))} == {}, what
        for name, s in used.items():
            used_by_some.setdefault(name, set()).update(s)
    assert {name: s for name, s in warmed.items() if len(s) > 1 and not set(s) <= used_by_some.get(name, set())} == {}


def test_warm_up_if_needed_returns_at_once_when_marked(tmp_path, monkeypatch):
    """``--warm --if-needed`` (what ``make demo`` and ``make test`` run every time) starts no
    process when this version of the compiled modules was already warmed."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(warmup, "enabled", lambda: True)
    (tmp_path / "pounding-warmed.json").write_text("{}\n")
    monkeypatch.setattr(subprocess, "Popen", lambda *a, **k: pytest.fail("a warm-up process was started"))
    assert warmup.warm(if_needed=True, quiet=True)["skipped"] is True


@needs_numba
def test_borrowed_functions_compile_without_reference_counts_and_cannot_allocate():
    """@njit(borrowed=True): numba's reference counts off (_nrt=False), and the promise that keeps
    that safe, no array allocated or returned, checked by numba when it types the function."""
    import numba

    from pounding.framework.engine import spring_core

    assert spring_core.solve_group.borrowed
    assert spring_core.solve_group.dispatcher.targetoptions["_nrt"] is False
    assert not spring_core.stretch.borrowed  # it allocates its work buffers

    def allocates(n):
        return np.empty(n)[0]

    with pytest.raises(numba.core.errors.TypingError):
        numba.njit(_nrt=False)(allocates)(3)


unrolled_in(globals())  # numba's type of a law tuple (kernel_tuple), as a module whose compiled code takes laws registers it


@compiler.njit
def _total(a):
    return a.sum()


@compiler.njit
def _scaled_total(pair):
    a, k = pair
    return k * a.sum()


@compiler.njit
def _twice(x):
    return 2.0 * x


@compiler.njit
def _thrice(x):
    return 3.0 * x


@compiler.njit
def _call_with(f, x):
    return f(x)


@compiler.njit
def _first_of(laws, x):
    return laws[0](x)


@needs_numba
def test_calls_passing_tuples_run_the_machine_code_numba_chose_for_their_argument_types():
    """A compiled function called from Python with a plain tuple, a law tuple or a compiled function
    (which numba types slowly at every call) runs, for each fingerprint of its arguments, the machine
    code numba's dispatcher chose for their types (pounding.compiler._Entries): a C-ordered array, a
    read-only copy, a strided view and a Fortran-ordered one inside the tuple are four numba types and
    get four entries, each call summing its own array (integers: exact); compiled functions and law
    tuples passed as arguments are told apart by identity, each call running its own law. A function
    called with arrays alone keeps numba's own dispatch (faster there)."""
    a = np.arange(12.0).reshape(3, 4)
    ro = a.copy()
    ro.flags.writeable = False
    views = (a, ro, a[:, ::2], a.T)
    for v in views + views:  # the second round runs the kept entries
        assert _scaled_total((v, 2.0)) == 2.0 * v.sum()
    assert len(_scaled_total._call.entries) == 4
    assert [_call_with(f, 1.5) for f in (_twice, _thrice, _twice)] == [3.0, 4.5, 3.0]
    assert [_first_of(kernel_tuple((f,)), 2.0) for f in (_thrice, _twice, _thrice)] == [6.0, 4.0, 6.0]
    assert len(_call_with._call.entries) == 2 and len(_first_of._call.entries) == 2
    assert _total(a) == a.sum() and not isinstance(_total._call, compiler._Entries)


@needs_numba
def test_a_compiled_function_that_ran_still_pickles_as_numbas_cache_pickles_it():
    """numba's cache pickles a compiled function by value when one defined outside an importable
    module names it (a plugin's maps calling the package's ``alpha_transition``): after calls, with
    machine code kept per argument fingerprint, a compiled function still pickles, and the copy runs."""
    from numba.core import serialize

    assert _total(np.arange(4.0)) == 6.0
    copy = pickle.loads(serialize.dumps(_total))
    assert copy(np.arange(5.0)) == 10.0
