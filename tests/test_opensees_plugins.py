"""The OpenSees peer and ``pounding export opensees`` ask each plugin for its OpenSees counterpart.

A plugin written outside the package, in this file, with no edit to ``pounding/``:

* a planar element gives its OpenSees model (``PlanarElement.opensees_model``): the peer builds it,
  and its periods are the element's condensed stiffness's; the export writes it;
* a hysteresis law gives its material (``HysteresisLaw.opensees_material``): each storey spring
  of the law gets it;
* a contact law gives its material (``ContactLaw.opensees_material``): the contact elements get it;
* a plugin that gives none is refused with a message naming it (elements and hysteresis laws) or
  left out with a note saying so (contact laws), as the built-ins without one are.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

from pounding.elements.base import PlanarElement
from pounding.elements.storey_springs import StoreySprings
from pounding.framework.model.assembly import assemble
from pounding.io.scene import load_scene

pytestmark = pytest.mark.opensees

ROOT = Path(__file__).resolve().parents[1]
PAIR = ROOT / "examples" / "paper" / "pair_gap_0.5.toml"


# --------------------------------------------------------------------------- a third-party element
@dataclass(frozen=True, eq=False)
class Cantilever(PlanarElement):
    """One column on a plan line, fixed at its base and free to rotate at every floor it passes: the
    Euler-Bernoulli cantilever of flexural stiffness E I [N m^2] (E [Pa], A [m^2], I [m^4]),
    resisting the floors' displacements along ``direction`` at ``point``."""

    name: ClassVar[str] = "cantilever"

    point: np.ndarray
    direction: np.ndarray
    heights: tuple[float, ...]
    E: float
    A: float
    I: float

    @property
    def floors(self) -> tuple[int, ...]:
        return tuple(range(1, len(self.heights) + 1))

    @classmethod
    def from_table(cls, table, *, storey_heights):
        raise NotImplementedError("built in Python here")

    def plan_segment(self):
        return self.point, self.point

    def lateral_stiffness(self) -> np.ndarray:
        """The inverse of the cantilever's flexibility: f_ij = z_i^2 (3 z_j - z_i) / (6 E I), z_i <= z_j
        the floors' heights above the base [m]."""
        z = np.cumsum(self.heights)
        low, high = np.minimum.outer(z, z), np.maximum.outer(z, z)
        return np.linalg.inv(low**2 * (3.0 * high - low) / (6.0 * self.E * self.I))

    def opensees_model(self, ops, place) -> list[int]:
        """One ``elasticBeamColumn`` per storey on the column's nodes, ``Iz = I`` in the element's plane and
        ``Iy = place.out_of_plane * I`` out of it; no torsional constant (J = 0: the floors' diaphragms hold
        the twist of every node above the base, which is fixed)."""
        transf, grid = self.opensees_plane(ops, place, [0.0], self.heights)
        eps = place.out_of_plane
        members = []
        for i in range(len(self.heights)):
            tag = place.tag()
            ops.element("elasticBeamColumn", tag, grid[i][0], grid[i + 1][0], self.A, self.E, self.E / 2.4,
                        0.0, eps * self.I, self.I, transf)
            members.append(tag)
        return members


class Unexportable(Cantilever):
    """The same column from a plugin that gives no OpenSees model (the base class's default)."""

    name: ClassVar[str] = "unexportable"
    opensees_model = PlanarElement.opensees_model


def _on_cantilevers(building, cls=Cantilever):
    """``building`` (the paper's "low": 15 m x 10 m, three storeys of 3.2 m) held by a column along x and one
    along y at each slab corner, all of the same 0.5 m x 0.5 m concrete section."""
    h, E = 0.5, 30e9
    corners = [(0.0, 0.0), (15.0, 0.0), (15.0, 10.0), (0.0, 10.0)]
    columns = tuple(cls(np.array(c), np.array(d), tuple(building.storey_heights), E, h * h, h**4 / 12.0)
                    for c in corners for d in ((1.0, 0.0), (0.0, 1.0)))
    return replace(building, elements=columns)


