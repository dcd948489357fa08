"""Ground-motion records: the built-in El Centro record, AT2 and column files.

A :class:`GroundMotion` is one horizontal component of ground acceleration,
``acc(t)`` in m/s^2, acting in the plan direction ``angle`` (degrees,
counter-clockwise from the global x axis towards y). All records are converted
to SI on reading; ``G`` below is the only value of g in the package.

Scenes reach this module through :func:`load_record`, which takes the
``[ground_motion]`` table of a scene file::

    [ground_motion]
    record = "elcentro"        # built-in, or a path relative to the scene file
    format = "auto"            # "auto" | "at2" | "single_column" | "two_columns"
    dt     = 0.01              # s; single-column files only
    units  = "g"               # "g" | "m/s2" | "m/s^2" | "cm/s2" | "cm/s^2"
    pga    = 0.32              # target peak |acc| in g (or: scale = 1.5)
    angle  = 0.0               # degrees from the global x axis

Errors are :class:`~pounding.errors.InputError`: problems with a key name the
scene file and ``ground_motion.<key>``; problems inside a record file name the
record file and the line (``line 7``) or header item (``NPTS``, ``DT``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.units import G  # standard gravity [m/s2]

__all__ = [
    "G",
    "GroundMotion",
    "read_at2",
    "read_single_column",
    "read_two_columns",
    "load_record",
    "BUILTIN_RECORDS",
]

#: Names accepted as ``record`` for the records shipped in ``pounding/io/data``.
BUILTIN_RECORDS = {"elcentro": "elcentro_1940_ns.at2"}

#: Unit name -> factor to m/s^2.
UNITS = {"g": G, "m/s2": 1.0, "m/s^2": 1.0, "cm/s2": 0.01, "cm/s^2": 0.01}

FORMATS = ("auto", "at2", "single_column", "two_columns")

#: Keys of the ``[ground_motion]`` table, in the order they are documented.
SPEC_KEYS = ("record", "format", "dt", "units", "pga", "scale", "angle")

# A sample interval counts as uniform if every step is within this fraction
# of the mean step: two-column files print times with few decimals, so their
# steps differ by parsing round-off (~1e-15 relative) but not by more.
_UNIFORM_RTOL = 1e-6


# --------------------------------------------------------------------------
# The record
# --------------------------------------------------------------------------


@dataclass(frozen=True, eq=False, repr=False)
class GroundMotion:
    """One horizontal component of ground acceleration.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s], strictly increasing, ``t[0] >= 0``, n >= 2.
    acc : array_like, shape (n,)
        Ground acceleration at ``t`` [m/s^2], finite.
    name : str
        Short label (file stem, or ``"elcentro"``).
    source : str
        Where the samples came from: a file path or ``"builtin:elcentro"``.
    angle : float
        Plan direction of shaking [degrees], counter-clockwise from the global
        x axis (90 = along +y).

    Notes
    -----
    The arrays are stored as read-only float64 copies, so a motion can be
    shared between runs without one run changing another's input.
    Instances compare by identity (``eq=False``): element-wise array equality
    has no single truth value.
    """

    t: np.ndarray
    acc: np.ndarray
    name: str = ""
    source: str = ""
    angle: float = 0.0

    def __post_init__(self) -> None:
        where = self.source or None
        t = _frozen_vector(self.t, "t", where)
        acc = _frozen_vector(self.acc, "acc", where)
        if acc.shape != t.shape:
            raise InputError(
                f"acc has {acc.size} samples but t has {t.size}; expected one acceleration per time",
                file=where, field="acc")
        if t.size < 2:
            raise InputError(f"a record needs at least 2 samples, got {t.size}", file=where, field="t")
        if t[0] < 0.0:
            raise InputError(f"starts at t = {t[0]:g} s; expected t >= 0", file=where, field="t")
        steps = np.diff(t)
        if np.any(steps <= 0.0):
            i = int(np.argmax(steps <= 0.0))
            raise InputError(
                f"times must be strictly increasing: t[{i + 1}] = {t[i + 1]:g} s "
                f"after t[{i}] = {t[i]:g} s", file=where, field="t")
        angle = _finite_number(self.angle, "angle", where)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "acc", acc)
        object.__setattr__(self, "angle", angle)
        object.__setattr__(self, "name", str(self.name))
        object.__setattr__(self, "source", str(self.source))

    def __repr__(self) -> str:
        # The default dataclass repr would print thousands of samples.
        dt = "non-uniform" if self.dt is None else f"{self.dt:g} s"
        return (f"GroundMotion(name={self.name!r}, n={self.t.size}, dt={dt}, "
                f"duration={self.duration:g} s, pga={self.pga / G:.5g} g, "
                f"angle={self.angle:g} deg, source={self.source!r})")

    # -- properties ---------------------------------------------------------

    @cached_property
    def dt(self) -> float | None:
        """Sample interval [s] if the samples are uniformly spaced, else None.

        Uniform means every step is within 1e-6 of the mean step (relative);
        the mean step ``(t[-1] - t[0]) / (n - 1)`` is returned.
        """
        steps = np.diff(self.t)
        mean = (self.t[-1] - self.t[0]) / (self.t.size - 1)
        if np.max(np.abs(steps - mean)) <= _UNIFORM_RTOL * mean:
            return float(mean)
        return None

    @property
    def duration(self) -> float:
        """End time of the record, ``t[-1]`` [s] (not ``t[-1] - t[0]``)."""
        return float(self.t[-1])

    @property
    def pga(self) -> float:
        """Peak ground acceleration, ``max |acc|`` [m/s^2]."""
        return float(np.max(np.abs(self.acc)))

    # -- methods ------------------------------------------------------------

    def direction(self) -> np.ndarray:
        """Unit vector of the shaking direction in plan.

        Returns
        -------
        ndarray, shape (2,)
            ``(cos angle, sin angle)`` in global (x, y). Multiples of 90
            degrees give exact 0/±1, so a motion along y puts exactly nothing
            on the x degrees of freedom.
        """
        quarter, rest = divmod(self.angle, 90.0)
        if rest == 0.0:
            return np.array(((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4])
        a = math.radians(self.angle)
        return np.array((math.cos(a), math.sin(a)))

    @property
    def components(self) -> tuple["GroundMotion"]:
        """The components of the motion: this one record (see :class:`~pounding.io.motion_pair.GroundMotionPair`)."""
        return (self,)

    def directions(self) -> np.ndarray:
        """Plan unit vector of every component, shape (c, 2) = (1, 2): ``direction()[None]``."""
        return self.direction()[None, :]

    def piecewise_linear(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(times (m,) [s], accelerations (m, c) [m/s^2]) whose linear interpolation, zero outside the
        record, :meth:`samples` is; the engine then interpolates the record in its compiled search with
        the same arithmetic. A subclass whose ``samples`` is anything else returns None."""
        return self.t, np.asarray(self.acc, dtype=float).reshape(len(self.t), -1)

    def samples(self, times: Any) -> np.ndarray:
        """Acceleration of every component at ``times`` [m/s^2]: shape (m, 1), or (1,) for a scalar time.

        The values are those of :meth:`at`; the component axis is what the analysis
        stacks the modal load over (``p = -L @ ag``, L (n, c)).
        """
        out = np.interp(times, self.t, self.acc, left=0.0, right=0.0)
        return np.reshape(out, np.shape(out) + (1,))

    def at(self, times: Any) -> np.ndarray | float:
        """Ground acceleration at arbitrary times, by linear interpolation.

        Parameters
        ----------
        times : float or array_like, shape (m,)
            Times [s].

        Returns
        -------
        float or ndarray, shape (m,)
            Acceleration [m/s^2]; exact at the sample times. Zero before
            ``t[0]`` and after ``t[-1]``: the ground is at rest before the
            record starts and after it ends, so an analysis may run past the
            record to watch the free vibration.
        """
        out = np.interp(times, self.t, self.acc, left=0.0, right=0.0)
        return float(out) if np.ndim(out) == 0 else out

    def scaled(self, factor: float) -> "GroundMotion":
        """A copy with every acceleration multiplied by ``factor`` (> 0, finite)."""
        factor = _finite_number(factor, "scale", self.source or None)
        if factor <= 0.0:
            raise InputError(f"scale factor must be > 0, got {factor:g}", file=self.source or None,
                             field="scale")
        return replace(self, acc=self.acc * factor)

    def scaled_to_pga(self, pga_g: float) -> "GroundMotion":
        """A copy scaled so that its peak ``|acc|`` is ``pga_g * G``.

        Parameters
        ----------
        pga_g : float
            Target peak ground acceleration [g], > 0.
        """
        pga_g = _finite_number(pga_g, "pga", self.source or None)
        if pga_g <= 0.0:
            raise InputError(f"target PGA must be > 0 g, got {pga_g:g}", file=self.source or None,
                             field="pga")
        if self.pga == 0.0:
            raise InputError("the record is all zeros and cannot be scaled to a PGA",
                             file=self.source or None, field="pga")
        return replace(self, acc=self.acc * (pga_g * G / self.pga))

    def with_angle(self, angle: float) -> "GroundMotion":
        """A copy shaking along ``angle`` degrees from x (the incidence angle; same samples)."""
        return replace(self, angle=_finite_number(angle, "angle", self.source or None))

    def rotated(self, angle: float) -> "GroundMotion":
        """A copy whose direction is turned by ``angle`` degrees (counter-clockwise).

        ``m.rotated(90)`` of a motion along x shakes along y. The result's
        ``angle`` is ``self.angle + angle``, not reduced modulo 360.
        """
        return replace(self, angle=self.angle + _finite_number(angle, "angle", self.source or None))


