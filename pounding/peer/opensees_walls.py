"""A storey-spring building against fixed walls in OpenSees: the peer of ``[[wall]]`` with a force law.

The building is :func:`pounding.peer.opensees_springs.build_spring_building`'s (rigid diaphragms on
``twoNodeLink`` elements: ``Steel01`` for bilinear springs such as lead-rubber isolators, ``Elastic``
otherwise; each building's Rayleigh damping on its initial stiffness). A wall is what the OpenSees
user models: at both ends of every slab edge that faces it (a face along y, the slab beside it
along x), a ``zeroLength`` element along x between a node fixed in every DOF (the wall) and a node
slaved to the slab's diaphragm, carrying the contact law's OpenSees material
(:func:`pounding.peer.opensees_contact.law_material`: ``ViscoelasticGap`` for ``kelvin`` with
``tension = true``) with half the contact (the face rule: the two ends share it) at the point's
effective mass, that of the slab alone (1 / m + (y - y_c)^2 / J)^-1, and the clear distance as its
negative gap. The element's deformation is u_j - u_i: the fixed node is i for a wall on the slab's
-x side (contact when u_slab <= -clear), j on its +x side (contact when u_slab >= clear).

:func:`scene_walls` places every wall of a scene against every building; the peer run of the
tests (:func:`run_wall_pounding`) and ``pounding export opensees`` (:mod:`pounding.peer.export`)
both call it, so a wall is built one way.
"""

from __future__ import annotations

import numpy as np

from pounding.framework.model.levels import reaches

#: every DOF of the wall's node
FIXED = (1, 1, 1, 1, 1, 1)


def wall_springs(ops, building, masters: list[int], wall, law, tags, screened=frozenset()) -> list[int]:
    """The zero-length wall elements of ``building`` (a scene Building, its diaphragm ``masters`` per
    floor) against ``wall`` (a straight face along y) with contact law instance ``law``; ``tags()`` gives
    the next free tag; ``screened``: the 0-based slabs that face the wall only through other buildings
    (:func:`pounding.framework.model.walls.screened_from`), which get none, as in the engine. Returns
    the element tags (two per slab at or below the wall's top)."""
    from pounding.peer.opensees_contact import law_material
    from pounding.peer.opensees_springs import MASTER_FIX

    face = np.asarray(wall.face, float)
    if len(face) != 2 or abs(face[0, 0] - face[1, 0]) > 1e-12:
        raise ValueError(f"wall {wall.name!r}: the OpenSees peer models a straight face along y")
    x_wall = float(face[0, 0])
    span = (float(face[:, 1].min()), float(face[:, 1].max()))
    material = law_material(law)
    out, made = [], {}
    for f, slab in enumerate(building.slabs):
        if not reaches(slab.elevation, wall.top) or f in screened:
            continue
        xs = np.asarray(slab.vertices, float)[:, 0]
        west = x_wall < xs.min()
        x_edge = float(xs.min() if west else xs.max())
        clear = (x_edge - x_wall) if west else (x_wall - x_edge)
        ends_y = sorted({float(v[1]) for v in slab.vertices if abs(v[0] - x_edge) < 1e-9})
        if len(ends_y) < 2:
            raise ValueError(f"wall {wall.name!r}: building {building.name!r}'s slab {f + 1} meets it at a corner "
                             "(the OpenSees peer models an edge along y facing the wall)")
        if ends_y[-1] < span[0] or ends_y[0] > span[1]:
            continue  # the slab's edge passes beside the face: it never strikes it
        if ends_y[0] < span[0] or ends_y[-1] > span[1]:
            raise ValueError(f"wall {wall.name!r}: building {building.name!r}'s slab {f + 1} faces it over part of its "
                             "edge only (the OpenSees peer puts the contact at the edge's two ends)")
        for y in (ends_y[0], ends_y[-1]):
            m_eff = 1.0 / (1.0 / slab.mass + (y - float(slab.centre[1])) ** 2 / slab.polar_inertia)
            args = tuple(material(0.5, m_eff, clear))
            if args not in made:
                made[args] = tags()
                ops.uniaxialMaterial(args[0], made[args], *args[1:])
            fixed, on_slab = tags(), tags()
            ops.node(fixed, x_wall, y, float(slab.elevation))
            ops.fix(fixed, *FIXED)
            ops.node(on_slab, x_edge, y, float(slab.elevation))
            ops.fix(on_slab, *MASTER_FIX)
            ops.rigidDiaphragm(3, masters[f], on_slab)
            ends = (fixed, on_slab) if west else (on_slab, fixed)
            tag = tags()
            ops.element("zeroLength", tag, *ends, "-mat", made[args], "-dir", 1)
            out.append(tag)
    return out


