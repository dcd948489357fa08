"""Exact integration of each mode under a load linear in the step.

The unit-mass oscillator ``q'' + 2 zeta omega q' + omega**2 q = p(t)`` with
``p`` linear between ``p0`` and ``p1`` has a closed-form solution
(Nigam & Jennings, 1969, Bull. Seismol. Soc. Am. 59, 909-922). Written
naively its coefficients cancel catastrophically for small ``omega dt``;
written as matrix exponentials they do not, so each mode takes one of two
routes, both accurate to ~1e-14 of the natural scale of each entry
(checked against 50-digit arithmetic for ``omega dt`` in [1e-4, 1e4],
``zeta`` in [0, 10]):

Both are compiled mode by mode in :func:`pounding.solvers.exact_partial.exact_transition`, the one
transition of this integrator (grid steps, contact events' partial steps, the impact search):

* ``omega dt <= 1/2``: the exponential (scaling and squaring, Taylor) of a 4x4 augmented matrix
  (Van Loan, 1978, IEEE Trans. Autom. Control 23, 395-404), scaled by 2**j to a 1-norm of at most
  1/2 (j is 1 or 2 for damping ratios up to 1/2, at most 3 up to zeta = 3): a few squarings, each at
  most doubling a relative error at the ulp level.
* ``omega dt > 1/2``: the closed form of ``exp(F)``, ``F = omega dt [[0, 1],
  [-1, -2 zeta]]``, and the load responses ``F^-1 (exp(F) - I)`` and
  ``F^-2 (exp(F) - I - F)``. There ``expm`` would square many times and lose
  up to 1e-12 on lightly damped modes; the closed form loses nothing.
"""

from __future__ import annotations

import numpy as np

from pounding.solvers.base import Integrator, Transition


class Exact(Integrator):
    """Free of integration error for piecewise-linear modal loads.

    ``(q, q')`` at the end of the step is the exact solution; ``q''`` at the
    end follows from equilibrium, ``q''1 = p1 - 2 zeta omega q'1 - omega**2 q1``,
    so the start acceleration is not an input (its column of ``A`` is zero).
    ``order`` is 2 because a sampled record is followed to second order by
    its linear interpolation.
    """

    name = "exact"
    order = 2
    # Only when work_maps cannot serve (a mode with omega = 0): 4 Gauss points on the exact
    # trajectory integrate the work to ~(omega dt)^8 / 1e9 relative per step.
    energy_nodes = 4
    exact_within_step = True

    def work_maps(self, omega, zeta, dt):
        """Exact work integrals of a step of dt [s] on the exact trajectory, for the energy audit of
        grid steps and of contact events' partial steps alike (the base class's
        :meth:`~pounding.solvers.base.Integrator.partial_work_maps` is this).

        Returns a1, a2 (n, 4) and M (n, 4, 4): for x = (q0, q'0, p0, p1),
        int q' ds = a1 x, int s q' ds = a2 x, int q'^2 ds = x M x over the step
        (:func:`pounding.solvers.exact_work.work_maps`: compiled mode by mode for omega dt <=
        max(3, 1.5 zeta), numpy above; to ~1e-14 of their scale for omega dt up to 1e5 and zeta up
        to 10, also at critical damping).
        """
        from pounding.solvers.exact_work import work_maps

        return work_maps(np.asarray(omega, dtype=float), np.asarray(zeta, dtype=float), float(dt))

    def search_maps(self):
        """(:func:`pounding.solvers.exact_partial.exact_maps`, no parameters): the compiled
        :meth:`transition` in the impact search's form (the same function, so the same numbers); None
        without the compiler (:meth:`~pounding.solvers.base.Integrator.search_maps`)."""
        from pounding.compiler import is_compiled
        from pounding.solvers.exact_partial import exact_maps

        return (exact_maps, np.zeros(0)) if is_compiled(exact_maps) else None

    def transition(self, omega, zeta, dt):
        """Per-mode maps (A (n, 3, 3), B (n, 3, 2)) of a step of dt [s]: the two routes of the module
        docstring, mode by mode (:func:`pounding.solvers.exact_partial.exact_transition`, compiled;
        with the compiler off the same function as Python). The one transition of this integrator:
        grid steps, the partial steps of contact events and the compiled impact search build it so."""
        from pounding.solvers.exact_partial import exact_transition

        omega, zeta = _modes_flat(omega, zeta)
        A, B = exact_transition(omega, zeta, float(dt))
        return Transition(A=A, B=B, dt=float(dt))

    def step(self, q, qd, qdd, p0, p1, omega, zeta, dt):
        omega = np.asarray(omega, dtype=float)
        zeta = np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape)
        tr = self.transition(omega.reshape(-1), zeta.reshape(-1), dt)
        z = np.stack(np.broadcast_arrays(q, qd, qdd), axis=1)  # (n, 3) or (n, 3, k)
        u = np.stack(np.broadcast_arrays(p0, p1), axis=1)  # (n, 2) or (n, 2, k)
        z1 = np.einsum("nij,nj...->ni...", tr.A, z) + np.einsum("nij,nj...->ni...", tr.B, u)
        return z1[:, 0], z1[:, 1], z1[:, 2]


def _modes_flat(omega, zeta):
    """omega, zeta as writable contiguous float arrays (n,) for the compiled one-off maps (one argument
    type, so one compilation); the driver's (:class:`pounding.solvers.base.TransitionCache`) already
    are, and pass through untouched: these maps are built a few times per contact event."""
    if (type(omega) is np.ndarray and type(zeta) is np.ndarray and omega.ndim == 1 and omega.shape == zeta.shape
            and omega.dtype == np.float64 and zeta.dtype == np.float64 and omega.flags.c_contiguous and zeta.flags.c_contiguous
            and omega.flags.writeable and zeta.flags.writeable):
        return omega, zeta
    omega = np.array(omega, dtype=float).reshape(-1)
    return omega, np.array(np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape))
