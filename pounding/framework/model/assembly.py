"""Assemble one building: mass, stiffness and damping over slab DOFs, and its modes.

DOFs are ordered floor by floor, ``(u_1, v_1, phi_1, u_2, v_2, phi_2, ...)``:
translations [m] of each slab's centre of mass and its rotation [rad],
counter-clockwise positive (right hand about the upward z axis, as in
OpenSees). A planar element with unit direction d through point p contributes
``T^T k T`` where row f of T holds ``(d_x, d_y, (p - c_f) x d)`` in the columns
of floor f (c_f its centre of mass, a x b = a_x b_y - a_y b_x): the
displacement along d of the slab point p under (u, v, phi).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.model.kinematics import placement
from scipy.linalg import eigh

from pounding.errors import InputError
from pounding.framework.model.scene import Building, Damping, Slab


@dataclass(frozen=True, eq=False)
class System:
    """The assembled building, ready for modal or step-by-step analysis.

    Attributes
    ----------
    name : str
    slabs : tuple of Slab
    mass : ndarray (3N,)
        Diagonal of M: (m, m, J) per floor [kg, kg, kg m^2].
    K : ndarray (3N, 3N)
        Stiffness [N/m, N, N m].
    C : ndarray (3N, 3N)
        Damping [N s/m, ...].
    omega : ndarray (3N,)
        Circular frequencies, ascending [rad/s].
    modes : ndarray (3N, 3N)
        Mass-normalised mode shapes in columns (Phi^T M Phi = I).
    zeta : ndarray (3N,)
        Modal damping ratios [-].
    storey_heights : tuple of float
        [m], bottom first.
    elements : tuple of PlacedElement
        Every element as placed (stiffness modifier included), scene order: what storey
        forces are computed from (:mod:`pounding.framework.post.response`).
    """

    name: str
    slabs: tuple[Slab, ...]
    mass: np.ndarray
    K: np.ndarray
    C: np.ndarray
    omega: np.ndarray
    modes: np.ndarray
    zeta: np.ndarray
    storey_heights: tuple[float, ...] = ()
    elements: tuple["PlacedElement", ...] = ()

    @property
    def n_storeys(self) -> int:
        return len(self.slabs)

    @property
    def n_dof(self) -> int:
        return 3 * len(self.slabs)

    @property
    def M(self) -> np.ndarray:
        return np.diag(self.mass)

    @property
    def periods(self) -> np.ndarray:
        """Natural periods [s], descending (mode 1 first)."""
        return 2.0 * np.pi / self.omega

    def influence(self, direction: np.ndarray) -> np.ndarray:
        """Influence vector b (3N,) of a ground motion along the plan unit vector ``direction``."""
        b = np.zeros(self.n_dof)
        b[0::3], b[1::3] = direction[0], direction[1]
        return b

    def participation(self, b: np.ndarray) -> np.ndarray:
        """Modal participation factors Gamma_i = phi_i^T M b (mass-normalised modes), shape (3N,)."""
        return self.modes.T @ (self.mass * b)

    def centres_of_rigidity(self) -> np.ndarray:
        """Centre of rigidity of every floor [m], shape (N, 2).

        The point of floor f where a horizontal force applied to that floor
        alone (the others free) causes no rotation of that floor, from the
        flexibility F = K^{-1}: e_y = F[phi, u] / F[phi, phi],
        e_x = -F[phi, v] / F[phi, phi] measured from the centre of mass (the
        per-diaphragm definition used by ETABS).
        """
        F = np.linalg.solve(self.K, np.eye(self.n_dof))
        out = np.empty((self.n_storeys, 2))
        for f, slab in enumerate(self.slabs):
            iu, iv, ip = 3 * f, 3 * f + 1, 3 * f + 2
            out[f] = slab.centre + np.array([-F[ip, iv], F[ip, iu]]) / F[ip, ip]
        return out


@dataclass(frozen=True, eq=False)
class PlacedElement:
    """One element as placed in its building.

    k : ndarray (n_e, n_e)
        Condensed lateral stiffness times the stiffness modifier [N/m].
    T : ndarray (n_e, 3N)
        Placement: the element's floor displacements along its line are ``T x`` [m].
    floors : tuple of int
        1-based floors of the building its stiffness acts on: the floors it spans, and first the
        floor it stands on when that is not the ground
        (:meth:`~pounding.elements.base.PlanarElement.placed_stiffness`).
    direction : ndarray (2,)
        Unit vector of its line.
    """

    k: np.ndarray
    T: np.ndarray
    floors: tuple[int, ...]
    direction: np.ndarray

    def __iter__(self):  # (k, T), as assembly uses it
        return iter((self.k, self.T))


def placed_elements(building: Building) -> list[PlacedElement]:
    """Every element as placed in the building: (k, T) in scene order.

    k (n_e, n_e) [N/m] is the element's condensed lateral stiffness times its
    stiffness modifier (``Building.modifiers``), T (n_e, 3N) its placement
    (:func:`placement`): the element's floor displacements along its line are
    ``T x`` and its floor forces along the line ``k T x`` [N]. The one place
    where element stiffness meets slab DOFs (assembly and storey forces both use it). An element
    standing on a floor above the ground (``first_storey`` > 1) acts on that floor too, with the
    stiffness of its floors relative to it (:meth:`~pounding.elements.base.PlanarElement.placed_stiffness`).
    """
    n = building.n_storeys
    centres = np.array([s.centre for s in building.slabs])
    out = []
    for e, factor in zip(building.elements, building.element_modifiers()):
        floors, k = e.placed_stiffness()
        T = placement(centres, floors, np.asarray(e.point, float), np.asarray(e.direction, float), n)
        out.append(PlacedElement(factor * k, T, tuple(floors), np.asarray(e.direction, dtype=float)))
    return out


def stiffness(building: Building, placed: list[PlacedElement] | None = None) -> np.ndarray:
    """Global stiffness K (3N, 3N) of a building: its elements, plus the P-Delta geometric
    stiffness of its gravity loads when ``building.p_delta`` is set (:mod:`pounding.framework.model.pdelta`)."""
    n = building.n_storeys
    K = np.zeros((3 * n, 3 * n))
    for k, T in placed if placed is not None else placed_elements(building):
        K += T.T @ k @ T
    if building.p_delta is not None:
        from pounding.framework.model.pdelta import geometric_stiffness

        K += geometric_stiffness(building)
    return 0.5 * (K + K.T)


def modal_damping(damping: Damping, omega: np.ndarray, name: str) -> np.ndarray:
    """Damping ratio of every mode [-] for a classical damping model."""
    n = len(omega)
    field = f"building {name!r} damping"
    if damping.kind == "modal":
        r = np.atleast_1d(np.asarray(damping.ratio, dtype=float))
        if r.size == 1:
            return np.full(n, r[0])
        if r.size != n:
            raise InputError(f"expected one ratio or {n} (one per mode), got {r.size}", field=field)
        return r
    if damping.kind == "stiffness":
        (mode,) = damping.modes
        if mode > n:
            raise InputError(f"mode {mode} requested but the building has {n} modes", field=field)
        a1 = 2.0 * damping.ratio / omega[mode - 1]
        return a1 * omega / 2.0
    a0, a1 = rayleigh_coefficients(damping, omega, name)
    return a0 / (2.0 * omega) + a1 * omega / 2.0


def rayleigh_coefficients(damping: Damping, omega: np.ndarray, name: str) -> tuple[float, float]:
    """(a0, a1) of C = a0 M + a1 K giving ``damping.ratio`` at two modes or periods."""
    if damping.periods is not None:
        wi, wj = 2 * np.pi / np.asarray(damping.periods, dtype=float)
    else:
        i, j = damping.modes
        if max(i, j) > len(omega):
            raise InputError(f"mode {max(i, j)} requested but the building has {len(omega)} modes", field=f"building {name!r} damping.modes")
        wi, wj = omega[i - 1], omega[j - 1]
    z = damping.ratio
    return 2 * z * wi * wj / (wi + wj), 2 * z / (wi + wj)


def check_stable(building: Building, field: str | None = None) -> None:
    """Raise InputError if the building is a mechanism (see :func:`assemble`)."""
    mass = np.concatenate([[s.mass, s.mass, s.polar_inertia] for s in building.slabs])
    lam, vecs = eigh(stiffness(building), np.diag(mass))
    _check_mechanism(building, lam, vecs, field)


def _check_mechanism(building: Building, lam: np.ndarray, vecs: np.ndarray, field: str | None = None) -> None:
    # A zero eigenvalue (relative to the largest) means a displacement pattern that no element resists.
    if lam[0] > 1e-10 * lam[-1] and lam[0] > 0:
        return
    v = vecs[:, 0]
    if building.p_delta is not None:
        from dataclasses import replace

        lam0 = eigh(stiffness(replace(building, p_delta=None)), np.diag(np.concatenate([[s.mass, s.mass, s.polar_inertia] for s in building.slabs])), eigvals_only=True)
        if lam0[0] > 1e-10 * lam0[-1]:
            raise InputError(
                f"building {building.name!r} buckles under its gravity loads: with P-Delta its stiffness is no longer "
                f"positive (lowest eigenvalue {lam[0]:.3g} 1/s^2); check p_delta loads and the element stiffness",
                field=(field.rsplit(".", 1)[0] + ".p_delta") if field else f"building {building.name!r} p_delta",
            )
    _check_units(building, field)  # units before mechanism: a unit slip also looks like a mechanism
    k = int(np.argmax(np.abs(v) * np.tile([1.0, 1.0, building.slabs[0].radius], building.n_storeys)))
    storey, dof = k // 3 + 1, ("x translation", "y translation", "rotation")[k % 3]
    raise InputError(
        f"building {building.name!r} is a mechanism: nothing resists {dof} of storey {storey} "
        "(add a frame or wall in that direction, or away from the others for rotation)",
        field=field or f"building {building.name!r}",
    )


def _check_units(building: Building, field: str | None) -> None:
    """Raise InputError naming the element if a unit slip (one element far stiffer than the others) explains a
    near-zero eigenvalue: beside an element 1e12 times too stiff the others' stiffness is lost to rounding."""
    from pounding.framework.model.stiffness_scale import describe, outliers

    found = outliers(building)
    if not found:
        return
    i, k, med = max(found, key=lambda o: o[1])
    where = f"{field}[{i}]" if field else f"building {building.name!r} element[{i}]"
    raise InputError(describe(building, i, k, med) + " Beside it the other elements' stiffness is lost to rounding, "
                     "so the building looks like a mechanism; units are SI (m, Pa).", field=where)


def assemble(building: Building) -> System:
    """Assemble M, K, C and the modes of one building.

    Raises
    ------
    InputError
        If the building is a mechanism (K singular): names the storey and the
        direction that nothing resists.
    """
    mass = np.concatenate([[s.mass, s.mass, s.polar_inertia] for s in building.slabs])
    placed = placed_elements(building)
    K = stiffness(building, placed)
    lam, vecs = eigh(K, np.diag(mass))
    _check_mechanism(building, lam, vecs)
    # Deterministic signs: the largest component of every mode is positive.
    signs = np.sign(vecs[np.argmax(np.abs(vecs), axis=0), np.arange(vecs.shape[1])])
    vecs = vecs * signs
    omega = np.sqrt(lam)
    zeta = modal_damping(building.damping, omega, building.name)
    Mphi = mass[:, None] * vecs
    C = Mphi @ np.diag(2.0 * zeta * omega) @ Mphi.T  # classical: Phi^T C Phi = diag(2 zeta omega)
    return System(building.name, building.slabs, mass, K, 0.5 * (C + C.T), omega, vecs, zeta, tuple(building.storey_heights), tuple(placed))
