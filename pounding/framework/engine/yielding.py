"""Yielding storey springs inside the pounding driver (the Python path).

The same equations as :mod:`pounding.framework.engine.inelastic` (contact off), on the driver's stacked
modal model: every spring's force is its initial elastic part (in the modes) plus a remainder
f = r - k0 u, a modal load g = G^T f. A step of any length h from (z, t) (a grid step, the rest of
one after an impact, a trial of the impact locator) is

    z_lin = step with loads p(t) + fc - g0 at the start and p(t + h) + fc1 at the end,
    u1 + S(h) f(u1) = G q_lin          (Newton, as in the contact-free stepping),
    z1 = z_lin - B1 G^T f(u1),

with S(h) = G diag(B1(h)) G^T per building (the buildings' springs are uncoupled). A trial
writes only a trial buffer (:class:`~pounding.framework.engine.bundles.LinkTrial`); the driver commits it with the step it
accepts, so a rejected or bisected step leaves the springs as they were. Impulses change
velocities only, so the springs' states stay valid across impacts.

Steps in which forces act that depend on the end state (pairs held in sustained contact,
penalty forces) solve the springs by an outer fixed-point loop on their end remainders around
the contact solve (:meth:`Yielding.fixed_point`): the map's contraction is the share of a
spring's end deformation its own remainder takes back in the step (S k0, below 1; ~1e-2 for
storeys at dt = 0.01 s), so it converges in a few passes; it is solved to the same tolerance.

Between contact events the driver's grid steps run compiled (:meth:`Yielding.advance`,
:func:`pounding.framework.engine.spring_core.stretch`): the same step, and the slab pairs' check of the
elastic kernel after it; a step ending with a pair within the contact tolerance is rolled back for
the driver's Python step, which handles every contact event. The springs are links with laws in flat arrays
over every building (:class:`Yielding`); both paths solve them with the same compiled functions,
which take the scene's laws as arguments (:mod:`pounding.framework.engine.links`), so they agree to
rounding (bit for bit measured where no contact force acts at a step's end).
"""

from __future__ import annotations

import numpy as np

from pounding.framework.engine.bundles import LinkRecord, Links, LinkStepping, LinkTrial, Status
from pounding.framework.engine.inelastic import MAX_ITER, NEWTON_TOL, SpringSet, spring_set

#: what a diverged Newton of the links suggests: a smaller step, or, for a damper whose force rises
#: with an infinite slope at rest (a viscous exponent below about 0.7), its brace (docs/modelling.md)
NEWTON_HINT = ("try a smaller dt; a viscous damper with an exponent below about 0.7 converges modelled with its brace "
               "stiffness as `maxwell`")


class Group:
    """The yielding springs of one building: its slice of the flat spring arrays and of the modes."""

    def __init__(self, springs, lo: int, start: int, n_modes: int, building: int, tolerance: float = NEWTON_TOL):
        self.springs = springs
        self.building = building
        self.lo, self.hi = lo, lo + springs.size
        self.sl = slice(start, start + n_modes)
        self.tol = tolerance * newton_scale(springs)


#: drift ratio [-] that scales the Newton tolerance of a building whose links have no yield deformation
#: (dampers, linear springs): 1/1000 of the storey height, the order of a frame's yield drift
NO_YIELD_DRIFT = 1e-3


def newton_scale(springs) -> float:
    """The deformation [m] that scales a building's Newton tolerance: its links' smallest yield
    deformation (the laws' ``deformation_scale``), or, when none yields, NO_YIELD_DRIFT of the lowest
    storey's height."""
    scale = springs.yield_deformation
    finite = scale[np.isfinite(scale)]
    return float(finite.min()) if finite.size else NO_YIELD_DRIFT * float(springs.height.min())


