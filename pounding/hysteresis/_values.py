"""Checks of the scene parameters the link laws share (finite numbers in their valid ranges)."""

from __future__ import annotations

import math

from pounding.errors import InputError
from pounding.framework.model.law_tables import number, positive
from pounding.hysteresis.base import HysteresisLaw

#: (number and positive are the scene tables' checks, pounding.framework.model.law_tables, named here for the laws)
__all__ = ["EXPONENT_SCHEMA", "NoYieldLaw", "check_exponent", "number", "positive"]

#: the scene schema of a damper's velocity exponent (viscous, maxwell, kelvin)
EXPONENT_SCHEMA = {"type": "number", "units": "-", "default": 1.0, "description": "Velocity exponent alpha, in (0, 2]: 1 = linear."}


class NoYieldLaw(HysteresisLaw):
    """A link law with no deformation at which its behaviour changes (a linear spring, a dashpot):
    ``deformation_scale`` is inf, so the engine scales its Newton tolerance by the storey height."""

    @staticmethod
    def deformation_scale(params) -> float:
        """inf: no yield deformation."""
        return math.inf


def check_exponent(key: str, value) -> float:
    """A damper's velocity exponent alpha in (0, 2] (1: linear; 0.2-1 for fluid viscous dampers)."""
    x = number(key, value)
    if not 0.0 < x <= 2.0:
        raise InputError(f"the velocity exponent must be in (0, 2] (1 = a linear dashpot), got {x:g}", field=key)
    return x
