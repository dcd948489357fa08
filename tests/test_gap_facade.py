"""Separation gap of buildings with unequal storey heights: a slab against the neighbour's facade.

A slab whose level lies between two floors of the other building strikes its facade there; the
facade moves with the Hermite blend N1 u_below + N2 u_above of the two floors (N2 = 3 eta^2 -
2 eta^3, :mod:`pounding.framework.model.facade`). ``pounding gap`` designs the gap against these
contacts too.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from pounding.framework.engine import peaks
from pounding.framework.post.run import run
from pounding.framework.model.placement import adjacent_pairs, pair_sites
from pounding.framework.studies.gap import gap_from_result, minimum_gap, no_contact, verify_gap
from scenes_for_tests import scene as build, side_by_side


def _stepped(gap: float = 0.02, duration: float = 3.0) -> dict:
    """"left" [0, 10] x [0, 10], one storey of 3.0 m; "right" [10 + gap, 22 + gap] x [0, 10], two storeys
    of 2.0 m (floors at 2.0 and 4.0 m): no common level. Left's slab (3.0 m) meets right's second storey
    at eta = 1/2; right's first slab (2.0 m) meets left's only storey at eta = 2/3 (the ground below).
    Both symmetric about y = 5 and shaken along x: no rotation."""
    data = side_by_side(gap, storeys=(1, 2), duration=duration, pga=0.5, columns=(0.3, 0.5), columns_y=(0.5, 0.6))
    data["building"][0]["storey_heights"] = [3.0]
    data["building"][1]["storey_heights"] = [2.0, 2.0]
    return data


def _n2(eta: float) -> float:
    return 3.0 * eta**2 - 2.0 * eta**3


@pytest.fixture(scope="module")
def stepped():
    return build(_stepped())


@pytest.fixture(scope="module")
def stepped_report(stepped):
    return minimum_gap(stepped)


def test_a_pair_with_no_common_level_meets_at_the_facades(stepped):
    """No slab of either building is at a level of the other's, yet each slab lies between two floors (or
    the ground and the first floor) of the other, below its roof: two slab-facade sites, and the pair is
    adjacent (before facades it was skipped as never meeting)."""
    a, b = stepped.buildings
    assert pair_sites(a, b) == [(0, 1, "b"), (0, 0, "a")]
    assert adjacent_pairs(stepped) == ([(0, 1)], [])


def test_required_gap_is_the_peak_of_slab_minus_hermite_blend_of_the_floors(stepped, stepped_report):
    """Closed form. Without rotation the clear distance along x between left's slab and right's facade is
    g0 - (u_L - (N1(1/2) u_R1 + N2(1/2) u_R2)), and between right's first slab and left's facade
    g0 - (N2(2/3) u_L - u_R1) (the ground takes N1 there): both linear in the modal coordinates, with
    N2 = 3 eta^2 - 2 eta^3 written out here. The required gap is g0 + the larger signed peak over the
    continuous trajectory (the closed-form extreme of the integrator's interpolant per step,
    :func:`pounding.framework.engine.peaks.abs_peaks`); at the step ends it is the largest value of the same
    combination of the floors' step-end displacements. Tolerances as for common levels (test_gap):
    the bounded search inside a step (xatol 1e-10) and the modal sums in another order leave ~1e-15
    relative, hence rel 1e-12."""
    res = run(no_contact(stepped))
    uL = res.cm("left")[:, 0, 0]
    uR1, uR2 = res.cm("right")[:, 0, 0], res.cm("right")[:, 1, 0]
    # symmetric: v and phi are rounding of the mode shapes (~1e-18 m, rad); times the lever arms (< 10 m)
    # they move the clear distance by < 1e-16 m, far inside the tolerances below
    assert np.max(np.abs(res.cm("left")[:, :, 1:])) < 1e-15 and np.max(np.abs(res.cm("right")[:, :, 1:])) < 1e-15
    n2b, n2a = _n2(0.5), _n2(2.0 / 3.0)
    rel_b = uL - ((1.0 - n2b) * uR1 + n2b * uR2)
    rel_a = n2a * uL - uR1
    r = stepped_report
    assert r.current_gap == pytest.approx(0.02, abs=1e-12) and np.array_equal(r.direction, [1.0, 0.0])
    assert r.min_gap_grid == pytest.approx(max(rel_b.max(), rel_a.max()), rel=1e-12, abs=1e-14)
    assert np.allclose(r.clearance, 0.02 - np.stack([rel_b, rel_a], axis=1), rtol=0, atol=1e-13)
    PL, PR = res.systems[0].modes, res.systems[1].modes
    row_b = np.concatenate([PL[0], -((1.0 - n2b) * PR[0] + n2b * PR[3])])
    row_a = np.concatenate([n2a * PL[0], -PR[0]])
    seg = peaks.segments(res)
    cont = peaks.abs_peaks(seg, np.stack([row_b, row_a]), signed=True)
    assert [g for _, _, g, _ in r.required] == pytest.approx(list(cont), rel=1e-12, abs=1e-14)
    assert r.min_gap == pytest.approx(max(cont), rel=1e-12, abs=1e-14) and r.min_gap >= r.min_gap_grid
    # evaluating only the steps that can govern (full=False, as the fragility runs do) gives the same answer:
    # the same element-wise computation on fewer steps
    fast = gap_from_result(stepped, res, full=False)
    assert (fast.min_gap, fast.time, fast.facade, fast.vertex) == (r.min_gap, r.time, r.facade, r.vertex)
    # the report says which contact governs: a slab, its level, the struck storey and eta
    k = int(np.argmax(cont))
    F = r.facade
    assert F == r.facades[k]
    if k == 0:
        assert F == {"striking": "left", "slab_storey": 1, "height": 3.0, "struck": "right", "struck_storey": 2, "eta": 0.5}
        assert (r.storey, r.storey_b) == (1, 2)
    else:
        assert F["striking"] == "right" and F["struck_storey"] == 1 and F["eta"] == pytest.approx(2.0 / 3.0, abs=1e-15)


def test_impacts_on_the_facade_just_below_the_answer_and_none_just_above(stepped, stepped_report):
    """Two full runs with contact (impulse law): at 0.99 x the required gap the slab strikes the facade (the
    impacts are on slab-facade pairs, the only ones there are), at 1.01 x nothing touches. The margin,
    0.01 x the gap (~1e-3 m here), exceeds the law's detection tolerance (1e-4 m)."""
    r = stepped_report
    assert 0.01 * r.min_gap > 1e-4
    below = run(stepped.with_gap(0.99 * r.min_gap, r.direction))
    assert below.n_impacts > 0 and all(imp.pair in below.facades for imp in below.impacts)
    check = verify_gap(stepped, r)
    assert check.n_impacts == (below.n_impacts, 0) and check.ok


