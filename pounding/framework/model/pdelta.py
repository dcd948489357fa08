"""P-Delta: the linear geometric stiffness of a building's gravity loads, storey by storey.

A gravity load W that rides on a floor and is carried down through storey s
(height h) by vertical members tilts with them when the storey drifts: a
member carrying the axial force N_i whose ends move apart horizontally by
Delta_i pushes its storey sideways with N_i Delta_i / h (the P-Delta shear of
a linear P-Delta transformation, no P-delta along the member). Its potential is
``-N_i |Delta_i|^2 / (2 h)``, so the storey's geometric stiffness is the
negative of that quadratic form, and the model stays linear.

Rigid diaphragms. The relative displacement of the plan point r between floor
s and the floor below is ``Delta(r) = Delta(r_G) + dphi R (r - r_G)`` with
``R (x, y) = (-y, x)`` and dphi the storey's twist, for any reference point
r_G. Summed over the members with ``sum N_i = P`` and ``sum N_i r_i = P r_G``
(r_G the centre of the load, so the cross term vanishes):

    sum_i N_i |Delta(r_i)|^2 = P |Delta(r_G)|^2 + I_P dphi^2,
    I_P = sum_i N_i |r_i - r_G|^2   [N m^2]

P and r_G follow from statics alone (vertical force and moment equilibrium of
everything above storey s under gravity): P = sum of the floor loads W_f
above, r_G their centroid. I_P, the polar moment of the column loads about
r_G, depends on how the members share the load; here the load of each floor
is taken distributed over the plan like that floor's mass (the ETABS
"from masses" P-Delta), so ``I_P = sum_f W_f (J_f / m_f + |c_f - r_G|^2)``.
The storey adds

    K_G = -(P / h) (t_x^T t_x + t_y^T t_y) - (I_P / h) t_phi^T t_phi

where t_x, t_y (3N,) give Delta(r_G) along x and y (the rows of
:func:`pounding.framework.model.kinematics.placement` at r_G for floor s minus those of
the floor below; for the first storey the ground does not move) and t_phi
gives dphi. A one-storey column of lateral stiffness k carrying P: k_eff = k -
P / h, and the period grows by sqrt(k / (k - P / h)).

Reference: Wilson & Habibullah (1987), "Static and dynamic analysis of
multi-story buildings, including P-Delta effects", Earthquake Spectra 3(2);
Chopra, *Dynamics of Structures*, sec. 8.7 (geometric stiffness).
"""

from __future__ import annotations

import numpy as np

from pounding.framework.model.kinematics import placement
from pounding.framework.model.scene import Building
from pounding.framework.model.units import G

#: standard gravity [m/s^2]
GRAVITY = G


def floor_loads(building: Building) -> np.ndarray:
    """Gravity load W_f of every floor [N], shape (N,): ``p_delta.loads``, else load_factor g m_f."""
    pd = building.p_delta
    if pd is None:
        return np.zeros(building.n_storeys)
    if pd.loads is not None:
        return np.asarray(pd.loads, dtype=float)
    return pd.load_factor * GRAVITY * np.array([s.mass for s in building.slabs])


def storey_loads(building: Building) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What each storey carries: P (N,) [N], load centre r_G (N, 2) [m], polar moment I_P (N,) [N m^2].

    Storey s (0-based index) carries the loads of floors s..N-1, each spread over
    its slab like the slab's mass (radius of gyration^2 = J_f / m_f).
    """
    W = floor_loads(building)
    c = np.array([s.centre for s in building.slabs])
    rho2 = np.array([s.polar_inertia / s.mass for s in building.slabs])
    n = building.n_storeys
    P, rG, IP = np.zeros(n), np.zeros((n, 2)), np.zeros(n)
    for s in range(n):
        w = W[s:]
        P[s] = w.sum()
        rG[s] = (w[:, None] * c[s:]).sum(axis=0) / P[s] if P[s] > 0 else c[s]
        IP[s] = float(np.sum(w * (rho2[s:] + np.sum((c[s:] - rG[s]) ** 2, axis=1))))
    return P, rG, IP


def geometric_stiffness(building: Building) -> np.ndarray:
    """Geometric stiffness K_G (3N, 3N) of the building's gravity loads (see the module docstring).

    Negative semi-definite; added to the elements' K by
    :func:`pounding.framework.model.assembly.stiffness` when ``building.p_delta`` is set.
    """
    n = building.n_storeys
    centres = np.array([s.centre for s in building.slabs])
    P, rG, IP = storey_loads(building)
    K = np.zeros((3 * n, 3 * n))
    for s in range(n):
        h = building.storey_heights[s]
        floors = (s + 1,) if s == 0 else (s, s + 1)  # 1-based; the ground below storey 1 does not move
        diff = np.array([1.0]) if s == 0 else np.array([-1.0, 1.0])  # top floor minus the floor below
        for d in ((1.0, 0.0), (0.0, 1.0)):
            t = diff @ placement(centres, floors, rG[s], np.array(d), n)
            K -= (P[s] / h) * np.outer(t, t)
        t = np.zeros(3 * n)
        t[3 * s + 2] = 1.0
        if s > 0:
            t[3 * s - 1] = -1.0
        K -= (IP[s] / h) * np.outer(t, t)
    return K
