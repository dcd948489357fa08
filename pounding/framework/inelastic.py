"""Buildings with yielding storey springs, stepped in the modal coordinates of their initial model.

Method (in the spirit of CSI's Fast Nonlinear Analysis, Wilson 2002)
--------------------------------------------------------------------
Every spring's force is split into its initial elastic part and a nonlinear
remainder, ``r(u) = k0 u + f(u)``. The elastic part stays in the initial
stiffness K0 of the building, so the modes Phi of (K0, M) and the classical
damping of the initial model (:mod:`pounding.solvers.base`) are unchanged;
the remainders enter as modal loads through the spring rows G = T Phi
(ns, n), u = G q:

    q'' + 2 zeta omega q' + omega^2 q = -L ag(t) - G^T f(G q).

Each step is the integrator's own transition with the load linear in the
step (``z1 = A z0 + B0 p0 + B1 p1``). The remainder at the step start is
known; the one at the end depends on the end deformations u1, which depend
on it through the step's compliance S = G diag(B1[:, 0]) G^T (ns, ns):

    u1 + S f(u1) = u_lin,      u_lin = G q1 of the step without f(u1),

solved by Newton with the laws' consistent tangents, J = I + S diag(k_t - k0),
to a residual below 1e-12 of the smallest yield deformation. J is well
conditioned: S diag(k0) is the share of each spring's end deformation that its
own force takes back within the step, below 1 because the step's stiffness
includes the inertia, so the eigenvalues of S D lie in (-1, 0] for tangents in
[0, k0]; then
``z1 = z_lin - B1 G^T f(u1)``. These are the integrator's equations of
motion of the nonlinear building, exactly (OpenSees' Newton on the same
equations gives the same answer to its tolerance), with the elastic part
solved mode by mode. Where no spring has yielded, f = 0 exactly (each law
computes its elastic branch as k0 (u - u_p) with u_p = 0, see
:mod:`pounding.hysteresis.base`), the Newton residual is zero at the
predictor and the step is the elastic modal step bit for bit.

Why not event-to-event: see the README (design, inelastic storeys). In short,
an event (a spring yields or unloads) changes the tangent stiffness, which the
initial modes no longer diagonalise, so each event needs a coupled 3N x 3N
transition for every step length it is used with and the location of the
instant; the measured event counts make that slower than a few Newton
iterations with the ns x ns compliance, and it serves bilinear laws only.

Energy audit
------------
Per building: input = kinetic + strain + damping + hysteretic, by the
integrator's energy rule (for Newmark's average acceleration the trapezoidal
rule on step ends, its exact identity, so it closes to rounding there): the
work of the remainders is that of their modal loads g = G^T f, with the
trapezoidal rule ``dt (g0 + g1)/2 . (q'0 + q'1)/2``; the springs' hysteretic
energy is their whole work (sum k0 u^2 / 2 + that) minus what their laws store.
Per spring, the hysteretic energy reported is the law's own dissipation along
its path (exact for the bilinear law), whose sum differs from the audit's
term only where a step crosses a kink of the loop.

Damping stays classical on the initial elastic model: C = Phi^-T diag(2 zeta omega) Phi^-1
whatever the springs do (Rayleigh with the initial stiffness, as OpenSees'
``rayleigh(a0, 0, a1, 0)``).

Contact is off here: :func:`run_inelastic` is the pounding driver with contact off, whose
compiled stepping of the springs (:mod:`pounding.framework.spring_core`, the laws taken as
arguments: :mod:`pounding.framework.links`) is the one implementation of these equations
(:mod:`pounding.framework.yielding` for the driver's side).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pounding.contact.geometry import njit
from pounding.errors import InputError
from pounding.framework.assembly import System, placement
from pounding.framework.model import Building, Scene
from pounding.hysteresis.bilinear import Bilinear

NEWTON_TOL = 1e-12  # residual tolerance, as a fraction of the smallest yield deformation
MAX_ITER = 50


@dataclass(frozen=True, eq=False)
class SpringSet:
    """The yielding storey springs of one building.

    Attributes
    ----------
    laws : tuple of type
        The hysteresis-law classes of the building's springs, in order of first appearance (any mix).
    law_id : ndarray (ns,) int
        Index in ``laws`` of every spring's law.
    T : ndarray (ns, 3N)
        Deformation of every spring from the slab DOFs: u = T x [m].
    params : ndarray (ns, n_params)
        Law parameters (k0 [N/m], Fy [N], b [-], ...), zero-padded to the widest law.
    element, storey : ndarray (ns,) int
        Element index in the building (0-based) and storey (1 = first floor).
    height : ndarray (ns,)
        Storey height [m].
    """

    laws: tuple
    law_id: np.ndarray
    T: np.ndarray
    params: np.ndarray
    element: np.ndarray
    storey: np.ndarray
    height: np.ndarray

    @property
    def n_state(self) -> int:
        """Width of the law states: the widest of the building's laws."""
        return max(cls.n_state for cls in self.laws)

    @property
    def size(self) -> int:
        return self.T.shape[0]

    @property
    def k0(self) -> np.ndarray:
        return self.params[:, 0]

    @property
    def yield_deformation(self) -> np.ndarray:
        """u_y = Fy / k0 [m] per spring."""
        return self.params[:, 1] / self.params[:, 0]

    def stored_energy(self, state: np.ndarray) -> np.ndarray:
        """Recoverable energy [J] of every spring (ns,) in the states ``state`` (ns, >= n_state)."""
        return np.array([self.laws[self.law_id[s]].stored_energy(state[s], self.params[s]) for s in range(self.size)])


