"""Which elements of a building are its isolation layer.

A base-isolated building is its isolators in storey 1, between the ground and the base slab (floor
1), and a superstructure that stands on the base slab (elements with ``first_storey = 2``). The
layer is recognised from what the elements declare, never from their type: storey 1 is an
isolation layer when every element acting in it is a line of storey springs
(:attr:`~pounding.elements.base.PlanarElement.spring_line`) spanning that storey alone, and some
element stands on floor 1. The plausibility checks leave its low stiffness alone and the run's
summary reports the isolators per line (:mod:`pounding.framework.post.isolators`).
"""

from __future__ import annotations


def isolator_lines(building) -> tuple[int, ...]:
    """Indices (0-based, scene order) of the elements forming the isolation layer of ``building``
    (a scene :class:`~pounding.framework.model.scene.Building`); empty when it has none (see the
    module docstring)."""
    in_storey_1 = [i for i, e in enumerate(building.elements) if 1 in e.building_floors]
    lines = all(building.elements[i].spring_line and len(building.elements[i].floors) == 1 for i in in_storey_1)
    stands_on_it = any(e.base_floor == 1 for e in building.elements)
    return tuple(in_storey_1) if building.n_storeys > 1 and in_storey_1 and lines and stands_on_it else ()


def isolation_layer(building) -> bool:
    """True when storey 1 of ``building`` is an isolation layer (:func:`isolator_lines` is not empty)."""
    return bool(isolator_lines(building))
