"""Small helpers for text the user reads."""

from __future__ import annotations


def plural(n: int, word: str, words: str | None = None) -> str:
    """``'1 storey'``, ``'3 storeys'``, ``'0 impacts'`` (``words``: an irregular plural)."""
    return f"{n} {word if n == 1 else (words or word + 's')}"
