"""Import OpenSeesPy wherever it can run, and build the same scene in it.

The openseespy 3.7.1 wheels for Python 3.11 link against the system's
libblas.so.3 / liblapack.so.3 but also ship copies in
``openseespylinux/lib``. Loading those copies with ``RTLD_GLOBAL`` before the
import lets the dynamic linker resolve them by soname, so no system package
and no ``LD_LIBRARY_PATH`` is needed.
"""

from __future__ import annotations

import ctypes
import importlib.util
from pathlib import Path
from typing import Any, Sequence

import numpy as np


def load_opensees():
    """Return the ``openseespy.opensees`` module, loading its bundled BLAS/LAPACK first.

    Raises
    ------
    ImportError
        If openseespy is not installed or cannot run here.
    """
    spec = importlib.util.find_spec("openseespylinux")
    if spec is not None and spec.origin:
        lib = Path(spec.origin).parent / "lib"
        for name in ("libgfortran.so.4", "libquadmath.so.0", "libgomp.so.1", "libblas.so.3", "liblapack.so.3"):
            if (lib / name).exists():
                try:
                    ctypes.CDLL(str(lib / name), mode=ctypes.RTLD_GLOBAL)
                except OSError:
                    pass  # the system copy may already be loaded; the import below decides
    try:
        import openseespy.opensees as ops
    except RuntimeError as exc:  # openseespy wraps its loader failure in RuntimeError
        raise ImportError(str(exc)) from exc
    return ops


# --------------------------------------------------------------------------- the peer model
#
# The same building, modelled "as an OpenSees user would": a 3-D model
# (ndm 3, ndf 6) where every planar element is a real planar structure of
# elastic beam-columns, every floor a rigid diaphragm with its mass at one
# master node. Nothing here uses pounding's condensed stiffness: agreement with
# :func:`pounding.framework.model.assembly.assemble` is an independent check.

#: DOFs of a diaphragm master node that are fixed (uz, rx, ry); ux, uy, rz stay free.
MASTER_FIX = (0, 0, 1, 1, 1, 0)


class _Tags:
    """A running tag counter shared by nodes, elements and transformations (disjoint by construction)."""

    def __init__(self, offset: int):
        self.last = int(offset)

    def __call__(self) -> int:
        self.last += 1
        return self.last


class Placement:
    """Where one building's elements go in the peer's OpenSees model: what the peer hands every
    element's :meth:`~pounding.elements.base.PlanarElement.opensees_model`.

    The element adds its own nodes, materials and elements with ``ops``; through this object it
    takes tags, creates nodes (recorded as the building's, for its Rayleigh damping) and ties them
    to the building's floors, whose rigid diaphragms the peer closes once every element is placed.

    Attributes
    ----------
    ops : module
        ``openseespy.opensees`` or a recorder of its commands (:class:`pounding.peer.script.ScriptOps`).
    building : str
        The building's name (for messages).
    storey_heights : tuple of float
        The building's storey heights [m], bottom first (elevations: :meth:`PlanarElement.base_elevation`).
    out_of_plane : float
        Out-of-plane bending inertia and torsional constant of a member, as a fraction of its in-plane
        inertia [-], > 0 (:func:`build_building`).
    boucwen_tol : float
        Tolerance of OpenSees' ``BoucWen`` material, as a fraction of the yield displacement [-]
        (:meth:`pounding.hysteresis.base.HysteresisLaw.opensees_material`).
    slaves : list of list of int
        ``slaves[f - 1]``: the nodes tied to floor f's diaphragm so far.
    nodes : list of int
        Every node the building's elements created, in order.
    """

    def __init__(self, ops, building, tags, *, out_of_plane: float = 1e-6, boucwen_tol: float = 1e-13):
        self.ops = ops
        self.building = building.name
        self.storey_heights = tuple(float(h) for h in building.storey_heights)
        self.out_of_plane = float(out_of_plane)
        self.boucwen_tol = float(boucwen_tol)
        self.slaves: list[list[int]] = [[] for _ in building.slabs]
        self.nodes: list[int] = []
        self._tags = tags

    def tag(self) -> int:
        """The next free tag (nodes, elements, materials and transformations share one counter)."""
        return self._tags()

    def node(self, x: float, y: float, z: float) -> int:
        """A new node at (x, y, z) [m] (``ops.node``), free in all six DOFs; its tag."""
        tag = self._tags()
        self.ops.node(tag, float(x), float(y), float(z))
        self.nodes.append(tag)
        return tag

    def on_floor(self, tag: int, floor: int) -> None:
        """Node ``tag`` moves with floor ``floor`` (1-based, the building's numbering) in ux, uy, rz: a
        slave of its rigid diaphragm. Its uz, rx, ry stay free: the element's members hold them."""
        self.slaves[floor - 1].append(tag)

    def stand_on(self, tag: int, floor: int) -> None:
        """Node ``tag`` is a base of the element on floor ``floor`` (0: the ground, fixed in all six DOFs;
        above: a slave of the floor's diaphragm, fixed in uz, rx, ry): :func:`pounding.peer.opensees_links.stand_on`."""
        from pounding.peer.opensees_links import stand_on

        stand_on(self.ops, tag, floor, self.slaves)


