"""examples/linked_pair/run_linked.py: the paper's pair unlinked, linked by dampers and tied, one table and four plots.

Run here over the first 3 s of the record (the unlinked pair first pounds near 1.9 s), four runs of a
few hundredths of a second each; the whole record is the example's own run (its README).
"""

from __future__ import annotations

import csv
import importlib.util
import math
import sys

import numpy as np
import pytest

from conftest import EXAMPLES

SCRIPT = EXAMPLES / "linked_pair" / "run_linked.py"
DURATION = 3.0  # [s]
EPS = np.finfo(float).eps


def _load():
    spec = importlib.util.spec_from_file_location("run_linked", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    pytest.importorskip("matplotlib")
    module = _load()
    out = tmp_path_factory.mktemp("linked_pair")
    return module, out, module.main(out, duration=DURATION)


def test_the_table_has_every_scene_and_the_plots_are_written(example):
    """table.csv holds one row per scene (in :data:`SCENES` order) with every column, each number finite
    and equal to the run's row at full precision; table.md has the same scenes; the four figures exist."""
    module, out, runs = example
    with open(out / "table.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0] == [h for h, _ in module.COLUMNS]
    assert [r[0] for r in rows[1:]] == list(module.SCENES)
    for written, r in zip(rows[1:], runs):
        assert all(math.isfinite(float(x)) for x in written[1:])
        assert [float(x) for x in written[1:]] == [float(r.row[k]) for _, k in module.COLUMNS[1:]]
    md = (out / "table.md").read_text().splitlines()
    assert [line.split("|")[1].strip() for line in md[2:]] == list(module.SCENES)
    for name in ("top_displacement.png", "drift_profile.png", "acceleration_profile.png", "damper_loop.png"):
        assert (out / name).stat().st_size > 10_000


def test_the_tables_numbers_are_the_runs_own(example):
    """Each row reads its run: the impacts are the run's ``n_impacts``; the top displacement the peak
    |x| of the top slab's centre over the continuous trajectory (summary.json's ``peak_u``), which is at
    least the largest recorded step end's and exceeds it by at most a h^2 / 8 (a parabola through its
    peak seen half a step away), a <= peak absolute floor acceleration + PGA the relative acceleration;
    a link's peak force is the largest |force| of the links' recorded histories, its stroke the largest
    |deformation|, and the energy the sum of the links' final cumulative dissipation."""
    _, _, runs = example
    for r in runs:
        res = r.result
        assert r.row["impacts"] == res.n_impacts, r.key
        pga = float(np.max(np.abs(res.scene.ground_motion.acc)))  # [m/s2]
        for name in ("low", "high"):
            b = r.summary["buildings"][name]
            top = 1e3 * np.max(np.abs(res.cm(name)[:, -1, 0]))
            a = max(b["peak_floor_acceleration"]) + pga
            assert r.row[f"top_{name}"] == 1e3 * b["peak_u"][-1], (r.key, name)
            assert top * (1 - 4 * EPS) <= r.row[f"top_{name}"] <= top + 1e3 * a * res.dt**2 / 8, (r.key, name)
        force = max((np.max(np.abs(rec["force"])) for rec in res.links.values()), default=0.0)
        stroke = max((np.max(np.abs(rec["deformation"])) for rec in res.links.values()), default=0.0)
        energy = sum(rec["dissipated"][-1] for rec in res.links.values())
        assert r.row["link_force"] == force / 1e3, r.key
        assert r.row["link_stroke"] == stroke * 1e3, r.key
        assert r.row["link_energy"] == pytest.approx(energy / 1e3, rel=4 * EPS, abs=0.0), r.key


def test_the_unlinked_pair_pounds_and_every_link_is_passive(example):
    """Within 3 s the unlinked pair pounds; the dampers dissipate energy at every step (their
    cumulative dissipation never falls and ends > 0) while the elastic ties dissipate none; every
    run's energy account closes (the links' work on the buildings is what they dissipate and store)."""
    from pounding.framework.post.energy_account import energy_balance

    _, _, runs = example
    by = {r.key: r for r in runs}
    assert by["unlinked"].row["impacts"] >= 1 and not by["unlinked"].result.links
    for key in ("viscous", "maxwell"):
        for rec in by[key].result.links.values():
            assert np.all(np.diff(rec["dissipated"]) >= 0.0) and rec["dissipated"][-1] > 0.0, key
    assert by["tie"].row["link_energy"] == 0.0 and by["tie"].row["link_force"] > 0.0
    for r in runs:
        assert energy_balance(r.result)["ok"], r.key


def test_the_dampers_add_the_stated_damping_to_each_buildings_x_mode():
    """The coefficient of pair_viscous.toml (and pair_maxwell.toml) was chosen for about 15 % added damping
    in the first mode of "high": zeta_j = sum_d c (t_d . phi_j)^2 / (2 w_j). The script's link rows t_d
    (made by hand from the slabs' centres, :func:`pair_matrices`: minus the first end's x, plus the
    second's) times each building's modes equal the engine's own link rows over the modes
    (``result.links[name]["rows"]``), sign included, to rounding (a sum of 3N terms of size |t| |phi|);
    and the ratio is 15 % +- 0.5 % for "high"'s x mode, 19 % +- 0.5 % for "low"'s (what the scene
    file states)."""
    from pounding import assemble, load_scene, run

    module = _load()
    scene = load_scene(module.SCENES["viscous"]).with_analysis(duration=0.05)
    res = run(scene)
    systems = {b.name: assemble(b) for b in scene.buildings}
    _, _, T, _ = module.pair_matrices(scene)
    for t, link in zip(T, scene.links):
        at = 0
        for name, s in systems.items():  # the scene's order: the stacked DOFs of pair_matrices
            t_b = t[at : at + s.M.shape[0]]
            at += s.M.shape[0]
            scale = np.abs(t_b) @ np.abs(s.modes)
            engine = res.links[link.name]["rows"][name]
            assert np.all(np.abs(t_b @ s.modes - engine) <= 8 * s.modes.shape[0] * EPS * scale), (link.name, name)
            assert np.max(np.abs(engine)) > 0.0  # not vacuous: each end moves with its building's modes
    zeta = module.added_damping(scene)
    for name, target in (("high", 0.15), ("low", 0.19)):
        j = int(np.argmax(module.x_effective_mass(systems[name])))
        assert abs(zeta[name][j] - target) <= 0.005, (name, zeta[name][j])
    assert module.added_damping(load_scene(module.SCENES["tie"])) == {n: pytest.approx(0.0) for n in systems}


def test_the_ties_are_the_rigid_limit_at_the_files_step():
    """pair_tie.toml's ties (k = 1e9 N/m) are stiff enough for the rigid limit: the tied pair's period of
    most mass along x is within 0.3 % of the rigid ties' (the eigenproblem kept in the null space of the
    ties' rows, where their stiffness vanishes), and they stiffen its highest mode no further than
    w dt < 1 at the file's 5 ms step (Newmark's period error (w dt)^2 / 12 < 9 % there, on a mode that
    carries almost no mass). As a check of the rigid eigenproblem, a tie 1e3 times stiffer gives the rigid
    period to (k / k')-order: within 1e-5."""
    from dataclasses import replace

    from pounding import assemble, load_scene
    from pounding.io.scene_links import parse_links

    module = _load()
    scene = load_scene(module.SCENES["tie"])
    p = module.tie_periods(scene)
    assert abs(p["first"] / p["rigid"] - 1.0) <= 0.003, p
    assert p["highest_w"] * scene.analysis.dt < 1.0, p
    high = assemble(scene.buildings[1])
    own = high.periods[int(np.argmax(module.x_effective_mass(high)))]
    assert p["rigid"] < 0.8 * own  # not vacuous: the ties stiffen the taller building's x mode (0.86 s alone)
    tables = [{"name": link.name, "between": list(link.between), "storeys": list(link.storeys),
               "points": link.points.tolist(), "law": {"name": "elastic", "stiffness": 1.0e12}} for link in scene.links]
    stiffer = replace(scene, links=parse_links(tables, list(scene.buildings)))
    assert abs(module.tie_periods(stiffer)["first"] / p["rigid"] - 1.0) <= 1e-5


def test_the_linked_scenes_are_the_paper_pair_plus_their_links():
    """Each linked scene file is the paper's pair at 0.03 m (same [analysis], the same record, buildings
    with the same mass and stiffness matrices) with two links at storey 3 of both buildings."""
    from pounding import assemble, load_scene

    module = _load()
    paper = load_scene(module.SCENES["unlinked"])
    assert not paper.links
    for key in ("viscous", "maxwell", "tie"):
        scene = load_scene(module.SCENES[key])
        assert scene.analysis == paper.analysis, key
        assert np.array_equal(scene.ground_motion.acc, paper.ground_motion.acc), key
        for a, b in zip(scene.buildings, paper.buildings):
            sa, sb = assemble(a), assemble(b)
            assert np.array_equal(sa.M, sb.M) and np.array_equal(sa.K, sb.K), (key, a.name)
        assert [(link.between, link.storeys) for link in scene.links] == [(("low", "high"), (3, 3))] * 2, key


def test_the_readme_table_has_the_scripts_columns_and_scenes():
    """The example's README holds a table the script wrote (``--readme``): its header and one row per scene."""
    module = _load()
    text = (EXAMPLES / "linked_pair" / "README.md").read_text()
    block = text.split(module.README_START)[1].split(module.README_END)[0].strip().splitlines()
    assert block[0] == "| " + " | ".join(h for h, _ in module.COLUMNS) + " |"
    assert [line.split("|")[1].strip() for line in block[2:]] == list(module.SCENES)
