"""examples/contact_laws/run_laws.py: every contact law on the paper's pair, one table and three plots.

Run here over the first 3 s of the record (the first contacts are near 1.9 s), five runs of a few
tenths of a second each; the whole record is the example's own run (its README).
"""

from __future__ import annotations

import csv
import importlib.util
import math
import sys

import pytest

from conftest import EXAMPLES

SCRIPT = EXAMPLES / "contact_laws" / "run_laws.py"
DURATION = 3.0  # [s]


def _load():
    spec = importlib.util.spec_from_file_location("run_laws", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    pytest.importorskip("matplotlib")
    module = _load()
    out = tmp_path_factory.mktemp("contact_laws")
    return module, out, module.main(out, duration=DURATION)


def test_the_table_has_every_law_and_the_plots_are_written(example):
    """table.md and table.csv hold one row per law (in :data:`LAWS` order) with every column, each number
    finite; the three figures exist."""
    module, out, _ = example
    with open(out / "table.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == [h for h, _ in module.COLUMNS]
    assert [r[0] for r in rows[1:]] == list(module.LAWS)
    assert all(math.isfinite(float(x)) for r in rows[1:] for x in r[1:])
    md = (out / "table.md").read_text().splitlines()
    assert [line.split("|")[1].strip() for line in md[2:]] == list(module.LAWS)
    for name in ("top_displacement.png", "contact_force.png", "floor_acceleration.png"):
        assert (out / name).stat().st_size > 10_000


def test_every_law_pounds_and_the_dissipative_ones_take_energy_out(example):
    """Within 3 s every law makes contact with a positive peak force, in no more episodes than impacts, and the energy the dissipative laws'
    contacts take out of the buildings is > 0 (a passive contact never adds energy). The elastic hertz
    is left out: what its episodes report is the step's error on the work of a non-linear spring
    (the trapezoid of the force over each step), of either sign."""
    _, _, runs = example
    for r in runs:
        assert r.row["episodes"] >= 1 and r.row["impacts"] >= 1, r.law
        assert r.row["episodes"] <= r.row["impacts"], r.law  # an episode holds one impact or more
        assert r.row["force"] > 0.0, r.law
        if r.law != "hertz":
            assert r.row["energy"] > 0.0, r.law


def test_the_readme_table_has_the_scripts_columns_and_laws():
    """The example's README holds a table the script wrote (``--readme``): its header and one row per law."""
    module = _load()
    text = (EXAMPLES / "contact_laws" / "README.md").read_text()
    block = text.split(module.README_START)[1].split(module.README_END)[0].strip().splitlines()
    assert block[0] == "| " + " | ".join(h for h, _ in module.COLUMNS) + " |"
    assert [line.split("|")[1].strip() for line in block[2:]] == list(module.LAWS)
