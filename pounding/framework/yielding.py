"""Yielding storey springs inside the pounding driver (the Python path).

The same equations as :mod:`pounding.framework.inelastic` (contact off), on the driver's stacked
modal model: every spring's force is its initial elastic part (in the modes) plus a remainder
f = r - k0 u, a modal load g = G^T f. A step of any length h from (z, t) (a grid step, the rest of
one after an impact, a trial of the impact locator) is

    z_lin = step with loads p(t) + fc - g0 at the start and p(t + h) + fc1 at the end,
    u1 + S(h) f(u1) = G q_lin          (Newton, as in the contact-free stepping),
    z1 = z_lin - B1 G^T f(u1),

with S(h) = G diag(B1(h)) G^T per building (the buildings' springs are uncoupled). A trial
writes only a trial buffer (:class:`SpringTrial`); the driver commits it with the step it
accepts, so a rejected or bisected step leaves the springs as they were. Impulses change
velocities only, so the springs' states stay valid across impacts.

Steps in which forces act that depend on the end state (pairs held in sustained contact,
penalty forces) solve the springs by an outer fixed-point loop on their end remainders around
the contact solve (:meth:`Yielding.fixed_point`): the map's contraction is the share of a
spring's end deformation its own remainder takes back in the step (S k0, below 1; ~1e-2 for
storeys at dt = 0.01 s), so it converges in a few passes; it is solved to the same tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.inelastic import MAX_ITER, NEWTON_TOL, SpringSet, spring_set


@dataclass
class SpringTrial:
    """The end-of-step remainders and law states of a trial step (one entry per spring group)."""

    f: list
    state: list
    g: np.ndarray  # (n,) modal load G^T f at the step's end


class Group:
    """The yielding springs of one building, over its slice of the stacked modes."""

    def __init__(self, springs: SpringSet, modes: np.ndarray, start: int, building: int):
        self.springs = springs
        self.law = springs.law
        self.building = building
        self.sl = slice(start, start + modes.shape[1])
        self.G = np.ascontiguousarray(springs.T @ modes)  # (ns, n_b)
        self.k0 = np.ascontiguousarray(springs.k0)
        self.params = np.ascontiguousarray(springs.params)
        ns = springs.size
        self.state = np.zeros((ns, self.law.n_state))
        self.f = np.zeros(ns)
        self.peak = np.zeros(ns)
        self.tol = NEWTON_TOL * float(springs.yield_deformation.min())
        self._S: dict = {}

    def S(self, B1: np.ndarray) -> np.ndarray:
        """The step's compliance G diag(B1) G^T (ns, ns) for the building's B1 = B[:, 0, 1]."""
        key = B1.tobytes()
        out = self._S.get(key)
        if out is None:
            if len(self._S) > 256:
                self._S.clear()
            out = self._S[key] = np.ascontiguousarray((self.G * B1) @ self.G.T)
        return out

    def forces(self, d: np.ndarray, trial: np.ndarray):
        """Remainders r - k0 u (ns,) and tangents (ns,) at deformations d, writing the trial states."""
        ns = d.shape[0]
        f1 = np.empty(ns)
        kt = np.empty(ns)
        update = self.law.update
        for s in range(ns):
            r, k = update(float(d[s]), self.state, self.params, trial, s)
            f1[s] = r - self.k0[s] * d[s]
            kt[s] = k
        return f1, kt

    def newton(self, dl: np.ndarray, S: np.ndarray):
        """End remainders f1 and trial states solving u + S f(u) = dl (see the inelastic module)."""
        trial = np.zeros_like(self.state)
        d = dl - S @ self.f  # predictor: the start remainders kept through the step
        for it in range(MAX_ITER + 1):
            f1, kt = self.forces(d, trial)
            if it == 0 and np.array_equal(f1, self.f):
                return f1, trial  # nothing changed: the predictor solves the step
            res = d - dl + S @ f1
            if np.max(np.abs(res)) <= self.tol:
                return f1, trial
            J = np.eye(len(d)) + S * (kt - self.k0)
            d = d - np.linalg.solve(J, res)
        raise FloatingPointError(
            f"building {self.building}: the yielding springs' Newton iteration did not converge (try a smaller dt)")


class Yielding:
    """The yielding springs of every building of a driver's model; None-like when there are none."""

    def __init__(self, groups: list[Group], n: int):
        self.groups = groups
        self.n = n
        self.g = np.zeros(n)  # current modal load of the remainders, G^T f
        self.work = np.zeros(max((grp.building for grp in groups), default=-1) + 1)

    @classmethod
    def of(cls, scene, model) -> "Yielding | None":
        from pounding.errors import InputError

        groups = []
        for i, (b, system) in enumerate(zip(scene.buildings, model.systems)):
            try:
                springs = spring_set(b, i)
            except InputError as exc:
                raise exc.located(file=str(scene.source) if scene.source else None) from None
            if springs.size:
                groups.append(Group(springs, system.modes, int(model.mode_start[i]), i))
        if not groups:
            return None
        out = cls(groups, model.n)
        out.work = np.zeros(len(model.systems))
        return out

    @property
    def size(self) -> int:
        return sum(grp.springs.size for grp in self.groups)

    def record(self, row: np.ndarray) -> None:
        """row (3, ns): deformation, force and dissipated energy of every spring, groups in order."""
        j = 0
        for grp in self.groups:
            ns = grp.springs.size
            row[:, j:j + ns] = grp.state[:, :3].T
            j += ns

    def histories(self, hist: np.ndarray, names: list) -> dict:
        """Per building name with yielding springs: :func:`spring_record` of its springs."""
        out, j = {}, 0
        for grp in self.groups:
            ns = grp.springs.size
            d, r, h = hist[0, :, j:j + ns], hist[1, :, j:j + ns], hist[2, :, j:j + ns]
            out[names[grp.building]] = spring_record(grp.springs, d, r, h, grp.peak.copy(), grp.G)
            j += ns
        return out

    def end_load(self, f: list) -> np.ndarray:
        g = np.zeros(self.n)
        for grp, f1 in zip(self.groups, f):
            g[grp.sl] = grp.G.T @ f1
        return g

    def solve(self, q_lin: np.ndarray, B1: np.ndarray) -> SpringTrial:
        """Newton on every building for the linear step's end displacements q_lin (n,)."""
        fs, states = [], []
        for grp in self.groups:
            f1, trial = grp.newton(grp.G @ q_lin[grp.sl], grp.S(B1[grp.sl]))
            fs.append(f1)
            states.append(trial)
        return SpringTrial(fs, states, self.end_load(fs))

    def at(self, q1: np.ndarray) -> SpringTrial:
        """Remainders and trial states at given end displacements q1 (n,) (the fixed-point pass)."""
        fs, states = [], []
        for grp in self.groups:
            trial = np.zeros_like(grp.state)
            f1, _ = grp.forces(grp.G @ q1[grp.sl], trial)
            fs.append(f1)
            states.append(trial)
        return SpringTrial(fs, states, self.end_load(fs))

    def fixed_point(self, solve):
        """Solve a step whose contact forces depend on its end: ``solve(g1) -> (step, q1)`` with the
        remainders' end load g1; iterate g1 until the springs' end deformations agree to tolerance."""
        sp = SpringTrial([grp.f.copy() for grp in self.groups], [grp.state.copy() for grp in self.groups], self.g.copy())
        for _ in range(4 * MAX_ITER):
            st, q1 = solve(sp.g)
            new = self.at(q1)
            # a change of the remainders by df moves the end deformations by about S df <= df / k0
            if all(np.max(np.abs(a - b), initial=0.0) <= grp.tol * grp.k0.min() for grp, a, b in zip(self.groups, new.f, sp.f)):
                return st, new
            sp = new
        raise FloatingPointError("the yielding springs' fixed-point iteration with contact forces did not converge (try a smaller dt)")

    def commit(self, sp: SpringTrial) -> None:
        for grp, f1, trial in zip(self.groups, sp.f, sp.state):
            grp.f = f1
            grp.state = trial
            np.maximum(grp.peak, np.abs(trial[:, 0]), out=grp.peak)
        self.g = sp.g

    def energy(self, building: int, q: np.ndarray, omega: np.ndarray, start: int) -> dict:
        """Strain and hysteretic energy of a building's springs [J] at modal displacements q (n,)."""
        for grp in self.groups:
            if grp.building != building:
                continue
            u = grp.G @ q[grp.sl]
            stored = sum(grp.law.stored_energy(grp.state[s], grp.params[s]) for s in range(len(u)))
            elastic = 0.5 * float(np.sum(grp.k0 * u * u))
            return {"elastic_springs": elastic, "stored": float(stored),
                    "hysteretic": elastic + float(self.work[building]) - float(stored)}
        return {"elastic_springs": 0.0, "stored": 0.0, "hysteretic": 0.0}


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
    """Raise InputError (naming the scene's file) if a building's yielding springs cannot be stepped
    (they mix hysteresis laws)."""
    from pounding.errors import InputError

    for i, b in enumerate(scene.buildings):
        try:
            spring_set(b, i)
        except InputError as exc:
            raise exc.located(file=str(scene.source) if scene.source else None) from None