# --------------------------------------------------------------------------
# Readers
# --------------------------------------------------------------------------

# "NPTS=   5372, DT=   .0100 SEC," (NGA-West2) and "NPTS=  1559, DT= .02000 SEC" (PEER 2000).
_NPTS_RE = re.compile(r"\bNPTS\s*=\s*([^\s,]+)", re.IGNORECASE)
_DT_RE = re.compile(r"\bDT\s*=\s*([^\s,]+)", re.IGNORECASE)
# The older NGA layout: "  4000    .0100    NPTS, DT".
_NPTS_DT_OLD_RE = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT\b", re.IGNORECASE)

_UNIT_G_RE = re.compile(r"\bUNITS?\s+(?:OF\s+|IN\s+|=\s*|:\s*)?G\b|\bIN\s+G\b|\(G\)", re.IGNORECASE)
_UNIT_SI_RE = re.compile(
    r"(?<![A-Z])(CM|M)\s*/\s*(?:S|SEC)\s*(?:/\s*(?:S|SEC)|\^\s*2|\*\*\s*2|2|²)(?![A-Z0-9])",
    re.IGNORECASE)


def read_at2(path: str | Path) -> GroundMotion:
    """Read a PEER acceleration record (.AT2, NGA-West2 or PEER 2000 layout).

    Parameters
    ----------
    path : str or Path
        The record file: 4 header lines (title; event, station, component;
        units line; ``NPTS=..., DT=... SEC``), then NPTS accelerations written
        row by row, first sample at t = 0.

    Returns
    -------
    GroundMotion
        ``t = arange(NPTS) * DT`` [s], ``acc`` [m/s^2], ``angle = 0``.

    Raises
    ------
    InputError
        Naming the file and ``line 3`` (units not stated as G, m/s^2 or
        cm/s^2), ``NPTS`` / ``DT`` (missing or invalid, or a value count that
        differs from NPTS), or ``line N`` (a value that is not a finite number).
    """
    return _read_at2(path)[0]


