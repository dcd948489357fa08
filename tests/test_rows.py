"""Rows of buildings: what the scene reader refuses and what it warns about.

A storey is the prism of its slab between the floor below and its own level;
two buildings may not claim the same space at rest, whether or not their slabs
are at a common level. Buildings with no slabs at a common level are valid; their
slabs can only strike each other's facades between floors: one warning says so,
naming every such pair.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.post.plausibility import findings
from pounding.io.scene import load_scene

from test_bad_input import BASE


def _scene_text(b_heights: str, b_slab_x0: float, extra: str = "") -> str:
    old = 'storey_heights = [3.0]\nslab = [[10.1, 0], [20, 0], [20, 8], [10.1, 8]]'
    assert old in BASE, "B's block changed: these scenes would not be what they say"
    return BASE.replace(old, f'storey_heights = {b_heights}\nslab = [[{b_slab_x0}, 0], [20, 0], [20, 8], [{b_slab_x0}, 8]]', 1) + extra


def _third(name: str, heights: str, x0: float) -> str:
    """A three-wall building standing on [x0, x0 + 10] x [0, 8]."""
    return f"""
[[building]]
name = "{name}"
storey_heights = {heights}
slab = [[{x0}, 0], [{x0 + 10}, 0], [{x0 + 10}, 8], [{x0}, 8]]
mass_per_area = 800.0
  [[building.element]]
  type = "shear_wall"
  start = [{x0}, 0]
  end = [{x0 + 10}, 0]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [{x0}, 8]
  end = [{x0 + 10}, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
  [[building.element]]
  type = "shear_wall"
  start = [{x0 + 5}, 0]
  end = [{x0 + 5}, 8]
  thickness = 0.2
  E = 30e9
  G = 12e9
"""


def test_overlap_at_different_levels_is_refused_with_exit_2_and_one_line(tmp_path):
    """B (one 3.5 m storey) reaches 0.6 m into A (3 m storeys): no slabs share a level, yet the
    storeys 0-3 m and 0-3.5 m share height and plan: `pounding check` exits 2 with one line."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 9.4))
    with pytest.raises(InputError, match=r"storey 1 of 'A' \(0-3 m\) and storey 1 of 'B' \(0-3.5 m\).*overlap by 0.6 m"):
        load_scene(path)
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "building[1].slab" in proc.stderr


def test_a_storey_above_a_lower_neighbours_roof_may_overhang_it(tmp_path):
    """C's second storey (3-6 m) overhangs B's roof (B is one 3 m storey) by 2 m in plan: the
    storeys share no height, so the scene is valid (a setback over a low neighbour)."""
    path = tmp_path / "scene.toml"
    # C's first storey stands clear of B (x >= 20.1), its second slab reaches back over B to x = 18
    extra = _third("C", "[3.0, 3.0]", 20.1).replace(
        "slab = [[20.1, 0], [30.1, 0], [30.1, 8], [20.1, 8]]",
        "slabs = [[[20.1, 0], [30.1, 0], [30.1, 8], [20.1, 8]], [[18, 0], [30.1, 0], [30.1, 8], [18, 8]]]")
    path.write_text(_scene_text("[3.0]", 10.1, extra))
    scene = load_scene(path)
    assert [b.name for b in scene.buildings] == ["A", "B", "C"]


def test_no_common_level_is_said_once_naming_every_pair(tmp_path):
    """A has 3 m storeys, B one of 3.5 m, C 3.7 m: no two share a level (only slab-to-facade impacts
    are checked between them); one warning names the three pairs, and none is given when B and C
    share A's levels."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 10.1, _third("C", "[3.7]", 20.2)))
    found = [f for f in findings(load_scene(path)) if f.check == "no_common_level"]
    assert len(found) == 1
    for pair in ("'A' and 'B'", "'A' and 'C'", "'B' and 'C'"):
        assert pair in found[0].message
    path.write_text(_scene_text("[3.0]", 10.1, _third("C", "[3.0]", 20.2)))
    assert [f for f in findings(load_scene(path)) if f.check == "no_common_level"] == []


def test_no_common_level_warning_reaches_stderr_once_and_is_silenced(tmp_path):
    """`pounding info` on the A (3 m) / B (3.5 m) scene prints exactly one no_common_level warning
    line (exit 0), and none with --silence no_common_level."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[3.5]", 10.1))
    proc = subprocess.run([sys.executable, "-m", "pounding", "info", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if "no_common_level" in ln]
    assert len(lines) == 1 and "'A' and 'B'" in lines[0]
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path), "--silence", "no_common_level"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "no_common_level" not in proc.stderr


# --------------------------------------------------------------------------- runs of rows
def _row(gap: float, *, far: float | None = None, duration: float = 2.0) -> dict:
    """``side_by_side`` (3 storeys each, `gap` apart along x), with a third 3-storey building of
    other columns either `gap` beyond "right" (a row of three) or `far` metres beyond it."""
    from scenes_for_tests import box_building, side_by_side

    data = side_by_side(gap, storeys=(3, 3), duration=duration, pga=0.5)
    x0 = 10.0 + gap + 12.0 + (gap if far is None else far)
    data["building"].append(box_building("third", x0, 9.0, 10.0, 3, 0.35, 0.45))
    return data


