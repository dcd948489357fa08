"""The compiled core built ahead of time (pounding.aot): the same numbers without numba at run time.

The module is the one ``make test`` builds (``python -m pounding.aot``: the warm-up's job, which
runs the paper pair with pounding and covers the small job below), or where none is current, one
built for these tests from that small job (the paper pair's first 3 s with pounding: its stretches,
the impacts located and struck from 1.9 s on, chatter held, HHT's transitions and the true peaks),
into a folder of its own. What is asserted:
a run served by it gives the recorded states bit for bit as numba's code does and never imports
numba; a call whose argument types the module was not built for goes to numba and gives numba's
answer; a module is found only for the version of the source it was built from.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"

JOB = (
    "from pounding.io.scene import load_scene\n"
    "from pounding.framework.post.run import run\n"
    f"SCENE = load_scene({str(PAPER)!r}).with_analysis(duration=3.0)\n"
)


def _python(code: str, **env) -> str:
    full = dict(os.environ, **env)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=full, cwd=str(ROOT), timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    return p.stdout.strip().splitlines()[-1]


def _pycc_importable() -> bool:
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            import numba.pycc.platform  # noqa: F401 - needs distutils or setuptools
        except ImportError:
            return False
    return True


def _compiler_works() -> bool:
    if not _pycc_importable():
        return False
    from numba.pycc.platform import external_compiler_works

    return external_compiler_works()


def _installed() -> Path | None:
    """The module ``make`` built for this version of the source (``python -m pounding.aot``), when it
    is valid in this process; None otherwise."""
    from pounding.compiler.prebuilt import _manifest, folder

    where = folder() if not os.environ.get("POUNDING_AOT_DIR") else None
    return where if where is not None and where.is_dir() and _manifest(where) is not None else None


@pytest.fixture(scope="module")
def module(tmp_path_factory):
    """The module the runs below are served by: the one ``make test`` built beside numba's cache (its
    warm-up job covers the job's paper pair), or, where none is current, one built here from the
    job (about two minutes: pycc compiles every entry point again)."""
    installed = _installed()
    if installed is not None:
        return installed
    if not _compiler_works():
        pytest.skip("no working C compiler here: the module cannot be built (the runs use numba's cache)")
    where = tmp_path_factory.mktemp("aot") / "built"
    code = JOB + (
        "from pounding import aot\n"
        f"out = aot.build(quiet=True, out=__import__('pathlib').Path({str(where)!r}), job=lambda: run(SCENE))\n"
        "print(out)\n"
    )
    assert _python(code, POUNDING_AOT="0") == str(where)
    return where


RUN = JOB + (
    "import hashlib, json, sys\n"
    "r = run(SCENE)\n"
    "h = hashlib.sha256(r.q.tobytes() + r.qd.tobytes() + __import__('numpy').asarray(r.slab_peaks).tobytes()\n"
    "                   + repr([(i.time, i.pair, i.impulse) for i in r.impacts]).encode()).hexdigest()\n"
    "print(json.dumps({'digest': h, 'impacts': len(r.impacts), 'numba': 'numba' in sys.modules}))\n"
)


def test_a_run_served_by_the_module_is_numbas_to_the_bit_and_imports_no_numba(module):
    served = json.loads(_python(RUN, POUNDING_AOT="1", POUNDING_AOT_DIR=str(module)))
    jit = json.loads(_python(RUN, POUNDING_AOT="0"))
    assert served["digest"] == jit["digest"] and served["impacts"] == jit["impacts"] > 0
    assert served["numba"] is False and jit["numba"] is True


def test_a_call_of_other_argument_types_goes_to_numba(module):
    """HHT's transition with a strided omega (layout 'A', the module has 'C'): numba compiles it and
    gives the transition of the same modes passed contiguous."""
    code = (
        "import json, sys\n"
        "import numpy as np\n"
        "from pounding.solvers.newmark import alpha_transition\n"
        "omega = np.linspace(1.0, 60.0, 24)\n"
        "zeta = np.full(24, 0.05)\n"  # per mode and writable, as the driver's transition cache holds and passes it
        "args = (0.005, 0.2756, 0.55, 0.0, -0.05)\n"
        "A1, B1 = alpha_transition(omega, zeta, *args)\n"  # the module's types
        "before = 'numba' in sys.modules\n"
        "wide = np.zeros(48); wide[::2] = omega\n"
        "A2, B2 = alpha_transition(wide[::2], zeta, *args)\n"
        "print(json.dumps({'before': before, 'after': 'numba' in sys.modules, 'same': bool(np.array_equal(A1, A2) and np.array_equal(B1, B2))}))\n"
    )
    out = json.loads(_python(code, POUNDING_AOT="1", POUNDING_AOT_DIR=str(module)))
    assert out == {"before": False, "after": True, "same": True}


@pytest.mark.parametrize("field", ["key", "numba", "cpu"])
def test_a_module_built_for_another_source_library_or_processor_is_not_used(module, tmp_path, field):
    """The manifest names what the module is valid for (the compiled source's key, numba's version,
    the processor, ...): a mismatch in any leaves the run to numba, with numba's numbers."""
    import shutil

    copy = tmp_path / "other"
    shutil.copytree(module, copy)
    m = json.loads((copy / "manifest.json").read_text())
    m["environment"][field] = "something else"
    (copy / "manifest.json").write_text(json.dumps(m))
    served = json.loads(_python(RUN, POUNDING_AOT="1", POUNDING_AOT_DIR=str(copy)))
    jit = json.loads(_python(RUN, POUNDING_AOT="0"))
    assert served == jit and served["numba"] is True