def _read_at2(path: str | Path) -> tuple[GroundMotion, str]:
    """:func:`read_at2`, also returning the header's unit name (a key of ``UNITS``)."""
    path = Path(path)
    lines = _read_lines(path)
    if len(lines) < 4:
        raise InputError(
            f"AT2 file has {len(lines)} line(s); expected 4 header lines (title, event, "
            "units, 'NPTS=..., DT=... SEC') followed by the accelerations",
            file=path, field=f"line {len(lines) + 1}")
    unit = _at2_units(lines[2], path)
    npts, dt = _at2_npts_dt(lines[3], path)
    values = _parse_values(lines[4:], first_line=5, path=path)
    if values.size != npts:
        raise InputError(f"header says NPTS = {npts} but the file holds {values.size} values",
                         file=path, field="NPTS")
    motion = GroundMotion(t=np.arange(npts) * dt, acc=values * UNITS[unit], name=path.stem,
                          source=str(path))
    return motion, unit


def read_single_column(path: str | Path, dt: float, units: str = "g") -> GroundMotion:
    """Read one acceleration per line, sampled every ``dt`` from t = 0.

    Parameters
    ----------
    path : str or Path
        Text file; leading lines whose first word is not a number (a header)
        are skipped, as are blank lines and lines starting with ``#``.
    dt : float
        Sample interval [s], > 0.
    units : str
        Units of the values: ``"g"`` (default), ``"m/s2"``/``"m/s^2"`` or
        ``"cm/s2"``/``"cm/s^2"``.

    Returns
    -------
    GroundMotion
        ``t = arange(n) * dt`` [s], ``acc`` [m/s^2].
    """
    path = Path(path)
    dt = _positive_number(dt, "dt", path)
    factor = _unit_factor(units, path, "units")
    rows = _numeric_rows(path, _read_lines(path))
    for lineno, row in rows:
        if len(row) != 1:
            raise InputError(f"expected one value per line (single-column record), found {len(row)}",
                             file=path, field=f"line {lineno}")
    acc = np.array([row[0] for _, row in rows])
    _check_finite(acc, [n for n, _ in rows], path, what="acceleration")
    return GroundMotion(t=np.arange(acc.size) * dt, acc=acc * factor, name=path.stem,
                        source=str(path))


