"""One step of one mode: the arithmetic every stepping path shares.

The integrators give each mode's step as a transition (:class:`~pounding.solvers.base.Transition`):
A (n, 3, 3) and B (n, 3, 2) with ``z1[i] = A[i] z0[i] + B[i, :, 0] p0[i] + B[i, :, 1] p1[i]``, z = (q,
q', q'') of mode i and p0, p1 its modal load at the step's ends. The compiled stretches, the held
and the links' steps, the impact search's stepped gap and the default step's peak estimate all
form it with :func:`stepped`: the same products in the same order, so every path steps to the bit.
"""

from __future__ import annotations

from pounding.compiler import njit


@njit(borrowed=True)
def stepped(A, B, i, r, z, p0, p1):
    """Component r (0: q, 1: q', 2: q'') of mode i after a step from the states z (n, 3) with the
    mode's loads p0, p1 at the step's ends: ``A[i, r] . z[i] + B[i, r, 0] p0 + B[i, r, 1] p1``."""
    return A[i, r, 0] * z[i, 0] + A[i, r, 1] * z[i, 1] + A[i, r, 2] * z[i, 2] + B[i, r, 0] * p0 + B[i, r, 1] * p1
