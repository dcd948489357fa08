"""The names the commands' help texts list, taken from the registries the code looks them up in.

A help text built from these cannot list a name the code refuses nor leave out one it accepts
(tests/test_docs.py checks each against what the code accepts). Only light modules are imported
here: every ``pounding`` command builds the whole parser, so ``pounding run`` pays for them.
"""

from __future__ import annotations

#: named record sets that ``--records`` takes (:data:`pounding.io.records.RECORD_SETS`, which
#: imports numpy; tests/test_docs.py checks the two agree)
RECORD_SETS = ("fema-p695:farfield",)


def _names(registry) -> str:
    return ", ".join(registry.builtin_names())


def integrators() -> str:
    """The built-in integrators, comma-separated (a plugin adds its own name)."""
    from pounding.framework.model.registry import INTEGRATORS

    return _names(INTEGRATORS)


def elements() -> str:
    """The built-in element types, comma-separated."""
    from pounding.framework.model.registry import ELEMENTS

    return _names(ELEMENTS)


def intensity_measures() -> str:
    """What fragility's ``--im`` accepts, with units."""
    from pounding.framework.studies.fragility_inputs import INTENSITY_MEASURES, SPECTRAL

    plain = ", ".join(f"{name} [{unit}]" for name, (_, unit) in INTENSITY_MEASURES.items())
    first = next(iter(SPECTRAL))
    return (f"{plain}; or a 5 %-damped spectral acceleration [g], {', '.join(SPECTRAL)}, at the first period of the "
            f"taller building, or at T seconds as NAME:T (e.g. {first}:1.0)")
