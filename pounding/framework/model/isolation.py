"""Which elements of a building are its isolation layer.

A base-isolated building is its isolators in storey 1, between the ground and the base slab (floor
1), and a superstructure that stands on the base slab (elements with ``first_storey = 2``). The
layer is recognised from what the elements declare, never from their type: storey 1 is an
isolation layer when every element acting in it is a line of storey springs
(:attr:`~pounding.elements.base.PlanarElement.spring_line`) spanning that storey alone, and some
element stands on floor 1. Its isolators are those lines that have a stiffness; lines without one
(dampers beside the isolators) are part of the layer but not isolators. The plausibility checks leave its low stiffness alone and the run's
summary reports the isolators per line (:mod:`pounding.framework.post.isolators`).
"""

from __future__ import annotations

import numpy as np


def isolator_lines(building) -> tuple[int, ...]:
    """Indices (0-based, scene order) of the elements forming the isolation layer of ``building``
    (a scene :class:`~pounding.framework.model.scene.Building`); empty when it has none (see the
    module docstring)."""
    in_storey_1 = [i for i, e in enumerate(building.elements) if 1 in e.building_floors]
    lines = all(building.elements[i].spring_line and len(building.elements[i].floors) == 1 for i in in_storey_1)
    stands_on_it = any(e.base_floor == 1 for e in building.elements)
    # lines with no stiffness (dampers beside the isolators) belong to the layer but are not isolators
    isolators = tuple(i for i in in_storey_1 if np.any(np.asarray(building.elements[i].lateral_stiffness()) != 0.0))
    return isolators if building.n_storeys > 1 and isolators and lines and stands_on_it else ()


def isolation_layer(building) -> bool:
    """True when storey 1 of ``building`` is an isolation layer (:func:`isolator_lines` is not empty)."""
    return bool(isolator_lines(building))