def test_a_broken_manifest_leaves_the_run_to_numba(module, tmp_path):
    import shutil

    copy = tmp_path / "broken"
    shutil.copytree(module, copy)
    text = (copy / "manifest.json").read_text()
    (copy / "manifest.json").write_text(text[: len(text) // 2])
    served = json.loads(_python(RUN, POUNDING_AOT="1", POUNDING_AOT_DIR=str(copy)))
    assert served["numba"] is True and served["impacts"] > 0


def _build_cli(where, **env):
    full = dict(os.environ, POUNDING_AOT_DIR=str(where), **env)
    return subprocess.run([sys.executable, "-m", "pounding.aot"], capture_output=True, text=True, env=full, cwd=str(ROOT), timeout=600)


def test_without_a_c_compiler_the_build_says_so_in_one_line_and_succeeds(tmp_path):
    if not _pycc_importable():
        pytest.skip("numba's pycc cannot be imported here (no setuptools): the build stops before the compiler check")
    p = _build_cli(tmp_path / "none", CC="/nonexistent/cc")
    assert p.returncode == 0
    assert p.stderr.strip().splitlines() == ["pounding: no extension module built (no working C compiler, which numba's pycc "
                                             "needs); runs use numba's cache"]
    assert not (tmp_path / "none").exists()


def test_a_folder_holding_other_files_is_left_as_it_is(tmp_path):
    where = tmp_path / "mine"
    where.mkdir()
    (where / "precious.txt").write_text("a user's file")
    p = _build_cli(where)
    assert p.returncode == 0 and len(p.stderr.strip().splitlines()) == 1 and "holds other files" in p.stderr
    assert [f.name for f in where.iterdir()] == ["precious.txt"]


def test_equal_fingerprints_mean_equal_numba_types():
    """The property the check rests on, over arrays (dtypes with byte order and fields, dimensions,
    layouts, writability, alignment), scalars and bundles: wherever two fingerprints are equal,
    numba types the values alike; kinds numba types apart from their base (a masked array, an
    IntEnum, an int beyond int64) have no fingerprint (numba decides)."""
    import enum
    from collections import namedtuple

    from numba import typeof

    from pounding.compiler.prebuilt import fingerprint

    a = np.zeros((3, 4))
    ro = a.copy()
    ro.flags.writeable = False
    unaligned = np.frombuffer(bytearray(8 * 12 + 1), dtype=np.uint8)[1:].view(np.float64).reshape(3, 4)
    rec = np.zeros(3, dtype=[("t", "<f8"), ("p", "<i8")])
    P1 = namedtuple("P1", "x y")
    P2 = namedtuple("P2", "x z")
    values = [a, a.T, a[:, ::2], a.astype(np.int64), a[0], ro, unaligned, rec, rec.copy(),
              1.0, 2.5, 1, 7, True, np.True_, np.float64(1.0), np.int64(3), np.float32(1.0), None,
              P1(a, 1.0), P1(a.copy(), 2.0), P2(a, 1.0), P1(ro, 1.0), (a, 1), (a, 1.0)]
    prints = [fingerprint(v) for v in values]
    assert all(p is not None for p in prints)
    for v, p in zip(values, prints):
        for w, q in zip(values, prints):
            if p == q:
                assert typeof(v) == typeof(w), (v, w)

    class Kind(enum.IntEnum):
        A = 1

    for other in (np.ma.masked_array(a), Kind.A, 2**63, object()):
        assert fingerprint(other) is None
    assert fingerprint(a.astype(">f8")) != fingerprint(a)  # (numba takes only native byte order: it refuses this one)


def test_the_run_command_uses_the_module_unless_told_not_to(module, tmp_path):
    """`pounding run` of a scene the module was built for (the job's), POUNDING_AOT unset: no numba in
    the process, and the recorded states of a run with POUNDING_AOT=0 (numba) to the bit."""
    assert "restitution = 0.5" in PAPER.read_text()
    text = PAPER.read_text().replace("restitution = 0.5", "restitution = 0.5\nduration = 3.0")
    scene = tmp_path / "first_3_s.toml"
    scene.write_text(text)
    code = (
        "import json, sys\n"
        "from pounding.cli import main\n"
        f"code = main(['run', {str(scene)!r}, '--out', sys.argv[1], '--quiet'])\n"
        "print(json.dumps({'code': code, 'numba': 'numba' in sys.modules}))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "POUNDING_AOT"}
    out = {}
    for label, extra in (("module", {"POUNDING_AOT_DIR": str(module)}), ("numba", {"POUNDING_AOT": "0"})):
        p = subprocess.run([sys.executable, "-c", code, str(tmp_path / label)], capture_output=True, text=True,
                           env=dict(env, **extra), cwd=str(ROOT), timeout=600)
        assert p.returncode == 0, p.stderr[-2000:]
        out[label] = json.loads(p.stdout.strip().splitlines()[-1])
    assert out == {"module": {"code": 0, "numba": False}, "numba": {"code": 0, "numba": True}}
    a, b = np.load(tmp_path / "module" / "modal.npz"), np.load(tmp_path / "numba" / "modal.npz")
    assert sorted(a.files) == sorted(b.files) and all(np.array_equal(a[k], b[k]) for k in a.files)


def test_a_manifest_gives_back_the_dtypes_it_was_written_with():
    """Record dtypes (the impact log's), sub-arrays and nested records survive the manifest's JSON."""
    from pounding.compiler.prebuilt import _from_json, _to_json

    kinds = (np.dtype("<f8"), np.dtype("bool"), np.dtype(">i4"), np.dtype([("time", "<f8"), ("pair", "<i8")]),
             np.dtype([("a", "<f8", (2,)), ("b", [("c", "<i4")])]))
    for d in kinds:
        assert _from_json(json.loads(json.dumps(_to_json(("a", d, 1))))) == ("a", d, 1)
