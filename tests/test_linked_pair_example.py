"""examples/linked_pair/run_linked.py: the paper's pair unlinked, linked by dampers, tied and with a bumper, one
table and four plots.

Run here over the first 2.2 s of the record (the unlinked pair first pounds at 1.91 s, the damped ones at
1.96 s, the bare pair under the force law from 1.91 to 2.02 s; the bumper's layer is first touched at 1.41 s,
then from 1.85 to 2.07 s): four impulse-law runs of a few hundredths of a second each and the two force-law
runs (0.25 ms steps) of one to three seconds; the whole record is the example's own run (its README).
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
DURATION = 2.2  # [s]
EPS = np.finfo(float).eps
#: the table's columns a contact law by impulses has no figure for (NaN in table.csv, "-" in table.md)
FORCE_ONLY = ("contact_force", "penetration")


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
        by_force = module.by_forces(r.result)
        for x, (_, k) in zip(written[1:], module.COLUMNS[1:]):
            assert math.isfinite(float(x)) or (k in FORCE_ONLY and not by_force), (r.key, k, x)
            assert float(x) == float(r.row[k]) or (math.isnan(float(x)) and math.isnan(r.row[k])), (r.key, k)
    md = (out / "table.md").read_text().splitlines()
    assert [line.split("|")[1].strip() for line in md[2:]] == list(module.SCENES)
    for line, r in zip(md[2:], runs):  # "-" exactly where the scene's law has no such figure
        cells = [c.strip() for c in line.split("|")[2:-1]]
        assert [c == "-" for c in cells] == [isinstance(r.row[k], float) and math.isnan(r.row[k]) for _, k in module.COLUMNS[1:]]
    for name in ("top_displacement.png", "drift_profile.png", "acceleration_profile.png", "damper_loop.png"):
        assert (out / name).stat().st_size > 10_000


def test_the_tables_numbers_are_the_runs_own(example):
    """Each row reads its run: the impacts are the run's ``n_impacts``; the top displacement the peak
    |x| of the top slab's centre over the continuous trajectory (summary.json's ``peak_u``), which is at
    least the largest recorded step end's and exceeds it by at most a h^2 / 8 (a parabola through its
    peak seen half a step away), a <= peak absolute floor acceleration + the contact forces' part (force
    laws) + PGA the relative acceleration; a link's peak force is the largest |force| of the links'
    recorded histories; its stroke is the link's own peak |deformation| over every committed state, the
    step ends and the impact instants between them (``peak``), so at least the recorded histories' and
    above them by at most the stroke's largest travel in one step (the deformation is continuous); the
    energy is the sum of the links' final cumulative dissipation; the contacts' energy is the sum over the run's contacts of what each
    dissipated, and under a force law the peak force and penetration are the largest of its episodes'."""
    module, _, runs = example
    for r in runs:
        res = r.result
        assert r.row["impacts"] == res.n_impacts, r.key
        pga = float(np.max(np.abs(res.scene.ground_motion.acc)))  # [m/s2]
        for name in ("low", "high"):
            b = r.summary["buildings"][name]
            top = 1e3 * np.max(np.abs(res.cm(name)[:, -1, 0]))
            a = max(b["peak_floor_acceleration"]) + np.max(module.contact_acceleration(res, r.forces, name)) + pga
            assert r.row[f"top_{name}"] == 1e3 * b["peak_u"][-1], (r.key, name)
            assert top * (1 - 4 * EPS) <= r.row[f"top_{name}"] <= top + 1e3 * a * res.dt**2 / 8, (r.key, name)
        force = max((np.max(np.abs(rec["force"])) for rec in res.links.values()), default=0.0)
        stroke = max((np.max(np.abs(rec["deformation"])) for rec in res.links.values()), default=0.0)
        travel = max((np.max(np.abs(np.diff(rec["deformation"]))) for rec in res.links.values()), default=0.0)
        energy = sum(rec["dissipated"][-1] for rec in res.links.values())
        assert r.row["link_force"] == force / 1e3, r.key
        assert r.row["link_stroke"] == max((rec["peak"] for rec in res.links.values()), default=0.0) * 1e3, r.key
        assert stroke * 1e3 <= r.row["link_stroke"] <= (stroke + travel) * 1e3, r.key
        assert r.row["link_energy"] == pytest.approx(energy / 1e3, rel=4 * EPS, abs=0.0), r.key
        eps = res.episodes()
        assert r.row["contact_energy"] == pytest.approx(sum(e.energy_dissipated for e in eps) / 1e3, rel=len(eps) * EPS, abs=0.0)
        if module.by_forces(res):
            assert r.row["contact_force"] == max(e.peak_force for e in eps) / 1e3, r.key
            assert r.row["penetration"] == 1e3 * max(e.peak_penetration for e in eps), r.key
        else:
            assert math.isnan(r.row["contact_force"]) and math.isnan(r.row["penetration"]), r.key


