"""ParaView output: written series read back with VTK's own readers."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EPS = np.finfo(float).eps
EXAMPLES = ROOT / "examples"

pytest.importorskip("vtkmodules")

WALLS_SCENE = """
title = "walls and frames"
[ground_motion]
record = "elcentro"
pga = 0.3
angle = 30.0
[analysis]
dt = 0.01
duration = 0.6
contact = "impulse"

[[building]]
name = "walls"
storey_heights = [3.0, 3.5]
slab = [[0.0, 0.0], [8.0, 0.0], [8.0, 6.0], [0.0, 6.0]]
mass_per_area = 800.0
  [[building.element]]
  type = "shear_wall"
  start = [0.0, 0.0]
  end = [4.0, 0.0]
  thickness = 0.2
  E = 30e9
  nu = 0.2
  [[building.element]]
  type = "shear_wall"
  start = [4.0, 6.0]
  end = [8.0, 6.0]
  thickness = 0.2
  E = 30e9
  nu = 0.2
  [[building.element]]
  type = "shear_wall"
  start = [0.0, 1.0]
  end = [0.0, 5.0]
  thickness = 0.2
  E = 30e9
  nu = 0.2
  [[building.element]]
  type = "frame"
  start = [8.0, 0.0]
  angle = 90.0
  columns = [0.0, 6.0]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }

[[building]]
name = "frames"
storey_heights = [3.0]
slab = [[8.05, 0.0], [14.0, 0.0], [14.0, 6.0], [8.05, 6.0]]
mass_per_area = 800.0
  [[building.element]]
  type = "frame"
  start = [8.05, 0.0]
  angle = 0.0
  columns = [0.0, 5.95]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }
  [[building.element]]
  type = "frame"
  start = [8.05, 6.0]
  angle = 0.0
  columns = [0.0, 5.95]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }
  [[building.element]]
  type = "frame"
  start = [14.0, 0.0]
  angle = 90.0
  columns = [0.0, 6.0]
  column = { E = 30e9, b = 0.4, h = 0.4 }
  beam = { E = 30e9, b = 0.3, h = 0.5 }
"""


@pytest.fixture(scope="module")
def paper():
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene

    scene = load_scene(EXAMPLES / "paper" / "pair_gap_0.03.toml").with_analysis(duration=3.0)
    result = run(scene)
    assert result.impacts, "the example must pound within 3 s"
    return scene, result


@pytest.fixture(scope="module")
def series(paper, tmp_path_factory):
    from pounding.io.vtk import write_vtk_series

    scene, result = paper
    out = tmp_path_factory.mktemp("vtk")
    pvd = write_vtk_series(scene, result, out, every=20, scale=7.0)
    pvd1 = write_vtk_series(scene, result, out / "unscaled", every=200, scale=1.0)
    return pvd, pvd1


def read_vtu(path: Path):
    """(points (np, 3), cells [ids], point data {name: array}, cell data, field data) via vtkXMLUnstructuredGridReader."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    rd = vtkXMLUnstructuredGridReader()
    rd.SetFileName(str(path))
    rd.Update()
    g = rd.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData()).astype(float)
    cells = []
    for c in range(g.GetNumberOfCells()):
        ids = g.GetCell(c).GetPointIds()
        cells.append([ids.GetId(j) for j in range(ids.GetNumberOfIds())])

    def arrays(data):
        return {data.GetArrayName(i): vtk_to_numpy(data.GetAbstractArray(i)) for i in range(data.GetNumberOfArrays())}

    return pts, cells, arrays(g.GetPointData()), arrays(g.GetCellData()), arrays(g.GetFieldData())


def expected_times(result, every: int) -> np.ndarray:
    t = np.asarray(result.t)
    times = np.unique(np.concatenate([t[::every], [i.time for i in result.impacts]]))
    keep = np.concatenate([[True], np.diff(times) > 1e-12])
    return times[keep]


