"""The yielding buildings of a scene run without contact, one response per building.

The driver with contact off (:class:`pounding.framework.engine.driver.Driver`) steps the buildings;
this module reads each building's springs from the driver's records: deformations, forces,
dissipated energy, peaks and residuals, ductility and drift ratios.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pounding.errors import InputError
from pounding.framework.engine.inelastic import NEWTON_TOL, SpringSet, spring_set
from pounding.framework.model.assembly import System
from pounding.framework.model.scene import Scene


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
    This is the pounding driver with contact off (:class:`pounding.framework.engine.driver.Driver`): the
    same compiled stepping of the springs (:func:`pounding.framework.engine.spring_core.stretch`), whose
    records are read here per building. Buildings may mix hysteresis laws.

    Parameters
    ----------
    tolerance : float
        Newton residual tolerance, as a fraction of every building's smallest yield deformation.

    Raises
    ------
    InputError
        If the scene asks for contact between its buildings (run it with :func:`pounding.framework.post.run.run`).
    FloatingPointError
        If Newton does not converge in a step (names the time).
    """
    from pounding.framework.engine.driver import Driver
    from pounding.framework.engine.integrator_choice import OTHERWISE
    from pounding.framework.engine.yielding import Yielding
    from pounding.framework.model.registry import watches_contact

    an = scene.analysis
    if watches_contact(an) and len(scene.buildings) > 1:
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
    blk = next((b for b in driver.springs.blocks if b.building == i), None) if driver.springs is not None else None
    if blk is None:
        ns = springs.size
        D = R = H = np.zeros((len(Q), ns))
        state, peak, work, counts = np.zeros((ns, 3)), np.zeros(ns), 0.0, np.zeros(3, dtype=np.int64)
    else:
        lo, hi = blk.lo, blk.hi
        hist = driver.spring_hist
        D, R, H = hist[0, :, lo:hi].copy(), hist[1, :, lo:hi].copy(), hist[2, :, lo:hi].copy()
        state, peak = driver.springs.state[lo:hi].copy(), driver.springs.peak[lo:hi].copy()
        # (the links between slabs' share is not the springs': run_inelastic's scenes have none)
        work = float(driver.springs.work[i] - driver.springs.joined_work[i])
        counts = driver.springs.rec.counts[blk.group]
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
    if driver.springs is not None and driver.springs.joined:  # the work of the links between slabs on it
        energy["links"] = -float(driver.springs.joined_work[i])
    err = energy["input"] + energy.get("links", 0.0) - (kinetic + strain + energy["damping"] + energy["hysteretic"])
    energy["balance_error"] = float(err)
    energy["relative_error"] = float(abs(err) / max(abs(energy["input"]), 1e-300))
    return BuildingResponse(
        driver.scene.buildings[i].name, system, springs, Q, V, D, R, H, peak, state[:, 0].copy(), state[:, 2].copy(), energy,
        {"newton_iterations": int(counts[0]), "nonlinear_steps": int(counts[1]), "tangent_changes": int(counts[2])},
    )
