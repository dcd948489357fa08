"""Practice in the model: element stiffness modifiers and P-Delta from gravity loads.

P-Delta is a storey geometric stiffness (pounding.framework.model.pdelta): -P/h on the storey
drift at the load centre, -I_P/h on the storey twist, with P the gravity load above and
I_P its polar moment (loads spread like the slab masses). Checked against closed forms
and against OpenSees' PDelta transformation on a frame.
"""

from __future__ import annotations

import copy
import subprocess
import sys

import numpy as np
import pytest

from pounding.errors import InputError
from pounding.framework.model.assembly import assemble
from pounding.framework.model.pdelta import GRAVITY
from tests.scenes_for_tests import box_building
from tests.scenes_for_tests import scene as build_scene
from tests.rounding import EPS, SAFETY, sym_eig_rel


def _one(table: dict):
    return build_scene({"building": [table], "ground_motion": {"record": "elcentro"}})


def _box(storeys: int = 1, **extra) -> dict:
    """A symmetric box building 12 x 8 m, two identical frames along x and two along y
    (translation along x, along y and torsion uncouple)."""
    t = box_building("b", 0.0, 12.0, 8.0, storeys, 0.5, 0.45, height=3.2)
    for fr in t["element"][:2]:
        fr["columns"] = [0.0, 6.0, 12.0]
    t.update(extra)
    return t


def _mode(system, dof: int) -> int:
    """Index of the mode of the uncoupled building that moves the ``dof`` (0 u, 1 v, 2 phi) of floor 1."""
    return int(np.argmax(np.abs(system.modes[dof, :]) * np.sqrt(system.mass[dof])))


def test_one_storey_translation_and_torsion_follow_the_closed_form():
    """One storey, height h, mass m, polar inertia J, gravity load P = m g spread like the mass.
    Translation along x: k_eff = k_x - P/h, k_x the x-frames' lateral stiffness summed (from the
    elements themselves), so omega^2 = (k_x - P/h)/m. Torsion about the centre of mass (the
    load centre): k_phi = sum_e k_e r_e^2 over all four frames (r_e the frame's distance from the
    centre), minus I_P/h with I_P = P J/m = g J: omega^2 = (k_phi - g J/h)/J. Eigenvalues of a
    3x3 problem, to rounding: 1e-12. A test load of 200 x the weight (P/(k_x h) = 0.29) makes the
    shifts large (20 % on the period) so the check discriminates."""
    lf = 200.0
    b0 = _one(_box()).buildings[0]
    b = _one(_box(p_delta={"load_factor": lf})).buildings[0]
    s0, s = assemble(b0), assemble(b)
    m, J, h = b.slabs[0].mass, b.slabs[0].polar_inertia, b.storey_heights[0]
    c = b.slabs[0].centre
    kx = sum(float(e.lateral_stiffness()[0, 0]) for e in b.elements if abs(e.direction[0]) == 1.0)
    kphi = 0.0
    for e in b.elements:
        r = np.asarray(e.point) - c
        kphi += float(e.lateral_stiffness()[0, 0]) * (r[0] * e.direction[1] - r[1] * e.direction[0]) ** 2
    P = lf * m * GRAVITY
    w2x = (kx - P / h) / m
    w2phi = (kphi - lf * GRAVITY * J / h) / J
    # LAPACK's symmetric eigen-solve: each omega^2 within SAFETY n eps max(omega^2) (Weyl; rounding.sym_eig_rel),
    # plus the closed form's own few ulps; the period ratio takes half of each relative error, twice
    lam, lam0 = s.omega**2, s0.omega**2
    ulps = 8 * EPS
    assert lam[_mode(s, 0)] == pytest.approx(w2x, rel=sym_eig_rel(lam)[_mode(s, 0)] + ulps)
    assert lam[_mode(s, 2)] == pytest.approx(w2phi, rel=sym_eig_rel(lam)[_mode(s, 2)] + ulps)
    ratio = s.periods[_mode(s, 0)] / s0.periods[_mode(s0, 0)]
    tol = 0.5 * (sym_eig_rel(lam)[_mode(s, 0)] + sym_eig_rel(lam0)[_mode(s0, 0)]) + ulps
    assert ratio == pytest.approx(np.sqrt(kx / (kx - P / h)), rel=tol) and ratio > 1.1


def test_loads_in_newtons_equal_the_load_factor_form():
    """p_delta.loads [N] per floor = load_factor g m_f give the same stiffness (to rounding)."""
    b1 = _one(_box(3, p_delta={"load_factor": 1.5})).buildings[0]
    loads = [1.5 * GRAVITY * s.mass for s in b1.slabs]
    b2 = _one(_box(3, p_delta={"loads": loads})).buildings[0]
    np.testing.assert_allclose(assemble(b2).K, assemble(b1).K, rtol=0, atol=1e-12 * np.abs(assemble(b1).K).max())