def test_pvd_lists_every_nth_step_and_every_impact_instant(paper, series):
    import pyvista as pv

    from pounding.io.vtk import read_pvd

    _, result = paper
    pvd, _ = series
    entries = read_pvd(pvd)
    times = np.array([t for t, _ in entries])
    np.testing.assert_allclose(times, expected_times(result, 20), rtol=0, atol=1e-12)
    assert all(f.is_file() for _, f in entries)
    assert np.all(np.diff(times) > 0)
    # ParaView's view of the same collection
    reader = pv.get_reader(str(pvd))
    np.testing.assert_allclose(reader.time_values, times, rtol=0, atol=1e-12)
    reader.set_active_time_value(times[1])
    mesh = reader.read()
    mesh = mesh[0] if isinstance(mesh, pv.MultiBlock) else mesh
    assert "in_contact" in mesh.cell_data and "displacement" in mesh.point_data


def test_slab_vertices_move_as_the_result_says(paper, series):
    from pounding.io.vtk import read_pvd

    scene, result = paper
    pvd, _ = series
    entries = read_pvd(pvd)
    scale = 7.0
    checked = 0
    for t, f in entries[::7]:
        k = int(np.argmin(np.abs(result.t - t)))
        if abs(result.t[k] - t) > 1e-12:
            continue  # an impact instant between output steps
        pts, cells, pd, cd, fd = read_vtu(f)
        if fd["impact_instant"][0]:
            continue
        assert fd["time"][0] == pytest.approx(t, abs=1e-12)
        slabs = np.flatnonzero(cd["element_type"] == 0)
        assert len(slabs) == sum(b.n_storeys for b in scene.buildings)
        for c in slabs:
            b, storey = int(cd["building"][c]), int(cd["storey"][c])
            name = result.names[b]
            slab = scene.building(name).slabs[storey - 1]
            ids = cells[c]
            n = len(slab.vertices)
            assert len(ids) == n
            want = result.vertices(name)[k, storey - 1, :n]
            np.testing.assert_allclose(pts[ids, :2] - slab.vertices, scale * want, rtol=0, atol=1e-9 * scale)
            np.testing.assert_allclose(pts[ids, 2], slab.elevation, rtol=0, atol=1e-12)
            np.testing.assert_allclose(pd["displacement"][ids, :2], want, rtol=0, atol=1e-9)
            np.testing.assert_allclose(pd["velocity"][ids, :2], result.vertices(name, velocity=True)[k, storey - 1, :n], rtol=0, atol=1e-9)
        # the ground does not move
        ground = np.abs(pts[:, 2]) < 1e-12
        assert ground.any()
        np.testing.assert_array_equal(pd["displacement"][ground], 0.0)
        checked += 1
    assert checked >= 3


def test_in_contact_marks_the_pair_at_every_impact_instant(paper, series):
    from pounding.contact.geometry import signed_gap
    from pounding.io.vtk import contact_tolerance, read_pvd

    scene, result = paper
    _, pvd = series  # scale 1: the written geometry is the physical one
    tol = contact_tolerance(result)
    entries = read_pvd(pvd)
    by_time = {round(t, 12): f for t, f in entries}
    assert len(entries) == len(expected_times(result, 200))
    first = read_vtu(entries[0][1])
    assert not first[3]["in_contact"].any()  # at rest, 30 mm apart
    for imp in result.impacts:
        pts, cells, pd, cd, fd = read_vtu(by_time[round(imp.time, 12)])
        assert fd["impact_instant"][0] == 1
        a, fa, b, fb, _ = result.pairs[imp.pair]
        polys = []
        for bld, f in ((a, fa), (b, fb)):
            c = int(np.flatnonzero((cd["element_type"] == 0) & (cd["building"] == bld) & (cd["storey"] == f + 1))[0])
            assert cd["in_contact"][c] == 1, f"pair {imp.pair} not marked at t = {imp.time}"
            polys.append(np.ascontiguousarray(pts[cells[c], :2]))
        g = signed_gap(*polys)
        assert abs(g) <= tol, f"written slabs {g:.3g} m apart at the impact at t = {imp.time}"
        # slabs of pairs far apart are not marked
        for p, (a2, fa2, b2, fb2, _) in enumerate(result.pairs):
            if not any(i.pair == p and abs(i.time - imp.time) < 1e-12 for i in result.impacts):
                c = int(np.flatnonzero((cd["element_type"] == 0) & (cd["building"] == a2) & (cd["storey"] == fa2 + 1))[0])
                if cd["gap"][c] > 10 * tol:
                    assert cd["in_contact"][c] == 0


