"""Separation-gap design (`pounding gap`): the smallest gap at which no slabs touch, and the code estimates."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pounding.contact.geometry import ccw, signed_gap
from pounding.errors import InputError
from pounding.framework.post.run import run
from pounding.framework.model.placement import direction_vector, rest_gap, translation_to_contact, with_gap
from pounding.framework.studies.gap import correlation, minimum_gap, no_contact, verify_gap
from pounding.io.scene import load_scene
from scenes_for_tests import scene as build, side_by_side

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"


@pytest.fixture(scope="module")
def symmetric_pair():
    """Two single-storey symmetric buildings side by side along x, 0.02 m apart, shaken along x (no rotation)."""
    return build(side_by_side(0.02, duration=4.0, columns=(0.3, 0.55), columns_y=(0.5, 0.6), pga=0.5))


@pytest.fixture(scope="module")
def paper6():
    """The paper's pair (gap 0.03 m), first 6 s."""
    return load_scene(PAPER).with_analysis(duration=6.0)


@pytest.fixture(scope="module")
def paper6_report(paper6):
    return minimum_gap(paper6)


# --------------------------------------------------------------------------- geometry
def test_translation_along_a_direction_of_two_squares():
    """Unit square A; B a unit square 0.5 m to its right: B must move back 0.5 m along +x to touch; along y it never does."""
    A = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    B = A + [1.5, 0.0]
    delta, info = translation_to_contact(A, B, [1.0, 0.0])
    assert delta == pytest.approx(-0.5, abs=1e-15)
    assert translation_to_contact(A, B, [0.0, 1.0])[0] == -np.inf
    # B beyond A along d: the last contact moving B backwards along -x is 2.5 m the other way
    assert translation_to_contact(A, B, [-1.0, 0.0])[0] == pytest.approx(2.5, abs=1e-15)
    # a diamond whose left corner (2, 0.5) points at A's face x = 1: the corner strikes
    D = np.array([[2.0, 0.5], [2.5, 0.0], [3.0, 0.5], [2.5, 1.0]])
    delta, info = translation_to_contact(A, D, [1.0, 0.0])
    assert delta == pytest.approx(-1.0, abs=1e-15)
    assert int(info["who"]) == 1 and int(info["vertex"]) == 0 and int(info["edge"]) == 1


def test_translation_through_a_non_convex_slab():
    """A C-shaped slab with a notch x in [5, 10], y in [4, 6]; a small slab B sits in the notch.

    Along +x B escapes through the opening (last contact 1 m back, at the notch bottom); along +y it
    must cross the solid part and leaves it at y = 10 (5.5 m on).
    """
    A = np.array([[0, 0], [10, 0], [10, 4], [5, 4], [5, 6], [10, 6], [10, 10], [0, 10]], dtype=float)
    B = np.array([[6, 4.5], [8, 4.5], [8, 5.5], [6, 5.5]], dtype=float)
    assert translation_to_contact(A, B, [1.0, 0.0])[0] == pytest.approx(-1.0, abs=1e-14)
    assert translation_to_contact(A, B, [0.0, 1.0])[0] == pytest.approx(5.5, abs=1e-14)
    assert translation_to_contact(A, B, [0.0, -1.0])[0] == pytest.approx(5.5, abs=1e-14)