def force_work(tr, h, L_load0, L_load1, z0, z1, ftot0, ftot1, w0, w1):
    """Work (n,) of a modal load w linear in a step of h [s] (w0 at its start, w1 at its end), on
    the integrator's trajectory driven by the ground loads and the total extra loads ftot: the same
    three rules as :func:`pounding.framework.kernel._accumulate_forces` (closed-form maps, Gauss
    points on the trajectory, or the trapezoidal rule)."""
    A, B, GA, GB, gc, gw, WA1, WA2, WM = tr
    if WA1.shape[0] > 0:
        x = np.stack([z0[:, 0], z0[:, 1], L_load0 + ftot0, L_load1 + ftot1], axis=1)
        iv0 = np.sum(WA1 * x, axis=1)
        iv1 = np.sum(WA2 * x, axis=1)
        return w0 * iv0 + (w1 - w0) / h * iv1
    if gc.shape[0] == 0:
        vm = 0.5 * (z0[:, 1] + z1[:, 1])
        return h * vm * 0.5 * (w0 + w1)
    out = np.zeros(z0.shape[0])
    for j in range(gc.shape[0]):
        pj = L_load0 + gc[j] * (L_load1 - L_load0)
        fj = ftot0 + gc[j] * (ftot1 - ftot0)
        vj = (GA[j, :, 1, 0] * z0[:, 0] + GA[j, :, 1, 1] * z0[:, 1] + GA[j, :, 1, 2] * z0[:, 2]
              + GB[j, :, 1, 0] * (L_load0 + ftot0) + GB[j, :, 1, 1] * (pj + fj))
        out += h * gw[j] * vj * (w0 + gc[j] * (w1 - w0))
    return out
