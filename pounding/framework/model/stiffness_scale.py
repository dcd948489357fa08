"""How stiff each element of a building is, against the others: the units check of the model.

A section typed in mm (b = 500 for 0.5 m) makes a frame's lateral stiffness ~1e12 times what it
should be (I grows as b h^3), a modulus in kPa or MPa mixed with Pa 1e3-1e6 times. Real lateral
systems differ far less: a wall is 10-300 times as stiff as a frame. One element more than
:data:`STIFF_RATIO` times the median of its building's elements is therefore read as a unit slip:
the plausibility warning ``stiff_element`` says so for a valid scene, and
:func:`pounding.framework.model.assembly.check_stable` says so instead of "mechanism" when the
slip is large enough that the other elements' stiffness is lost to rounding beside it (the
building then has a near-zero eigenvalue, relative to its largest, for that reason alone).
"""

from __future__ import annotations

import numpy as np

#: element stiffness / the building's median above which a unit slip is suspected [-]
STIFF_RATIO = 1000.0
#: what is said about a suspected unit slip
LIKELY_CAUSE = "a section in mm instead of m, or E in kPa/MPa mixed with Pa?"


def element_stiffness(element) -> float:
    """A scalar lateral stiffness of an element [N/m]: the largest eigenvalue of its condensed matrix."""
    return float(np.linalg.eigvalsh(np.asarray(element.lateral_stiffness(), float))[-1])


def outliers(building) -> list[tuple[int, float, float]]:
    """Elements far stiffer than the building's others: ``[(index, stiffness [N/m], median [N/m])]``.

    Elements without stiffness (dampers) are left out. Empty with fewer than three elements (no median to stand against) or none above
    :data:`STIFF_RATIO` times the median. An isolation layer's lines
    (:func:`pounding.framework.model.isolation.isolator_lines`) are left out: isolators are soft by
    design, often 1000 times softer than the walls they carry, and would make those look like slips.
    """
    from pounding.framework.model.isolation import isolator_lines

    isolators = set(isolator_lines(building))
    index = [i for i in range(len(building.elements)) if i not in isolators]
    k = np.array([element_stiffness(building.elements[i]) for i in index])
    index, k = [i for i, ki in zip(index, k) if ki > 0.0], k[k > 0.0]  # dampers have no stiffness to compare
    if len(index) < 3:
        return []
    med = float(np.median(k))
    return [(i, float(ki), med) for i, ki in zip(index, k) if med > 0 and ki > STIFF_RATIO * med]


def describe(building, index: int, k: float, med: float) -> str:
    """One line naming the element, its stiffness against the median and the likely unit slip."""
    e = building.elements[index]
    return (f"building {building.name!r} element[{index}] ({e.name}): lateral stiffness {k:.3g} N/m is {k / med:.3g}x the "
            f"median of the building's elements ({med:.3g} N/m): {LIKELY_CAUSE}")
