"""The contact law of a bumper: a layer's law, and the slabs' law once the layer is spent.

A bumper (:mod:`pounding.framework.model.bumpers`) is a layer of thickness t on one slab's facing
faces; the pair's gap is measured to the layer's surface, so the penetration delta [m] the engine
gives is the layer's compression (t - the bare gap). Its force is

    F(delta, delta', delta'_0) = F_b(delta, delta', delta'_0) + F_s(delta - c t, delta', delta'_0)

with F_b the layer's law, F_s the slabs' law (zero for delta <= c t) and c the ``compressible``
fraction of t. The layer stays in parallel with the slabs' law beyond c t: the compressed rubber
is still there and still pushes (its stress does not vanish when the concrete behind it begins to
bear), so the force is continuous in delta when F_s starts from zero (Hertz-type laws), and jumps
by F_s's damping term (c_s delta' for ``kelvin``) at delta = c t, as F_s itself does at first touch.
Both laws are passive, so their sum never adds energy.

History: the slabs' law is given the closing speed of the episode's start (when the layer was
first touched), not the speed at delta = c t, which the engine does not record; a law whose
damping is normalised by it (``hertzdamp``) therefore damps the slabs' share less than for a bare
impact at the lower speed c t later. ``kelvin``, ``hertz`` and ``penalty`` do not read it.

The solve: when both laws are given point by point (:meth:`~pounding.contact.base.ContactLaw.point_law`),
the sum is one point law solved with the step by Newton's method
(:func:`pounding.contact.pointwise.contact_forces`); otherwise the two laws' forces are swept in
turn, each seeing the other's as a known load (block Gauss-Seidel, as
:func:`pounding.framework.engine.contact_laws.solve_forces` does for two pairs).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pounding.contact.base import ContactLaw
from pounding.contact.pointwise import contact_forces, point_solver

#: block Gauss-Seidel of two laws not given point by point: relative change at which it stops
SWEEP_RTOL = 1e-12
#: and the most sweeps it makes
SWEEPS = 500


class BumperLaw(ContactLaw):
    """The force law of a pair that a bumper stands in (see the module docstring).

    Parameters
    ----------
    layer : ContactLaw
        The layer's law, acting by forces (:attr:`~pounding.contact.base.ContactLaw.with_step`).
    slabs : ContactLaw
        The slabs' law, acting by forces, on delta - ``compressible`` t.
    thickness : float
        t [m] (> 0).
    compressible : float
        c in (0, 1] [-].
    """

    name: ClassVar[str] = "bumper"
    kind: ClassVar[str] = "force"

    def __init__(self, *, layer: ContactLaw, slabs: ContactLaw, thickness: float, compressible: float):
        for what, law in (("layer", layer), ("slabs", slabs)):
            if not law.with_step:
                raise ValueError(f"a bumper needs a force law (a layer compresses): its {what}' law "
                                 f"{law.name or type(law).__name__!r} acts by impulses")
            if law.keeps_state:  # its forces are summed with the other law's: no commit could split them
                raise ValueError(f"a bumper's {what}' law {law.name or type(law).__name__!r} keeps a state of its own "
                                 "point by point, which a bumper cannot commit: give it a law without one")
        super().__init__(restitution=layer.restitution)
        self.layer, self.slabs = layer, slabs
        self.thickness, self.compressible = float(thickness), float(compressible)
        self.tolerance = layer.tolerance

    @property
    def reach(self) -> float:
        """c t [m]: the layer's compression at which the slabs' law begins to act."""
        return self.compressible * self.thickness

    def describe(self) -> dict:
        """Name, the two laws' descriptions, t and c, for summary.json."""
        return {"name": self.name, "layer": self.layer.describe(), "slabs": self.slabs.describe(),
                "thickness": self.thickness, "compressible": self.compressible}

    def contact_duration(self, m_eff: float, approach_speed: float) -> float:
        """The shorter of the two laws' contacts [s] at ``m_eff`` [kg], ``approach_speed`` [m/s]: a
        lower bound of the bumper's, whose contact is the layer's while delta < c t and whose
        stiffest phase is the slabs' law in parallel with it (stiffer than either alone)."""
        durations = [self.layer.contact_duration(m_eff, approach_speed), self.slabs.contact_duration(m_eff, approach_speed)]
        return min(d for d in durations if not math.isnan(d))

    def point_law(self, m_eff: np.ndarray):
        """The two point laws in parallel, the slabs' on the penetration less c t (see the module
        docstring: :meth:`PointLaw.beside <pounding.contact.pointwise.PointLaw.beside>`), or None
        when either law is not given point by point."""
        layer, slabs = self.layer.point_law(m_eff), self.slabs.point_law(m_eff)
        if layer is None or slabs is None:
            return None
        return layer.beside(slabs, self.reach)

    def point_force(self, delta: float, rate: float, approach_rate: float, m_eff: float) -> tuple[float, float, float]:
        """(force [N], d/d delta [N/m], d/d rate [N s/m]) of one whole contact of effective mass
        ``m_eff`` [kg] (both laws point by point)."""
        return self.point_law(np.array([float(m_eff)])).at(0, delta, rate, approach_rate)

    def forces(self, contact) -> np.ndarray:
        """End-of-step forces lambda (m,) [N] of the m pressed points (the contact-law contract)."""
        joint = self.point_law(1.0 / np.diag(np.asarray(contact.W, dtype=float)))
        if joint is not None:
            return contact_forces(joint, contact)
        return self._swept(contact)

    def forces_solver(self, contact):
        """The compiled solve of both laws point by point where both are given so
        (:func:`~pounding.contact.pointwise.point_solver`), else :meth:`forces` from Python."""
        joint = self.point_law(1.0 / np.diag(np.asarray(contact.W, dtype=float)))
        if joint is not None:
            return point_solver(joint, contact)
        return super().forces_solver(contact)

    def _swept(self, contact) -> np.ndarray:
        """The two laws' forces by block Gauss-Seidel: the layer on the gap, the slabs' law on the
        gap plus c t, each moved by the other's forces through S_q, S_v."""
        S_q, S_v = np.asarray(contact.S_q, dtype=float), np.asarray(contact.S_v, dtype=float)
        gap, rate = np.asarray(contact.gap, dtype=float), np.asarray(contact.rate, dtype=float)
        lam_b, lam_s = np.zeros(len(gap)), np.zeros(len(gap))
        for _ in range(SWEEPS):
            new_b = np.asarray(self.layer.forces(contact._replace(gap=gap + S_q @ lam_s, rate=rate + S_v @ lam_s)), dtype=float)
            new_s = np.asarray(self.slabs.forces(contact._replace(gap=gap + self.reach + S_q @ new_b, rate=rate + S_v @ new_b)),
                               dtype=float)
            change = max(float(np.max(np.abs(new_b - lam_b))), float(np.max(np.abs(new_s - lam_s))))
            lam_b, lam_s = new_b, new_s
            if change <= SWEEP_RTOL * max(float(np.max(np.abs(lam_b + lam_s))), 1e-300):
                break
        return lam_b + lam_s
