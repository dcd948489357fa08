"""Hysteresis laws of yielding springs (plugin family ``pounding.hysteresis``)."""
