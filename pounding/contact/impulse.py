"""Rigid-body impact with Newton's restitution (the paper, eqs. 8-12).

At an instant of contact with approaching slabs, equal and opposite impulses
act along the normal at Q; with one contact point

    I = (1 + k) b / a,   a = sum_i (1/m_i + h_i^2 / J_i),   b = v_n1 - v_n2 > 0

and the kinetic energy lost is (1 - k^2) b^2 / (2 a). Two or more points at
once (parallel edges meeting face to face) get coupled impulses so that no
point keeps approaching (:func:`~pounding.contact.base.newton_impulses`).

Reference: the method paper (shared/paper), after Goldsmith, *Impact* (1960).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from pounding.contact.base import AFTER_IMPACT, LOCATORS, ContactLaw, newton_impulses
from pounding.errors import InputError


class Impulse(ContactLaw):
    """Instantaneous impact, restitution k in [0, 1].

    Parameters
    ----------
    restitution : float
        Coefficient of restitution k.
    locate : {"halving", "root"}
        How the instant of contact inside an overlapping step is found:
        halve the step until the slabs touch within ``tolerance`` (the paper),
        or solve gap(t) = 0 with a bracketing root finder (Brent).
    tolerance : float
        Contact length tolerance [m].
    after_impact : {"keep", "equilibrium"}
        Accelerations after an impact: kept as they were (the paper), or
        recomputed from equilibrium with the new velocities.
    """

    name: ClassVar[str] = "impulse"
    kind: ClassVar[str] = "impulse"
    #: impulses() is newton_impulses: the compiled core applies them itself (a subclass that
    #: overrides impulses() must set this to False)
    compiled_impulses: ClassVar[bool] = True

    def __init__(self, *, restitution: float = 0.5, locate: str = "halving", tolerance: float = 1e-4, after_impact: str = "keep"):
        super().__init__(restitution=restitution)
        if locate not in LOCATORS:
            raise InputError(f"expected 'halving' or 'root', got {locate!r}", field="locate")
        if not (isinstance(tolerance, (int, float)) and 0 < tolerance < 1):
            raise InputError(f"expected a length tolerance in (0, 1) m, got {tolerance!r}", field="tolerance")
        if after_impact not in AFTER_IMPACT:
            raise InputError(f"expected 'keep' or 'equilibrium', got {after_impact!r}", field="after_impact")
        self.locate = locate
        self.tolerance = float(tolerance)
        self.after_impact = after_impact

    def impulses(self, W: np.ndarray, b: np.ndarray) -> np.ndarray:
        return newton_impulses(W, b, self.restitution)