def _build(ops, building, out_of_plane: float, tags: _Tags) -> tuple[list[int], list[int], list[int]]:
    """Build one building; return (master tags per floor, all node tags, all element tags).

    Every element places itself (:meth:`~pounding.elements.base.PlanarElement.opensees_model`, with a
    :class:`Placement`); the floors' masters and diaphragms follow."""
    if not out_of_plane > 0.0:
        raise ValueError(f"out_of_plane must be > 0 (a zero out-of-plane stiffness leaves the frames unstable), got {out_of_plane}")
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    place = Placement(ops, building, tags, out_of_plane=out_of_plane)
    elements: list[int] = []
    for e in building.elements:
        elements.extend(e.opensees_model(ops, place))
    nodes = place.nodes

    masters = []
    for f, slab in enumerate(building.slabs):
        tag = tags()
        cx, cy = (float(c) for c in slab.centre)
        ops.node(tag, cx, cy, float(slab.elevation))
        ops.fix(tag, *MASTER_FIX)
        ops.mass(tag, slab.mass, slab.mass, 0.0, 0.0, 0.0, slab.polar_inertia)
        if place.slaves[f]:
            ops.rigidDiaphragm(3, tag, *place.slaves[f])
        masters.append(tag)
        nodes.append(tag)
    return masters, nodes, elements


def build_building(ops, building, *, out_of_plane: float = 1e-6, tag_offset: int = 0) -> list[int]:
    """Add one pounding :class:`~pounding.framework.model.scene.Building` to the OpenSees domain.

    The model is 3-D (``ndm 3, ndf 6``), in SI units (m, N, kg, s). Every element places
    itself: its :meth:`~pounding.elements.base.PlanarElement.opensees_model` adds its nodes,
    materials and elements through a :class:`Placement` (an element type without one raises
    NotImplementedError naming it). The built-in elements:

    * every frame is an independent planar structure: a node at every column
      line and floor (x, y = point + s direction, z = floor elevation [m]),
      ``elasticBeamColumn`` columns and beams with the frame's (E, A, I) for
      bending in the frame plane (``Iz``), ``Iy = J = out_of_plane * I`` out of
      it, G = E / (2 (1 + 0.2)); ``geomTransf Linear`` with vecxz = the plane's
      horizontal normal. Frames that cross in plan keep their own nodes
      (:meth:`pounding.elements.frame.Frame.opensees_model`);
    * every shear wall is a chain of ``ElasticTimoshenkoBeam`` elements (one
      per storey) on the wall's centre line with E, G, A = t L, Iz = t L^3/12
      and shear area As in plane (``Iy = J = out_of_plane * Iz``): the exact
      Timoshenko cantilever that :class:`~pounding.elements.shear_wall.ShearWall`
      condenses;
    * storey springs are one ``twoNodeLink`` per storey with the material of their
      hysteresis law (:meth:`pounding.elements.storey_springs.StoreySprings.opensees_model`);
    * base nodes are fixed in all six DOFs on the ground; an element standing on floor b > 0
      (``first_storey`` = b + 1) has its base nodes at that floor's elevation, slaves of its
      diaphragm and fixed in uz, rx, ry (:meth:`Placement.stand_on`);
    * every floor has a master node at the slab's centre of mass carrying
      ``mass(m, m, 0, 0, 0, J)`` [kg, kg m^2], fixed in uz, rx, ry and free in
      ux, uy, rz, tied to all element nodes of that floor by
      ``rigidDiaphragm 3``. The slave nodes keep their uz, rx, ry free.

    The caller wipes the domain if needed (this function does not); analyses
    need ``constraints('Transformation')``.

    Parameters
    ----------
    ops : module
        The ``openseespy.opensees`` module from :func:`load_opensees`.
    building : Building
    out_of_plane : float
        Out-of-plane bending inertia and torsional constant of every member, as
        a fraction of its in-plane inertia [-], > 0. It adds that fraction of
        stiffness the condensed model does not have, so periods differ from
        pounding's by about that relative amount.
    tag_offset : int
        Node, element and transformation tags start at ``tag_offset + 1``.

    Returns
    -------
    list of int
        Master node tag of every floor, bottom first (length ``n_storeys``).
    """
    masters, _, _ = _build(ops, building, out_of_plane, _Tags(tag_offset))
    return masters