def test_p_delta_periods_match_opensees_pdelta_transformation(opensees):
    """Peer: a 3-storey building of two identical x-frames (3 columns, 2 bays, sections changing with
    height) and two y-frames, symmetric, so its x-modes are those of one x-frame carrying half
    the mass and half the gravity load. OpenSees: that frame in 2-D with PDelta columns, the floor
    loads on its joints, a linear gravity step, loadConst, then eigen (pounding.peer.opensees.
    pdelta_frame_periods). Gravity loads of 10 x the floor weights shift the periods by 1.1-2.6 %;
    the agreement asserted, 1e-12, is rounding amplified by the stiffness contrast the two
    models eliminate (axial EA/L over lateral stiffness, ~1e4, times 1e-16; measured 1.4e-15,
    and 6e-15 on the shifts themselves), so it
    isolates the geometric stiffness: all three x-periods agree, with and without P-Delta."""
    from pounding.peer.opensees import pdelta_frame_periods

    lf = 10.0
    t = _box(3, storey_heights=[4.0, 3.2, 3.2], p_delta={"load_factor": lf})
    for fr in t["element"][:2]:
        fr["column"] = [{"E": 30e9, "b": 0.55, "h": 0.55}, {"E": 30e9, "b": 0.5, "h": 0.5}, {"E": 30e9, "b": 0.4, "h": 0.4}]
        fr["beam"] = {"E": 30e9, "b": 0.3, "h": 0.6}
    b = _one(t).buildings[0]
    b0 = _one({k: v for k, v in t.items() if k != "p_delta"}).buildings[0]
    s, s0 = assemble(b), assemble(b0)
    xmodes = sorted(i for i in range(s.n_dof) if np.abs(s.modes[0::3, i]).max() > 1e-6 * np.abs(s.modes[:, i]).max())
    assert len(xmodes) == 3
    ours = np.sort(s.periods[xmodes])[::-1]
    half_mass = [0.5 * sl.mass for sl in b.slabs]
    peer = pdelta_frame_periods(opensees, b.elements[0], half_mass, [lf * GRAVITY * m for m in half_mass], 3)
    peer0 = pdelta_frame_periods(opensees, b.elements[0], half_mass, [0.0] * 3, 3)
    # the rounding both sides may carry: the stiffness contrast the condensation eliminates (the stiffest
    # column's EA/h over the frame's softest lateral stiffness) times SAFETY n eps for the frame's DOFs
    # (rounding.SAFETY), a bound of ~1e-10 that holds for any LAPACK; measured 1.4e-15 here
    fr = b.elements[0]
    ndof = len(fr.heights) * (1 + 2 * len(fr.columns))
    contrast = max(E * A / hh for (E, A, _), hh in zip(fr.column_sections, fr.heights)) / np.linalg.eigvalsh(fr.lateral_stiffness()).min()
    tol = SAFETY * ndof * EPS * contrast
    np.testing.assert_allclose(ours, peer, rtol=tol)
    shift = ours / np.sort(s0.periods[sorted(i for i in range(s0.n_dof) if np.abs(s0.modes[0::3, i]).max() > 1e-6 * np.abs(s0.modes[:, i]).max())])[::-1]
    assert np.all(shift > 1.01)
    np.testing.assert_allclose(peer / peer0, shift, rtol=4 * tol)


def test_buckling_under_gravity_is_one_clear_error():
    """A load beyond the first storey's critical load k h: InputError naming p_delta, not a NaN period."""
    with pytest.raises(InputError, match="buckles under its gravity loads") as exc:
        _one(_box(p_delta={"load_factor": 500.0}))
    assert "p_delta" in str(exc.value) or "element" in str(exc.value)


def test_modifier_scales_the_periods_exactly():
    """Every element's stiffness x c: K x c, so every period x 1/sqrt(c) (the modes do not change)."""
    b1 = _one(_box(3)).buildings[0]
    t = _box(3)
    for e in t["element"]:
        e["stiffness_modifier"] = 0.49
    b2 = _one(t).buildings[0]
    # K x 0.49 exactly up to one rounding per entry, so the eigen-solves see the same problem: each period
    # within half of rounding.sym_eig_rel of its omega^2 on both sides
    p1, p2 = assemble(b1), assemble(b2)
    np.testing.assert_allclose(p2.periods, p1.periods / 0.7, rtol=sym_eig_rel(p1.omega**2).max() + 8 * EPS)


def test_modifier_on_one_element_changes_only_its_share():
    """A modifier on one x-frame scales its contribution T^T k T to K and nothing else:
    K(modified) - K = (c - 1) T^T k T for that frame (placement from first principles here)."""
    t = _box(2)
    t2 = copy.deepcopy(t)
    t2["element"][0]["stiffness_modifier"] = 0.6
    b1, b2 = _one(t).buildings[0], _one(t2).buildings[0]
    e = b1.elements[0]
    n = b1.n_storeys
    T = np.zeros((len(e.floors), 3 * n))
    for row, f in enumerate(e.floors):
        r = np.asarray(e.point) - b1.slabs[f - 1].centre
        T[row, 3 * (f - 1) : 3 * f] = (e.direction[0], e.direction[1], r[0] * e.direction[1] - r[1] * e.direction[0])
    diff = assemble(b2).K - assemble(b1).K
    expected = -0.4 * T.T @ e.lateral_stiffness() @ T
    assert np.abs(diff - expected).max() <= 1e-12 * np.abs(assemble(b1).K).max()


