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
compiled stepping of the springs (:mod:`pounding.framework.engine.spring_core`, the laws taken as
arguments: :mod:`pounding.framework.engine.links`) is the one implementation of these equations
(:mod:`pounding.framework.engine.yielding` for the driver's side).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.compiler import njit
from pounding.framework.model.kinematics import relative_row
from pounding.framework.model.scene import Building
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
        Element index in the building (0-based) and the building's storey (1 = ground to first floor;
        an element standing on floor b has its springs from storey b + 1).
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
        """u_y [m] per spring: its law's ``deformation_scale`` (Fy / k0; inf for a law that does not
        yield: a linear spring, a damper)."""
        return np.array([self.laws[self.law_id[s]].deformation_scale(self.params[s]) for s in range(self.size)])

    def stored_energy(self, state: np.ndarray) -> np.ndarray:
        """Recoverable energy [J] of every spring (ns,) in the states ``state`` (ns, >= n_state)."""
        return np.array([self.laws[self.law_id[s]].stored_energy(state[s], self.params[s]) for s in range(self.size)])


def spring_set(building: Building, index: int = 0) -> SpringSet:
    """The yielding springs of a building (ns may be 0), elements in order, storeys bottom first.

    Elements may follow different hysteresis laws (``law_id`` says which).
    """
    n = building.n_storeys
    centres = np.array([s.centre for s in building.slabs])
    rows, params, elem, storey, height, ids, laws = [], [], [], [], [], [], []
    for e_idx, e in enumerate(building.elements):
        if not e.yields:  # a linear element: in the modal stiffness only
            continue
        if type(e.law) not in laws:
            laws.append(type(e.law))
        P = e.spring_parameters()
        for f, (below, above) in enumerate(e.storey_floors()):  # in the building's numbering, 0 = the ground
            rows.append(relative_row(centres, below, above, np.asarray(e.point, float), np.asarray(e.direction, float), n))
            params.append(P[f])
            elem.append(e_idx)
            storey.append(above)
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


@njit(borrowed=True)
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