def build_scene(ops, scene, *, out_of_plane: float = 1e-6) -> dict[str, list[int]]:
    """Wipe the domain and build every building of ``scene`` with disjoint tags.

    Returns
    -------
    dict
        Building name -> master node tags per floor (bottom first).
    """
    ops.wipe()
    return {name: masters for name, (masters, _, _) in _build_all(ops, scene.buildings, out_of_plane).items()}


def _build_all(ops, buildings, out_of_plane: float) -> dict[str, tuple[list[int], list[int], list[int]]]:
    tags = _Tags(0)
    out = {}
    for b in buildings:
        out[b.name] = _build(ops, b, out_of_plane, tags)
    return out


def eigen_periods(ops, n: int) -> np.ndarray:
    """The first ``n`` natural periods of the current model [s], shape (n,), descending.

    Sets ``constraints('Transformation')`` and solves with ``'-fullGenLapack'``
    (the mass matrix is singular: only the masters carry mass, so the default
    Arpack solver does not apply). Call it before defining a transient analysis.
    """
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    lam = np.asarray(ops.eigen("-fullGenLapack", int(n)), dtype=float)
    ops.wipeAnalysis()
    return 2.0 * np.pi / np.sqrt(lam)


def run_transient(
    ops,
    scene_or_building,
    ground_motion,
    dt: float,
    n_steps: int,
    integrator: Sequence[Any] = ("Newmark", 0.5, 0.25),
    rayleigh: tuple[float, float] | Sequence[tuple[float, float]] | None = None,
    *,
    out_of_plane: float = 1e-6,
):
    """Linear time history of a building (or every building of a scene) under a ground motion.

    Wipes the domain, builds the model (:func:`build_building`), applies the
    ground acceleration as ``UniformExcitation`` along the motion's direction
    (two patterns, x and y, with the record scaled by cos and sin of the angle
    when it is not a multiple of 90 degrees) and runs ``n_steps`` steps of
    ``dt`` with ``constraints('Transformation')``, ``system('UmfPack')`` and a
    ``Linear -factorOnce`` algorithm (the model is linear and dt constant).

    Damping is C = a0 M + a1 K_initial: ``rayleigh(a0, 0, a1, 0)`` (the initial
    stiffness; the model is linear, so it is also the current and committed
    one, and it is fixed once instead of following the committed state). With
    the stiffness term applied to every element, the massless internal DOFs
    carry (1 + a1 d/dt) K forces that condense exactly to a1 times the
    condensed K on the floor DOFs, so this is pounding's C = a0 M + a1 K.

    Parameters
    ----------
    ops : module
        From :func:`load_opensees`.
    scene_or_building : Scene or Building
    ground_motion : GroundMotion or GroundMotionPair
        Each of its ``components`` with ``t`` [s], ``acc`` [m/s^2] and ``angle`` [deg]; the record is zero
        outside its time span (as ``GroundMotion.at``). OpenSees starts from
        zero acceleration, i.e. it does not solve for a consistent initial
        acceleration when ``acc(0) != 0``.
    dt : float
        Time step [s].
    n_steps : int
    integrator : tuple
        Arguments of ``ops.integrator``, e.g. ``("Newmark", 0.5, 0.25)`` or
        ``("HHT", 1 + alpha)``: OpenSees' HHT alpha is 1 + Hilber's alpha
        (pounding's ``alpha = -0.05`` is OpenSees' ``0.95``).
    rayleigh : (a0, a1) or list of (a0, a1), optional
        [1/s, s]. One pair for all buildings, one pair per building (applied
        per building through ``region``), or None for each building's own
        Rayleigh coefficients from its ``damping`` (Rayleigh kind only).
    out_of_plane : float
        See :func:`build_building`.

    Returns
    -------
    ndarray (n_steps + 1, n_storeys, 3) for a Building, or dict name -> such an array for a Scene
        Master-node displacements (ux [m], uy [m], rz [rad]) relative to the
        ground, row 0 the initial rest state, row k at time k dt.
    """
    from pounding.framework.model.scene import Building

    single = isinstance(scene_or_building, Building)
    buildings = (scene_or_building,) if single else tuple(scene_or_building.buildings)
    ops.wipe()
    built = _build_all(ops, buildings, out_of_plane)

    rayleigh_damping(ops, [built[b.name][1:3] for b in buildings], _rayleigh_pairs(buildings, rayleigh))

    uniform_excitation(ops, ground_motion)

    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.algorithm("Linear", "-factorOnce")  # linear model, constant dt: one factorisation serves every step
    ops.integrator(*integrator)
    ops.analysis("Transient")

    masters = [built[b.name][0] for b in buildings]
    out = [np.zeros((n_steps + 1, b.n_storeys, 3)) for b in buildings]

    def record(k):
        for arr, tags in zip(out, masters):
            for f, tag in enumerate(tags):
                arr[k, f] = (ops.nodeDisp(tag, 1), ops.nodeDisp(tag, 2), ops.nodeDisp(tag, 6))

    step_through(ops, n_steps, dt, record)
    ops.wipeAnalysis()
    if single:
        return out[0]
    return {b.name: arr for b, arr in zip(buildings, out)}


