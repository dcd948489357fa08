"""Checks of the scene parameters the link laws share (finite numbers in their valid ranges)."""

from __future__ import annotations

import math

import numpy as np

from pounding.errors import InputError
from pounding.hysteresis.base import HysteresisLaw

#: the scene schema of a damper's velocity exponent (viscous, maxwell, kelvin)
EXPONENT_SCHEMA = {"type": "number", "units": "-", "default": 1.0, "description": "Velocity exponent alpha, in (0, 2]: 1 = linear."}


class NoYieldLaw(HysteresisLaw):
    """A link law with no deformation at which its behaviour changes (a linear spring, a dashpot):
    ``deformation_scale`` is inf, so the engine scales its Newton tolerance by the storey height."""

    @staticmethod
    def deformation_scale(params) -> float:
        """inf: no yield deformation."""
        return math.inf


def number(key: str, value) -> float:
    """``value`` as a float, or InputError naming ``key`` when it is not a finite number."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value!r}", field=key)
    return float(value)


def positive(key: str, value, what: str) -> float:
    """``value`` > 0 as a float (InputError naming ``key`` and saying what it is otherwise)."""
    x = number(key, value)
    if x <= 0.0:
        raise InputError(f"{what} must be > 0, got {x:g}", field=key)
    return x


def check_exponent(key: str, value) -> float:
    """A damper's velocity exponent alpha in (0, 2] (1: linear; 0.2-1 for fluid viscous dampers)."""
    x = number(key, value)
    if not 0.0 < x <= 2.0:
        raise InputError(f"the velocity exponent must be in (0, 2] (1 = a linear dashpot), got {x:g}", field=key)
    return x