def spring_set(building: Building, index: int = 0) -> SpringSet:
    """The yielding springs of a building (ns may be 0), elements in order, storeys bottom first.

    Elements may follow different hysteresis laws (``law_id`` says which).
    """
    from pounding.elements.storey_springs import StoreySprings

    n = building.n_storeys
    centres = np.array([s.centre for s in building.slabs])
    rows, params, elem, storey, height, ids, laws = [], [], [], [], [], [], []
    for e_idx, e in enumerate(building.elements):
        if not (isinstance(e, StoreySprings) and e.yields):
            continue
        if type(e.law) not in laws:
            laws.append(type(e.law))
        T = placement(centres, e.floors, np.asarray(e.point, float), np.asarray(e.direction, float), n)
        P = e.spring_parameters()
        for f in range(len(e.floors)):
            row = T[f] - (T[f - 1] if f > 0 else 0.0)  # floor f minus the floor below (ground: 0)
            rows.append(row)
            params.append(P[f])
            elem.append(e_idx)
            storey.append(f + 1)
            height.append(e.heights[f])
            ids.append(laws.index(type(e.law)))
    if not laws:
        laws = [Bilinear]
    ns = len(rows)
    width = max(cls.n_params for cls in laws)
    packed = np.zeros((ns, width))
    for s, p in enumerate(params):
        packed[s, : len(p)] = p
    return SpringSet(
        tuple(laws),
        np.array(ids, dtype=np.int64),
        np.array(rows, dtype=float).reshape(ns, 3 * n),
        packed,
        np.array(elem, dtype=np.int64),
        np.array(storey, dtype=np.int64),
        np.array(height, dtype=float),
    )


@njit
def solve_in_place(J, x, m):
    """x[:m] <- J[:m, :m]^-1 x[:m] by Gaussian elimination with partial pivoting, overwriting J.

    The Newton matrices here are small (the springs off their initial branch) and well
    conditioned (I + S D with the eigenvalues of S D in (-1, 0]: see the module docstring), and a
    loop without allocation is several times faster than a LAPACK call at these sizes.
    """
    for c in range(m):
        p = c
        big = abs(J[c, c])
        for r in range(c + 1, m):
            if abs(J[r, c]) > big:
                big = abs(J[r, c])
                p = r
        if p != c:
            for j in range(m):
                J[c, j], J[p, j] = J[p, j], J[c, j]
            x[c], x[p] = x[p], x[c]
        piv = J[c, c]
        for r in range(c + 1, m):
            f = J[r, c] / piv
            if f != 0.0:
                for j in range(c + 1, m):
                    J[r, j] -= f * J[c, j]
                x[r] -= f * x[c]
    for c in range(m - 1, -1, -1):
        acc = x[c]
        for j in range(c + 1, m):
            acc -= J[c, j] * x[j]
        x[c] = acc / J[c, c]


