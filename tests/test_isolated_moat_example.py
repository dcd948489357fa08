"""examples/isolated_moat/run_isolated.py: a base-isolated building alone, in a moat, beside a neighbour, and fixed-base.

Run here over the first 3.6 s of the record (the base slab first reaches the moat's west face at
2.75 s, the superstructure first strikes the neighbour at 3.48 s), four runs of a few seconds
together, at twice the files' step; the whole record at the files' step is the example's own run
(its README).
"""

from __future__ import annotations

import csv
import importlib.util
import math
import sys

import numpy as np
import pytest

from conftest import EXAMPLES

SCRIPT = EXAMPLES / "isolated_moat" / "run_isolated.py"
DURATION = 3.6  # [s]
DT = 0.0005  # [s]: twice the files' step (20 steps over the shortest contact), to keep the test fast
EPS = np.finfo(float).eps
G = 9.80665  # [m/s2]


def _load():
    spec = importlib.util.spec_from_file_location("run_isolated", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    pytest.importorskip("matplotlib")
    module = _load()
    out = tmp_path_factory.mktemp("isolated_moat")
    return module, out, module.main(out, duration=DURATION, dt=DT)


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
    for name in ("base_displacement.png", "drift_profile.png", "acceleration_profile.png", "isolator_loop.png"):
        assert (out / name).stat().st_size > 10_000


def test_the_isolator_columns_are_the_runs_own(example):
    """The isolator displacement D is the peak |deformation| of the x lines' recorded history (their
    own ``peak`` over every step; the base slab's x displacement, as the slab does not turn) and their
    force F the largest |force| recorded; the effective period is 2 pi sqrt(M / sum K_eff) over the two
    x lines, K_eff = F / D, M every slab's mass (to rounding: a few operations on numbers of one sign);
    the isolator energy is what the four lines' laws dissipated by the end (their recorded cumulative
    dissipation, summed in another order: to rounding)."""
    _, _, runs = example
    for r in runs[:3]:
        rec, res = r.result.springs["isolated"], r.result
        sel = np.flatnonzero(np.isin(rec["element"], (0, 1)))
        assert r.row["iso_d"] == 1e3 * max(rec["peak"][sel]), r.key
        assert r.row["iso_d"] >= 1e3 * np.max(np.abs(rec["deformation"][:, sel])) * (1 - 4 * EPS), r.key
        assert r.row["iso_f"] == np.max(np.abs(rec["force"][:, sel])) / 1e3, r.key
        mass = sum(s.mass for s in res.scene.buildings[0].slabs)
        k_eff = 2 * r.row["iso_f"] * 1e3 / (r.row["iso_d"] / 1e3)
        assert r.row["t_eff"] == pytest.approx(2 * np.pi * np.sqrt(mass / k_eff), rel=16 * EPS), r.key
        dissipated = float(np.sum(rec["dissipated"][-1]))  # every yielding spring: the four isolator lines
        assert r.row["iso_energy"] == pytest.approx(dissipated / 1e3, rel=16 * EPS), r.key
        assert r.row["iso_energy"] > 0.0, r.key  # not vacuous: the lead cores yield within 3.6 s


def test_the_floor_accelerations_are_the_runs_own(example):
    """Without contact the floor acceleration columns are summary.json's ``peak_floor_acceleration``
    (the smooth part, exact there) over the superstructure's floors. With contact they add M^-1 f_c,
    the contact forces rebuilt from the recorded states: in the moat scene the wall pushes on the base
    slab alone, along x, so the part added to slab 1 is the wall pairs' total force over its mass m_1
    at every step (Phi Phi^T = M^-1 to rounding: the force's size times a few eps, relative), and the
    superstructure's floors get none. The largest rebuilt force is the run's own peak (summary.json's
    ``walls``) to 1e-6: rebuilt forces come back to 1e-9 on a scene that does not twist
    (pounding.framework.post.contact_forces). The fixed-base building's "base" is the ground, at the PGA."""
    from pounding.framework.post.contact_forces import contact_force_history
    from pounding.io.results import response_histories

    module, _, runs = example
    for r in runs:
        name, first = module.SUPERSTRUCTURE[r.key]
        if not r.result.contacts:
            assert r.row["acc"] == max(r.summary["buildings"][name]["peak_floor_acceleration"][first:]), r.key
        if r.key == "fixed_base":
            assert r.row["acc_base"] == pytest.approx(0.45 * G, rel=1e-12)
    moat = next(r for r in runs if r.key == "moat")
    res = moat.result
    smooth = response_histories(res)["isolated"]["floor_acceleration"]
    added = moat.floor_acceleration - smooth  # (nt, N, 3)
    walls = [p for p in range(len(res.pairs)) if p in res.walls]
    force = contact_force_history(res).pair_force[:, walls].sum(axis=1)  # (nt,) [N]
    m1 = res.scene.buildings[0].slabs[0].mass
    assert np.all(np.abs(np.abs(added[:, 0, 0]) - force / m1) <= 64 * EPS * force.max() / m1)
    assert np.all(np.abs(added[:, 1:, :2]) <= 64 * EPS * force.max() / m1)
    assert force.max() == pytest.approx(moat.row["wall_force"] * 1e6, rel=1e-6)
    assert force.max() > 0.0  # not vacuous: the base slab presses on the wall within 3.6 s


def test_the_contact_columns_split_the_runs_contacts(example):
    """The wall and neighbour columns partition the run's contact episodes: their counts add to
    ``n_impacts``, their energies to summary.json's ``contacts.energy_dissipated``, and the wall's peak
    force is summary.json's ``walls`` peak; within 3.6 s the base slab strikes the moat and, beside the
    neighbour, the superstructure strikes it too, and the isolated building alone strikes nothing."""
    _, _, runs = example
    for r in runs:
        s = r.summary
        assert r.row["wall_contacts"] + r.row["nb_contacts"] == s["n_impacts"], r.key
        # the same positive terms summed in another order: within n eps of the sum (n < 32 here)
        assert r.row["contact_energy"] == pytest.approx(s["contacts"]["energy_dissipated"] / 1e3, rel=32 * EPS, abs=0.0), r.key
        walls = s.get("walls", {})
        assert r.row["wall_force"] == max((w["peak_force"] for w in walls.values()), default=0.0) / 1e6, r.key
    by = {r.key: r.row for r in runs}
    assert by["alone"]["wall_contacts"] == by["alone"]["nb_contacts"] == 0
    assert by["moat"]["wall_contacts"] >= 1 and by["moat"]["nb_contacts"] == 0
    assert by["moat_neighbour"]["wall_contacts"] >= 1 and by["moat_neighbour"]["nb_contacts"] >= 1


def test_every_run_keeps_its_energy_account_and_the_contacts_add_none(example):
    """Each run's energy account closes (input = kinetic + strain + damping + hysteretic + what the
    contacts took), and the contacts take energy out of the buildings, never put it in."""
    from pounding.framework.post.energy_account import energy_balance

    _, _, runs = example
    for r in runs:
        assert energy_balance(r.result)["ok"], r.key
        assert r.summary["contacts"]["energy_dissipated"] >= 0.0, r.key
        assert all(e.energy_dissipated >= 0.0 for e in r.result.episodes()), r.key


def test_the_scenes_share_one_superstructure_and_the_stated_isolators():
    """The four scenes have the same superstructure (the fixed-base building's mass and stiffness are
    the isolated building's with the isolation layer's row and column removed, as its frames stand on
    the base slab: condensed frames depend on the storeys they span, not where they stand); the moat's
    clearance is 0.07 m; the isolators give the stated post-yield period 2 pi sqrt(M / K_d) = 2.52 s
    (+- 0.01 s, the stated figure's rounding) and a yield force of 5.0 % of the weight along x."""
    from pounding import assemble, load_scene
    from pounding.framework.model.isolation import isolator_lines

    module = _load()
    scenes = {k: load_scene(p) for k, p in module.SCENES.items()}
    iso = assemble(scenes["alone"].buildings[0])
    fixed = assemble(scenes["fixed_base"].buildings[0])
    keep = np.arange(3, iso.M.shape[0])  # the DOFs of floors 2-5
    layer = isolator_lines(scenes["alone"].buildings[0])
    assert len(layer) == 4
    k_layer = sum(iso.elements[i].T.T @ iso.elements[i].k @ iso.elements[i].T for i in layer)  # the isolators' part of K
    assert np.array_equal(iso.M[np.ix_(keep, keep)], fixed.M)
    scale = np.max(np.abs(fixed.K))
    assert np.max(np.abs((iso.K - k_layer)[np.ix_(keep, keep)] - fixed.K)) <= 64 * EPS * scale
    for key in ("alone", "moat", "moat_neighbour"):
        assert np.array_equal(assemble(scenes[key].buildings[0]).K, iso.K), key
    assert module.clearance(scenes["moat"]) == pytest.approx(0.07, abs=1e-12)
    elements = scenes["alone"].buildings[0].elements
    lines = [elements[i] for i in layer if abs(elements[i].direction[0]) > 0.5]
    assert len(lines) == 2
    mass = sum(s.mass for s in scenes["alone"].buildings[0].slabs)
    k_d = sum(e.hardening * e.stiffness[0] for e in lines)
    assert abs(2 * np.pi * np.sqrt(mass / k_d) - 2.52) <= 0.01
    fy = sum(e.yield_force[0] for e in lines)
    assert fy / (mass * G) == pytest.approx(0.050, abs=0.0005)


def test_the_readme_table_has_the_scripts_columns_and_scenes():
    """The example's README holds a table the script wrote (``--readme``): its header and one row per scene."""
    module = _load()
    text = (EXAMPLES / "isolated_moat" / "README.md").read_text()
    block = text.split(module.README_START)[1].split(module.README_END)[0].strip().splitlines()
    assert block[0] == "| " + " | ".join(h for h, _ in module.COLUMNS) + " |"
    assert [line.split("|")[1].strip() for line in block[2:]] == list(module.SCENES)