def test_a_far_third_building_changes_nothing_of_the_pair():
    """The two-building run and the same run with a third building 200 m away (no slab pair within
    reach) give the same responses and impacts. Tolerance 1e-12 of each building's peak: the third
    building only lengthens the stacked modal arrays, and every per-mode step and the pair's impulse
    solve use the same numbers in the same order, so only summation order of the energy terms may
    differ (rounding, ~1e-16 relative)."""
    from pounding.framework.post.run import run

    from scenes_for_tests import scene

    pair_data = _row(0.01)
    pair_data["building"].pop()
    two = run(scene(pair_data))
    three = run(scene(_row(0.01, far=200.0)))
    assert two.n_impacts > 0, "the pair must pound, or the comparison says nothing"
    assert three.n_impacts == two.n_impacts
    assert np.array_equal(three.t, two.t)
    for name in ("left", "right"):
        a, b = two.cm(name), three.cm(name)
        assert np.max(np.abs(b - a)) <= 1e-12 * np.max(np.abs(a))
    peak_impulse = max(i.impulse for i in two.impacts)
    for i2, i3 in zip(two.impacts, three.impacts):
        assert (i2.striker, i2.vertex) == (i3.striker, i3.vertex)
        assert abs(i3.time - i2.time) <= 1e-12 * two.t[-1]
        assert abs(i3.impulse - i2.impulse) <= 1e-12 * peak_impulse
        assert np.allclose(i3.point, i2.point, rtol=0, atol=1e-12 * 22.0)  # 22 m: the pair's plan length
    assert np.max(np.abs(three.cm("third"))) > 0, "the far building still responds to the ground"


def test_every_impulse_in_a_row_of_three_conserves_momentum():
    """A row of three 3-storey buildings 0.01 m apart under El Centro at 0.5 g: both pairs pound.
    Each impulse, taken from the driver just before and after, conserves the linear and angular
    momentum of all slabs to 1e-12 of the size of the jumps (as for the pair, test_impacts)."""
    from test_impacts import RTOL, RecordingDriver, momenta

    from scenes_for_tests import scene

    d = RecordingDriver(scene(_row(0.01)))
    result = d.run()
    touched = {i.pair for ev in d.events for i in ev["impacts"]}
    pairs = result.pairs
    struck = {(pairs[p][0], pairs[p][2]) for p in touched}
    assert struck == {(0, 1), (1, 2)}, f"both neighbours must pound, not {struck}"
    for ev in d.events:
        p0, L0, _, _ = momenta(d.model, ev["q"], ev["before"])
        _, _, ps, Ls = momenta(d.model, ev["q"], ev["after"] - ev["before"])
        p1, L1, _, _ = momenta(d.model, ev["q"], ev["after"])
        assert np.all(np.abs(p1 - p0) <= RTOL * ps), ev["t"]
        assert abs(L1 - L0) <= RTOL * Ls, ev["t"]


# --------------------------------------------------------------------------- gap of a row
def test_gap_of_a_row_reports_each_adjacent_pair_as_if_it_stood_alone():
    """Row left | right | third, 3 storeys each, 0.01 m apart: the adjacent pairs are (left, right)
    and (right, third); (left, third) is screened by "right" at every level. Each pair's required
    gap from the one run of the row equals minimum_gap of that pair alone: without contact the
    buildings do not interact, so the two runs give the same histories to rounding; tolerance
    1e-12 of the gap (a few roundings of coordinates ~20 m against gaps of ~0.05 m: 1e-14 m)."""
    from pounding.framework.model.placement import adjacent_pairs, pair_scene
    from pounding.framework.studies.gap import minimum_gap, minimum_gaps

    from scenes_for_tests import scene

    sc = scene(_row(0.01, duration=3.0))
    assert adjacent_pairs(sc) == ([(0, 1), (1, 2)], [(0, 2)])
    row = minimum_gaps(sc)
    assert [r.buildings for r in row.reports] == [("left", "right"), ("right", "third")]
    assert row.screened == [("left", "third")]
    for r, (i, j) in zip(row.reports, [(0, 1), (1, 2)]):
        alone = minimum_gap(pair_scene(sc, i, j))
        assert r.min_gap > r.current_gap, "the pair must need more than it has, or the comparison is idle"
        assert abs(r.min_gap - alone.min_gap) <= 1e-12 * alone.min_gap
        assert (r.storey, r.striking, r.vertex, r.time) == (alone.storey, alone.striking, alone.vertex, alone.time)


