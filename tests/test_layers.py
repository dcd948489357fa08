"""The package's layers, as pyproject.toml declares them ([tool.importlinter]): an import only goes down.

The layers, top to bottom: the command line; the warm-up and the commands; the studies; io; the
OpenSees peers; post-processing; the engine; the plugins (elements, solvers, contact, hysteresis);
the model; the compiler set-up; errors and words. docs/design.md says what each holds.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
needs_linter = pytest.mark.skipif(LINT is None, reason="import-linter is not installed (test extra)")


def _lint(root: Path) -> subprocess.CompletedProcess:
    """lint-imports on the package under ``root`` (that tree first on the import path), with its pyproject."""
    env = dict(os.environ, PYTHONPATH=str(root))
    return subprocess.run([LINT, "--config", str(root / "pyproject.toml"), "--no-cache"], cwd=str(root),
                          capture_output=True, text=True, env=env, timeout=300)


@needs_linter
def test_every_import_goes_down_the_declared_layers():
    """The package as it is keeps the layers contract."""
    proc = _lint(ROOT)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-2000:]
    assert "1 kept, 0 broken" in proc.stdout


@needs_linter
def test_an_upward_import_breaks_the_contract(tmp_path):
    """A copy of the package in which the model imports the engine fails the same check, naming
    the import: the test above would catch it."""
    shutil.copytree(ROOT / "pounding", tmp_path / "pounding", ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    units = tmp_path / "pounding" / "framework" / "model" / "units.py"
    units.write_text(units.read_text() + "\nfrom pounding.framework.engine import driver  # noqa: E402,F401 - upward\n")
    proc = _lint(tmp_path)
    assert proc.returncode != 0
    assert "pounding.framework.model is not allowed to import pounding.framework.engine" in proc.stdout
    assert "pounding.framework.model.units -> pounding.framework.engine.driver" in proc.stdout


def test_no_module_imports_itself_back():
    """No import cycle, not even through imports inside functions: the module graph has no strongly
    connected component of more than one module (grimp's graph of the package, the layers' own)."""
    grimp = pytest.importorskip("grimp")
    graph = grimp.build_graph("pounding", exclude_type_checking_imports=True)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.find_modules_directly_imported_by(v):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    for m in sorted(graph.modules):
        if m not in index:
            visit(m)
    assert cycles == []
