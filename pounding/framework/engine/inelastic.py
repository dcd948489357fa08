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

Why not event-to-event (docs/accuracy.md, *Yielding storeys*): in short,
an event (a spring yields or unloads) changes the tangent stiffness, which the
initial modes no longer diagonalise, so each event needs a coupled 3N x 3N
transition for every step length it is used with and the location of the
instant; the measured event counts make that slower than a few Newton
iterations with the ns x ns compliance, and it serves bilinear laws only.

Energy audit
------------
Per building: input = kinetic + strain + damping + hysteretic, with the
trapezoidal rule on step ends (average acceleration's exact identity, so it
closes to rounding there): the work of the remainders is that of their modal
loads g = G^T f, ``dt (g0 + g1)/2 . (q'0 + q'1)/2``; the springs' hysteretic
energy is their whole work (sum k0 u^2 / 2 + that) minus what their laws store.
Per spring, the hysteretic energy reported is the law's own dissipation along
its path (exact for the bilinear law), whose sum differs from the audit's
term only where a step crosses a kink of the loop.

Damping stays classical on the initial elastic model: C = Phi^-T diag(2 zeta omega) Phi^-1
whatever the springs do (Rayleigh with the initial stiffness, as OpenSees'
``rayleigh(a0, 0, a1, 0)``).

