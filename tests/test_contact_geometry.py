"""Contact geometry of slab polygons (pounding.contact.geometry): hand-checked values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pounding.contact import geometry as geo


def rect(x0, y0, w, h):
    return np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]], dtype=float)


def rotate(P, angle, about=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return (np.asarray(P, float) - about) @ R.T + about


def square_at(center, side, angle):
    """Square of the given side centred at ``center``, rotated by ``angle`` (ccw)."""
    return rotate(rect(-side / 2, -side / 2, side, side), angle) + center


# L-shape: [0,4]x[0,1] plus [0,1]x[1,3]
L_SHAPE = np.array([[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]], dtype=float)
# U-shape: 5 x 3 with a 3 x 2 notch open at the top, walls x in [0,1] and [4,5]
U_SHAPE = np.array([[0, 0], [5, 0], [5, 3], [4, 3], [4, 1], [1, 1], [1, 3], [0, 3]], dtype=float)


# the compiled dispatchers, captured before any test patches the module
COMPILED = {name: getattr(geo, name) for name in ("signed_gap", "contact_points", "displaced")}


@pytest.fixture
def pure_python(monkeypatch):
    """Make every compiled kernel of the module resolve to its pure-Python function."""
    for name in dir(geo):
        obj = getattr(geo, name)
        if hasattr(obj, "py_func") and obj.py_func is not obj:
            monkeypatch.setattr(geo, name, obj.py_func)
    return geo


# ---------------------------------------------------------------- polygon properties


def test_rectangle_properties():
    """4 x 2 rectangle at (1, 3): A = 8, centroid (3, 4), J = b h (b^2 + h^2)/12 = 40/3."""
    area, c, J = geo.polygon_properties(rect(1, 3, 4, 2))
    assert area == pytest.approx(8.0, rel=1e-14)
    np.testing.assert_allclose(c, [3.0, 4.0], rtol=1e-14)
    assert J == pytest.approx(4 * 2 * (16 + 4) / 12, rel=1e-13)


def test_l_shape_properties():
    """L = [0,4]x[0,1] + [0,1]x[1,3]: A = 6, centroid (1.5, 1).

    J by parallel axes = 68/12 + 4*0.5 + 10/12 + 2*2 = 12.5.
    """
    area, c, J = geo.polygon_properties(L_SHAPE)
    assert area == pytest.approx(6.0, rel=1e-14)
    np.testing.assert_allclose(c, [1.5, 1.0], rtol=1e-14)
    # parallel axes: each rectangle's own J plus its area times the squared centroid offset
    J1 = 4 * 1 * (16 + 1) / 12 + 4 * ((2 - 1.5) ** 2 + (0.5 - 1) ** 2)
    J2 = 1 * 2 * (1 + 4) / 12 + 2 * ((0.5 - 1.5) ** 2 + (2 - 1) ** 2)
    assert J1 + J2 == pytest.approx(12.5)
    assert J == pytest.approx(12.5, rel=1e-13)


def test_rotated_rectangle_properties_invariant():
    """Rotating the 4 x 2 rectangle by 0.7 rad about (-2, 5): A = 8 and J = 40/3 unchanged, centroid
    rotated.
    """
    P = rotate(rect(1, 3, 4, 2), 0.7, about=(-2.0, 5.0))
    area, c, J = geo.polygon_properties(P)
    assert area == pytest.approx(8.0, rel=1e-13)
    np.testing.assert_allclose(c, rotate([[3.0, 4.0]], 0.7, about=(-2.0, 5.0))[0], rtol=1e-13)
    assert J == pytest.approx(40.0 / 3.0, rel=1e-12)


def test_vertex_order_does_not_matter():
    """The clockwise L-shape has the same A = 6, centroid (1.5, 1), J = 12.5; ccw() keeps vertex 0
    first.
    """
    cw = L_SHAPE[::-1]
    area, c, J = geo.polygon_properties(cw)
    assert area == pytest.approx(6.0) and J == pytest.approx(12.5)
    np.testing.assert_allclose(c, [1.5, 1.0])
    P = geo.ccw(cw)
    assert geo._signed_area(P) > 0.0
    np.testing.assert_array_equal(P[0], cw[0])
    np.testing.assert_array_equal(geo.ccw(L_SHAPE), L_SHAPE)
    # and gaps do not depend on the order the user gave
    B = rect(4.3, 0.2, 1, 1)
    assert geo.signed_gap(geo.ccw(cw), B) == pytest.approx(0.3, abs=1e-14)


@pytest.mark.parametrize(
    "vertices, ok, word",
    [
        (L_SHAPE, True, ""),
        ([[0, 0], [2, 2], [2, 0], [0, 1]], False, "intersect"),  # bow tie
        ([[0, 0], [1, 0], [1, 0], [1, 1]], False, "repeats"),
        ([[0, 0], [1, 0], [2, 0]], False, "zero area"),
        ([[0, 0], [2, 0], [1, 0], [1, 1]], False, "fold back"),  # spike back along an edge
        ([[0, 0], [2, 0], [2, 2], [1, 0.0], [0, 2]], False, "intersect"),  # vertex touching an edge
    ],
)
def test_is_simple(vertices, ok, word):
    """Simple polygons pass; a bow tie, a repeated vertex, zero area, a spike or a touching vertex
    fail.
    """
    got, reason = geo.is_simple(vertices)
    assert got is ok
    assert word in reason


# ---------------------------------------------------------------- kinematics and gaps


def test_displaced_is_the_rigid_map():
    """A slab with c = (1, 1), u = 0.01, v = -0.02, phi = 0.001: a vertex P goes to
    c + (u, v) + R(phi) (P - c), to rounding (1e-15 m on coordinates of a few metres); and at
    phi = 0 a vertex keeps its coordinates plus the translation to the bit."""
    P = np.array([[3.0, 1.0], [1.0, 4.0], [0.0, 0.0]])
    c, phi = np.array([1.0, 1.0]), 0.001
    R = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    out = geo.displaced(P, c, 0.01, -0.02, phi)
    np.testing.assert_allclose(out, c + np.array([0.01, -0.02]) + (P - c) @ R.T, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(geo.displaced(P, c, 0.25, -0.5, 0.0), P + np.array([0.25, -0.5]))


def test_two_squares_apart():
    """Unit squares 0.1 apart along x: gap 0.1 (either argument order)."""
    A, B = rect(0, 0, 1, 1), rect(1.1, 0.3, 1, 1)
    assert geo.signed_gap(A, B) == pytest.approx(0.1, abs=1e-14)
    assert geo.signed_gap(B, A) == pytest.approx(0.1, abs=1e-14)


def test_rotated_corner_approaching_an_edge():
    """Unit square rotated 30°, centred at (3, 0.5): nearest corner at x = 3 - cos(15°)/sqrt(2),
    gap = 2 - cos(15°)/sqrt(2).
    """
    B = square_at((3.0, 0.5), 1.0, math.radians(30))
    xmin = 3.0 - math.sqrt(0.5) * math.cos(math.radians(15))  # the corner at 165° from the centre
    assert B[:, 0].min() == pytest.approx(xmin)
    assert geo.signed_gap(rect(0, 0, 1, 1), B) == pytest.approx(xmin - 1.0, abs=1e-13)


def test_overlap_depth():
    """Unit squares overlapping by 0.02 along x (offset 0.3 along y): gap -0.02."""
    gap = geo.signed_gap(rect(0, 0, 1, 1), rect(0.98, 0.3, 1, 1))
    assert gap == pytest.approx(-0.02, abs=1e-14)


@pytest.mark.parametrize("dy", [0.0, 1e-9, -1e-9])
def test_overlap_depth_collinear_facades(dy):
    """Equal-depth slabs side by side (facades collinear, or off by 1e-9) overlapping by 0.02: gap
    -0.02, not ~0.
    """
    assert geo.signed_gap(rect(0, 0, 1, 1), rect(0.98, dy, 1, 1)) == pytest.approx(-0.02, abs=1e-12)


def test_square_in_u_notch():
    """Square [2.8,3.6]x[1.7,2.5] in the U's notch (walls x = 1, 4; floor y = 1): gap 4 - 3.6 = 0.4."""
    S = rect(2.8, 1.7, 0.8, 0.8)
    assert geo.signed_gap(U_SHAPE, S) == pytest.approx(0.4, abs=1e-14)
    assert geo.signed_gap(S, U_SHAPE) == pytest.approx(0.4, abs=1e-14)