def read_two_columns(path: str | Path, units: str = "g") -> GroundMotion:
    """Read ``time, acceleration`` pairs, one pair per line.

    Parameters
    ----------
    path : str or Path
        Text file, columns separated by whitespace or commas; leading lines
        whose first word is not a number (a header such as ``time,acc``) are
        skipped, as are blank lines and lines starting with ``#``.
    units : str
        Units of the accelerations (see :func:`read_single_column`); times are
        in seconds.

    Returns
    -------
    GroundMotion
        ``t`` [s] as in the file (strictly increasing, ``t[0] >= 0``; the
        spacing need not be uniform) and ``acc`` [m/s^2].
    """
    path = Path(path)
    factor = _unit_factor(units, path, "units")
    rows = _numeric_rows(path, _read_lines(path))
    for lineno, row in rows:
        if len(row) != 2:
            raise InputError(f"expected two values per line (time, acceleration), found {len(row)}",
                             file=path, field=f"line {lineno}")
    linenos = [n for n, _ in rows]
    data = np.array([row for _, row in rows])
    t, acc = data[:, 0], data[:, 1]
    _check_finite(t, linenos, path, what="time")
    _check_finite(acc, linenos, path, what="acceleration")
    if t[0] < 0.0:
        raise InputError(f"record starts at t = {t[0]:g} s; expected t >= 0", file=path,
                         field=f"line {linenos[0]}")
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise InputError(f"time {t[i]:g} s does not increase after {t[i - 1]:g} s; "
                         "expected strictly increasing times", file=path, field=f"line {linenos[i]}")
    return GroundMotion(t=t, acc=acc * factor, name=path.stem, source=str(path))


# --------------------------------------------------------------------------
# Scene entry point
# --------------------------------------------------------------------------