@pytest.mark.parametrize(
    "key, value, expected",
    [
        ("stiffness_modifier", 0.0, "building[0].element[0].stiffness_modifier"),
        ("stiffness_modifier", -0.5, "building[0].element[0].stiffness_modifier"),
        ("stiffness_modifier", "half", "building[0].element[0].stiffness_modifier"),
        ("p_delta", {"load_factor": -1.0}, "building[0].p_delta.load_factor"),
        ("p_delta", {"loads": [1.0, 2.0]}, "building[0].p_delta.loads"),
        ("p_delta", {"load_factr": 1.0}, "building[0].p_delta"),
    ],
)
def test_bad_modifier_or_p_delta_is_one_clear_message_and_exit_2(tmp_path, key, value, expected):
    """Bad values: exit code 2, one line naming the file and the key path, nothing written."""
    t = _box(3)
    if key == "stiffness_modifier":
        t["element"][0][key] = value
    else:
        t[key] = value
    path = tmp_path / "bad.toml"
    path.write_text(_toml({"building": [t], "analysis": {"duration": 0.1}}))
    proc = subprocess.run([sys.executable, "-m", "pounding", "run", str(path), "--out", str(tmp_path / "o"), "--quiet"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert str(path) in proc.stderr and expected in proc.stderr, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def _toml(data: dict) -> str:
    """A minimal TOML writer for the test scenes (tables, arrays of tables, numbers, strings, lists)."""
    lines: list[str] = []

    def value(v):
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(float(v)) if isinstance(v, float) else str(v)

    for top, content in data.items():
        if isinstance(content, list):
            for item in content:
                lines.append(f"[[{top}]]")
                subs = {k: v for k, v in item.items() if isinstance(v, list) and v and isinstance(v[0], dict) and k == "element"}
                for k, v in item.items():
                    if k not in subs:
                        lines.append(f"{k} = {value(v)}")
                for k, v in subs.items():
                    for el in v:
                        lines.append(f"[[{top}.{k}]]")
                        lines.extend(f"{kk} = {value(vv)}" for kk, vv in el.items())
        else:
            lines.append(f"[{top}]")
            lines.extend(f"{k} = {value(v)}" for k, v in content.items())
    return "\n".join(lines) + "\n"


def test_p_delta_torsion_matches_opensees_leaning_columns_in_3d(opensees):
    """Peer, translation and torsion coupled: the non-symmetric 3-storey box (12 x 8 m, its far
    x-frame softer) in OpenSees' 3-D model (pounding.peer.opensees.build_building: planar frames,
    rigid diaphragms), its gravity loads (10 x the floor weights) carried by four leaning
    corotTruss columns at (+-a/sqrt 12, +-b/sqrt 12) from the centre: the same load, centre and
    polar moment P (a^2 + b^2)/12 as a load spread like the uniform slab mass, which is what
    pounding assumes. All nine periods agree to 1e-6, the bound the 3-D model's out-of-plane
    stiffness (1e-6 of in-plane) allows (measured 5e-7), while P-Delta shifts them by up to 12 %.
    The same loads on one column at the centre (no polar moment) miss by 2.7 %: the torsional
    term is what is checked."""
    from pounding.peer.opensees import pdelta_building_periods

    lf = 10.0
    t = box_building("b", 0.0, 12.0, 8.0, 3, 0.5, 0.45, height=3.2, column_x_far=0.35)
    b0 = _one(copy.deepcopy(t)).buildings[0]
    t["p_delta"] = {"load_factor": lf}
    b = _one(t).buildings[0]
    ours = assemble(b).periods
    c = b.slabs[0].centre
    x0, y0 = 12.0 / np.sqrt(12.0), 8.0 / np.sqrt(12.0)
    corners = c + np.array([[x0, y0], [-x0, y0], [-x0, -y0], [x0, -y0]])
    loads = [lf * GRAVITY * sl.mass for sl in b.slabs]
    peer = pdelta_building_periods(opensees, b, corners, loads, 9, out_of_plane=1e-6)
    np.testing.assert_allclose(ours, peer, rtol=1e-6)
    assert (ours / assemble(b0).periods).max() > 1.1
    centre_only = pdelta_building_periods(opensees, b, c[None, :], loads, 9, out_of_plane=1e-6)
    assert np.abs(centre_only / ours - 1).max() > 1e-3


def test_impact_force_keys_belong_to_their_model():
    """[analysis.impact_force]: stiffness is Hertz's, duration the half-sine's; a mix is one error."""
    from pounding.io.scene import parse_scene

    data = {"building": [_box()], "analysis": {"impact_force": {"model": "duration", "stiffness": 1e9}}}
    with pytest.raises(InputError, match="stiffness applies to model = 'hertz'") as exc:
        parse_scene(data)
    assert exc.value.field == "analysis.impact_force.stiffness"
    data["analysis"]["impact_force"] = {"model": "hertz", "stiffness": -1.0}
    with pytest.raises(InputError) as exc:
        parse_scene(data)
    assert exc.value.field == "analysis.impact_force.stiffness"