def test_cli_reports_the_facade_contact(tmp_path):
    """`pounding gap --json` on the stepped pair names the governing facade contact and writes one
    clearance column per slab-facade site."""
    path = tmp_path / "stepped.toml"
    from strategies import to_toml

    path.write_text(to_toml(_stepped(duration=1.5)))
    hist = tmp_path / "h.csv"
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(path), "--json", "--no-check", "--history", str(hist)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    assert data["facade"]["struck"] in ("left", "right")
    assert all("facade" in row for row in data["required_per_storey"])
    header = hist.read_text().splitlines()[0].split(",")
    assert header == ["time", "clearance_left_slab_1_right_facade_storey_2", "clearance_right_slab_1_left_facade_storey_1"]
    text = subprocess.run([sys.executable, "-m", "pounding", "gap", str(path), "--no-check"], capture_output=True, text=True, timeout=120)
    assert text.returncode == 0 and "against the facade of" in text.stdout


def test_a_stepped_building_between_two_equal_ones_screens_them_and_faces_both():
    """A row: "left" (one 3.0 m storey), "middle" (two 2.0 m storeys), "right" (one 3.0 m storey), 0.02 m apart
    along x. left and right share the level 3.0 m, but middle's facade stands between them there: screened.
    left-middle and middle-right share no level yet meet at the facades: both adjacent. Each pair's required
    gap from the run of the row equals the pair's run alone (without contact the buildings are independent:
    the same modal histories, so the same numbers to the rounding of the report, 1e-12 relative)."""
    from pounding.framework.model.placement import facing_storeys, pair_scene
    from pounding.framework.studies.gap import minimum_gaps
    from scenes_for_tests import box_building

    data = _stepped(duration=1.5)
    data["building"][1]["name"] = "middle"
    third = box_building("right", 22.04, 10.0, 10.0, 1, 0.3, 0.5)
    third["storey_heights"] = [3.0]
    data["building"].append(third)
    sc = build(data)
    assert adjacent_pairs(sc) == ([(0, 1), (1, 2)], [(0, 2)])
    assert facing_storeys(sc, 0, 2) == [] and pair_sites(*sc.buildings[::2]) == [(0, 0)]
    row = minimum_gaps(sc)
    assert [r.buildings for r in row.reports] == [("left", "middle"), ("middle", "right")] and row.screened == [("left", "right")]
    for r, (i, j) in zip(row.reports, [(0, 1), (1, 2)]):
        alone = minimum_gap(pair_scene(sc, i, j))
        assert r.min_gap == pytest.approx(alone.min_gap, rel=1e-12) and r.facade == alone.facade
        assert r.facade is not None and r.current_gap == pytest.approx(0.02, abs=1e-12)