def uniform_excitation(ops, ground_motion) -> int:
    """One UniformExcitation pattern per component and plan axis it has a share on (a pair along x
    and y is two patterns, each component with its own time series); returns the number of patterns."""
    pattern = 0
    for component in ground_motion.components:
        direction = component.direction()
        t = [float(x) for x in component.t]
        acc = [float(x) for x in component.acc]
        for dof, factor in ((1, float(direction[0])), (2, float(direction[1]))):
            if factor == 0.0:
                continue
            pattern += 1
            ops.timeSeries("Path", pattern, "-time", *t, "-values", *acc, "-factor", factor)
            ops.pattern("UniformExcitation", pattern, dof, "-accel", pattern)
    return pattern


def rayleigh_damping(ops, parts, pairs) -> None:
    """Classical damping C = a0 M + a1 K_initial of each building.

    ``parts[k]`` = (node tags, element tags) of building k, ``pairs[k]`` = its (a0 [1/s], a1 [s]).
    One pair for all: ``rayleigh(a0, 0, a1, 0)`` on the whole domain. Otherwise per building, two
    ``region``s: its elements with ``-rayleigh 0 0 a1 0`` (elements of the storey-spring links
    take it with ``-doRayleigh``) and its nodes with ``-nodeOnly -rayleigh a0 0 0 0`` (only the
    diaphragm masters carry mass). Gap elements belong to no region and get no damping.
    """
    pairs = [(float(a0), float(a1)) for a0, a1 in pairs]
    if all(pq == pairs[0] for pq in pairs):
        a0, a1 = pairs[0]
        ops.rayleigh(a0, 0.0, a1, 0.0)
        return
    for k, ((nodes, elements), (a0, a1)) in enumerate(zip(parts, pairs), start=1):
        ops.region(k, "-ele", *elements, "-rayleigh", 0.0, 0.0, a1, 0.0)
        ops.region(len(parts) + k, "-nodeOnly", *nodes, "-rayleigh", a0, 0.0, 0.0, 0.0)


