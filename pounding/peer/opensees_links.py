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
    fy = float(element.yield_force[storey])
    b = float(element.hardening)
    law = element.law.name
    if law == "bilinear":
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)
    elif law == "bouc_wen":
        uy = fy / k0
        n, beta, gamma = element.law.n, element.law.beta, element.law.gamma
        ops.uniaxialMaterial("BoucWen", tag, b, k0, n, gamma / uy**n, beta / uy**n, 1.0, 0.0, 0.0, 0.0, float(boucwen_tol * uy), 200)
    elif law == "friction_pendulum" and element.law.friction_slow is None:
        # constant friction: W/R beside the elastic-perfectly-plastic slider (mu W / u_y, yield mu W) is
        # kinematic hardening with the law's k0, Fy and b (singleFPBearing also adds F u / R to the
        # normal force, which the law leaves out)
        ops.uniaxialMaterial("Steel01", tag, fy, k0, b)
    elif law == "elastic":
        ops.uniaxialMaterial("Elastic", tag, element.law.stiffness)
    elif law == "viscous":
        ops.uniaxialMaterial("Viscous", tag, element.law.coefficient, element.law.exponent)
    elif law == "maxwell":
        # the adaptive Dormand-Prince of the material, to 1e-10 relative (its default is 1e-6)
        ops.uniaxialMaterial("ViscousDamper", tag, element.law.stiffness, element.law.coefficient, element.law.exponent,
                             0.0, 1, 1e-10, 1e-12, 20)
    elif law == "kelvin" and tags is not None:
        spring, dashpot = tags(), tags()
        ops.uniaxialMaterial("Elastic", spring, element.law.stiffness)
        ops.uniaxialMaterial("Viscous", dashpot, element.law.coefficient, element.law.exponent)
        ops.uniaxialMaterial("Parallel", tag, spring, dashpot)
    else:
        raise NotImplementedError(f"no OpenSees material for hysteresis law {law!r}"
                                  + (" with velocity-dependent friction" if law == "friction_pendulum" else ""))


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
