"""The installed package's version, read from its metadata when asked (not at import: reading it costs
tens of milliseconds that every command would pay at start-up)."""

from __future__ import annotations


def package_version() -> str:
    """The version of the installed ``pounding`` distribution ("0.0.0+src" for a source tree that is not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("pounding")
    except PackageNotFoundError:
        return "0.0.0+src"