@dataclass(eq=False)
class BuildingResponse:
    """What one building did (arrays at the output rate unless stated).

    Attributes
    ----------
    name : str
    system : System
        The initial elastic model (modes, damping).
    springs : SpringSet
    q, v : ndarray (nt, n)
        Modal displacements and velocities.
    deformation : ndarray (nt, ns)
        Spring deformations (storey drift along the spring's line) [m].
    force : ndarray (nt, ns)
        Spring forces (storey shear carried by the spring) [N].
    dissipated : ndarray (nt, ns)
        Energy dissipated by every spring, by its law's own rule [J].
    peak : ndarray (ns,)
        Peak |deformation| over every step [m].
    residual : ndarray (ns,)
        Deformation at the end of the record [m].
    hysteretic : ndarray (ns,)
        Hysteretic energy of every spring at the end: what its law dissipated along its own path [J].
    energy : dict
        ``input``, ``kinetic``, ``strain``, ``damping``, ``hysteretic`` [J] at the end (the
        audit's terms, trapezoidal rule on step ends), ``hysteretic_law`` (the sum of the
        springs' own dissipation, which differs from the audit's by the steps' kinks),
        ``balance_error`` = input - (kinetic + strain + damping + hysteretic) [J] and
        ``relative_error`` (of the input).
    counts : dict
        ``newton_iterations``, ``nonlinear_steps``, ``tangent_changes``.
    """

    name: str
    system: System
    springs: SpringSet
    q: np.ndarray
    v: np.ndarray
    deformation: np.ndarray
    force: np.ndarray
    dissipated: np.ndarray
    peak: np.ndarray
    residual: np.ndarray
    hysteretic: np.ndarray
    energy: dict
    counts: dict = field(default_factory=dict)

    @property
    def ductility(self) -> np.ndarray:
        """Ductility demand per spring: peak |deformation| / yield deformation [-], shape (ns,)."""
        return self.peak / self.springs.yield_deformation

    @property
    def drift_ratio(self) -> np.ndarray:
        """Peak inter-storey drift ratio per spring: peak |deformation| / storey height [-]."""
        return self.peak / self.springs.height

    @property
    def residual_drift_ratio(self) -> np.ndarray:
        """Residual inter-storey drift ratio per spring [-]."""
        return self.residual / self.springs.height

    def cm(self) -> np.ndarray:
        """(u, v, phi) of every slab's centre of mass, shape (nt, storeys, 3)."""
        return (self.q @ self.system.modes.T).reshape(len(self.q), self.system.n_storeys, 3)


@dataclass(eq=False)
class InelasticResult:
    """The no-contact response of every building of a scene with yielding storeys."""

    t: np.ndarray
    dt: float
    steps: int
    integrator: dict
    buildings: list[BuildingResponse]
    runtime_s: float

    def building(self, name: str) -> BuildingResponse:
        for b in self.buildings:
            if b.name == name:
                return b
        raise KeyError(name)


