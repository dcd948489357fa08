"""An OpenSeesPy stand-in that writes the commands it is given as lines of a Python script.

The peer builders of :mod:`pounding.peer.opensees` take the ``openseespy.opensees`` module as
an argument and only call its model-building commands (``node``, ``fix``, ``element``,
``rigidDiaphragm``, ``uniaxialMaterial``, ``timeSeries``, ``pattern``, ``rayleigh``,
``region``...). Given a :class:`ScriptOps` instead, the same builders write those commands
down, so the model a user runs from ``pounding export opensees`` is, command for command, the
model the cross-check tests build in memory: one description, two uses.

Floats are written with ``repr`` (the shortest text that reads back to the same double), so the
script's model holds the same numbers bit for bit. Long runs of numbers (a record's time and
acceleration samples, not tags) are written once as a named list and spread into the command (``*name``).
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

#: A run of more numbers than this becomes a named list above the command that uses it.
LONG_RUN = 12


class ScriptOps:
    """Records OpenSeesPy commands as Python source (the builders' ``ops`` argument).

    Only commands that build a model can be recorded: a query (``nodeDisp``, ``eigen``,
    ``analyze``...) has no value to return here, so asking one raises ``AttributeError``.

    Attributes
    ----------
    lines : list of str
        The recorded statements, in order, each calling ``ops.<command>(...)``.
    data : list of (str, list of float)
        The named lists the statements spread (``*name``), in order of first use.
    """

    #: commands whose result a builder would read: not recordable
    QUERIES = frozenset({"nodeDisp", "nodeVel", "nodeAccel", "eleResponse", "eigen", "analyze", "getNodeTags",
                         "getEleTags", "testIter", "nodeCoord", "getTime", "nodeReaction", "basicForce"})

    def __init__(self, name: str = "ops"):
        self.name = name
        self.lines: list[str] = []
        self.data: list[tuple[str, list[float]]] = []

    def __getattr__(self, command: str):
        if command.startswith("_") or command in self.QUERIES:
            raise AttributeError(f"{command!r} is not a model-building command: a script recorder cannot answer it")

        def record(*args: Any) -> None:
            self.lines.append(f"{self.name}.{command}({self._arguments(args)})")

        return record

    def comment(self, text: str) -> None:
        """Add a comment line (``# text``) at this point of the script."""
        self.lines.extend(f"# {line}".rstrip() for line in text.splitlines())

    def _arguments(self, args: tuple) -> str:
        out, run = [], []
        for a in args:
            if _is_number(a):
                run.append(_plain(a))
                continue
            out.extend(self._spread(run))
            run = []
            out.append(repr(a))
        out.extend(self._spread(run))
        return ", ".join(out)

    def _spread(self, run: list) -> list[str]:
        if len(run) <= LONG_RUN or all(isinstance(x, int) for x in run):  # tags stay in the command, readable
            return [repr(x) for x in run]
        for name, values in self.data:  # the same samples twice (a record along x and y): one list
            if values == run:
                return [f"*{name}"]
        name = f"data_{len(self.data) + 1}"
        self.data.append((name, list(run)))
        return [f"*{name}"]

    def source(self, indent: str = "") -> str:
        """The recorded statements as source, one per line, each prefixed by ``indent``."""
        return "\n".join(indent + line for line in self.lines)

    def data_source(self, per_line: int = 6) -> str:
        """The named lists as module-level assignments (``per_line`` numbers a line)."""
        blocks = []
        for name, values in self.data:
            rows = [", ".join(repr(v) for v in values[i:i + per_line]) for i in range(0, len(values), per_line)]
            blocks.append(f"{name} = [\n" + "".join(f"    {row},\n" for row in rows) + "]")
        return "\n".join(blocks)


def _is_number(a: Any) -> bool:
    # bool is an int subclass but is never a tag nor a coordinate
    return isinstance(a, (numbers.Integral, numbers.Real)) and not isinstance(a, (bool, np.bool_))


def _plain(a: Any) -> int | float:
    """A Python int or float (numpy scalars' repr names their type; the script needs the bare number)."""
    return int(a) if isinstance(a, numbers.Integral) else float(a)