def _alone(building):
    """The paper pair's scene with ``building`` alone (Newmark, no contact)."""
    scene = load_scene(PAIR).with_analysis(integrator="newmark", integrator_params={}, contact="none", contact_params={})
    return replace(scene, buildings=(building,))


def test_a_third_party_element_is_built_by_its_own_opensees_model(opensees):
    """The peer builds a building of a plugin's element from the element's ``opensees_model`` alone, and its
    nine periods are those of the element's condensed stiffness, with the out-of-plane stiffness OpenSees
    needs.

    Every corner has a column along x and one along y of one section, so the out-of-plane bending
    (``out_of_plane`` = eps times the in-plane inertia) gives each column eps times the in-plane
    stiffness of its partner at the same point: the OpenSees model's stiffness is K (1 + eps) exactly
    and its periods the condensed model's times (1 + eps)^-1/2 (5e-7 shorter at eps = 1e-6). What is
    left is rounding: the model's stiffness terms span EA/L = 2.3e9 N/m to eps 4 E I / L = 2e2 N m, a
    ratio of 1e7, so 1e7 x 2.2e-16 = 2.2e-9 relative bounds it (measured 8e-13), far below the 5e-7
    a model without the out-of-plane stiffness, or any other, would be off by."""
    from pounding.peer.opensees import build_building, eigen_periods

    eps = 1e-6
    building = _on_cantilevers(load_scene(PAIR).building("low"))
    expected = assemble(building).periods
    opensees.wipe()
    build_building(opensees, building, out_of_plane=eps)
    periods = eigen_periods(opensees, 3 * building.n_storeys)
    opensees.wipe()
    np.testing.assert_allclose(periods, expected * (1.0 + eps) ** -0.5, rtol=1e7 * np.finfo(float).eps, atol=0)


def test_a_third_party_element_is_exported_by_its_own_opensees_model():
    """``pounding export opensees`` writes the element's own commands: one ``elasticBeamColumn`` per column
    and storey (8 columns, 3 storeys), each on the transformation the column's plane gave."""
    from pounding.peer.export import opensees_script

    text, _ = opensees_script(_alone(_on_cantilevers(load_scene(PAIR).building("low"))))
    members = re.findall(r"ops\.element\('elasticBeamColumn', (\d+), .*, (\d+)\)", text)
    transforms = set(re.findall(r"ops\.geomTransf\('Linear', (\d+),", text))
    assert len(members) == 8 * 3
    assert {t for _, t in members} == transforms and len(transforms) == 8


def test_an_element_without_an_opensees_model_is_refused_naming_it(tmp_path):
    """A plugin element that gives no OpenSees model: the peer raises NotImplementedError naming the building
    and the element type; the export, one InputError saying so, and no file."""
    from pounding.errors import InputError
    from pounding.peer.export import write_script
    from pounding.peer.opensees import build_building
    from pounding.peer.script import ScriptOps

    building = _on_cantilevers(load_scene(PAIR).building("low"), Unexportable)
    message = "building 'low': no OpenSees model for element type 'unexportable'"
    with pytest.raises(NotImplementedError, match=message):
        build_building(ScriptOps(), building)
    with pytest.raises(InputError, match="cannot export to OpenSees: " + message):
        write_script(_alone(building), tmp_path / "model.py")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- a third-party hysteresis law
def _linear_law(with_material: bool):
    """tests/hysteresis_plugin.py's law (force k0 u), with or without an OpenSees material (``Elastic(k0)``)."""
    from hysteresis_plugin import Linear

    class Exportable(Linear):
        name = "exportable_linear"

        def opensees_material(self, ops, tag, k0, fy, b, *, tags, boucwen_tol):
            ops.uniaxialMaterial("Elastic", tag, k0)

    return Exportable() if with_material else Linear()


def _on_springs(building, law):
    """``building`` on two lines of storey springs of ``law`` along x (k0 per storey 3e7, 2.5e7, 2e7 N/m, Fy 1e5 N)."""
    k, fy = (3.0e7, 2.5e7, 2.0e7), (1.0e5,) * 3
    lines = tuple(StoreySprings(np.array([0.0, y]), np.array([1.0, 0.0]), 15.0, tuple(building.storey_heights), k, fy,
                                0.0, law) for y in (0.0, 10.0))
    return replace(building, elements=lines), k


