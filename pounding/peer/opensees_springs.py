"""Buildings of storey springs in OpenSees: the independent peer of the inelastic stepping.

The model an OpenSees user would build for :class:`~pounding.elements.storey_springs.StoreySprings`
(3-D, ``ndm 3, ndf 6``, SI units):

* every floor is a rigid diaphragm: a master node at the slab's centre of mass
  carrying ``mass(m, m, 0, 0, 0, J)``, fixed in uz, rx, ry;
* every storey spring is a ``twoNodeLink`` between a node on the element line
  at the floor below (fixed at the ground) and one at the floor above, both
  slaves of their floors' diaphragms (``rigidDiaphragm 3``) and restrained in
  uz, rx, ry, which nothing else stiffens; the link acts along the line only
  (``-dir 1 -orient d_x d_y 0 -d_y d_x 0``), so with the Transformation handler
  its deformation is the relative displacement of the two floors along the
  line at the line's position, as in pounding;
* the spring's material: ``Steel01(Fy, k0, b)`` for ``bilinear`` (no isotropic
  hardening: a1..a4 left at 0), ``BoucWen(b, k0, n, gamma / u_y^n, beta / u_y^n,
  1, 0, 0, 0)`` for ``bouc_wen`` (OpenSees' z is u_y times pounding's), ``Elastic(k0)``
  for elastic springs;
* damping C = a0 M + a1 K_initial per building (``region`` with ``-rayleigh``,
  links with ``-doRayleigh``): the classical damping of the initial elastic model.

:func:`build_spring_building` models buildings of storey-spring lines only (elements that declare
``spring_line``); each line places its own links
(:meth:`~pounding.elements.base.PlanarElement.opensees_model`), as it does in a building of frames and
walls (:mod:`pounding.peer.opensees`).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

#: DOFs of a diaphragm master node that are fixed (uz, rx, ry); ux, uy, rz stay free.
MASTER_FIX = (0, 0, 1, 1, 1, 0)


def build_spring_building(ops, building, tag_offset: int, boucwen_tol: float = 1e-13, extra_slaves=None):
    """Add one storey-spring building to the domain (see the module docstring).

    Returns
    -------
    (masters, nodes, elements, yielding) : master tags per floor, every node tag, every
    element tag, and the link tags of the yielding springs in the order of
    :func:`pounding.framework.engine.inelastic.spring_set`. ``extra_slaves(masters)`` may add
    nodes of other elements to the floors' diaphragms: a list of node lists, one per floor.
    """
    from pounding.peer.opensees import Placement, _Tags

    for e in building.elements:
        if not e.spring_line:
            raise NotImplementedError(f"building {building.name!r}: only lines of storey springs are modelled here, "
                                      f"got element type {e.name or type(e).__name__!r}")
    tags = _Tags(tag_offset)
    elements, yielding = [], []
    masters = []
    for slab in building.slabs:
        tag = tags()
        ops.node(tag, float(slab.centre[0]), float(slab.centre[1]), float(slab.elevation))
        ops.fix(tag, *MASTER_FIX)
        ops.mass(tag, slab.mass, slab.mass, 0.0, 0.0, 0.0, slab.polar_inertia)
        masters.append(tag)
    place = Placement(ops, building, tags, boucwen_tol=boucwen_tol)
    for e in building.elements:
        links = e.opensees_model(ops, place)
        elements.extend(links)
        if e.yields:  # its links are its storey springs, bottom first (the base class's contract)
            yielding.extend(links)
    nodes, slaves = masters + place.nodes, place.slaves
    if extra_slaves is not None:
        for f, more in enumerate(extra_slaves(masters)):
            slaves[f].extend(more)
    for master, sl in zip(masters, slaves):
        if sl:
            ops.rigidDiaphragm(3, master, *sl)
    return masters, nodes, elements, yielding


def run_springs_transient(
    ops,
    buildings: Sequence[Any],
    ground_motion,
    dt: float,
    n_steps: int,
    integrator: Sequence[Any] = ("Newmark", 0.5, 0.25),
    *,
    tol: float = 1e-13,
    max_iter: int = 100,
    boucwen_tol: float = 1e-13,
):
    """Nonlinear time history of storey-spring buildings (no contact) in OpenSees.

    Newton with ``NormDispIncr`` ``tol`` [m], ``UmfPack``, Transformation
    constraints, the ground acceleration as ``UniformExcitation`` along the
    motion's direction, each building's own Rayleigh damping on its initial
    stiffness (from its ``damping``, Rayleigh kind).

    Returns
    -------
    (disp, forces, iterations) : dict name -> (n_steps + 1, storeys, 3) master-node
    (ux [m], uy [m], rz [rad]); dict name -> (n_steps + 1, ns) basic force of the
    yielding links [N] (spring_set order); the total Newton iterations.
    """
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    built = {}
    for i, b in enumerate(buildings):
        built[b.name] = build_spring_building(ops, b, 100_000 * i, boucwen_tol)
    from pounding.peer.opensees import building_rayleigh, rayleigh_damping, step_through, transient_analysis, uniform_excitation

    rayleigh_damping(ops, [built[b.name][1:3] for b in buildings], building_rayleigh(buildings))

    uniform_excitation(ops, ground_motion)
    transient_analysis(ops, integrator, tol, max_iter)

    disp = {b.name: np.zeros((n_steps + 1, b.n_storeys, 3)) for b in buildings}
    forces = {b.name: np.zeros((n_steps + 1, len(built[b.name][3]))) for b in buildings}

    def record(k):
        for b in buildings:
            masters, _, _, links = built[b.name]
            arr = disp[b.name]
            for f, tag in enumerate(masters):
                arr[k, f] = (ops.nodeDisp(tag, 1), ops.nodeDisp(tag, 2), ops.nodeDisp(tag, 6))
            forces[b.name][k] = [ops.eleResponse(e, "basicForce")[0] for e in links]

    iterations = step_through(ops, n_steps, dt, record)
    ops.wipe()
    return disp, forces, iterations


def run_springs_gap_pounding(ops, scene, stiffness: float, dt: float, n_steps: int, *, tol: float = 1e-12, max_iter: int = 100):
    """Two storey-spring buildings side by side along x pounding through zero-length gap springs.

    The buildings of :func:`build_spring_building` (yielding links, each building's Rayleigh damping
    on its initial stiffness) and, at every common storey, two ``zeroLength`` springs in x with
    ``ElasticPPGap`` (``stiffness`` [N/m], the clear distance as its gap, never yielding) at the
    ends of the common facade, each end a slave of its building's diaphragm, as
    :func:`pounding.peer.opensees.run_gap_pounding` adds them to frame buildings. Newmark average
    acceleration, Newton (``NormDispIncr`` ``tol`` [m]), ``n_steps`` steps of ``dt`` [s]; one
    ground-motion component along x; the facades collinear and the motion planar (x only).

    Returns
    -------
    (disp, forces, gap_forces, iterations) : dict name -> (n_steps + 1, storeys, 3) master-node
    (ux, uy, rz); dict name -> (n_steps + 1, ns) yielding links' basic force [N];
    (n_steps + 1, common storeys, 2) gap springs' basic force [N] (negative in compression);
    total Newton iterations.
    """
    from pounding.peer.opensees import _Tags, building_rayleigh, face_gap_springs, rayleigh_damping

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    built = {b.name: build_spring_building(ops, b, 100_000 * i) for i, b in enumerate(scene.buildings)}
    rayleigh_damping(ops, [built[b.name][1:3] for b in scene.buildings], building_rayleigh(scene.buildings))
    masters = {name: parts[0] for name, parts in built.items()}
    gaps, _ = face_gap_springs(ops, scene.buildings, masters, stiffness, _Tags(1_000_000))
    from pounding.peer.opensees import newmark_along_x, step_through

    newmark_along_x(ops, scene.ground_motion, "run_springs_gap_pounding", tol, max_iter)
    disp = {b.name: np.zeros((n_steps + 1, b.n_storeys, 3)) for b in scene.buildings}
    forces = {b.name: np.zeros((n_steps + 1, len(built[b.name][3]))) for b in scene.buildings}
    gap_forces = np.zeros((n_steps + 1, len(gaps), 2))

    def record(k):
        for b in scene.buildings:
            masters, _, _, links = built[b.name]
            for f, t in enumerate(masters):
                disp[b.name][k, f] = (ops.nodeDisp(t, 1), ops.nodeDisp(t, 2), ops.nodeDisp(t, 6))
            forces[b.name][k] = [ops.eleResponse(e, "basicForce")[0] for e in links]
        for f, row in enumerate(gaps):
            gap_forces[k, f] = [ops.eleResponse(e, "basicForce")[0] for e in row]

    iterations = step_through(ops, n_steps, dt, record)
    ops.wipe()
    return disp, forces, gap_forces, iterations


def run_linked_transient(ops, scene, dt: float, n_steps: int, *, tol: float = 1e-13, max_iter: int = 100):
    """Storey-spring buildings joined by the scene's ``[[link]]`` s, in OpenSees: the buildings of
    :func:`build_spring_building`, each link a ``zeroLength`` element with its law's material between
    nodes on the two slabs, slaves of their floors' diaphragms (:func:`pounding.peer.opensees_links.scene_links`,
    which the export calls too); each building's Rayleigh damping on its initial stiffness; Newmark average
    acceleration, Newton (``NormDispIncr`` ``tol`` [m]), the ground motion along x.

    Returns
    -------
    (disp, forces) : dict name -> (n_steps + 1, storeys, 3) master-node (ux [m], uy [m], rz [rad]);
    (n_steps + 1, n_links) the links' basic forces [N] (scene order).
    """
    from pounding.peer.opensees import _Tags, building_rayleigh, newmark_along_x, rayleigh_damping
    from pounding.peer.opensees_links import scene_links

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    built = {b.name: build_spring_building(ops, b, 100_000 * i) for i, b in enumerate(scene.buildings)}
    rayleigh_damping(ops, [built[b.name][1:3] for b in scene.buildings], building_rayleigh(scene.buildings))
    links = scene_links(ops, scene, {name: parts[0] for name, parts in built.items()}, _Tags(5_000_000))
    newmark_along_x(ops, scene.ground_motion, "run_linked_transient", tol, max_iter)
    disp = {b.name: np.zeros((n_steps + 1, b.n_storeys, 3)) for b in scene.buildings}
    forces = np.zeros((n_steps + 1, len(links)))

    def record(k):
        for b in scene.buildings:
            for f, t in enumerate(built[b.name][0]):
                disp[b.name][k, f] = (ops.nodeDisp(t, 1), ops.nodeDisp(t, 2), ops.nodeDisp(t, 6))
        forces[k] = [ops.eleResponse(e, "basicForce")[0] for e in links]

    from pounding.peer.opensees import step_through

    step_through(ops, n_steps, dt, record)
    ops.wipe()
    return disp, forces