def test_the_force_laws_contact_spikes_carry_the_contact_force(example):
    """Under a force law the impact spike is the contact forces' own floor acceleration M^-1 f_c, rebuilt
    from the recorded states (pounding.framework.post.contact_forces). Its floors' forces are the contact
    force: sum over floors of m_f a_f (in plan) is, on each building, the pair's force along the contact
    normal (x here, to the slabs' twist: 1e-3), equal and opposite on the two (action and reaction, to
    rounding of a sum of mass times acceleration over all floors); the rebuilt force peaks at its episode's
    recorded peak force (to 1e-4: the rebuild's tolerance on this twisting pair, 3.3e-5 measured), the
    recorded steps outside the contact episodes, where it is not rebuilt, pressing no pair; and the spike
    is at least that force over the struck building's total mass (max_f |a_f| sum m_f >= |sum m_f a_f|)."""
    from pounding import assemble

    module, _, runs = example
    forced = [r for r in runs if module.by_forces(r.result)]
    assert [r.key for r in forced] == ["unlinked_force", "bumper"]
    for r in forced:
        res, f = r.result, r.forces
        assert res.episodes() and f is not None, r.key
        resultant = {}
        for name in module.BUILDINGS:
            s = assemble(next(b for b in res.scene.buildings if b.name == name))
            a = f.floor_acceleration(res, name)  # (nt, N, 3)
            resultant[name] = np.einsum("fk,tfk->tk", s.mass.reshape(-1, 3)[:, :2], a[:, :, :2])  # (nt, 2) [N]
        total = np.abs(f.pair_force).sum(axis=1)  # [N]
        scale = np.max(total)
        assert np.all(np.abs(resultant["low"] + resultant["high"]) <= 1e-9 * scale), r.key
        assert np.all(np.abs(np.abs(resultant["high"][:, 0]) - total) <= 1e-3 * scale), r.key
        peak = max(e.peak_force for e in res.episodes())
        assert abs(np.max(f.pair_force) / peak - 1.0) <= 1e-4, r.key
        # forces are rebuilt at the steps in contact only: no pair is pressed at the others (a sample of 200)
        others = np.setdiff1d(np.arange(len(res.t)), r.force_steps)
        for p in range(len(res.pairs)):
            assert np.all(module.pair_penetration(res, p, others[:: max(len(others) // 200, 1)]) == 0.0), (r.key, p)
        lightest = min(float(np.sum(assemble(b).mass[0::3])) for b in res.scene.buildings)
        assert r.row["spike"] >= peak / lightest * (1 - 1e-3), r.key


def test_the_unlinked_pair_pounds_and_every_link_is_passive(example):
    """Within 2.2 s the unlinked pair pounds; the dampers dissipate energy at every step (their
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


def test_the_bumper_is_struck_passive_and_never_spent(example):
    """Within 2.2 s the bumper is struck: every contact of the bumper scene is on the layer (the pair of
    "low"'s storey 3 and "high"'s slab at its level, whose rest gap is the bare 0.03 m less the layer's
    0.02 m), each of its episodes dissipates energy (a passive contact never adds any: >= 0, and > 0 in
    all: the layer is lossy), and its deepest compression stays below the compressible fraction c t, so
    the slabs' own law never acts (the layer is not spent, as the README says of the whole record). Every
    contact of the two bare pairs is at that storey too, which is why the layer is there."""
    module, _, runs = example
    by = {run.key: run for run in runs}
    for key in ("unlinked", "unlinked_force"):
        hits = by[key].result.episodes()
        assert hits and all(by[key].result.pairs[e.pair][:4] == (0, 2, 1, 2) for e in hits), key
    r = by["bumper"]
    res = r.result
    pair, bumper = module.bumper_pair(res)
    assert res.pairs[pair][:4] == (0, 2, 1, 2)
    assert abs(res.pairs[pair][4] - (0.03 - bumper.thickness)) <= 1e-12
    eps = res.episodes()
    assert eps and all(e.pair == pair for e in eps)
    assert all(e.energy_dissipated > 0.0 for e in eps)
    assert r.row["penetration"] < 1e3 * bumper.compressible * bumper.thickness


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


def test_the_bumper_scene_is_its_reference_plus_the_bumper():
    """pair_bumper.toml is the paper's pair (the same record, buildings with the same mass and stiffness
    matrices) under a force law for the slabs, with one bumper at storey 3 of "low"; its reference
    ``unlinked_force`` is the same scene without its [[contact]] table (the same [analysis]: like with
    like); ``--refine`` divides each file's own step."""
    from pounding import assemble, load_scene

    module = _load()
    paper = load_scene(module.SCENES["unlinked"])
    bumper, reference = module.scene_for("bumper", None), module.scene_for("unlinked_force", None)
    assert np.array_equal(bumper.ground_motion.acc, paper.ground_motion.acc)
    for a, b in zip(bumper.buildings, paper.buildings):
        sa, sb = assemble(a), assemble(b)
        assert np.array_equal(sa.M, sb.M) and np.array_equal(sa.K, sb.K), a.name
    assert module.SCENES["unlinked_force"] == module.SCENES["bumper"]  # the same file: the same buildings
    assert reference.analysis == bumper.analysis and not reference.contacts
    assert bumper.analysis.contact == "jankowski" and bumper.analysis.dt == 0.00025
    assert [(rule.bumper.on, rule.bumper.storeys) for rule in bumper.contacts] == [("low", (3,))]
    assert module.scene_for("bumper", None, refine=2).analysis.dt == bumper.analysis.dt / 2
    assert module.scene_for("unlinked", None, refine=2).analysis.dt == paper.analysis.dt / 2


def test_the_layer_is_sized_as_the_readme_says():
    """The layer's stiffness is E A / t of rubber pads pressed flat (E = 5 MPa, A = 0.44 m^2, t = 0.02 m,
    exponent 1). Struck by the two roof slabs, free, at the unlinked force-law pair's fastest approach
    (0.714 m/s, README), it compresses less than c t = 15 mm: 11.8 mm, below the undamped spring's
    v sqrt(m_eff / k) (its damping only adds force while the slabs close), with a peak force of 1.92 MN
    against the bare slabs' law's 2.66 MN (README: the layer is the softer); its rebound is the "ye"
    calibration's 0.4704 at e = 0.5 (docs/contact-laws.md's rebound table, computed at exponent 1.5: the
    rebound of k delta^n (1 + xi delta' / delta'_0) does not depend on n, as m v dv = -F d delta shows
    with w = delta^(n+1) / (n+1)), each to the integration's 1e-4."""
    from pounding import load_scene

    module = _load()
    scene = load_scene(module.SCENES["bumper"])
    layer = scene.contacts[0].bumper
    assert layer.params["stiffness"] == pytest.approx(5e6 * 0.44 / layer.thickness, rel=EPS) and layer.params["exponent"] == 1.0
    d = module.layer_design(scene, 0.714)
    m1, m2 = d["masses"]
    elastic = 0.714 * math.sqrt(m1 * m2 / (m1 + m2) / layer.params["stiffness"])
    assert d["penetration"] < d["reach"] == pytest.approx(0.015, rel=EPS)
    assert d["penetration"] < elastic
    assert abs(d["penetration"] - 0.0118) <= 0.5e-4  # the README's 11.8 mm
    assert abs(d["rebound"] - 0.4704) <= 1e-4
    assert abs(d["force"] - 1.92e6) <= 0.005e6 and abs(d["slabs_force"] - 2.66e6) <= 0.005e6


def test_the_readme_table_has_the_scripts_columns_and_scenes():
    """The example's README holds a table the script wrote (``--readme``): its header and one row per scene."""
    module = _load()
    text = (EXAMPLES / "linked_pair" / "README.md").read_text()
    block = text.split(module.README_START)[1].split(module.README_END)[0].strip().splitlines()
    assert block[0] == "| " + " | ".join(h for h, _ in module.COLUMNS) + " |"
    assert [line.split("|")[1].strip() for line in block[2:]] == list(module.SCENES)
