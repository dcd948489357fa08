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
    point either I_j > 0 with post-impact closing speed ``b_j - (W I)_j = -k b_j``,
    or I_j = 0 with ``b_j - (W I)_j <= 0`` (not approaching). With m <= 4
    points the active sets are enumerated, largest first.

    Parameters
    ----------
    W : ndarray (m, m)
        Delassus matrix [1/kg].
    b : ndarray (m,)
        Closing speeds before impact [m/s].
    k : float
        Coefficient of restitution.
    """
    m = len(b)
    target = (1.0 + k) * b
    best = np.zeros(m)
    for size in range(m, 0, -1):
        for mask in range(1 << m):
            idx = [j for j in range(m) if mask >> j & 1]
            if len(idx) != size or any(b[j] <= 0 for j in idx):
                continue
            sub = W[np.ix_(idx, idx)]
            try:
                I_act = np.linalg.solve(sub, target[idx])
            except np.linalg.LinAlgError:
                I_act = np.linalg.lstsq(sub, target[idx], rcond=None)[0]
            if np.any(I_act < 0):
                continue
            I = np.zeros(m)
            I[idx] = I_act
            after = b - W @ I
            if np.all(after[[j for j in range(m) if j not in idx]] <= 1e-12 * max(1.0, np.abs(b).max())):
                return I
    return best
