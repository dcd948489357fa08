"""The end-of-step contact forces solved with the step: one Newton iteration for every force law.

A force law's contact points press in a trial step; the engine gives, at the step's end, their
penetrations delta_0 and rates delta'_0 without contact forces and the compliances S_q, S_v
(m, m) to end-of-step forces (a force vector lambda moves them by -S_q lambda, -S_v lambda). The
forces solve

    lambda_i = share_i F_i(delta_0 - S_q lambda, delta'_0 - S_v lambda),     i = 1..m,

where F_i is point i's law and share_i its share of the contact (the face rule,
:mod:`pounding.contact.pointwise`). :func:`solve_forces` does it by Newton's method with the
Jacobian I + diag(share dF/d delta) S_q + diag(share dF/d delta') S_v, halving a step that does
not lower the residual's norm (the residual's kinks, where a point lets go or a material yields,
can overshoot), to :data:`NEWTON_RTOL` of the largest force.

What a point's force is comes in as a plugin: ``evaluate(data, i, delta, rate) -> (F, dF/d delta,
dF/d rate)`` with the law's own ``data`` (a tuple of arrays and numbers), passed as a one-member
:class:`~pounding.compiler.unroll.LawTuple` so that the solve is compiled once per evaluator (a
direct call, no function pointer). The point laws' evaluator (:func:`pounding.contact.pointwise.point_at`:
compiled kernels of the penetration, its rate and the rate when the contact began) and the link
laws' at contact points (:func:`pounding.contact.material.material_point`: a uniaxial material from
its committed state, which parts rather than pulls) are the two the package has: one solve serves
both. With the compiler off it runs as the same function in Python (a law only Python knows).

Glossary: delta [m] penetration (> 0 in contact), delta' [m/s] its rate, lambda [N], S_q [m/N],
S_v [m/(N s)], share [-].
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.compiler.unroll import literal_unroll, unrolled_in

unrolled_in(globals())  # this module's literal_unroll: numba's once numba is set up

#: Newton on the end-of-step forces: relative residual at which it stops
NEWTON_RTOL = 1e-12
#: and the most iterations it makes (quadratic convergence needs < 10 from lambda = 0)
NEWTON_ITERATIONS = 60


@njit
def _residual(evaluate, data, delta0, rate0, share, S_q, S_v, lam, out):
    """out (3, m) <- the residual lam - share F(delta0 - S_q lam, rate0 - S_v lam) and the residual's
    tangent coefficients share dF/d delta, share dF/d rate at each point; returns max |residual|."""
    m = delta0.shape[0]
    norm = 0.0
    for i in range(m):
        d, v = delta0[i], rate0[i]
        for j in range(m):
            d -= S_q[i, j] * lam[j]
            v -= S_v[i, j] * lam[j]
        f, fd, fr = 0.0, 0.0, 0.0
        for law in literal_unroll(evaluate):  # (one evaluator)
            f, fd, fr = law(data, i, d, v)
        out[0, i] = lam[i] - share[i] * f
        out[1, i] = share[i] * fd
        out[2, i] = share[i] * fr
        norm = max(norm, abs(out[0, i]))
    return norm


@njit
def solve_forces(evaluate, data, delta0, rate0, share, S_q, S_v):
    """(lambda (m,) [N], settled) of m points solved with the step (module docstring): the forces,
    and whether the residual met :data:`NEWTON_RTOL` of the largest force within
    :data:`NEWTON_ITERATIONS`.

    Parameters
    ----------
    evaluate : LawTuple
        The one evaluator ``(data, i, delta, rate) -> (F [N], dF/d delta [N/m], dF/d rate [N s/m])``.
    data : tuple
        Its data (the law's parameters and history at the m points).
    delta0, rate0 : ndarray (m,)
        Penetrations [m] and their rates [m/s] at the step's end without contact forces.
    share : ndarray (m,)
        The share of the contact each point carries.
    S_q, S_v : ndarray (m, m)
        Compliances of the end-of-step gaps [m/N] and rates [m/(N s)] to the forces.
    """
    m = delta0.shape[0]
    lam, trial = np.zeros(m), np.zeros(m)
    now, new = np.empty((3, m)), np.empty((3, m))  # residual and its tangent coefficients: at lam, and at a trial
    J = np.empty((m, m))
    norm = _residual(evaluate, data, delta0, rate0, share, S_q, S_v, lam, now)
    scale = max(norm, 1e-300)  # the largest force at lambda = 0
    for _ in range(NEWTON_ITERATIONS):
        if norm <= NEWTON_RTOL * scale:
            return lam, True
        for i in range(m):
            for j in range(m):
                J[i, j] = (1.0 if i == j else 0.0) + now[1, i] * S_q[i, j] + now[2, i] * S_v[i, j]
        step = np.linalg.solve(J, -now[0])
        t = 1.0
        trial_norm = norm
        for _ in range(40):  # backtrack: the residual's kinks (contact lost, force clamped, a yield) can overshoot
            for i in range(m):
                trial[i] = lam[i] + t * step[i]
            trial_norm = _residual(evaluate, data, delta0, rate0, share, S_q, S_v, trial, new)
            if trial_norm < norm:
                break
            t *= 0.5
        for i in range(m):
            lam[i] = trial[i]
            scale = max(scale, abs(lam[i]))
        now[:] = new
        norm = trial_norm
    return lam, norm <= NEWTON_RTOL * scale