def test_translation_is_where_the_signed_gap_closes_for_random_polygons():
    """For random convex polygons and directions, B moved to the answer touches A, a bit further it is clear, a bit less it overlaps."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(7)
    for _ in range(40):
        pa = rng.normal(size=(9, 2))
        pb = rng.normal(size=(9, 2)) + rng.normal(scale=0.5, size=2)
        A = ccw(pa[ConvexHull(pa).vertices])
        B = ccw(pb[ConvexHull(pb).vertices])
        ang = rng.uniform(0, 2 * np.pi)
        d = np.array([np.cos(ang), np.sin(ang)])
        delta, _ = translation_to_contact(A, B, d)
        assert np.isfinite(delta)
        assert abs(signed_gap(A, B + delta * d)) < 1e-9
        assert signed_gap(A, B + (delta + 1e-4) * d) > 0
        assert signed_gap(A, B + (delta - 1e-4) * d) < 0


def test_translation_is_vectorised_over_time():
    A = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    shifts = np.linspace(1.2, 2.0, 5)
    B = np.stack([A + [s, 0.0] for s in shifts])  # (5, 4, 2)
    delta, info = translation_to_contact(A[None], B, [1.0, 0.0])
    assert delta.shape == (5,) and np.allclose(delta, 1.0 - shifts, rtol=0, atol=1e-15)


def test_direction_parsing():
    assert np.array_equal(direction_vector("x"), [1.0, 0.0]) and np.array_equal(direction_vector("y"), [0.0, 1.0])
    assert np.array_equal(direction_vector("180"), [-1.0, 0.0])
    assert np.allclose(direction_vector(30.0), [math.cos(math.pi / 6), 0.5])
    assert direction_vector(None) is None
    with pytest.raises(InputError):
        direction_vector("diagonal")


# --------------------------------------------------------------------------- closed form
def test_minimum_gap_is_the_peak_relative_displacement_without_rotation(symmetric_pair):
    """Two single-storey symmetric buildings shaken along x, "left" on the left: min gap = max_t (u_left - u_right),
    over the continuous trajectory (the closed-form extreme of the integrator's interpolant in each step,
    :mod:`pounding.framework.engine.peaks`), which the step ends bound from below.

    The gap search maximises the translation to contact (here u_left - u_right, linear in q) by a bounded
    Brent search on each step's fraction (xatol 1e-10): the value then differs from the closed-form
    extreme by <= |y''| (1e-10 h)^2 / 2, far below 1e-12 of the peak; the same modal sums in another
    order leave ~1e-15 (eps times a few terms), hence rel 1e-12."""
    from pounding.framework.engine import peaks

    res = run(no_contact(symmetric_pair))
    cm_l, cm_r = res.cm("left")[:, 0], res.cm("right")[:, 0]
    assert np.max(np.abs(cm_l[:, 1:])) == 0.0 and np.max(np.abs(cm_r[:, 1:])) == 0.0  # no v, no rotation
    report = minimum_gap(symmetric_pair)
    seg = peaks.segments(res)
    n_l = res.systems[0].n_dof
    rel_row = np.concatenate([res.systems[0].modes[0], -res.systems[1].modes[0]])  # u_left - u_right
    expected = peaks.abs_peaks(seg, rel_row[None, :], signed=True)[0]
    step_ends = np.max(cm_l[:, 0] - cm_r[:, 0])
    assert expected >= step_ends
    assert report.min_gap == pytest.approx(expected, rel=1e-12, abs=1e-14)
    k = int(np.argmax(cm_l[:, 0] - cm_r[:, 0]))
    assert res.t[k - 1] <= report.time <= res.t[k + 1]  # inside a step next to the largest step end
    assert report.current_gap == pytest.approx(0.02, abs=1e-12)
    assert np.array_equal(report.direction, [1.0, 0.0]) and report.storey == 1 and report.buildings == ("left", "right")
    # the clear distance history along x is the rest gap minus the relative displacement, at the step ends
    assert np.allclose(report.clearance[:, 0], 0.02 - (cm_l[:, 0] - cm_r[:, 0]), rtol=0, atol=1e-13)
    assert report.min_gap_grid == pytest.approx(step_ends, rel=1e-12, abs=1e-14)
    # the facing points are the facades: without rotation their peaks are the peak displacements (continuous)
    assert report.peaks == pytest.approx((res.peaks("left")[0, 0], res.peaks("right")[0, 0]), rel=1e-12)
    assert n_l == res.mode_start[1]


def test_rotation_moves_the_governing_point_to_a_corner(paper6, paper6_report):
    """The paper's pair twists: the gap is governed by slab corners, not by the centres of mass.

    Both facades are nearly straight lines at x = 15 and 15.03 spanning y in [0, 10], so the clear
    distance along x is almost the smaller of the distances between facing corners.
    """
    r = paper6_report
    res = run(no_contact(paper6))
    corners, centres = -np.inf, -np.inf
    for f in range(3):
        vl, vh = res.vertices("low")[:, f], res.vertices("high")[:, f]
        corners = max(corners, np.max(np.maximum(vl[:, 1, 0] - vh[:, 0, 0], vl[:, 2, 0] - vh[:, 3, 0])))
        centres = max(centres, np.max(res.cm("low")[:, f, 0] - res.cm("high")[:, f, 0]))
    assert r.min_gap == pytest.approx(corners, rel=1e-3)
    assert r.min_gap > centres + 0.005  # torsion adds more than 5 mm here
    assert r.vertex in (0, 3) if r.striking == "high" else r.vertex in (1, 2)
    assert r.point[0] == pytest.approx(15.0, abs=0.1)
    assert [g[0] for g in r.required] == [1, 2, 3] and max(g[2] for g in r.required) == pytest.approx(r.min_gap)


# --------------------------------------------------------------------------- check and placement
def test_impacts_just_below_the_minimum_gap_and_none_just_above(symmetric_pair, paper6, paper6_report):
    for sc, rep in ((symmetric_pair, minimum_gap(symmetric_pair)), (paper6, paper6_report)):
        check = verify_gap(sc, rep)
        assert check.n_impacts[0] > 0, check
        assert check.n_impacts[1] == 0, check
        assert check.ok and rep.check is check
        assert check.gaps == pytest.approx((0.99 * rep.min_gap, 1.01 * rep.min_gap))


def test_with_gap_places_the_second_building(paper6):
    moved = with_gap(paper6, 0.2)
    g, d = rest_gap(moved)
    assert g == pytest.approx(0.2, abs=1e-12) and np.array_equal(d, [1.0, 0.0])
    assert moved.building("high").slabs[0].vertices[0] == pytest.approx([15.2, 0.0])
    assert moved.building("high").elements[0].point == pytest.approx([15.2, 0.0])
    # the direction is oriented from the first building to the second whichever sign is given
    assert np.array_equal(rest_gap(paper6, "-x")[1], [1.0, 0.0])
    with pytest.raises(InputError, match="do not face"):
        rest_gap(paper6, "y")


# --------------------------------------------------------------------------- code estimates
def test_correlation_coefficient():
    """Der Kiureghian's CQC correlation: 1 for equal oscillators, symmetric, the equal-damping form, small when far apart."""
    assert correlation(0.5, 0.5, 0.05, 0.05) == pytest.approx(1.0, abs=1e-15)
    assert correlation(0.4, 0.9, 0.03, 0.07) == pytest.approx(correlation(0.9, 0.4, 0.07, 0.03), rel=1e-13)
    z, r = 0.05, 0.5
    assert correlation(r, 1.0, z, z) == pytest.approx(8 * z**2 * (1 + r) * r**1.5 / ((1 - r**2) ** 2 + 4 * z**2 * r * (1 + r) ** 2), rel=1e-14)
    assert correlation(0.3, 1.2, 0.05, 0.05) < 0.02