def test_a_third_party_hysteresis_law_gives_each_storey_spring_its_material():
    """Every storey spring of a plugin law gets the material the law declares (here ``Elastic(k0)`` with the
    storey's k0), and its link is made of it; the springs are the yielding links, bottom first."""
    from pounding.peer.opensees_springs import build_spring_building
    from pounding.peer.script import ScriptOps

    building, k = _on_springs(load_scene(PAIR).building("low"), _linear_law(True))
    ops = ScriptOps()
    _, _, elements, yielding = build_spring_building(ops, building, 0)
    materials = {int(tag): float(k0) for tag, k0 in re.findall(r"uniaxialMaterial\('Elastic', (\d+), ([^)]+)\)", "\n".join(ops.lines))}
    links = re.findall(r"element\('twoNodeLink', (\d+), \d+, \d+, '-mat', (\d+),", "\n".join(ops.lines))
    assert [int(t) for t, _ in links] == elements == yielding
    assert [materials[int(m)] for _, m in links] == list(k) * 2


def test_a_hysteresis_law_without_an_opensees_material_is_refused_naming_it(tmp_path):
    """A plugin law that gives no material: the peer raises NotImplementedError naming the law; the export,
    one InputError saying so, and no file."""
    from pounding.errors import InputError
    from pounding.peer.export import write_script
    from pounding.peer.opensees import build_building
    from pounding.peer.script import ScriptOps

    building, _ = _on_springs(load_scene(PAIR).building("low"), _linear_law(False))
    with pytest.raises(NotImplementedError, match="no OpenSees material for hysteresis law 'linear'"):
        build_building(ScriptOps(), building)
    with pytest.raises(InputError, match="cannot export to OpenSees: no OpenSees material for hysteresis law 'linear'"):
        write_script(_alone(building), tmp_path / "model.py")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- a third-party contact law
def _hertz(with_material: bool):
    """tests/contact_plugins.py's elastic Hertz law, with or without an OpenSees material (``Hertzdamp`` with
    no damping, the share of k_h)."""
    from contact_plugins import Hertz

    class Exportable(Hertz):
        name: ClassVar[str] = "exportable_hertz"

        def opensees_material(self, share, m_eff, clear):
            return ("Hertzdamp", share * self.stiffness, 0.0, -clear, 1.5)

    return Exportable if with_material else Hertz


def test_a_third_party_contact_law_gives_the_contact_elements_its_material():
    """The pair of tests/test_opensees_pounding.py with a plugin force law: each contact element (two per
    common storey) gets the material the law declares, with half of k_h (the two ends of a face) and the
    clear distance as its negative gap; a law that gives none is left out, with a note naming it."""
    from test_opensees_pounding import _penalty, _scene_dict

    from pounding.io.scene import parse_scene
    from pounding.peer.export import opensees_script

    k_h = 2.75e9
    base = parse_scene(_scene_dict(_penalty(), duration=1.0))
    clear = min(v[0] for v in base.buildings[1].slabs[0].vertices) - max(v[0] for v in base.buildings[0].slabs[0].vertices)
    text, notes = opensees_script(base.with_analysis(contact=_hertz(True), contact_params={"stiffness": k_h}))
    materials = re.findall(r"uniaxialMaterial\('Hertzdamp', \d+, ([^,]+), ([^,]+), ([^,]+), ([^)]+)\)", text)
    assert [tuple(float(x) for x in m) for m in materials] == [(0.5 * k_h, 0.0, -clear, 1.5)]
    storeys = min(b.n_storeys for b in base.buildings)
    assert len(re.findall(r"element\('zeroLength'", text)) == 2 * storeys
    assert not [n for n in notes if "no OpenSees material" in n]

    text, notes = opensees_script(base.with_analysis(contact=_hertz(False), contact_params={"stiffness": k_h}))
    assert "zeroLength" not in text
    assert [n for n in notes if n.startswith("contact law 'hertz' has no OpenSees material")]