def test_plus_sign_overlap_is_negative():
    """Bars [-2,2]x[-0.5,0.5] and [-0.3,0.3]x[-2,2] cross with no vertex inside: gap -0.5 (midpoint
    rule).
    """
    A = rect(-2, -0.5, 4, 1)
    B = rect(-0.3, -2, 0.6, 4)
    assert geo.signed_gap(A, B) == pytest.approx(-0.5)
    n, Q, N, gap, who, idx, pair = geo.contact_points(A, B, 1e-3)
    assert n >= 1 and np.all(idx[:n] == -1) and gap[0] == pytest.approx(-0.5)


@pytest.mark.parametrize(
    "B0",
    [square_at((1.0 + math.sqrt(0.5), 0.5), 1.0, math.radians(45)),  # corner onto an edge
     rect(1.0, 0.0, 1, 1)],  # collinear facades, face to face
    ids=["corner", "facades"],
)
def test_gap_is_linear_through_contact(B0):
    """Translating B along x by -d, 0, +d from first contact gives gaps -d, 0, +d (d = 1e-3)."""
    A = rect(0, 0, 1, 1)
    assert geo.signed_gap(A, B0) == pytest.approx(0.0, abs=1e-14)
    for d in (-1e-3, 1e-3):
        assert geo.signed_gap(A, B0 + [d, 0.0]) == pytest.approx(d, abs=1e-13)