class Yielding:
    """The yielding springs of every building of a driver's model, as links with laws in flat arrays
    (:class:`~pounding.framework.engine.bundles.Links`, stepped by :mod:`pounding.framework.engine.spring_core`);
    ``Yielding.of`` is None when there are none.

    Attributes
    ----------
    laws : tuple of type
        The run's law classes; ``updates`` their compiled updates, the tuple the stepping takes.
    links : Links
    now : LinkTrial
        The committed links (remainders f (ns,), law states, modal load g (n,)).
    rec : LinkRecord
        Peaks, last tangents, the remainders' work per building, Newton counts per group, and the
        output rows' histories (allocated by :meth:`record_rows`).
    """

    def __init__(self, groups: list[Group], G_rows: list[np.ndarray], n: int, n_buildings: int):
        from pounding.framework.engine.links import law_tuple

        self.groups = groups
        self.n = n
        laws: list = []
        for grp in groups:
            for cls in grp.springs.laws:
                if cls not in laws:
                    laws.append(cls)
        self.laws = tuple(laws)
        self.updates = law_tuple(self.laws)
        ns = sum(grp.springs.size for grp in groups)
        width = max(cls.n_params for cls in laws)
        self.n_state = max(cls.n_state for cls in laws)
        nmax = max(gr.shape[1] for gr in G_rows)
        G = np.zeros((ns, nmax))
        params = np.zeros((ns, width))
        law = np.zeros(ns, dtype=np.int64)
        for grp, gr in zip(groups, G_rows):
            sp = grp.springs
            G[grp.lo:grp.hi, : gr.shape[1]] = gr
            params[grp.lo:grp.hi, : sp.params.shape[1]] = sp.params
            law[grp.lo:grp.hi] = [self.laws.index(sp.laws[i]) for i in sp.law_id]
        self.links = Links(
            law, G, np.array([grp.lo for grp in groups] + [ns], dtype=np.int64),
            np.array([[grp.sl.start, grp.sl.stop - grp.sl.start] for grp in groups], dtype=np.int64).reshape(-1, 2),
            np.ascontiguousarray(params[:, 0]), np.array([grp.tol for grp in groups]), params,
        )
        self.now = LinkTrial(np.zeros(ns), np.zeros((ns, self.n_state)), np.zeros(n))
        self.rec = LinkRecord(np.zeros(ns), self.links.k0.copy(), np.zeros(n_buildings),
                              np.zeros((len(groups), 3), dtype=np.int64), np.zeros((3, 1, ns)))
        # the committed links and the records, by name (the driver and the energy account read them;
        # the same arrays as the bundles', which the compiled stretch updates in place)
        self.f, self.state, self.g = self.now.f, self.now.state, self.now.g
        self.peak, self.work = self.rec.peak, self.rec.work
        self._S: dict = {}

    @classmethod
    def of(cls, scene, model, tolerance: float = NEWTON_TOL) -> "Yielding | None":
        """The yielding springs of ``scene`` on the driver's ``model``; ``tolerance`` is the Newton
        residual's, as a fraction of every building's smallest yield deformation."""
        from pounding.errors import InputError

        groups, rows, lo = [], [], 0
        for i, (b, system) in enumerate(zip(scene.buildings, model.systems)):
            try:
                springs = spring_set(b, i)
            except InputError as exc:
                raise exc.located(file=str(scene.source) if scene.source else None) from None
            if springs.size:
                groups.append(Group(springs, lo, int(model.mode_start[i]), system.modes.shape[1], i, tolerance))
                rows.append(springs.T @ system.modes)
                lo += springs.size
        if not groups:
            return None
        return cls(groups, rows, model.n, len(model.systems))

    @property
    def size(self) -> int:
        return self.now.f.shape[0]

    def record_rows(self, n_out: int) -> np.ndarray:
        """Allocate the output rows' histories (3, n_out, ns) and return them."""
        self.rec = self.rec._replace(hist=np.zeros((3, n_out, self.size)))
        return self.rec.hist

    def S(self, B1: np.ndarray) -> np.ndarray:
        """The step's compliance (ns, ns), block diagonal by building: G diag(B1) G^T for the
        stacked B1 = B[:, 0, 1] (n,) of the step."""
        key = B1.tobytes()
        out = self._S.get(key)
        if out is None:
            if len(self._S) > 256:
                self._S.clear()
            out = np.zeros((self.size, self.size))
            for grp in self.groups:
                Gg = self.links.G[grp.lo:grp.hi, : grp.sl.stop - grp.sl.start]
                out[grp.lo:grp.hi, grp.lo:grp.hi] = (Gg * B1[grp.sl]) @ Gg.T
            self._S[key] = out
        return out

    def record(self, row: np.ndarray) -> None:
        """row (3, ns): deformation, force and dissipated energy of every spring, groups in order."""
        row[:, :] = self.state[:, :3].T

    def histories(self, hist: np.ndarray, names: list) -> dict:
        """Per building name with yielding springs: :func:`spring_record` of its springs."""
        out = {}
        for grp in self.groups:
            lo, hi = grp.lo, grp.hi
            G = np.ascontiguousarray(self.links.G[lo:hi, : grp.sl.stop - grp.sl.start])
            out[names[grp.building]] = spring_record(grp.springs, hist[0, :, lo:hi], hist[1, :, lo:hi], hist[2, :, lo:hi],
                                                     self.peak[lo:hi].copy(), G)
        return out

    def _diverged(self, j: int, t: float | None = None) -> FloatingPointError:
        when = "" if t is None else f" in the step starting at t = {t:g} s"
        return FloatingPointError(f"building {self.groups[j].building}: the yielding springs' Newton iteration did not converge"
                                  f"{when} ({NEWTON_HINT})")

    def _trial(self) -> LinkTrial:
        # slots a narrower law does not write keep their committed values
        return LinkTrial(np.empty(self.size), self.state.copy(), np.empty(self.n))

    def solve(self, q_lin: np.ndarray, B1: np.ndarray, h: float) -> LinkTrial:
        """Newton on every building for a step of h [s] whose linear part ends at q_lin (n,)."""
        from pounding.framework.engine.spring_core import solve_springs

        out = self._trial()
        j = solve_springs(self.updates, self.links, self.S(np.ascontiguousarray(B1)), float(h), np.ascontiguousarray(q_lin),
                          self.now, out)
        if j >= 0:
            raise self._diverged(j)
        return out

    def at(self, q1: np.ndarray, h: float) -> LinkTrial:
        """Remainders and trial states of a step of h [s] ending at displacements q1 (n,) (the fixed-point pass)."""
        from pounding.framework.engine.spring_core import forces_at

        out = self._trial()
        forces_at(self.updates, self.links, float(h), np.ascontiguousarray(q1, dtype=float), self.now, out)
        return out

    def fixed_point(self, solve, h: float):
        """Solve a step of h [s] whose contact forces depend on its end: ``solve(g1) -> (step, q1)``
        with the remainders' end load g1; iterate g1 until the springs' end deformations agree to
        tolerance.

        Plain substitution first; where it does not settle (buildings held together by contact
        forces, whose coupled compliance can make the plain map expand), under-relaxed
        substitution g <- g + w (g_new - g) with w = 1/2, then 1/4: the same fixed point, reached
        from a contracting map. It stops when successive end deformations of every building's links
        differ by at most w times its Newton tolerance, so that a relaxed iteration stops at the same
        residual as a plain one (deformations, not forces: a damper has no stiffness to scale a force by)."""
        for w in (1.0, 0.5, 0.25):
            g, prev = self.g.copy(), self.state[:, 0].copy()
            for _ in range(4 * MAX_ITER):
                st, q1 = solve(g)
                new = self.at(q1, h)
                # the end deformations themselves (a law with no initial stiffness, a damper, has no
                # force scale to convert a change of its remainder into one of its deformation)
                d = new.state[:, 0]
                if all(np.max(np.abs(d[grp.lo:grp.hi] - prev[grp.lo:grp.hi]), initial=0.0) <= w * grp.tol for grp in self.groups):
                    return st, new
                prev = d.copy()
                g = new.g if w == 1.0 else g + w * (new.g - g)
        raise FloatingPointError(f"the yielding springs' fixed-point iteration with contact forces did not converge ({NEWTON_HINT})")

    def commit(self, sp: LinkTrial) -> None:
        self.f[:] = sp.f
        self.state[:] = sp.state
        np.maximum(self.peak, np.abs(sp.state[:, 0]), out=self.peak)
        self.g[:] = sp.g

    def energy(self, building: int, q: np.ndarray, omega: np.ndarray, start: int) -> dict:
        """Strain and hysteretic energy of a building's springs [J] at modal displacements q (n,)."""
        for grp in self.groups:
            if grp.building != building:
                continue
            G = self.links.G[grp.lo:grp.hi, : grp.sl.stop - grp.sl.start]
            u = G @ q[grp.sl]
            stored = float(grp.springs.stored_energy(self.state[grp.lo:grp.hi]).sum())
            k0 = self.links.k0[grp.lo:grp.hi]
            elastic = 0.5 * float(np.sum(k0 * u * u))
            return {"elastic_springs": elastic, "stored": stored,
                    "hysteretic": elastic + float(self.work[building]) - stored}
        return {"elastic_springs": 0.0, "stored": 0.0, "hysteretic": 0.0}

    # ------------------------------------------------------------ the compiled stretch
    def advance(self, driver, k0: int, k1: int):
        """Grid steps k0 -> k1 compiled (:func:`pounding.framework.engine.spring_core.stretch`), until a slab
        pair comes within the contact tolerance: then (k, OVERLAP, pair) with the state at the start
        of step k, which the driver takes in Python (``Driver.python_step``). Same answers as
        :func:`pounding.framework.engine.kernel.advance` (DONE or OVERLAP)."""
        from pounding.framework.engine.spring_core import stretch

        tr = driver.transition(driver.dt)
        S = self.S(np.ascontiguousarray(tr.B[:, 0, 1]))
        run = LinkStepping(self.links, S, self.now, self.rec)
        k, status, pair = stretch(self.updates, tr, driver.model.modes, driver.ground, driver.z, int(k0), int(k1), driver.rec,
                                  driver.kgeo, float(driver.tol), run)
        if status == Status.DIVERGED:
            raise FloatingPointError(f"the yielding springs' Newton iteration did not converge in the step starting at "
                                     f"t = {k * driver.dt:g} s ({NEWTON_HINT})")
        return k, status, pair