def test_writer_reads_recorded_states_only(paper):
    """The VTK writer reads the states the run recorded and never integrates: an output step
    gives the record, an impact instant the driver's own state just before its impulses (its
    closing speed is the logged approach velocity, exactly), any other instant is refused."""
    from pounding.framework.engine.stacked_model import Model
    from pounding.io.vtk import StateAt

    scene, result = paper
    st = StateAt(scene, result)
    k = 150
    q, v = st(float(result.t[k]))
    np.testing.assert_array_equal(q, result.q[k])
    np.testing.assert_array_equal(v, result.qd[k])
    imp = result.impacts[0]
    q, v = st(imp.time)
    w = Model(scene).row(q, imp.pair, imp.point, imp.normal)
    assert -(w @ v) == pytest.approx(imp.approach_velocity, rel=1e-12)
    with pytest.raises(ValueError, match="no state was recorded"):
        st(float(result.t[100]) + 0.5 * result.dt)


def test_walls_frames_storeys_and_element_types(tmp_path):
    from pounding.framework.post.run import run
    from pounding.io.scene import load_scene
    from pounding.io.vtk import read_pvd, write_vtk_series

    path = tmp_path / "walls.toml"
    path.write_text(WALLS_SCENE)
    scene = load_scene(path)
    result = run(scene)
    pvd = write_vtk_series(scene, result, tmp_path / "out", every=30, scale=100.0)
    entries = read_pvd(pvd)
    np.testing.assert_allclose([t for t, _ in entries], result.t[::30], atol=1e-12)
    pts, cells, pd, cd, fd = read_vtu(entries[-1][1])
    kind, bld, storey = cd["element_type"], cd["building"], cd["storey"]
    # walls: 3 walls x 2 storeys of building 0, quads
    walls = np.flatnonzero(kind == 2)
    assert len(walls) == 6 and set(bld[walls]) == {0} and sorted(storey[walls]) == [1, 1, 1, 2, 2, 2]
    assert all(len(cells[c]) == 4 for c in walls)
    assert set(storey[kind == 0]) == {1, 2}
    lines = np.flatnonzero(kind == 1)
    assert set(storey[lines]) <= {1, 2} and all(len(cells[c]) == 2 for c in lines)
    # a wall panel's top edge moves with its slab, its bottom edge at the ground stays
    k = len(result.t) - 1
    name = result.names[0]
    cm = result.cm(name)[k]
    for c in walls:
        for j in cells[c]:
            z = pts[j, 2]
            disp = pd["displacement"][j]
            if abs(z) < 1e-9:
                np.testing.assert_array_equal(disp, 0.0)
            else:
                f = [s.elevation for s in scene.buildings[0].slabs].index(pytest.approx(z, abs=1e-9))
                rest = pts[j, :2] - 100.0 * disp[:2]
                r = rest - scene.buildings[0].slabs[f].centre
                u, v, phi = cm[f]
                np.testing.assert_allclose(disp[:2], [u - phi * r[1], v + phi * r[0]], rtol=0, atol=1e-12)
    assert not np.any(pd["displacement"][:, 2])