# ---------------------------------------------------------------- contact features


def test_vertex_edge_contact_of_b():
    """Diamond corner (vertex 1 of B) 5e-4 from A's right edge x = 1: Q = (1.0005, 0.5), n = (1, 0),
    who 1.
    """
    B = square_at((1.0005 + math.sqrt(0.5), 0.5), 1.0, math.radians(45 + 180))
    n, Q, N, gap, who, idx, pair = geo.contact_points(rect(0, 0, 1, 1), B, 1e-3)
    assert n == 1
    assert who[0] == 1 and pair[0] == -1
    assert idx[0] == int(np.argmin(B[:, 0]))
    np.testing.assert_allclose(Q[0], [1.0005, 0.5], atol=1e-14)
    np.testing.assert_allclose(N[0], [1.0, 0.0], atol=1e-14)
    assert gap[0] == pytest.approx(5e-4, abs=1e-14)


def test_vertex_edge_contact_of_a_penetrating():
    """A diamond's corner (vertex of A) 2e-4 past B's left edge x = 2: who 0, n = (1, 0) (minus B's
    normal), gap -2e-4.
    """
    A = square_at((2.0002 - math.sqrt(0.5), 0.5), 1.0, math.radians(45))
    n, Q, N, gap, who, idx, pair = geo.contact_points(A, rect(2, 0, 1, 1), 1e-3)
    assert n == 1 and who[0] == 0
    assert idx[0] == int(np.argmax(A[:, 0]))
    np.testing.assert_allclose(Q[0], [2.0002, 0.5], atol=1e-14)
    np.testing.assert_allclose(N[0], [1.0, 0.0], atol=1e-14)
    assert gap[0] == pytest.approx(-2e-4, abs=1e-14)


def test_vertex_vertex_contact():
    """Unit squares corner to corner at (1, 1): one feature, B's vertex 0, normal the bisector (1,
    1)/sqrt(2).
    """
    n, Q, N, gap, who, idx, pair = geo.contact_points(rect(0, 0, 1, 1), rect(1, 1, 1, 1), 1e-6)
    assert n == 1 and who[0] == 1 and idx[0] == 0
    np.testing.assert_allclose(Q[0], [1.0, 1.0])
    np.testing.assert_allclose(N[0], [math.sqrt(0.5)] * 2)
    assert gap[0] == 0.0


