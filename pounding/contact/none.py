"""No contact: the buildings pass through each other (for reference runs)."""

from __future__ import annotations

from typing import ClassVar

from pounding.contact.base import ContactLaw


class NoContact(ContactLaw):
    """Ignore contact altogether; no geometry is checked."""

    name: ClassVar[str] = "none"
    kind: ClassVar[str] = "none"