def load_record(spec: Mapping[str, Any], *, base_dir: str | Path | None = None,
                file: str | Path | None = None, section: str = "ground_motion") -> GroundMotion:
    """Build the ground motion described by a scene's ``[ground_motion]`` table.

    Parameters
    ----------
    spec : mapping
        Keys (all validated; others are rejected):

        ``record`` (str, required)
            ``"elcentro"`` for the packaged El Centro 1940 NS record (1560
            samples at 0.02 s, PGA 0.3188 g), or a path to a record file,
            relative to ``base_dir``.
        ``format`` (str, default ``"auto"``)
            ``"at2"``, ``"single_column"``, ``"two_columns"``, or ``"auto"``:
            a ``.at2`` extension (any case) means AT2, otherwise the number of
            values on the first data line decides (1 or 2).
        ``dt`` (float [s], > 0)
            Required for single-column files, rejected for the others (their
            times come from the file).
        ``units`` (str, default ``"g"``)
            Units of the file's accelerations: ``"g"``, ``"m/s2"``/``"m/s^2"``
            or ``"cm/s2"``/``"cm/s^2"``. AT2 files state their own units; if
            given, ``units`` must agree with the header.
        ``pga`` (float [g], > 0) or ``scale`` (float, > 0), optional, not both
            Scale the record to this peak ``|acc|``, or by this factor.
        ``angle`` (float [degrees], default 0)
            Plan direction of shaking, counter-clockwise from global x.
    base_dir : str or Path, optional
        Directory for relative record paths; default the directory of
        ``file``, else the current directory.
    file : str or Path, optional
        The scene file, named in errors about ``spec``.
    section : str
        Key path of the table, prefixed to field names in errors
        (``"ground_motion"`` -> ``"ground_motion.pga"``).

    Returns
    -------
    GroundMotion
        ``source`` is the record path, or ``"builtin:elcentro"``.

    Raises
    ------
    InputError
        For a bad key or value (naming ``file`` and ``section.key``) or a bad
        record file (naming the record file and the line or header item).
    """
    def fail(key: str, message: str) -> InputError:
        return InputError(message, file=file, field=f"{section}.{key}")

    if not isinstance(spec, Mapping):
        raise InputError(f"expected a table of {', '.join(SPEC_KEYS)}, got {type(spec).__name__}",
                         file=file, field=section)
    unknown = [k for k in spec if k not in SPEC_KEYS]
    if unknown:
        raise fail(str(unknown[0]), f"unknown key {unknown[0]!r}; accepted keys: {', '.join(SPEC_KEYS)}")

    fmt = _choice(spec.get("format", "auto"), FORMATS, fail, "format")
    units = spec.get("units")
    if units is not None:
        _unit_factor(units, file, f"{section}.units")
        units = units.strip().lower()
    dt = spec.get("dt")
    if dt is not None:
        dt = _positive_number(dt, f"{section}.dt", file)
    pga, scale = spec.get("pga"), spec.get("scale")
    if pga is not None and scale is not None:
        raise fail("scale", "give either pga (target peak, in g) or scale (a factor), not both")
    if pga is not None:
        pga = _positive_number(pga, f"{section}.pga", file)
    if scale is not None:
        scale = _positive_number(scale, f"{section}.scale", file)
    angle = _finite_number(spec.get("angle", 0.0), f"{section}.angle", file)

    motion = _read_record(spec, fmt, dt, units, base_dir, file, section, fail)
    if pga is not None:
        motion = motion.scaled_to_pga(pga)
    elif scale is not None:
        motion = motion.scaled(scale)
    return replace(motion, angle=angle)


def _read_record(spec, fmt, dt, units, base_dir, file, section, fail) -> GroundMotion:
    """Locate ``spec['record']`` and read it with the chosen format."""
    if "record" not in spec:
        raise fail("record", "missing; expected \"elcentro\" or the path of a record file")
    record = spec["record"]
    if not isinstance(record, str) or not record.strip():
        raise fail("record", f"expected \"elcentro\" or a file path (a non-empty string), got {record!r}")

    builtin = record.removeprefix("builtin:")
    if builtin in BUILTIN_RECORDS:
        if fmt not in ("auto", "at2"):
            raise fail("format", f"the built-in record {builtin!r} is an AT2 file; got format {fmt!r}")
        _reject_dt(dt, "AT2", fail)
        with resources.as_file(resources.files("pounding.io") / "data" / BUILTIN_RECORDS[builtin]) as p:
            motion, header_units = _read_at2(p)
        _check_at2_units(header_units, units, fail)
        return replace(motion, name=builtin, source=f"builtin:{builtin}")

    root = Path(base_dir) if base_dir is not None else (Path(file).parent if file else Path.cwd())
    path = Path(record).expanduser()
    path = path if path.is_absolute() else root / path
    if not path.is_file():
        raise fail("record", f"record file {str(path)!r} not found or not a file (built-in records: "
                             f"{', '.join(BUILTIN_RECORDS)})")

    if fmt == "auto":
        fmt = "at2" if path.suffix.lower() == ".at2" else _guess_columns(path)
    if fmt == "at2":
        _reject_dt(dt, "AT2", fail)
        motion, header_units = _read_at2(path)
        _check_at2_units(header_units, units, fail)
        return motion
    if fmt == "single_column":
        if dt is None:
            raise fail("dt", f"a single-column record needs the sample interval dt [s]; "
                             f"{path.name} has no time column")
        return read_single_column(path, dt, units or "g")
    _reject_dt(dt, "two-column", fail)
    return read_two_columns(path, units or "g")


