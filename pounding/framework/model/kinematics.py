"""Kinematic rows: how a displacement along a plan direction at a point follows a building's slab DOFs.

A slab has 3 DOF (u, v along x and y at its centre of mass, phi counter-clockwise). The
displacement along the unit direction d at plan point p of floor f is
``d . (u, v) + phi * ((p - c_f) x d)`` (a x b = a_x b_y - a_y b_x): one row over the 3N slab DOFs.
Elements are placed with it (K += T^T k T), the P-delta loads act through it, and every force
between two bodies (a storey spring, a contact) acts along such a row.
"""

from __future__ import annotations

import numpy as np


def placement(slab_centres: np.ndarray, floors, point: np.ndarray, direction: np.ndarray, n_storeys: int) -> np.ndarray:
    """Transformation T (n_floors, 3N) from slab DOFs to the element's in-plane floor displacements."""
    T = np.zeros((len(floors), 3 * n_storeys))
    d = np.asarray(direction, dtype=float)
    for row, f in enumerate(floors):
        r = point - slab_centres[f - 1]
        T[row, 3 * (f - 1) : 3 * f] = (d[0], d[1], r[0] * d[1] - r[1] * d[0])
    return T


def relative_row(slab_centres: np.ndarray, below: int, above: int, point: np.ndarray, direction: np.ndarray, n_storeys: int) -> np.ndarray:
    """Row (3N,) of the displacement along ``direction`` at plan ``point`` of floor ``above`` relative to
    floor ``below`` (1-based; ``below`` = 0: the ground, which does not move): a storey spring's deformation."""
    rows = placement(slab_centres, [above] + ([below] if below > 0 else []), point, direction, n_storeys)
    return rows[0] - (rows[1] if below > 0 else 0.0)
