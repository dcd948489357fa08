"""A storey-springs element as OpenSees links: one ``twoNodeLink`` per storey along the element's line,
its material the spring's law (``Elastic``, ``Steel01`` for the bilinear law and for the friction
pendulum with constant friction, ``BoucWen``; for the link laws ``Elastic``, ``Viscous``,
``ViscousDamper`` (``maxwell``) and ``Parallel`` of ``Elastic`` and ``Viscous`` (``kelvin``)).

Shared by the peer models of the tests (:mod:`pounding.peer.opensees`, :mod:`pounding.peer.opensees_springs`)
and the export, so that a storey spring is built one way.
"""

from __future__ import annotations

import numpy as np


def stand_on(ops, tag: int, floor: int, slaves: list[list[int]]) -> None:
    """Fix the base node ``tag`` of an element to what it stands on: the ground (``floor`` 0: all six
    DOFs) or floor ``floor`` (1-based): a slave of that floor's diaphragm in ux, uy, rz and fixed in
    uz, rx, ry, as a base fixed to a slab that is rigid in its plane and does not tilt."""
    if floor == 0:
        ops.fix(tag, 1, 1, 1, 1, 1, 1)
    else:
        ops.fix(tag, 0, 0, 1, 1, 1, 0)
        slaves[floor - 1].append(tag)


def _material(ops, tag: int, element, storey: int, boucwen_tol: float, tags=None) -> None:
    """The uniaxial material ``tag`` of one storey's spring; ``tags()`` gives the tags of the parts
    of a material made of several (``kelvin``: ``Parallel`` of ``Elastic`` and ``Viscous``)."""
    k0 = float(element.stiffness[storey])
    if not element.yields:
        ops.uniaxialMaterial("Elastic", tag, k0)
        return
    law_material(ops, tag, element.law, k0, float(element.yield_force[storey]), float(element.hardening), boucwen_tol, tags)


def law_material(ops, tag: int, law, k0: float, fy: float, b: float, boucwen_tol: float = 1e-13, tags=None) -> None:
    """The uniaxial material ``tag`` of a link law with initial stiffness k0 [N/m], yield force fy [N]
    and hardening b [-] (a storey spring's, or a ``[[link]]``'s from its parameter vector)."""
    name = law.name
    if name == "bilinear":
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)
    elif name == "bouc_wen":
        uy = fy / k0
        n, beta, gamma = law.n, law.beta, law.gamma
        ops.uniaxialMaterial("BoucWen", tag, b, k0, n, gamma / uy**n, beta / uy**n, 1.0, 0.0, 0.0, 0.0, float(boucwen_tol * uy), 200)
    elif name == "friction_pendulum" and law.friction_slow is None:
        # constant friction: W/R beside the elastic-perfectly-plastic slider (mu W / u_y, yield mu W) is
        # kinematic hardening with the law's k0, Fy and b (singleFPBearing also adds F u / R to the
        # normal force, which the law leaves out)
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)
    elif name == "elastic":
        ops.uniaxialMaterial("Elastic", tag, law.stiffness)
    elif name == "viscous":
        ops.uniaxialMaterial("Viscous", tag, law.coefficient, law.exponent)
    elif name == "maxwell":
        # the adaptive Dormand-Prince of the material, to 1e-10 relative (its default is 1e-6)
        ops.uniaxialMaterial("ViscousDamper", tag, law.stiffness, law.coefficient, law.exponent,
                             0.0, 1, 1e-10, 1e-12, 20)
    elif name == "kelvin" and tags is not None:
        spring, dashpot = tags(), tags()
        ops.uniaxialMaterial("Elastic", spring, law.stiffness)
        ops.uniaxialMaterial("Viscous", dashpot, law.coefficient, law.exponent)
        ops.uniaxialMaterial("Parallel", tag, spring, dashpot)
    else:
        raise NotImplementedError(f"no OpenSees material for hysteresis law {name!r}"
                                  + (" with velocity-dependent friction" if name == "friction_pendulum" else ""))