def test_the_ends_of_a_row_face_each_other_above_a_low_middle_building():
    """left and third (3 storeys) with a 1-storey building between: at storeys 2-3 nothing stands
    between the ends, so they are adjacent there (a gap across the low roof), and every pair is
    reported; the ends' required gap counts those storeys only (12.02 m apart at rest, far more than needed)."""
    from pounding.framework.model.placement import adjacent_pairs, facing_storeys
    from pounding.framework.studies.gap import minimum_gaps

    from scenes_for_tests import scene

    data = _row(0.01)
    data["building"][1]["storey_heights"] = data["building"][1]["storey_heights"][:1]
    sc = scene(data)
    assert adjacent_pairs(sc) == ([(0, 1), (0, 2), (1, 2)], [])
    assert facing_storeys(sc, 0, 2) == [(1, 1), (2, 2)]
    assert facing_storeys(sc, 0, 1) == [(0, 0)]
    row = minimum_gaps(sc)
    ends = row.reports[1]
    assert ends.buildings == ("left", "third")
    assert [fa for fa, _, _, _ in ends.required] == [2, 3], "only the storeys above the low roof"
    assert ends.current_gap > 12.0 > ends.min_gap


def test_pounding_gap_on_a_row_prints_every_adjacent_pair(tmp_path):
    """`pounding gap --json --no-check` on the row of three: two pairs in scene order and the
    screened one; --history is refused (exit 2, one line), as it writes one pair's clearances."""
    import json

    from strategies import to_toml

    path = tmp_path / "row.toml"
    path.write_text(to_toml(_row(0.01, duration=1.0)))
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(path), "--json", "--no-check"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert [(p["buildings"]["fixed"], p["buildings"]["moved"]) for p in out["pairs"]] == [("left", "right"), ("right", "third")]
    assert out["screened"] == [["left", "third"]]
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(path), "--history", str(tmp_path / "h.csv")],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1 and "--history" in proc.stderr
    assert not (tmp_path / "h.csv").exists()


def test_pounding_check_says_which_pairs_of_a_row_are_not_adjacent(tmp_path):
    """`pounding check` on the row of three lists every pair of buildings; only (left, third),
    screened by "right", is said to be not adjacent."""
    from strategies import to_toml

    path = tmp_path / "row.toml"
    path.write_text(to_toml(_row(0.01, duration=1.0)))
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    lines = {ln.split(":")[0]: ln for ln in proc.stdout.splitlines() if ln.startswith("'")}
    assert set(lines) == {"'left' and 'right'", "'left' and 'third'", "'right' and 'third'"}
    assert [k for k, ln in lines.items() if "not adjacent" in ln] == ["'left' and 'third'"]


def test_adjacency_in_the_row_of_five_example():
    """examples/row/row.toml: 10, 6, 8, 5, 10 storeys of 3.2 m, aligned facades, 0.04 m apart.
    Neighbours are adjacent; so are buildings that see each other above a lower one between
    (west_end and b3 at storeys 7-8 over b2, west_end and east_end at 9-10, b3 and east_end at
    6-8 over b4); the rest are screened, also where the shortest segment between the slabs runs
    along the facades of the buildings between and its midpoint falls in a gap (west_end-b4)."""
    from pathlib import Path

    from pounding.framework.model.placement import adjacent_pairs, facing_storeys

    sc = load_scene(Path(__file__).resolve().parents[1] / "examples" / "row" / "row.toml")
    adjacent, screened = adjacent_pairs(sc)
    assert adjacent == [(0, 1), (0, 2), (0, 4), (1, 2), (2, 3), (2, 4), (3, 4)]
    assert screened == [(0, 3), (1, 3), (1, 4)]
    assert [fa for fa, _ in facing_storeys(sc, 0, 2)] == [6, 7]
    assert [fa for fa, _ in facing_storeys(sc, 0, 4)] == [8, 9]
    assert [fa for fa, _ in facing_storeys(sc, 2, 4)] == [5, 6, 7]


def test_a_slab_below_ground_is_refused_naming_the_storey_height(tmp_path):
    """A negative storey height would put a slab below the one under it, the first one below
    ground: `pounding check` exits 2 with one line naming building[1].storey_heights[0]."""
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("[-3.0]", 10.1))
    proc = subprocess.run([sys.executable, "-m", "pounding", "check", str(path)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "building[1].storey_heights[0]" in proc.stderr


def test_the_far_building_s_pair_checks_are_all_settled_by_the_cheap_bound():
    """The pair with a third building 200 m away: summary info ``pair_checks`` counts, over the
    recorded states (every step: output_every = 1), the checks the clearance bound settles. The
    third building's slab pairs (with both others, 3 storeys each: 6 pairs) are settled at every
    step (their rest gap of ~200 m exceeds any motion by far), so at least 6 x (steps + 1) checks
    are skipped, and the count adds up."""
    from pounding.framework.post.run import run

    from scenes_for_tests import scene

    r = run(scene(_row(0.01, far=200.0)))
    c = r.info["pair_checks"]
    far = [p for p, (a, _, b, _, _) in enumerate(r.pairs) if 2 in (a, b)]
    assert len(far) == 6
    assert c["checks"] == len(r.t) * len(r.pairs) == c["skipped_by_bound"] + c["beyond_bound"]
    assert c["skipped_by_bound"] >= len(far) * len(r.t)
    assert c["beyond_bound"] > 0, "the near pair pounds: some checks go past the bound"