def spring_record(springs: SpringSet, d, r, h, peak, G) -> dict:
    """What a run keeps of one building's yielding springs (arrays at the output rate unless stated).

    Keys: ``element``, ``storey`` (ns,) int (0-based element index, 1-based storey),
    ``height`` (ns,) [m], ``k0`` (ns,) [N/m], ``yield_deformation`` (ns,) [m], ``G`` (ns, n_b)
    spring rows over the building's modes, ``deformation`` (nt, ns) [m], ``force`` (nt, ns) [N],
    ``dissipated`` (nt, ns) [J] (the law's own), ``peak`` (ns,) [m] peak |deformation| over every
    step.
    """
    return {"element": springs.element.copy(), "storey": springs.storey.copy(), "height": springs.height.copy(),
            "k0": springs.k0.copy(), "yield_deformation": springs.yield_deformation.copy(), "G": G,
            "deformation": np.ascontiguousarray(d), "force": np.ascontiguousarray(r), "dissipated": np.ascontiguousarray(h),
            "peak": peak}


def check_springs(scene) -> None:
    """Raise InputError (naming the scene's file) if a building's yielding springs cannot be stepped."""
    from pounding.errors import InputError

    for i, b in enumerate(scene.buildings):
        try:
            spring_set(b, i)
        except InputError as exc:
            raise exc.located(file=str(scene.source) if scene.source else None) from None


def force_work(tr, h, L_load0, L_load1, z0, z1, ftot0, ftot1, w0, w1):
    """Work (n,) [J] of a modal load w linear in a step of h [s] (w0 at its start, w1 at its end), on
    the integrator's trajectory driven by the modal ground loads L_load0, L_load1 (n,) and the total
    extra loads ftot (n,): :func:`pounding.framework.engine.spring_core.spring_work` (the compiled
    stretch books its steps with the same function)."""
    from pounding.framework.engine.spring_core import spring_work

    out = np.empty(z0.shape[0])
    c = np.ascontiguousarray
    spring_work(tr, float(h), c(L_load0, dtype=float), c(L_load1, dtype=float), c(z0), c(z1), c(ftot0, dtype=float),
                c(ftot1, dtype=float), c(w0, dtype=float), c(w1, dtype=float), out)
    return out
