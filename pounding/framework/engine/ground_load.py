"""The modal ground-motion load, p = -L ag: one function for every path that forms it.

L (n, c) is the modal load per unit ground acceleration of the n stacked modes (mass-normalised
modes: L = Phi^T M b), ag (c,) the ground acceleration's components [m/s^2] at one instant. The
compiled stepping forms it mode by mode (:func:`modal_load`), the driver's Python step, the impact
search and the peaks' intra-step solution for all modes at once (:func:`modal_loads`): the same
sum in the same order, so every path steps with the same load to the bit.
"""

from __future__ import annotations

from pounding.compiler import njit


@njit(borrowed=True)
def modal_load(L, i, ag):
    """Modal ground-motion load of mode i, p_i = -sum_j L[i, j] ag[j], for L (n, c) and ag (c,).

    Written as sum_j L[i, j] (-ag[j]) starting from the first term, so that with one
    component it is L[i, 0] * -ag[0] to the bit."""
    p = L[i, 0] * -ag[0]
    for j in range(1, L.shape[1]):
        p += L[i, j] * -ag[j]
    return p


@njit(borrowed=True)
def modal_loads(L, ag, p):
    """p (n,) <- the modal ground-motion load of every mode (:func:`modal_load`) [N/kg^0.5]."""
    for i in range(L.shape[0]):
        p[i] = modal_load(L, i, ag)
