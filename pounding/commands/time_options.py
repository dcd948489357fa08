"""The ``--dt`` / ``--duration`` options that every command running an analysis takes."""

from __future__ import annotations

from pounding.errors import InputError


def time_overrides(args) -> dict:
    """The --dt / --duration options of a command as Analysis overrides (checked positive)."""
    overrides = {}
    for key in ("dt", "duration"):
        val = getattr(args, key, None)
        if val is not None:
            if not val > 0:
                raise InputError(f"expected a positive number, got {val}", field=f"--{key}")
            overrides[key] = val
    return overrides
