"""A link law from its scene table: the parameters and checks the link laws' tables share.

A law of the ``pounding.hysteresis`` family is named in a scene by a table ``{ name = ..., ... }``
(a storey spring's ``hysteresis``, a ``[[link]]``'s ``law``, the ``material`` contact law's
``material``): :func:`make_law` builds it from its own parameters, :func:`link_law` with the initial
stiffness, yield force and hardening a law that does not set them itself takes beside them, and
:func:`number` and :func:`positive` are the checks every law's parameters use. Each raises
:class:`~pounding.errors.InputError` naming the key.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from pounding.errors import InputError

#: the keys of a yielding law's table that the link gives it (a storey_springs element's own keys)
SPRING_KEYS = ("stiffness", "yield_force", "hardening")


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


def make_law(law_cls, params: Mapping[str, Any], field: str):
    """An instance of a hysteresis law from its scene parameters (InputError naming ``field.key``)."""
    import inspect

    try:
        return law_cls(**params)
    except TypeError:
        sig = inspect.signature(law_cls.__init__)
        accepted = [p for p in sig.parameters if sig.parameters[p].kind is inspect.Parameter.KEYWORD_ONLY]
        bad = [k for k in params if k not in accepted]
        missing = [p for p in accepted if sig.parameters[p].default is inspect.Parameter.empty and p not in params]
        if missing and not bad:
            raise InputError(f"hysteresis {law_cls.name!r} needs {', '.join(missing)}: give "
                             f"{{ name = {law_cls.name!r}, {', '.join(m + ' = ...' for m in missing)} }}", field=field) from None
        raise InputError(
            f"unknown parameter(s) {', '.join(bad) or '?'} for hysteresis {law_cls.name!r}; accepted: {', '.join(accepted) or 'none'}",
            field=field,
        ) from None
    except InputError as exc:
        raise exc.located(field_prefix=field) from None


def link_law(spec: Mapping, where: str):
    """(law instance, parameter vector (n_params,)) of a link's ``law`` table; InputError naming ``where.key``.

    A law that sets its stiffness, yield force and hardening from its own parameters (``own_values``:
    elastic, viscous, maxwell, kelvin, friction_pendulum) takes only those; any other (bilinear,
    bouc_wen, a plugin's) takes ``stiffness`` [N/m] > 0, ``yield_force`` [N] > 0 and ``hardening`` in
    [0, 1) besides its own.
    """
    from pounding.framework.model.registry import HYSTERESIS

    params = {k: v for k, v in spec.items() if k != "name"}
    cls = HYSTERESIS.get(spec["name"], field=f"{where}.name")
    takes = _own_keys(cls)
    own = {k: v for k, v in params.items() if k in takes or k not in SPRING_KEYS}
    probe = make_law(cls, own, where)
    if probe.own_values() is not None:
        extra = [k for k in params if k not in own]
        if extra:
            raise InputError(f"the {cls.name} law sets the link's {extra[0]} from its own parameters; remove {extra[0]}",
                             field=f"{where}.{extra[0]}")
        return probe, np.asarray(probe.pack(*probe.own_values()), dtype=float)
    for key in ("stiffness", "yield_force"):
        if key not in params:
            raise InputError(f"hysteresis {cls.name!r} on a link needs stiffness [N/m] and yield_force [N]: give "
                             f"{{ name = {cls.name!r}, stiffness = ..., yield_force = ..., hardening = ... }}", field=where)
    k0 = positive(f"{where}.stiffness", params["stiffness"], "the link's initial stiffness [N/m]")
    fy = positive(f"{where}.yield_force", params["yield_force"], "the link's yield force [N]")
    b = number(f"{where}.hardening", params.get("hardening", 0.0))
    if not 0.0 <= b < 1.0:
        raise InputError(f"expected the post-yield / initial stiffness ratio in [0, 1), got {b:g}", field=f"{where}.hardening")
    return probe, np.asarray(probe.pack(k0, fy, b), dtype=float)


def _own_keys(cls) -> set:
    """The keyword parameters of the law class's ``__init__`` (its own scene parameters)."""
    import inspect

    return set(inspect.signature(cls.__init__).parameters) - {"self"}
