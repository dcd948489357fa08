"""Exceptions that reach the user.

An :class:`InputError` names the file, the field (a TOML key path such as
``building[1].element[0].columns``) and what was expected. The command line
prints it on one line and exits with code 2, without a traceback.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad user input: a scene, a record, or a command-line value.

    Parameters
    ----------
    message : str
        What is wrong and what was expected.
    file : str, optional
        The file the value came from.
    field : str, optional
        The key path of the value inside that file.
    """

    def __init__(self, message: str, *, file: str | None = None, field: str | None = None):
        self.message = message
        self.file = None if file is None else str(file)
        self.field = field
        super().__init__(self.__str__())

    def __str__(self) -> str:
        where = []
        if self.file:
            where.append(self.file)
        if self.field:
            where.append(self.field)
        prefix = ": ".join(where)
        return f"{prefix}: {self.message}" if prefix else self.message

    def located(self, *, file: str | None = None, field_prefix: str | None = None) -> "InputError":
        """A copy with the file set and the field prefixed (used while parsing nested tables)."""
        field = self.field
        if field_prefix:
            field = field_prefix if not field else f"{field_prefix}.{field}"
        return InputError(self.message, file=file or self.file, field=field)


class AnalysisWarning(UserWarning):
    """A run finished but something deserves attention (energy balance, clipping...)."""


class PlausibilityWarning(AnalysisWarning):
    """A valid scene with numbers unlikely for a real building (see :mod:`pounding.framework.post.plausibility`)."""