def between_slabs(ops, link, ends: list[tuple[int, float]], tags, boucwen_tol: float = 1e-13) -> tuple[int, list[int]]:
    """A ``[[link]]`` as OpenSees' ``zeroLength`` element with its law's material: a node at each
    attachment point at its slab's elevation (``ends``: (diaphragm master tag, elevation [m]) of each
    slab), restrained in uz, rx, ry, which nothing else stiffens; acting along the link's line
    (``-dir 1 -orient n_x n_y 0 -n_y n_x 0``), so its deformation is n . (u_b - u_a) at the points.
    Returns the element's tag and the two nodes, to be made slaves of their masters' diaphragms."""
    nodes = []
    for (_, z), (x, y) in zip(ends, link.points):
        tag = tags()
        ops.node(tag, float(x), float(y), float(z))
        ops.fix(tag, 0, 0, 1, 1, 1, 0)
        nodes.append(tag)
    mat = tags()
    k0, fy, b = (float(v) for v in link.params[:3])
    law_material(ops, mat, link.law, k0, fy, b, boucwen_tol, tags)
    d = link.direction
    tag = tags()
    ops.element("zeroLength", tag, *nodes, "-mat", mat, "-dir", 1,
                "-orient", float(d[0]), float(d[1]), 0.0, float(-d[1]), float(d[0]), 0.0)
    return tag, nodes


def scene_links(ops, scene, masters: dict, tags, boucwen_tol: float = 1e-13) -> list[int]:
    """Every ``[[link]]`` of ``scene`` as :func:`between_slabs` builds it, each end node made a slave of its
    slab's diaphragm (one ``rigidDiaphragm 3`` per node, after the buildings' own).

    ``masters`` maps a building's name to its diaphragm master tags per floor (bottom first); ``tags()``
    gives the next free tag. Shared by the peer run of the tests
    (:func:`pounding.peer.opensees_springs.run_linked_transient`) and ``pounding export opensees``.
    Returns the links' element tags, in scene order. Raises NotImplementedError for a law with no
    OpenSees material (:func:`law_material`).
    """
    slabs = {b.name: b.slabs for b in scene.buildings}
    out = []
    for link in scene.links:
        ends = [(masters[name][s - 1], float(slabs[name][s - 1].elevation)) for name, s in zip(link.between, link.storeys)]
        tag, nodes = between_slabs(ops, link, ends, tags, boucwen_tol)
        for (master, _), node in zip(ends, nodes):
            ops.rigidDiaphragm(3, master, node)
        out.append(tag)
    return out


def storey_links(ops, element, tags, slaves: list[list[int]], nodes: list[int], boucwen_tol: float = 1e-13, *,
                 heights) -> list[int]:
    """The ``twoNodeLink`` of every storey of one storey-springs element (module docstring); returns their tags.

    ``heights``: the building's storey heights [m] (the elevation of the floor the element stands on);
    ``tags()`` gives the next free tag; each link's upper node (and its lower one above the ground) is
    appended to ``slaves[floor - 1]`` for the floor's ``rigidDiaphragm``, every node to ``nodes``.
    """
    d = np.asarray(element.direction, dtype=float)
    x, y = (float(c) for c in element.point)
    z = np.concatenate([[0.0], np.cumsum(element.heights)]) + element.base_elevation(heights)
    links = []
    for f, floors in enumerate(element.storey_floors()):  # (below, above) in the building's numbering, 0 = the ground
        ends = []
        for level, floor in zip((f, f + 1), floors):
            tag = tags()
            ops.node(tag, x, y, float(z[level]))
            stand_on(ops, tag, floor, slaves)  # uz, rx, ry fixed: nothing stiffens them here
            nodes.append(tag)
            ends.append(tag)
        mat = tags()
        _material(ops, mat, element, f, boucwen_tol, tags)
        tag = tags()
        ops.element("twoNodeLink", tag, *ends, "-mat", mat, "-dir", 1,
                    "-orient", float(d[0]), float(d[1]), 0.0, float(-d[1]), float(d[0]), 0.0, "-doRayleigh")
        links.append(tag)
    return links