@pytest.mark.parametrize("turn", [6e-4, -6e-4, 9e-4])  # (within the face angle, 1e-3 rad)
def test_face_end_normals_are_the_gradients_of_their_gaps(turn):
    """A face pressed with its slabs turned a little against each other (A's edge and B's edge at an angle
    ``turn`` [rad], B slid along the face so that one end is A's vertex and the other B's): each end's gap
    moves, as B moves rigidly by (dx, dy, dphi) about its centre c, by N . (dx, dy) + dphi (Q - c) x N, the
    row of its own normal N and point Q. That makes a force along N at each end the gradient of a potential
    of the two gaps (an elastic face contact creates no energy around a closed path). Central differences
    at h = 1e-7 m (and rad) carry an error of order h^2 times the gap's curvature over 1 m (1e-14) and
    rounding of order eps / h times the coordinates (2e-9): 1e-7 of the gradient's unit size is asserted."""
    A = rect(0.0, 0.0, 1.0, 1.0)

    def features(dx, dy, dphi):
        B = rotate(rect(0.995, 0.2, 1.0, 1.0), turn + dphi, about=(1.495, 0.7)) + np.array([dx, dy])
        n, Q, N, gap, who, idx, pair = geo.contact_points(A, B, 2e-2)
        order = np.argsort(Q[:n, 1])  # the ends by height: the same two in every probe
        return Q[:n][order], N[:n][order], gap[:n][order], who[:n][order], pair[:n][order]

    Q, N, gap, who, pair = features(0.0, 0.0, 0.0)
    assert len(gap) == 2 and list(pair) == [0, 0] and set(who) == {0, 1} and np.all(gap < 0)
    c = np.array([1.495, 0.7])
    h = 1e-7
    for k, unit in enumerate(np.eye(3)):
        fd = (features(*(h * unit))[2] - features(*(-h * unit))[2]) / (2 * h)
        row = N[:, 0] * unit[0] + N[:, 1] * unit[1] + unit[2] * ((Q[:, 0] - c[0]) * N[:, 1] - (Q[:, 1] - c[1]) * N[:, 0])
        np.testing.assert_allclose(fd, row, rtol=0, atol=1e-7, err_msg=f"dof {k}")


def test_face_to_face_reports_overlap_end_points():
    """A = [0,1]^2, B = [1.0005,2]x[0.4,1.6]: faces overlap for y in [0.4, 1]; ends B's vertex 0 and
    A's vertex 2.
    """
    B = rect(1.0005, 0.4, 0.9995, 1.2)
    n, Q, N, gap, who, idx, pair = geo.contact_points(rect(0, 0, 1, 1), B, 1e-3)
    assert n == 2
    assert list(pair[:2]) == [0, 0]
    assert (who[0], idx[0]) == (1, 0)
    np.testing.assert_allclose(Q[0], [1.0005, 0.4])
    assert (who[1], idx[1]) == (0, 2)
    np.testing.assert_allclose(Q[1], [1.0, 1.0])
    np.testing.assert_allclose(N[:2], [[1.0, 0.0], [1.0, 0.0]], atol=1e-15)
    np.testing.assert_allclose(gap[:2], [5e-4, 5e-4], atol=1e-14)


def test_no_features_beyond_tolerance():
    """Squares 0.1 apart with tol = 1e-3: no feature."""
    assert geo.contact_points(rect(0, 0, 1, 1), rect(1.1, 0, 1, 1), 1e-3)[0] == 0


def test_features_agree_with_signed_gap():
    """Square squeezed into the U notch (0.02 into both walls): four face-to-face ends, gaps -0.02 =
    signed_gap.
    """
    S = rect(0.98, 1.5, 3.04, 1.0)
    g0 = geo.signed_gap(U_SHAPE, S)
    n, Q, N, gap, who, idx, pair = geo.contact_points(U_SHAPE, S, 1e-3)
    assert g0 == pytest.approx(-0.02)
    assert n == 4 and sorted(pair[:4]) == [0, 0, 1, 1]
    np.testing.assert_allclose(gap[:n], g0, atol=1e-12)
    assert sorted(N[:n, 0]) == pytest.approx([-1, -1, 1, 1])


# ---------------------------------------------------------------- clearance bound