def _reject_dt(dt, kind: str, fail) -> None:
    # Silently preferring one of two sample intervals would hide a mistake.
    if dt is not None:
        raise fail("dt", f"dt is only for single-column records; this {kind} record gives its own times")


def _check_at2_units(header: str, units: str | None, fail) -> None:
    """An AT2 header states its units; a differing ``units`` key is an error."""
    if units is not None and UNITS[units] != UNITS[header]:
        raise fail("units", f"{units!r} disagrees with the AT2 header, which says {header!r}; "
                            "remove the key or correct it")


def _guess_columns(path: Path) -> str:
    """``"single_column"`` or ``"two_columns"`` from the first data line of ``path``."""
    rows = _numeric_rows(path, _read_lines(path))
    lineno, row = rows[0]
    if len(row) == 1:
        return "single_column"
    if len(row) == 2:
        return "two_columns"
    raise InputError(f"cannot tell the format: {len(row)} values on the first data line; expected 1 "
                     "(accelerations, with dt) or 2 (time, acceleration), or set format", file=path,
                     field=f"line {lineno}")


# --------------------------------------------------------------------------
# Helpers: file text
# --------------------------------------------------------------------------


def _read_lines(path: Path) -> list[str]:
    """The lines of a text file (any line ending), or InputError if unreadable."""
    try:
        # latin-1 never fails to decode, so a stray byte in a title line does
        # not stop the read; the numbers are plain ASCII either way.
        text = path.read_text(encoding="latin-1")
    except FileNotFoundError:
        raise InputError("record file not found", file=path, field="record") from None
    except OSError as exc:
        raise InputError(f"cannot read the record file: {exc.strerror or exc}", file=path,
                         field="record") from None
    return text.splitlines()


def _to_float(token: str) -> float:
    """Parse one number; accepts Fortran ``D`` exponents (``.1D-02``)."""
    try:
        return float(token)
    except ValueError:
        return float(token.replace("D", "E").replace("d", "e"))


def _parse_values(lines: list[str], first_line: int, path: Path) -> np.ndarray:
    """All whitespace-separated numbers of ``lines``, row by row (AT2 body)."""
    values: list[float] = []
    for k, line in enumerate(lines):
        for token in line.split():
            try:
                v = _to_float(token)
            except ValueError:
                raise InputError(f"{token!r} is not a number; expected accelerations only",
                                 file=path, field=f"line {first_line + k}") from None
            if not math.isfinite(v):
                raise InputError(f"acceleration {token!r} is not finite", file=path,
                                 field=f"line {first_line + k}")
            values.append(v)
    return np.array(values, dtype=float)


def _numeric_rows(path: Path, lines: list[str]) -> list[tuple[int, list[float]]]:
    """Numeric rows of a column file as ``(1-based line number, values)``.

    Leading lines whose first token is not a number are a header and skipped;
    after the first data line every non-blank, non-``#`` line must be numbers.
    """
    rows: list[tuple[int, list[float]]] = []
    for lineno, line in enumerate(lines, start=1):
        tokens = line.replace(",", " ").replace(";", " ").split()
        if not tokens or tokens[0].startswith("#"):
            continue
        if not rows and not _is_number(tokens[0]):
            continue  # header line, e.g. "time,acc (g)"
        try:
            rows.append((lineno, [_to_float(tok) for tok in tokens]))
        except ValueError:
            bad = next(tok for tok in tokens if not _is_number(tok))
            raise InputError(f"{bad!r} is not a number", file=path, field=f"line {lineno}") from None
    if not rows:
        raise InputError("no numeric data; the file is empty or holds only text", file=path,
                         field=f"line {len(lines) + 1}")
    return rows


def _is_number(token: str) -> bool:
    try:
        _to_float(token)
    except ValueError:
        return False
    return True


def _check_finite(values: np.ndarray, linenos: list[int], path: Path, what: str) -> None:
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        i = int(bad[0])
        raise InputError(f"{what} {values[i]} is not finite", file=path, field=f"line {linenos[i]}")


