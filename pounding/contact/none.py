"""No contact: the buildings pass through each other (for reference runs)."""

from __future__ import annotations

from typing import ClassVar

from pounding.contact.base import ContactLaw


class NoContact(ContactLaw):
    """Ignore contact altogether: no slab pair is watched, no contact code is loaded.

    Parameters
    ----------
    restitution : float
        Accepted (as by every contact law, so that ``[analysis] restitution`` may stay in a scene) and unused.
    """

    name: ClassVar[str] = "none"
    kind: ClassVar[str] = "none"
