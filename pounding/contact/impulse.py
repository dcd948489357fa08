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
    locate : {"crossing", "halving", "root"}
        How the instant of contact is found. ``crossing`` (default): the impulse
        acts where the gap is zero to rounding (Brent's method on the gap over the
        integrator's own intra-step solution), in any step the gap crosses zero or
        may dip below it and back (a graze, screened by a bound on the slabs'
        relative motion); a gap within ``tolerance`` at a step's end is not struck.
        The paper's ``halving`` and ``root`` strike a closing pair as soon as its
        gap is within ``tolerance`` at a step's end, and search a step only when it
        ends overlapping by more than ``tolerance``: halve the step until the slabs
        touch within ``tolerance`` (the paper), or solve gap(t) = 0 with Brent's method.
    tolerance : float
        Contact length tolerance [m]. With ``crossing`` it only decides resting
        contact (points within it of the smallest gap are struck together; a pair held
        in contact is let go when it opens beyond it); chatter (ever smaller rebounds
        that end in a finite time, a Zeno sequence) is held in contact when its remaining
        duration is shorter than a step. With ``halving`` and ``root`` it is also how
        close a closing gap counts as contact, and a rebound too slow to open it within
        a step holds the pair.
    after_impact : {"equilibrium", "keep"}
        Accelerations after an impact: recomputed from equilibrium with the new
        velocities (default), or kept as they were (the paper).
    """

    name: ClassVar[str] = "impulse"
    kind: ClassVar[str] = "impulse"
    #: impulses() is newton_impulses: the compiled core applies them itself (a subclass that
    #: overrides impulses() must set this to False)
    compiled_impulses: ClassVar[bool] = True

    def __init__(self, *, restitution: float = 0.5, locate: str = "crossing", tolerance: float = 1e-4,
                 after_impact: str = "equilibrium"):
        super().__init__(restitution=restitution)
        if locate not in LOCATORS:
            raise InputError(f"expected one of {', '.join(repr(x) for x in LOCATORS)}, got {locate!r}", field="locate")
        if not (isinstance(tolerance, (int, float)) and 0 < tolerance < 1):
            raise InputError(f"expected a length tolerance in (0, 1) m, got {tolerance!r}", field="tolerance")
        if after_impact not in AFTER_IMPACT:
            raise InputError(f"expected 'keep' or 'equilibrium', got {after_impact!r}", field="after_impact")
        self.locate = locate
        self.tolerance = float(tolerance)
        self.after_impact = after_impact

    def impulses(self, W: np.ndarray, b: np.ndarray) -> np.ndarray:
        return newton_impulses(W, b, self.restitution)