def _at2_units(line: str, path: Path) -> str:
    """Unit name (a key of ``UNITS``) from an AT2 units line (line 3)."""
    upper = line.upper()
    if "ACCEL" not in upper and ("VELOC" in upper or "DISPL" in upper):
        raise InputError(f"units line {line.strip()!r} describes a velocity or displacement "
                         "record; expected an acceleration record (.AT2)", file=path, field="line 3")
    si = _UNIT_SI_RE.search(line)
    if si:
        return "cm/s^2" if si.group(1).upper() == "CM" else "m/s^2"
    if _UNIT_G_RE.search(line):
        return "g"
    raise InputError(f"units line {line.strip()!r} does not state the units; expected e.g. "
                     "'ACCELERATION TIME SERIES IN UNITS OF G' (or m/s^2, cm/s^2)",
                     file=path, field="line 3")


def _at2_npts_dt(line: str, path: Path) -> tuple[int, float]:
    """``(NPTS, DT [s])`` from an AT2 line 4, in either PEER layout."""
    old = _NPTS_DT_OLD_RE.match(line)
    npts_m, dt_m = _NPTS_RE.search(line), _DT_RE.search(line)
    npts_txt = old.group(1) if old else (npts_m.group(1) if npts_m else None)
    dt_txt = old.group(2) if old else (dt_m.group(1) if dt_m else None)
    expected = "expected e.g. 'NPTS=   5372, DT=   .0100 SEC'"
    if npts_txt is None:
        raise InputError(f"line 4 {line.strip()!r} has no NPTS; {expected}", file=path, field="NPTS")
    if dt_txt is None:
        raise InputError(f"line 4 {line.strip()!r} has no DT; {expected}", file=path, field="DT")
    try:
        npts = int(npts_txt)
    except ValueError:
        raise InputError(f"NPTS {npts_txt!r} is not a whole number", file=path, field="NPTS") from None
    if npts < 2:
        raise InputError(f"NPTS = {npts}; a record needs at least 2 samples", file=path, field="NPTS")
    try:
        dt = _to_float(dt_txt)
    except ValueError:
        raise InputError(f"DT {dt_txt!r} is not a number", file=path, field="DT") from None
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError(f"DT = {dt_txt}; expected a positive sample interval in seconds",
                         file=path, field="DT")
    return npts, dt


# --------------------------------------------------------------------------
# Helpers: values
# --------------------------------------------------------------------------


def _frozen_vector(values: Any, name: str, where: str | None) -> np.ndarray:
    """A read-only float64 1-D copy of ``values`` with finite entries."""
    try:
        arr = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of numbers", file=where, field=name) from None
    if arr.ndim != 1:
        raise InputError(f"{name} must be 1-D, got shape {arr.shape}", file=where, field=name)
    if not np.all(np.isfinite(arr)):
        i = int(np.argmax(~np.isfinite(arr)))
        raise InputError(f"{name}[{i}] = {arr[i]} is not finite", file=where, field=name)
    arr.setflags(write=False)
    return arr


def _finite_number(value: Any, field_: str, file: str | Path | None) -> float:
    """``value`` as a finite float; bools and strings are rejected."""
    # bool is an int subclass, but `pga = true` in a scene is a mistake.
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"expected a number, got {type(value).__name__} {value!r}", file=file,
                         field=field_)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(f"expected a finite number, got {value}", file=file, field=field_)
    return value


def _positive_number(value: Any, field_: str, file: str | Path | None) -> float:
    value = _finite_number(value, field_, file)
    if value <= 0.0:
        raise InputError(f"expected a number > 0, got {value:g}", file=file, field=field_)
    return value


def _unit_factor(units: Any, file: str | Path | None, field_: str) -> float:
    if not isinstance(units, str) or units.strip().lower() not in UNITS:
        raise InputError(f"unknown units {units!r}; expected one of {', '.join(map(repr, UNITS))}",
                         file=file, field=field_)
    return UNITS[units.strip().lower()]


def _choice(value: Any, choices: tuple[str, ...], fail, key: str) -> str:
    if not isinstance(value, str) or value not in choices:
        raise fail(key, f"got {value!r}; expected one of {', '.join(map(repr, choices))}")
    return value
