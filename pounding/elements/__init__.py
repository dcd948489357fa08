"""Planar lateral-load-resisting elements (plugin family ``pounding.elements``)."""