def test_clearance_bound_is_below_gap():
    """1000 random small motions (seed 0) of rectangle/L pairs 0.05 apart: clearance_bound <=
    signed_gap.
    """
    rng = np.random.default_rng(0)
    A = rect(0, 0, 12, 8)
    shapes = [rect(12.05, 1.0, 10, 6), L_SHAPE * 3 + [12.05, 0.0], rect(12.05, 0.0, 10, 8)]
    overlapping = 0
    for case in range(1000):
        B = shapes[case % 3]
        d_rest = geo.signed_gap(A, B)
        assert d_rest == pytest.approx(0.05)
        cA, cB = geo.polygon_properties(A)[1], geo.polygon_properties(B)[1]
        RA, RB = geo.radius(A, cA), geo.radius(B, cB)
        u1, v1, u2, v2 = rng.normal(scale=0.03, size=4)
        p1, p2 = rng.normal(scale=2e-3, size=2)
        gap = geo.signed_gap(geo.displaced(A, cA, u1, v1, p1), geo.displaced(B, cB, u2, v2, p2))
        bound = geo.clearance_bound(d_rest, u1, v1, p1, RA, u2, v2, p2, RB)
        assert bound <= gap
        overlapping += gap < 0
    assert overlapping > 50  # the overlapping regime is exercised too


def test_clearance_bound_ignores_a_common_translation():
    """Two slabs translating together keep their gap, and the bound keeps the rest gap: only the
    relative translation and the rotations count."""
    A, B = rect(0, 0, 12, 8), rect(12.05, 1.0, 10, 6)
    cA, cB = geo.polygon_properties(A)[1], geo.polygon_properties(B)[1]
    RA, RB = geo.radius(A, cA), geo.radius(B, cB)
    bound = geo.clearance_bound(0.05, 0.3, -0.2, 0.0, RA, 0.3, -0.2, 0.0, RB)
    assert bound == 0.05
    assert geo.signed_gap(geo.displaced(A, cA, 0.3, -0.2, 0.0), geo.displaced(B, cB, 0.3, -0.2, 0.0)) == pytest.approx(0.05, abs=1e-12)


# ---------------------------------------------------------------- compiled vs pure Python


def _random_cases(n, seed=1):
    rng = np.random.default_rng(seed)
    shapes = [rect(0, 0, 1, 1), L_SHAPE / 3, U_SHAPE / 5]
    for _ in range(n):
        A = geo.ccw(shapes[rng.integers(3)])
        B = geo.ccw(rotate(shapes[rng.integers(3)], rng.choice([0.0, rng.uniform(0, 6.3)])))
        B = B - B.mean(axis=0) + A.mean(axis=0) + rng.uniform(-1.5, 1.5, 2)
        yield A, B


def test_numba_and_python_agree(pure_python):
    """signed_gap, contact_points, displaced: bit-identical compiled and in pure Python (py_func)."""
    if COMPILED["signed_gap"] is COMPILED["signed_gap"].py_func:
        pytest.skip("numba is not compiling here (missing or NUMBA_DISABLE_JIT): a single path")
    for A, B in _random_cases(200):
        assert pure_python.signed_gap(A, B) == COMPILED["signed_gap"](A, B)
        py = pure_python.contact_points(A, B, 1e-2)
        for a, b in zip(py, COMPILED["contact_points"](A, B, 1e-2)):
            np.testing.assert_array_equal(a, b)
    A, c = rect(0, 0, 3, 2), np.array([1.5, 1.0])
    args = (A, c, 0.01, 0.02, 0.003)
    np.testing.assert_array_equal(pure_python.displaced(*args), COMPILED["displaced"](*args))


def _table_gap(A, B):
    """The smallest gap of the full feature table (:func:`_candidates`): what signed_gap returned
    before it had a path for polygons that are apart."""
    c, F, _ = geo._candidates(A, B, geo._tolerance(A, B))
    return min(F[:c, geo._F_GAP])


