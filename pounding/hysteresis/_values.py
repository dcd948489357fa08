"""Checks of the scene parameters the link laws share (finite numbers in their valid ranges)."""

from __future__ import annotations

import math

import numpy as np

from pounding.errors import InputError


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