def scene_walls(ops, scene, masters: dict, tags) -> tuple[list[int], list[str], list[str]]:
    """The zero-length elements of every wall of ``scene`` against every building (:func:`wall_springs`),
    each wall with its own law (else ``[analysis] contact``: :func:`pounding.contact.rules.wall_law`).

    ``masters`` maps a building's name to its diaphragm master tags per floor; ``tags()`` gives the next
    free tag. A wall the peer cannot model (a law with no OpenSees material, a face not straight along
    y, a slab beside part of it) is left out whole, with one sentence saying why.

    Returns
    -------
    (elements, left_out, differs) : the element tags (scene order of walls, then buildings and slabs);
    one sentence per wall left out; one per wall whose material computes differently from its law
    (:meth:`pounding.contact.base.ContactLaw.opensees_notes`).
    """
    from pounding.contact.rules import default_law, law_name, wall_law
    from pounding.framework.model.walls import screened_from
    from pounding.peer.opensees_contact import WITH_MATERIAL, has_material

    default = default_law(scene)
    elements, left_out, differs = [], [], []
    for wall in scene.walls:
        law = wall_law(scene, wall, default)
        if not has_material(law):
            why = " (OpenSees has no rigid impulse at events)" if law.at_events else ""
            left_out.append(f"wall {wall.name!r}: its contact law {law_name(law)!r} has no OpenSees material{why}, so the "
                            f"model's slabs strike nothing there; give the wall a force law that has one ({WITH_MATERIAL}) "
                            "to export it")
            continue
        face = np.asarray(wall.face, float)
        behind = [frozenset(f for f in range(len(b.slabs)) if screened_from(scene, i, f, face[0], face[-1]))
                  for i, b in enumerate(scene.buildings)]
        try:  # the whole wall or none of it: a dry run against every building before writing a command
            for b, skip in zip(scene.buildings, behind):
                wall_springs(_Silent(), b, masters[b.name], wall, law, tags, skip)
        except ValueError as exc:
            left_out.append(f"{exc}: the model leaves this wall out")
            continue
        for b, skip in zip(scene.buildings, behind):
            elements += wall_springs(ops, b, masters[b.name], wall, law, tags, skip)
        differs += [f"wall {wall.name!r}: {n}" for n in law.opensees_notes()]
    return elements, left_out, differs


class _Silent:
    """An ``ops`` that does nothing: a dry run of a builder, for its checks."""

    def __getattr__(self, command: str):
        return lambda *args: None


def run_wall_pounding(ops, scene, dt: float, n_steps: int, *, tol: float = 1e-12, max_iter: int = 100):
    """The scene's storey-spring buildings shaken along x against its walls (each with its own law,
    else ``[analysis] contact``), Newmark average acceleration, Newton (``NormDispIncr`` ``tol`` [m]),
    ``n_steps`` steps of ``dt`` [s].

    Returns
    -------
    (disp, wall_forces, iterations) : dict name -> (n_steps + 1, storeys, 3) master-node (ux [m], uy [m],
    rz [rad]); (n_steps + 1, elements) the wall elements' basic force [N] (negative in compression), in
    the order of the scene's walls, buildings and slabs; the total Newton iterations.
    """
    from pounding.peer.opensees import _Tags, building_rayleigh, newmark_along_x, rayleigh_damping, step_through
    from pounding.peer.opensees_springs import build_spring_building

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    built = {b.name: build_spring_building(ops, b, 100_000 * i) for i, b in enumerate(scene.buildings)}
    rayleigh_damping(ops, [built[b.name][1:3] for b in scene.buildings], building_rayleigh(scene.buildings))
    elements, left_out, _ = scene_walls(ops, scene, {name: parts[0] for name, parts in built.items()}, _Tags(1_000_000))
    if left_out:
        raise ValueError("; ".join(left_out))
    newmark_along_x(ops, scene.ground_motion, "run_wall_pounding", tol, max_iter)
    disp = {b.name: np.zeros((n_steps + 1, b.n_storeys, 3)) for b in scene.buildings}
    forces = np.zeros((n_steps + 1, len(elements)))

    def record(k):
        for b in scene.buildings:
            for f, t in enumerate(built[b.name][0]):
                disp[b.name][k, f] = (ops.nodeDisp(t, 1), ops.nodeDisp(t, 2), ops.nodeDisp(t, 6))
        forces[k] = [ops.eleResponse(e, "basicForce")[0] for e in elements]

    iterations = step_through(ops, n_steps, dt, record)
    ops.wipe()
    return disp, forces, iterations
