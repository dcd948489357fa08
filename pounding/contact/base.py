"""The contact-law plugin contract.

Geometry (where slabs touch, the point Q and the normal n) is found by
:mod:`pounding.contact.geometry`; the driver turns each touching feature k
into a row w_k over the modal coordinates of both buildings such that

* the feature's gap changes as ``d gap_k = w_k . dq`` (so its closing speed is
  ``b_k = -w_k . q'``, the paper's b = v_n1 - v_n2 of eq. 12), and
* a pair of equal and opposite impulses I_k along n at Q (pushing the slabs
  apart) changes the modal velocities by ``w_k I_k``; a force lambda_k adds
  ``w_k lambda_k`` to the modal load.

With mass-normalised modes, ``W = w^T w`` (the Delassus matrix) has on its
diagonal the paper's ``a = sum_i (1/m_i + h_i^2 / J_i)``.

A contact law is one of two kinds:

``impulse`` laws are asked, at an instant of contact with approaching
    slabs, for the impulses ``I >= 0`` (shape (m,)) given W (m, m) and the
    approach speeds b (m,) [m/s]; the driver locates those instants.
``force`` laws are asked, once per step while slabs touch, for the contact
    forces at the end of the step, solved implicitly: given the gaps and gap
    rates that the step would end with without contact forces, and the
    compliances ``S_q``, ``S_v`` (m, m) of those gaps and rates to end-of-step
    forces, return ``lambda >= 0`` (m,) [N].

To add a law: subclass :class:`ContactLaw`, set ``name`` and ``kind``, take
parameters keyword-only (``restitution`` always accepted), implement the
method of its kind, and register it under the entry-point group
``pounding.contact``.
"""

from __future__ import annotations

from abc import ABC
from typing import ClassVar

import numpy as np

from pounding.contact.geometry import njit
from pounding.errors import InputError


class ContactLaw(ABC):
    """Base class of every contact law (see the module docstring)."""

    name: ClassVar[str] = ""
    kind: ClassVar[str] = "impulse"

    def __init__(self, *, restitution: float = 0.5):
        if not (isinstance(restitution, (int, float)) and 0.0 <= restitution <= 1.0):
            raise InputError(f"expected a coefficient of restitution in [0, 1], got {restitution!r}", field="restitution")
        self.restitution = float(restitution)

    def impulses(self, W: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Impulses [N s] at the touching features of one slab pair (impulse laws)."""
        raise NotImplementedError

    def forces(self, gap: np.ndarray, rate: np.ndarray, S_q: np.ndarray, S_v: np.ndarray, W: np.ndarray) -> np.ndarray:
        """End-of-step contact forces [N] (force laws)."""
        raise NotImplementedError

    def describe(self) -> dict:
        return {"name": self.name, **{k: v for k, v in vars(self).items() if not k.startswith("_")}}


def newton_impulses(W: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """Impulses that give every approaching point the Newton rebound -k b.

    Solves the small linear complementarity problem: I >= 0, and for each
    point either I_j > 0 with post-impact closing speed ``b_j - (W I)_j = -k b_j``
    (or 0 for a point that was not approaching but would be pushed into the other
    slab), or I_j = 0 with ``b_j - (W I)_j <= 0`` (not approaching). The active sets
    are enumerated, largest first (m <= MAX_FEATURES = 8 points per slab pair).

    Parameters
    ----------
    W : ndarray (m, m)
        Delassus matrix [1/kg].
    b : ndarray (m,)
        Closing speeds before impact [m/s].
    k : float
        Coefficient of restitution.
    """
    return newton_lcp(np.ascontiguousarray(W, dtype=float), np.ascontiguousarray(b, dtype=float), float(k))


@njit
def newton_lcp(W, b, k):
    """Compiled core of :func:`newton_impulses` (same arguments, float64 arrays).

    Every subset of points is a candidate active set, largest first: an active point ends
    with the Newton rebound -k b if it approached (b > 0), or just stops closing (0) if the
    other impulses would drag it into the other slab; the inactive ones must not close.
    W is positive definite for distinct features, so the solution is unique.
    """
    m = b.shape[0]
    target = np.empty(m)
    for j in range(m):
        target[j] = (1.0 + k) * b[j] if b[j] > 0 else b[j]
    scale = 1.0
    for j in range(m):
        scale = max(scale, abs(b[j]))
    if not np.any(b > 0):
        return np.zeros(m)
    for size in range(m, 0, -1):
        for mask in range(1 << m):
            count = 0
            for j in range(m):
                if mask >> j & 1:
                    count += 1
            if count != size:
                continue
            idx = np.empty(size, dtype=np.int64)
            c = 0
            for j in range(m):
                if mask >> j & 1:
                    idx[c] = j
                    c += 1
            sub = np.empty((size, size))
            rhs = np.empty(size)
            for r in range(size):
                rhs[r] = target[idx[r]]
                for s in range(size):
                    sub[r, s] = W[idx[r], idx[s]]
            I_act = solve_small(sub, rhs)
            if np.any(I_act < -1e-12 * np.abs(I_act).max()):
                continue
            I = np.zeros(m)
            for r in range(size):
                I[idx[r]] = max(I_act[r], 0.0)
            after = b - W @ I
            good = True
            for j in range(m):
                if not (mask >> j & 1) and after[j] > 1e-12 * scale:
                    good = False
            if good:
                return I
    return np.zeros(m)


@njit
def solve_small(S, rhs):
    """x with S x = rhs for a small symmetric positive semi-definite S (a Delassus or compliance
    matrix), as the minimum-norm least-squares solution: directions whose eigenvalue is below
    1e-12 of the largest (features that repeat one another, to rounding) get nothing, instead
    of the huge values an LU solve would give them."""
    if S.shape[0] == 1:  # one point: the common case, without LAPACK
        return rhs / S[0, 0] if S[0, 0] > 0.0 else np.zeros(1)
    lam, V = np.linalg.eigh(0.5 * (S + S.T))
    top = 0.0
    for j in range(lam.shape[0]):
        top = max(top, abs(lam[j]))
    c = V.T @ rhs
    for j in range(lam.shape[0]):
        c[j] = c[j] / lam[j] if lam[j] > 1e-12 * top else 0.0
    return V @ c