def building_rayleigh(buildings) -> list[tuple[float, float]]:
    """Each building's own (a0 [1/s], a1 [s]) from its ``damping`` (Rayleigh kind only, else ValueError)."""
    return _rayleigh_pairs(buildings, None)


def _rayleigh_pairs(buildings, rayleigh) -> list[tuple[float, float]]:
    if rayleigh is None:
        from pounding.framework.model.assembly import assemble, rayleigh_coefficients

        pairs = []
        for b in buildings:
            if b.damping.kind != "rayleigh":
                raise ValueError(f"building {b.name!r} has {b.damping.kind!r} damping; give rayleigh=(a0, a1) explicitly")
            pairs.append(tuple(float(c) for c in rayleigh_coefficients(b.damping, assemble(b).omega, b.name)))
        return pairs
    arr = np.asarray(rayleigh, dtype=float)
    if arr.shape == (2,):
        return [(float(arr[0]), float(arr[1]))] * len(buildings)
    if arr.shape == (len(buildings), 2):
        return [(float(a), float(c)) for a, c in arr]
    raise ValueError(f"rayleigh must be (a0, a1) or one pair per building ({len(buildings)}), got shape {arr.shape}")


def run_gap_pounding(ops, scene, stiffness: float, dt: float, n_steps: int, *, out_of_plane: float = 1e-12):
    """Two buildings side by side along x pounding through zero-length gap springs, in OpenSees.

    :func:`run_face_pounding` with the gap springs of :func:`face_gap_springs` (``ElasticPPGap`` of
    stiffness ``stiffness`` [N/m] at each end of the common facade); returns what it returns.
    """
    return run_face_pounding(ops, scene, gap_material(stiffness), dt, n_steps, out_of_plane=out_of_plane)


def run_face_pounding(ops, scene, material, dt: float, n_steps: int, *, out_of_plane: float = 1e-12,
                      tol: float = 1e-12, max_iter: int = 50):
    """Two buildings side by side along x pounding through zero-length contact elements, in OpenSees.

    The pair as tests/test_opensees_pounding.py describes it: the full 3-D model of
    :func:`build_building` for each, each building's own Rayleigh damping (none on the contact
    elements), and the contact elements of :func:`face_springs` with the materials ``material``
    gives; Newmark average acceleration, Newton (``NormDispIncr`` ``tol`` [m], at most ``max_iter``
    iterations), ``n_steps`` steps of ``dt`` [s]. The facades must be collinear (face-to-face
    contact) and the motion along x.

    Returns (ux, forces, iterations, clear): ux dict name -> (n_steps + 1, storeys)
    master-node x displacements [m]; forces (n_steps + 1, common storeys, 2) basic force
    of the contact elements [N] (negative in compression); the total Newton iterations; the
    clear distance [m].
    """
    ops.wipe()
    tags = _Tags(0)
    built = {b.name: _build(ops, b, out_of_plane, tags) for b in scene.buildings}
    # each building's own Rayleigh damping C = a0 M + a1 K_initial, as pounding's (and run_transient's)
    rayleigh_damping(ops, [built[b.name][1:3] for b in scene.buildings], building_rayleigh(scene.buildings))
    masters = {name: parts[0] for name, parts in built.items()}
    springs, clear = face_springs(ops, scene.buildings, masters, material, tags)

    newmark_along_x(ops, scene.ground_motion, "run_face_pounding", tol, max_iter)

    ux = {b.name: np.zeros((n_steps + 1, b.n_storeys)) for b in scene.buildings}
    forces = np.zeros((n_steps + 1, len(springs), 2))

    def record(k):
        for name, tags_ in masters.items():
            ux[name][k] = [ops.nodeDisp(t, 1) for t in tags_]
        for f, row in enumerate(springs):
            forces[k, f] = [ops.eleResponse(e, "basicForce")[0] for e in row]

    iterations = step_through(ops, n_steps, dt, record)
    ops.wipe()
    return ux, forces, iterations, clear