def test_apart_path_gives_the_feature_tables_gap():
    """signed_gap takes a short path when the polygons are apart (every vertex outside the other by
    more than eps, no edges crossing); it must return the full feature table's number to the bit,
    and decline (-inf) whenever the polygons touch or overlap. Cases: the L, U and rectangles of the
    module at random small motions around contact (seed 1), collinear facades, and the plus sign,
    whose boundaries cross with every vertex far outside."""
    rng = np.random.default_rng(1)
    A = rect(0, 0, 12, 8)
    shapes = [rect(12.05, 1.0, 10, 6), L_SHAPE * 3 + [12.05, 0.0], rect(12.05, 0.0, 10, 8), U_SHAPE * 2 + [12.05, 0.0]]
    taken = declined = 0
    for case in range(2000):
        B = shapes[case % len(shapes)]
        cA, cB = geo.polygon_properties(A)[1], geo.polygon_properties(B)[1]
        u1, v1, u2, v2 = rng.normal(scale=0.03, size=4)
        p1, p2 = rng.normal(scale=2e-3, size=2)
        Ad, Bd = geo.displaced(A, cA, u1, v1, p1), geo.displaced(B, cB, u2, v2, p2)
        fast = geo._apart_gap(Ad, Bd, geo._tolerance(Ad, Bd))
        full = _table_gap(Ad, Bd)
        assert geo.signed_gap(Ad, Bd) == full
        if fast > -np.inf:
            taken += 1
            assert fast == full and full > 0
        else:
            declined += 1
    assert taken > 1000 and declined > 100  # both paths are exercised (1679 and 321 with this seed)
    plus_a, plus_b = rect(-5, -0.5, 10, 1), rect(-0.5, -5, 1, 10)
    assert geo._apart_gap(plus_a, plus_b, geo._tolerance(plus_a, plus_b)) == -np.inf
    assert geo.signed_gap(plus_a, plus_b) == _table_gap(plus_a, plus_b) < 0
    side_a, side_b = rect(0, 0, 10, 10), rect(10.05, 0, 10, 10)  # collinear top and bottom edges, 0.05 apart
    assert geo._apart_gap(side_a, side_b, geo._tolerance(side_a, side_b)) == pytest.approx(0.05, abs=1e-12)


def test_a_contact_row_is_the_gradient_of_the_gap_on_turned_slabs():
    """The modal row w of a contact is the gradient of the gap the geometry computes: for the
    pointed pair with both slabs turned (0.008 and -0.012 rad) and pressed 10 um, central
    differences of the gap along random modal directions dq equal w . dq. The slabs turn exactly
    (:func:`displaced`), so the lever arm of the contact point about a slab's displaced centre,
    which the row takes, is its exact derivative; with the linearised turn the same row was off
    by phi |r|: 7e-3 of |w| |dq| here.

    Tolerance 1e-7 of |w| |dq| = 1 um: the gap's rounding, a few ulps of the 20 m coordinates
    (4 x 2.2e-16 x 20 m = 1.8e-14 m) over 1 um is 2e-8; the central difference's error is third
    order in the turns the step makes (2e-7 rad over 5 m arms), far below it."""
    from scenes_for_tests import modal_from_physical, pointed_pair, scene
    from pounding.framework.engine import pairs as pg
    from pounding.framework.engine.stacked_model import Model

    m = Model(scene(pointed_pair(tip_y=3.0)))
    u_right = 0.0
    for _ in range(3):  # press the tip 10 um into the turned face
        q = modal_from_physical(m, {(0, 0): (0.0, 0.0, 0.008), (1, 0): (u_right, 0.0, -0.012)})
        u_right -= float(pg.pair_gap(q, 0, np.inf, m.geo)) + 1e-5
    q = modal_from_physical(m, {(0, 0): (0.0, 0.0, 0.008), (1, 0): (u_right, 0.0, -0.012)})
    touching = pg.pair_features(q, 0, 1e-4, m.n, m.geo)
    count, gap, W = touching.count, touching.gap, touching.W
    assert count == 1 and gap[0] == pytest.approx(-1e-5, rel=1e-3)
    rng = np.random.default_rng(7)
    for _ in range(8):
        dq = rng.standard_normal(m.n)
        dq *= 1e-6 / (np.linalg.norm(W[0]) * np.linalg.norm(dq))
        central = 0.5 * (pg.pair_gap(q + dq, 0, np.inf, m.geo) - pg.pair_gap(q - dq, 0, np.inf, m.geo))
        assert abs(central - W[0] @ dq) <= 1e-7 * 1e-6