def run_inelastic(scene: Scene, *, tolerance: float = NEWTON_TOL) -> InelasticResult:
    """No-contact time history of every building of ``scene``, with yielding storey springs.

    The scene's integrator (Newmark's average acceleration unless named), dt (the scene's, else the
    record's, else 0.01 s), duration and output rate; the buildings are independent (contact off).
    This is the pounding driver with contact off (:class:`pounding.framework.analysis.Driver`): the
    same compiled stepping of the springs (:func:`pounding.framework.spring_core.stretch`), whose
    records are read here per building. Buildings may mix hysteresis laws.

    Parameters
    ----------
    tolerance : float
        Newton residual tolerance, as a fraction of every building's smallest yield deformation.

    Raises
    ------
    InputError
        If the scene asks for contact between its buildings (run it with :func:`pounding.framework.analysis.run`).
    FloatingPointError
        If Newton does not converge in a step (names the time).
    """
    from pounding.framework.analysis import Driver
    from pounding.framework.integrator_choice import OTHERWISE
    from pounding.framework.yielding import Yielding

    an = scene.analysis
    if an.contact != "none" and len(scene.buildings) > 1:
        raise InputError("run_inelastic steps buildings without contact: set contact = \"none\", or run the scene with "
                         "pounding.run (the driver steps yielding buildings with pounding)", field="analysis.contact")
    gm = scene.ground_motion
    dt = float(an.dt or gm.dt or 0.01)
    free = scene.with_analysis(dt=dt, integrator=an.integrator or OTHERWISE, contact="none", contact_params={})
    driver = Driver(free)
    if driver.springs is not None and tolerance != NEWTON_TOL:
        driver.springs = Yielding.of(free, driver.model, tolerance)
        driver.spring_hist = driver.springs.record_rows(driver.Q.shape[0])
    res = driver.run()
    every = driver.every
    sets = [spring_set(b, i) for i, b in enumerate(scene.buildings)]
    out = [_building_response(driver, i, springs) for i, springs in enumerate(sets)]
    n_out = driver.Q.shape[0]
    return InelasticResult(driver.t_grid[::every][:n_out], driver.dt, driver.nsteps, driver.integrator.describe(), out,
                           res.runtime_s)


def _building_response(driver, i: int, springs: SpringSet) -> BuildingResponse:
    """What building i of the driver's run did, its springs read from the driver's records."""
    system = driver.model.systems[i]
    sl = slice(int(driver.model.mode_start[i]), int(driver.model.mode_start[i]) + system.modes.shape[1])
    Q, V = driver.Q[:, sl], driver.V[:, sl]
    q, v = driver.z[sl, 0], driver.z[sl, 1]
    E = driver.E[i]
    grp = next((g for g in driver.springs.groups if g.building == i), None) if driver.springs is not None else None
    if grp is None:
        ns = springs.size
        D = R = H = np.zeros((len(Q), ns))
        state, peak, work, counts = np.zeros((ns, 3)), np.zeros(ns), 0.0, np.zeros(3, dtype=np.int64)
    else:
        lo, hi = grp.lo, grp.hi
        hist = driver.spring_hist
        D, R, H = hist[0, :, lo:hi].copy(), hist[1, :, lo:hi].copy(), hist[2, :, lo:hi].copy()
        state, peak = driver.springs.state[lo:hi].copy(), driver.springs.peak[lo:hi].copy()
        work = float(driver.springs.work[i])
        counts = driver.springs.rec.counts[driver.springs.groups.index(grp)]
    kel = springs.k0
    u = springs.T @ system.modes @ q
    stored = springs.stored_energy(state)
    elastic_springs = 0.5 * float(np.sum(kel * u * u))
    # the springs' whole work (k0 u^2/2 through the modal strain energy, plus the remainders' work)
    # minus what they store: their hysteretic energy by the audit's own rule
    hysteretic = elastic_springs + work - float(stored.sum())
    kinetic = 0.5 * float(v @ v)
    strain = 0.5 * float(np.sum(system.omega**2 * q * q)) - elastic_springs + float(stored.sum())
    energy = {"input": float(E[0]), "kinetic": kinetic, "strain": strain, "damping": float(E[1]), "hysteretic": hysteretic,
              "hysteretic_law": float(state[:, 2].sum())}
    err = energy["input"] - (kinetic + strain + energy["damping"] + energy["hysteretic"])
    energy["balance_error"] = float(err)
    energy["relative_error"] = float(abs(err) / max(abs(energy["input"]), 1e-300))
    return BuildingResponse(
        driver.scene.buildings[i].name, system, springs, Q, V, D, R, H, peak, state[:, 0].copy(), state[:, 2].copy(), energy,
        {"newton_iterations": int(counts[0]), "nonlinear_steps": int(counts[1]), "tangent_changes": int(counts[2])},
    )
