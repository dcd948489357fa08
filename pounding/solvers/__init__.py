"""Time integrators (plugin family ``pounding.integrators``)."""