def test_code_estimates_are_ordered(paper6_report):
    r = paper6_report
    ua, ub = r.peaks
    assert r.abs == pytest.approx(ua + ub) and r.srss == pytest.approx(math.hypot(ua, ub))
    assert r.abs >= r.srss >= r.ddc >= abs(ua - ub)
    assert r.ddc == pytest.approx(math.sqrt(ua**2 + ub**2 - 2 * r.rho * ua * ub))
    assert 0 <= r.rho <= 1 and r.periods[0] < r.periods[1]  # the 3-storey building is the stiffer
    assert r.abs >= r.min_gap  # the absolute sum bounds the time-history answer


# --------------------------------------------------------------------------- command line
def test_cli_json_has_the_documented_keys():
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(PAPER), "--json", "--duration", "4"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    for key in ("min_gap", "current_gap", "direction", "storey", "time", "abs", "srss", "ddc"):
        assert key in data
    assert data["current_gap"] == pytest.approx(0.03) and data["direction"] == [1.0, 0.0]
    assert 0.03 < data["min_gap"] < data["abs"] and data["storey"] in (1, 2, 3)
    assert data["check"]["ok"] is True and data["check"]["above"]["n_impacts"] == 0


def test_cli_text_history_and_bad_direction(tmp_path):
    """The clear-distance history (--history, at the step ends) closes exactly to the minimum gap over the step ends:
    min clearance = current gap - min_gap_step_ends; the continuous minimum gap is at least that."""
    hist = tmp_path / "clearance.csv"
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(PAPER), "--duration", "2", "--no-check", "--direction", "x",
                           "--history", str(hist), "--json"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    table = np.loadtxt(hist, delimiter=",", skiprows=1)
    assert table.shape == (401, 4) and table[1, 0] == 0.005
    assert np.min(table[:, 1:]) == pytest.approx(data["current_gap"] - data["min_gap_step_ends"], abs=1e-15)
    assert data["min_gap"] >= data["min_gap_step_ends"]
    assert np.argmin(np.min(table[:, 1:], axis=0)) + 1 == data["storey"]
    proc = subprocess.run([sys.executable, "-m", "pounding", "gap", str(PAPER), "--duration", "2", "--no-check"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "minimum gap" in proc.stdout and "DDC" in proc.stdout and "SRSS" in proc.stdout
    bad = subprocess.run([sys.executable, "-m", "pounding", "gap", str(PAPER), "--direction", "y"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "--direction" in bad.stderr and bad.stdout == ""