def gap_material(stiffness: float):
    """The material of :func:`face_gap_springs`: ``ElasticPPGap(stiffness, -1e30, -clear, 0, "noDamage")`` at
    every point, whatever its share or effective mass (a spring ``stiffness`` [N/m] per point)."""
    k = float(stiffness)
    return lambda share, m_eff, clear: ("ElasticPPGap", k, -1e30, -clear, 0.0, "noDamage")


def face_gap_springs(ops, buildings, masters: dict, stiffness: float, tags) -> tuple[list[list[int]], float]:
    """Compression-only linear springs (``ElasticPPGap``, ``stiffness`` [N/m] each) between two buildings whose
    facing slab edges are collinear, along x: :func:`face_springs` with :func:`gap_material`.

    ``ElasticPPGap(stiffness, -1e30, -clear, 0, "noDamage")``: no force while the clear distance stays
    open, ``stiffness`` times the penetration once it closes (the huge negative yield force keeps it
    elastic). Returns what :func:`face_springs` returns.
    """
    return face_springs(ops, buildings, masters, gap_material(stiffness), tags)


def face_springs(ops, buildings, masters: dict, material, tags) -> tuple[list[list[int]], float]:
    """Zero-length contact elements between two buildings whose facing slab edges are collinear, along x.

    At both ends of the common facade, on every common storey, a ``zeroLength`` element in x
    between two coincident nodes, each a slave of its building's diaphragm
    (``rigidDiaphragm 3``, restrained in uz, rx, ry, which nothing stiffens). The element has no
    Rayleigh damping (``zeroLength`` takes it only with ``-doRayleigh 1``): its material is the
    whole contact. ``material(share, m_eff, clear)`` gives the ``uniaxialMaterial`` arguments after the
    tag for an element that carries ``share`` [-] of the contact of its storey (1/2: the two ends of
    the face) at a point of effective mass ``m_eff`` [kg] (:func:`point_effective_mass`), the clear
    distance being ``clear`` [m] (OpenSees' gap materials take it as the negative gap); elements
    with the same arguments share one material. ``buildings`` = (the one on the -x side, the one on
    the +x side); ``masters`` maps a building's name to its master tags per floor; ``tags()`` gives
    the next free tag.

    Returns (springs, clear): springs[f] = the two element tags of common storey f + 1; the
    clear distance [m].

    Raises ValueError when the facades are not collinear or a common storey is not at one level.
    """
    low, high = buildings
    x_low = max(float(v[0]) for v in low.slabs[0].vertices)
    x_high = min(float(v[0]) for v in high.slabs[0].vertices)
    clear = x_high - x_low
    ends_y = sorted({float(v[1]) for v in low.slabs[0].vertices})
    if ends_y != sorted({float(v[1]) for v in high.slabs[0].vertices}):
        raise ValueError("gap springs need collinear facades (face-to-face contact)")
    materials: dict[tuple, int] = {}
    springs = []
    for f in range(min(low.n_storeys, high.n_storeys)):
        z = float(low.slabs[f].elevation)
        if abs(z - float(high.slabs[f].elevation)) > 1e-9:
            raise ValueError(f"storey {f + 1} is not at the same level in both buildings")
        row = []
        for y in ends_y:
            ends = []
            for b in (low, high):  # i = low, j = high: deformation u_high - u_low, compression when < -clear
                tag = tags()
                ops.node(tag, 0.5 * (x_low + x_high), y, z)
                ops.fix(tag, *MASTER_FIX)  # uz, rx, ry carry no stiffness here; ux, uy, rz follow the diaphragm
                ops.rigidDiaphragm(3, masters[b.name][f], tag)
                ends.append(tag)
            args = tuple(material(1.0 / len(ends_y), point_effective_mass(low.slabs[f], high.slabs[f], y), clear))
            if args not in materials:
                materials[args] = tags()
                ops.uniaxialMaterial(args[0], materials[args], *args[1:])
            tag = tags()
            ops.element("zeroLength", tag, *ends, "-mat", materials[args], "-dir", 1)
            row.append(tag)
        springs.append(row)
    return springs, clear