Contact is off here; the driver steps yielding buildings with pounding by the
same equations (:mod:`pounding.framework.engine.yielding`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError
from pounding.framework.model.assembly import System, assemble
from pounding.framework.model.kinematics import placement
from pounding.framework.model.scene import Building, Scene
from pounding.framework.engine.kernel import _load_sum, modal_load
from pounding.hysteresis.bilinear import Bilinear

CONVERGED, DIVERGED = 0, 1
NEWTON_TOL = 1e-12  # residual tolerance, as a fraction of the smallest yield deformation
MAX_ITER = 50


@dataclass(frozen=True, eq=False)
class SpringSet:
    """The yielding storey springs of one building.

    Attributes
    ----------
    laws : tuple of type
        The hysteresis-law classes of the building's springs, in order of first appearance.
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
    def law(self) -> type:
        """The one hysteresis law of the springs (the contact-free stepper takes one law per building).

        Raises
        ------
        InputError
            If the building's springs follow more than one law.
        """
        if len(self.laws) > 1:
            names = ", ".join(sorted(cls.name for cls in self.laws))
            raise InputError(f"run_inelastic steps one hysteresis law per building, this one mixes {names}: "
                             "run the scene with pounding.run (the driver steps any mix of laws)", field="building.element")
        return self.laws[0]

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


@njit
def stretch(update, A, B, L, c2, dt, ag, z, k0, k1, every, G, S, kel, params, state, trial, fnl, tol,
            Q, V, D, R, H, peak, E, counts):
    """Grid steps k0 -> k1 of one building with yielding springs (see the module docstring).

    Parameters
    ----------
    update : compiled function
        The hysteresis law's ``update`` (:mod:`pounding.hysteresis.base`).
    A, B : (n, 3, 3), (n, 3, 2)
        Transition of the grid step dt [s].
    L : (n, c)
        Modal load per unit ground acceleration of each component (p = -L ag).
    c2 : (n,)
        2 zeta omega [1/s].
    ag : (nsteps + 1, c)
        Ground acceleration on the grid [m/s^2], one column per component.
    z : (n, 3)
        Modal state (q, q', q''), updated in place.
    every : int
        Output rate: grid index k is stored in row k // every when k % every == 0.
    G : (ns, n)
        Spring rows in modal coordinates (u = G q).
    S : (ns, ns)
        The step's compliance G diag(B[:, 0, 1]) G^T.
    kel : (ns,)
        Initial spring stiffnesses [N/m].
    params : (ns, n_params); state, trial : (ns, n_state)
        Law parameters, committed states (updated in place) and a trial buffer.
    fnl : (ns,)
        Nonlinear force remainders r - k0 u at the current instant [N], updated in place.
    tol : float
        Newton residual tolerance [m].
    Q, V : (n_out, n); D, R, H : (n_out, ns)
        Recorded modal displacements, velocities, spring deformations [m], forces [N]
        and dissipated energy (the law's own) [J].
    peak : (ns,)
        Running peak |u| [m].
    E : (3,)
        Accumulated ground-motion input, damping work and work of the remainders [J].
    counts : (3,) int
        Newton iterations, steps that needed iterations, and tangent changes (yield / unload events).

    Returns
    -------
    (k, status) : the grid index reached and CONVERGED or DIVERGED (Newton failed at step k).
    """
    n = z.shape[0]
    ns = G.shape[0]
    z0 = np.empty((n, 3))
    g = G.T @ fnl  # modal load of the remainders, G^T f, kept with f
    g1 = g.copy()
    sf = S @ fnl  # S f, the predictor's correction, kept with f
    dl = np.empty(ns)
    d = np.empty(ns)
    f1 = np.empty(ns)
    kt = np.empty(ns)
    kt_prev = kel.copy()
    res = np.empty(ns)
    act = np.empty(ns, dtype=np.int64)
    Ja = np.empty((ns, ns))
    xa = np.empty(ns)
    for k in range(k0, k1):
        for i in range(n):
            z0[i, 0] = z[i, 0]
            z0[i, 1] = z[i, 1]
            z0[i, 2] = z[i, 2]
        ag0 = ag[k]
        ag1 = ag[k + 1]
        for i in range(n):
            p0 = modal_load(L, i, ag0) - g[i]
            p1 = modal_load(L, i, ag1)
            for r in range(3):
                z[i, r] = A[i, r, 0] * z0[i, 0] + A[i, r, 1] * z0[i, 1] + A[i, r, 2] * z0[i, 2] + B[i, r, 0] * p0 + B[i, r, 1] * p1
        changed = False
        if ns > 0:
            for s in range(ns):
                acc = 0.0
                for i in range(n):
                    acc += G[s, i] * z[i, 0]
                dl[s] = acc
                d[s] = acc - sf[s]  # predictor: the start remainders kept through the step
            it = 0
            while True:
                same = True
                for s in range(ns):
                    r_s, kt_s = update(d[s], state, params, trial, s)
                    kt[s] = kt_s
                    f1[s] = r_s - kel[s] * d[s]
                    if f1[s] != fnl[s]:
                        same = False
                if same and it == 0:
                    # no remainder changed: the predictor solves the step (residual d + S f - dl = 0)
                    break
                worst = 0.0
                for s in range(ns):
                    acc = d[s] - dl[s]
                    for t in range(ns):
                        acc += S[s, t] * f1[t]
                    res[s] = acc
                    worst = max(worst, abs(acc))
                if worst <= tol:
                    break
                if it >= MAX_ITER:
                    return k, DIVERGED
                # J = I + S diag(k_t - k0) differs from I only in the columns of the springs off their
                # initial branch (the active set a): solve (I + S_aa D_a) x_a = res_a, then every row
                # follows as res - S[:, a] D_a x_a (which is x_a again on the active rows).
                na = 0
                for s in range(ns):
                    if kt[s] != kel[s]:
                        act[na] = s
                        na += 1
                if na > 0:
                    for a in range(na):
                        xa[a] = res[act[a]]
                        for c in range(na):
                            Ja[a, c] = S[act[a], act[c]] * (kt[act[c]] - kel[act[c]])
                        Ja[a, a] += 1.0
                    solve_in_place(Ja, xa, na)
                    for a in range(na):
                        xa[a] *= kt[act[a]] - kel[act[a]]
                    for s in range(ns):
                        acc = res[s]
                        for a in range(na):
                            acc -= S[s, act[a]] * xa[a]
                        d[s] -= acc
                else:
                    for s in range(ns):
                        d[s] -= res[s]
                it += 1
            counts[0] += it
            if it > 0:
                counts[1] += 1
            for s in range(ns):
                if abs(kt[s] - kt_prev[s]) > 1e-9 * kel[s]:
                    counts[2] += 1
                kt_prev[s] = kt[s]
                if f1[s] != fnl[s]:
                    changed = True
        if changed:
            # the end remainders as a load through the step's end-load response
            for i in range(n):
                acc = 0.0
                for s in range(ns):
                    acc += G[s, i] * f1[s]
                g1[i] = acc
            for s in range(ns):
                acc = 0.0
                for t in range(ns):
                    acc += S[s, t] * f1[t]
                sf[s] = acc
        for i in range(n):
            if g1[i] != 0.0:
                for r in range(3):
                    z[i, r] = z[i, r] - B[i, r, 1] * g1[i]
        # energy: trapezoidal rule on the step ends (average acceleration's exact identity)
        for i in range(n):
            vm = 0.5 * (z0[i, 1] + z[i, 1])
            E[0] += _load_sum(dt * vm * 0.5, L, i, ag0, ag1)
            E[1] += dt * c2[i] * vm * vm
            E[2] += dt * vm * 0.5 * (g[i] + g1[i])
        for i in range(n):
            g[i] = g1[i]
        for s in range(ns):
            fnl[s] = f1[s]
            for c in range(state.shape[1]):
                state[s, c] = trial[s, c]
            if abs(state[s, 0]) > peak[s]:
                peak[s] = abs(state[s, 0])
        if (k + 1) % every == 0:
            j = (k + 1) // every
            for i in range(n):
                Q[j, i] = z[i, 0]
                V[j, i] = z[i, 1]
            for s in range(ns):
                D[j, s] = state[s, 0]
                R[j, s] = state[s, 1]
                H[j, s] = state[s, 2]
    return k1, CONVERGED


_STEPPER_HEADER = """\
# Generated by pounding.framework.engine.inelastic.stepper for {key}: the source of
# pounding.framework.engine.inelastic.stretch with the law's update as a global. Do not edit.
# Sources: {digest}
import numpy as np

from pounding.framework.engine.inelastic import CONVERGED, DIVERGED, MAX_ITER, solve_in_place
from pounding.framework.engine.kernel import _load_sum, modal_load
from {module} import {cls} as _law

update = _law.update


"""

_STEPPERS: dict = {}


def stepper(law: type):
    """The compiled :func:`stretch` of one hysteresis law, cached on disk across processes.

    :func:`stretch` takes the law's ``update`` as an argument, and numba cannot cache a function
    that does (it keys the argument's type on the object, and the compiled code holds its address):
    every process would compile it again (~4 s per law). So each law gets a module generated once
    into the numba cache folder: the source of :func:`stretch` with ``update`` as a global, which
    numba caches like any other kernel. The module's text carries a digest of this file and of
    the law's module, so editing either makes numba compile afresh. Where nothing can be written,
    the generic :func:`stretch` is used (compiled per process).
    """
    import hashlib
    import os
    import sys

    key = f"{law.__module__}:{law.__qualname__}"
    if key in _STEPPERS:
        return _STEPPERS[key]
    fn = None
    try:
        import numba

        digest = hashlib.sha1()
        for module in (__name__, law.__module__):
            with open(sys.modules[module].__file__, "rb") as fh:
                digest.update(fh.read())
        import inspect

        body = inspect.getsource(stretch.py_func)
        head = "def stretch(update, A, "
        if head not in body:
            raise OSError("stretch's signature changed")
        body = "from pounding.compiler import njit\n\n\n" + body.replace(head, "def stretch(A, ", 1)
        header = _STEPPER_HEADER.format(key=key, digest=digest.hexdigest(), module=law.__module__, cls=law.__qualname__)
        text = header + body
        base = numba.config.CACHE_DIR or os.path.join(os.path.expanduser("~"), ".cache", "pounding")
        stem = "stepper_" + "".join(c if c.isalnum() else "_" for c in key)
        from pounding.compiler import generated_module

        module = generated_module(os.path.join(base, "steppers"), stem, text)
        fn = module.stretch
    except (ImportError, OSError):  # no numba, or nowhere to write: the generic kernel
        fn = None
    if fn is None:
        def fn(*args):
            return stretch(law.update, *args)
    _STEPPERS[key] = fn
    return fn


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

    Uses the scene's integrator, dt, duration and output rate exactly as
    :func:`pounding.framework.post.run.run` does; the buildings are independent
    (contact off), so each is stepped on its own.

    Raises
    ------
    InputError
        If the scene asks for contact (pounding with yielding storeys is not yet wired
        into the driver) or a building mixes hysteresis laws.
    FloatingPointError
        If Newton does not converge in a step (names the building and the time).
    """
    from pounding.framework.model.registry import INTEGRATORS
    from pounding.solvers.base import TransitionCache

    an = scene.analysis
    if an.contact != "none" and len(scene.buildings) > 1:
        raise InputError("run_inelastic steps buildings without contact: set contact = \"none\", or run the scene with "
                         "pounding.run (the driver steps yielding buildings with pounding)", field="analysis.contact")
    gm = scene.ground_motion
    dt = float(an.dt or gm.dt or 0.01)
    duration = float(an.duration or gm.duration)
    nsteps = max(1, int(np.ceil(duration / dt - 1e-9)))
    every = an.output_every
    from pounding.framework.engine.integrator_choice import OTHERWISE

    # yielding buildings: Newmark unless named (pounding.framework.engine.integrator_choice)
    integrator = INTEGRATORS.get(an.integrator or OTHERWISE)(**an.integrator_params)
    t_grid = np.arange(nsteps + 1) * dt
    # (nsteps + 1, c): one column per ground-motion component, as the driver takes them
    ag = np.ascontiguousarray(np.asarray(gm.samples(t_grid), dtype=float).reshape(nsteps + 1, -1))
    directions = np.asarray(gm.directions(), dtype=float).reshape(-1, 2)
    sets = [spring_set(b, i) for i, b in enumerate(scene.buildings)]
    systems = [assemble(b) for b in scene.buildings]
    n_out = nsteps // every + 1
    t0 = time.perf_counter()
    out = []
    for b, system, springs in zip(scene.buildings, systems, sets):
        out.append(_run_building(b, system, springs, integrator, dt, ag, nsteps, every, n_out, directions, tolerance, TransitionCache))
    runtime = time.perf_counter() - t0
    return InelasticResult(t_grid[::every][:n_out], dt, nsteps, integrator.describe(), out, runtime)


def _run_building(building, system, springs, integrator, dt, ag, nsteps, every, n_out, directions, tolerance, TransitionCache):
    n, ns = system.n_dof, springs.size
    tr = TransitionCache(integrator, system.omega, system.zeta)(dt)
    L = np.ascontiguousarray(np.stack([system.participation(system.influence(d)) for d in directions], axis=1))
    c2 = 2.0 * system.zeta * system.omega
    G = np.ascontiguousarray(springs.T @ system.modes)
    S = np.ascontiguousarray((G * tr.B[:, 0, 1]) @ G.T)
    kel = np.ascontiguousarray(springs.k0)
    tol = tolerance * float(springs.yield_deformation.min()) if ns else 0.0
    law = springs.law
    state = np.zeros((ns, law.n_state))
    trial = np.zeros((ns, law.n_state))
    fnl = np.zeros(ns)
    z = np.zeros((n, 3))
    Q, V = np.zeros((n_out, n)), np.zeros((n_out, n))
    D, R, H = np.zeros((n_out, ns)), np.zeros((n_out, ns)), np.zeros((n_out, ns))
    peak, E = np.zeros(ns), np.zeros(3)
    counts = np.zeros(3, dtype=np.int64)
    params = np.ascontiguousarray(springs.params)
    k, status = stepper(law)(tr.A, tr.B, L, c2, dt, ag, z, 0, nsteps, every, G, S, kel, params, state, trial, fnl, tol,
                             Q, V, D, R, H, peak, E, counts)
    if status != CONVERGED:
        raise FloatingPointError(
            f"building {building.name!r}: the yielding springs' Newton iteration did not converge in the step "
            f"starting at t = {k * dt:g} s (try a smaller dt)"
        )
    if not np.all(np.isfinite(Q)):
        raise FloatingPointError("the response is not finite: the integrator diverged (check dt against the shortest period)")
    q, v = z[:, 0], z[:, 1]
    u = G @ q
    stored = np.array([law.stored_energy(state[s], params[s]) for s in range(ns)])
    elastic_springs = 0.5 * float(np.sum(kel * u * u))
    # the springs' whole work (k0 u^2/2 through the modal strain energy, plus the remainders' work E[2])
    # minus what they store: their hysteretic energy by the audit's own (trapezoidal) rule
    hysteretic = elastic_springs + float(E[2]) - float(stored.sum())
    kinetic = 0.5 * float(v @ v)
    strain = 0.5 * float(np.sum(system.omega**2 * q * q)) - elastic_springs + float(stored.sum())
    energy = {"input": float(E[0]), "kinetic": kinetic, "strain": strain, "damping": float(E[1]), "hysteretic": hysteretic,
              "hysteretic_law": float(state[:, 2].sum()) if ns else 0.0}
    err = energy["input"] - (kinetic + strain + energy["damping"] + energy["hysteretic"])
    energy["balance_error"] = float(err)
    energy["relative_error"] = float(abs(err) / max(abs(energy["input"]), 1e-300))
    residual = state[:, 0].copy() if ns else np.zeros(0)
    return BuildingResponse(
        building.name, system, springs, Q, V, D, R, H, peak, residual, state[:, 2].copy() if ns else np.zeros(0), energy,
        {"newton_iterations": int(counts[0]), "nonlinear_steps": int(counts[1]), "tangent_changes": int(counts[2])},
    )