def test_no_heavy_imports_at_module_import():
    code = textwrap.dedent(
        """
        import sys
        import pounding.io.vtk, pounding.io.plots, pounding.io.render
        heavy = sorted({m.split('.')[0] for m in sys.modules} & {'vtk', 'vtkmodules', 'pyvista', 'matplotlib'})
        print(','.join(heavy))
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == ""


# --------------------------------------------------------------------------- walls and links
def _walled_linked_pair():
    """tests/test_links_between.py's pair (buildings "a" on [0, 10] and "b" on [10.05, 20.05], one storey each)
    joined by a linear dashpot at storey 1, with a wall of two face segments 1 mm west of "a" (top 3.2 m, the
    slabs' level; rigid impulses, e = 0.5): El Centro at 0.5 g for 1.5 s, dt = 0.01 s; "a" strikes the wall at
    0.61 s, between output steps."""
    from test_links_between import linked_pair

    data = linked_pair({"name": "viscous", "coefficient": 4.0e6, "exponent": 1.0}, duration=1.5, dt=0.01, pga=0.5)
    data["analysis"]["contact"] = {"name": "impulse", "restitution": 0.5}
    data["wall"] = [{"name": "moat", "face": [[-0.001, -1.0], [-0.001, 5.0], [-0.5, 11.0]], "top": 3.2}]
    return data


@pytest.fixture(scope="module")
def walled(tmp_path_factory):
    from pounding.framework.post.run import run
    from pounding.io.scene import parse_scene
    from pounding.io.vtk import write_vtk_series

    scene = parse_scene(_walled_linked_pair())
    result = run(scene)
    pvd = write_vtk_series(scene, result, tmp_path_factory.mktemp("walled"), every=10, scale=50.0)
    return scene, result, pvd


def test_a_wall_is_its_face_extruded_from_the_ground_to_its_top_at_every_instant(walled):
    """The wall's surface (part 1 of the collection, at every instant): its points are the face's vertices at
    z = 0 and at z = top, exactly (coordinates are copied, not computed), one quad per face segment."""
    from pounding.io.vtk import read_pvd

    scene, _, pvd = walled
    wall = scene.walls[0]
    buildings, walls = read_pvd(pvd), read_pvd(pvd, part=1)
    assert [t for t, _ in walls] == [t for t, _ in buildings] and len({f for _, f in walls}) == 1
    pts, cells, _, cd, _ = read_vtu(walls[0][1])
    expected = {(x, y, z) for z in (0.0, wall.top) for x, y in np.asarray(wall.face, float)}
    assert {tuple(p) for p in pts} == expected and len(pts) == len(expected)
    assert len(cells) == len(wall.face) - 1 and all(len(c) == 4 for c in cells)
    assert list(cd["wall"]) == [0, 0]
    for c in cells:  # each quad spans one segment, foot and top
        assert sorted(pts[c, 2]) == [0.0, 0.0, wall.top, wall.top]
    import pyvista as pv  # ParaView's view: one multiblock per instant, buildings, walls, links

    reader = pv.get_reader(str(pvd))
    reader.set_active_time_value(reader.time_values[3])
    blocks = reader.read()
    assert len(blocks) == 3 and [block.n_cells for block in blocks][1:] == [len(wall.face) - 1, len(scene.links)]


def test_a_link_is_a_line_between_its_slabs_displaced_attachment_points_with_the_runs_force(walled):
    """The link (part 2, one file per instant) at every output step written: its ends are the attachment points
    moved with their slabs' rigid motion from the run's own centre-of-mass history, (u - phi (y - y_c),
    v + phi (x - x_c)), magnified 50 times; its force is the run's recorded one, its deformation the run's too:
    the second end's displacement minus the first's along the line, computed from the slabs' motion, which
    the run computes from its modal rows, so the two differ by rounding: a few dot products of terms below
    the peak motion (64 eps of the peak displacement). Between output steps (the wall impact) the run keeps no
    link state: the force is NaN, the line still drawn from the state at the instant."""
    from pounding.io.vtk import read_pvd

    scene, result, pvd = walled
    link, rec = scene.links[0], result.links["l1"]
    links = read_pvd(pvd, part=2)
    assert len(links) == len(read_pvd(pvd)) and any(abs(result.t - t).min() > 1e-9 for t, _ in links)
    peak = max(np.abs(result.cm(n)).max() * 20.0 for n in result.names)  # u + phi x (lever <= 20 m) bounds a point's motion
    checked = 0
    for t, f in links:
        pts, cells, pd, cd, _ = read_vtu(f)
        assert cells == [[0, 1]]
        k = int(np.argmin(np.abs(result.t - t)))
        if abs(result.t[k] - t) > 1e-12:
            assert np.isnan(cd["force"][0])
            continue
        ends = []
        for (x, y), name, s in zip(link.points, link.between, link.storeys):
            slab = scene.building(name).slabs[s - 1]
            u, v, phi = result.cm(name)[k, s - 1]
            ends.append((u - phi * (y - slab.centre[1]), v + phi * (x - slab.centre[0])))
        ends = np.array(ends)
        rest = np.column_stack([link.points, [3.2, 3.2]])
        np.testing.assert_allclose(pts[:, :2], rest[:, :2] + 50.0 * ends, rtol=0, atol=8 * EPS * 20.05)
        np.testing.assert_array_equal(pts[:, 2], rest[:, 2])
        np.testing.assert_allclose(pd["displacement"][:, :2], ends, rtol=0, atol=4 * EPS * peak)
        assert cd["force"][0] == rec["force"][k]
        assert abs(cd["deformation"][0] - rec["deformation"][k]) <= 64 * EPS * peak
        checked += 1
    assert checked == len(result.t[::10]) and np.abs(rec["force"]).max() > 0.0