def point_effective_mass(slab_a, slab_b, y: float) -> float:
    """Effective mass [kg] of two slabs at a contact point of ordinate ``y`` [m] with an x normal.

    1 / a with a = sum over the two slabs of 1/m + (y - y_c)^2 / J (the paper's a: a unit pair of
    forces along x at the point moves each slab's centre by 1/m and twists it by (y - y_c) / J;
    m [kg], J [kg m^2] the slab's mass and polar inertia about its centre of mass (x_c, y_c)).
    """
    a = sum(1.0 / s.mass + (y - float(s.centre[1])) ** 2 / s.polar_inertia for s in (slab_a, slab_b))
    return 1.0 / a


# --------------------------------------------------------------------------- P-Delta peer
def step_through(ops, n_steps: int, dt: float, record) -> int:
    """Run the analysis set up in ``ops`` for n_steps steps of dt [s], calling ``record(k)`` after
    step k (1..n_steps); returns the Newton iterations taken in all (``ops.testIter()`` summed).
    A step OpenSees cannot take raises :class:`RuntimeError` naming it."""
    iterations = 0
    for k in range(1, n_steps + 1):
        if ops.analyze(1, float(dt)) != 0:
            raise RuntimeError(f"OpenSees analysis failed at step {k} (t = {k * dt:g} s)")
        iterations += ops.testIter()
        record(k)
    return iterations


def newmark_along_x(ops, gm, who: str, tol: float, max_iter: int) -> None:
    """Shake along x with the one component of ``gm`` (UniformExcitation) and set up a Newton,
    Newmark average-acceleration transient analysis (the gap and spring peers' set-up)."""
    if len(gm.components) != 1 or tuple(gm.direction()) != (1.0, 0.0):
        raise ValueError(f"{who} shakes with one component along x only")
    uniform_excitation(ops, gm)
    transient_analysis(ops, ("Newmark", 0.5, 0.25), tol, max_iter)


def transient_analysis(ops, integrator: Sequence[Any], tol: float, max_iter: int) -> None:
    """A Newton transient analysis: ``constraints('Transformation')`` (rigid diaphragms), RCM numbering,
    ``UmfPack``, ``NormDispIncr`` ``tol`` [m] in at most ``max_iter`` iterations, ``integrator`` the
    arguments of ``ops.integrator`` (``("Newmark", gamma, beta)``, ``("HHT_TP", 1 + Hilber's alpha)``)."""
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", float(tol), int(max_iter))
    ops.algorithm("Newton")
    ops.integrator(*integrator)
    ops.analysis("Transient")


def _gravity_step(ops) -> None:
    """One linear static step under the gravity loads of the current pattern, then held constant
    (``loadConst``) with the time reset, so the geometric stiffness of the PDelta transformation
    acts in what follows."""
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 10)
    ops.algorithm("Linear")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees gravity step failed")
    ops.loadConst("-time", 0.0)


