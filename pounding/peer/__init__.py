"""Peer codes used to validate and benchmark pounding (optional dependencies)."""
