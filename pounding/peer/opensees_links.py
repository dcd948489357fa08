"""Links in OpenSees: an element's base on its floor (:func:`stand_on`), and the ``[[link]]`` s between
slabs as ``zeroLength`` elements (:func:`between_slabs`, :func:`scene_links`).

A link's material is its law's own OpenSees counterpart
(:meth:`pounding.hysteresis.base.HysteresisLaw.opensees_material`): ``Steel01`` for the bilinear
law and for the friction pendulum with constant friction, ``BoucWen``, ``Elastic``, ``Viscous``,
``ViscousDamper`` (``maxwell``) and ``Parallel`` of ``Elastic`` and ``Viscous`` (``kelvin``); a law
without one raises NotImplementedError naming it. The storey springs of an element are the
element's own (:meth:`pounding.elements.storey_springs.StoreySprings.opensees_model`), with the
same materials.

Shared by the peer models of the tests (:mod:`pounding.peer.opensees`, :mod:`pounding.peer.opensees_springs`)
and the export, so that a link is built one way.
"""

from __future__ import annotations


def stand_on(ops, tag: int, floor: int, slaves: list[list[int]]) -> None:
    """Fix the base node ``tag`` of an element to what it stands on: the ground (``floor`` 0: all six
    DOFs) or floor ``floor`` (1-based): a slave of that floor's diaphragm in ux, uy, rz and fixed in
    uz, rx, ry, as a base fixed to a slab that is rigid in its plane and does not tilt."""
    if floor == 0:
        ops.fix(tag, 1, 1, 1, 1, 1, 1)
    else:
        ops.fix(tag, 0, 0, 1, 1, 1, 0)
        slaves[floor - 1].append(tag)


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
    link.law.opensees_material(ops, mat, k0, fy, b, tags=tags, boucwen_tol=boucwen_tol)
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
    OpenSees material (:meth:`pounding.hysteresis.base.HysteresisLaw.opensees_material`).
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