def pdelta_frame_periods(ops, frame, floor_masses: Sequence[float], floor_loads: Sequence[float], n: int) -> np.ndarray:
    """Periods [s] of one planar frame with OpenSees' ``PDelta`` transformation under gravity loads.

    A 2-D model (ndm 2, ndf 3) "as an OpenSees user would" build it: the frame's
    columns (``PDelta`` transformation) and beams (``Linear``) as ``elasticBeamColumn``
    members, fixed bases, the joints of a floor tied in x by ``equalDOF`` (a rigid
    diaphragm) with the floor mass on the first joint's x. The floor loads act
    downwards, split equally over the floor's joints; a linear static step gives the
    columns' axial forces, ``loadConst`` keeps them, and the eigen solution of the
    tangent stiffness (elastic plus the columns' geometric stiffness N/L) gives the
    periods. Nothing here uses pounding's storey geometric stiffness.

    Parameters
    ----------
    frame : pounding.elements.frame.Frame
    floor_masses, floor_loads : sequences of float, one per floor
        [kg] on this frame's x DOF, and [N] of gravity load on this frame.
    n : int
        Number of periods (at most the number of floors).
    """
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    z = np.concatenate([[0.0], np.cumsum(frame.heights)])
    nc = len(frame.columns)
    tag = lambda level, j: 1 + level * nc + j  # noqa: E731
    for level, zl in enumerate(z):
        for j, s in enumerate(frame.columns):
            ops.node(tag(level, j), float(s), float(zl))
            if level == 0:
                ops.fix(tag(level, j), 1, 1, 1)
    ops.geomTransf("PDelta", 1)
    ops.geomTransf("Linear", 2)
    ele = 0
    for i in range(len(frame.heights)):
        E, A, I = frame.column_sections[i]
        for j in range(nc):
            ele += 1
            ops.element("elasticBeamColumn", ele, tag(i, j), tag(i + 1, j), A, E, I, 1)
        E, A, I = frame.beam_sections[i]
        for j in range(nc - 1):
            ele += 1
            ops.element("elasticBeamColumn", ele, tag(i + 1, j), tag(i + 1, j + 1), A, E, I, 2)
    for level in range(1, len(z)):
        for j in range(1, nc):
            ops.equalDOF(tag(level, 0), tag(level, j), 1)
        ops.mass(tag(level, 0), float(floor_masses[level - 1]), 0.0, 0.0)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for level in range(1, len(z)):
        for j in range(nc):
            ops.load(tag(level, j), 0.0, -float(floor_loads[level - 1]) / nc, 0.0)
    _gravity_step(ops)
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("FullGeneral")
    lam = np.asarray(ops.eigen("-fullGenLapack", int(n)), dtype=float)
    ops.wipe()
    return 2.0 * np.pi / np.sqrt(lam)


def pdelta_building_periods(ops, building, leaning: np.ndarray, floor_loads: Sequence[float], n: int, *, out_of_plane: float = 1e-9) -> np.ndarray:
    """Periods [s] of a 3-D building whose gravity loads ride on leaning columns (``corotTruss``).

    The building is :func:`build_building`'s model. Its gravity loads are carried by
    leaning columns at the plan points ``leaning`` (k, 2) [m]: a ``corotTruss`` per
    storey and point (axially stiff, no bending), their floor nodes slaved to the
    floor's rigid diaphragm, each carrying 1/k of every floor's load ``floor_loads``
    [N] (applied downwards at its nodes). A linear static step gives their axial
    forces; the eigen solution of the tangent (the trusses' geometric stiffness N/L
    across their axis, through the diaphragms onto translation and twist) gives the
    periods. The load centre and the polar moment of the load about it are those
    of the points: place them where the assumption under test puts the load.
    """
    ops.wipe()
    tags = _Tags(0)
    masters, _, _ = _build(ops, building, out_of_plane, tags)
    mat = 1
    ops.uniaxialMaterial("Elastic", mat, 1e15)
    z = np.concatenate([[0.0], np.cumsum(building.storey_heights)])
    k = len(leaning)
    chains = []
    for x, y in np.asarray(leaning, dtype=float):
        chain = []
        for level, zl in enumerate(z):
            tag = tags()
            ops.node(tag, float(x), float(y), float(zl))
            if level == 0:
                ops.fix(tag, 1, 1, 1, 1, 1, 1)
            else:
                ops.fix(tag, 0, 0, 0, 1, 1, 0)
            chain.append(tag)
        for level in range(len(z) - 1):
            ops.element("corotTruss", tags(), chain[level], chain[level + 1], 1.0, mat)
        chains.append(chain)
    for f, master in enumerate(masters):
        ops.rigidDiaphragm(3, master, *[c[f + 1] for c in chains])
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for f in range(len(masters)):
        for c in chains:
            ops.load(c[f + 1], 0.0, 0.0, -float(floor_loads[f]) / k, 0.0, 0.0, 0.0)
    _gravity_step(ops)
    periods = eigen_periods(ops, n)
    ops.wipe()
    return periods
