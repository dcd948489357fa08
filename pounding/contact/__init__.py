"""Contact geometry and contact laws (plugin family pounding.contact)."""
