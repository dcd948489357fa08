"""Two orthogonal horizontal components of ground acceleration acting together.

A :class:`GroundMotionPair` holds two records on one time base: the first acts
in the plan direction ``angle`` (degrees, counter-clockwise from global x), the
second at ``angle + 90``. It offers the same interface the analysis uses for a
single :class:`~pounding.io.ground_motion.GroundMotion` (``dt``, ``duration``,
``directions()`` (c, 2), ``samples(t)`` (m, c), ``components``), so every
command takes either.

One time base
-------------
Components recorded with different sample intervals or lengths are put on one
grid when the pair is made (:func:`common_time_base`):

* the interval is the finer of the two (for a record with non-uniform times,
  its smallest step);
* the grid runs from t = 0 to the later of the two ends;
* each component is linearly interpolated onto it, which is exact at its own
  samples (so two records with the same dt are copied unchanged) and is the
  same piecewise-linear reading ``GroundMotion.at`` gives;
* the shorter record is padded with zeros after its end (the ground is at rest
  after a record ends), as is a record before its first sample.

Scene table (see :func:`load_pair`)::

    [ground_motion]
    components = ["RSN1111_KOBE_NIS000.AT2", "RSN1111_KOBE_NIS090.AT2"]
    angle = 30.0     # direction of the first from x [deg]; the second acts at angle + 90
    scale = 1.5      # one factor for both (or pga = ..., the larger component's peak, in g)

A component may also be a table with its own ``record``, ``format``, ``dt``,
``units`` and ``baseline``: ``components = [{record = "a.txt", dt = 0.005,
units = "cm/s2"}, "b.AT2"]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any, Sequence

import numpy as np

from pounding.errors import InputError
from pounding.framework.model.units import G
from pounding.io.ground_motion import GroundMotion

__all__ = ["GroundMotionPair", "common_time_base", "baseline_corrected", "BASELINES"]

#: ``baseline`` key -> degree of the least-squares polynomial removed from the acceleration.
BASELINES = {"none": None, "mean": 0, "linear": 1, "quadratic": 2, "cubic": 3}


def common_time_base(records: Sequence[GroundMotion]) -> tuple[np.ndarray, np.ndarray]:
    """Put records on one uniform time grid (module docstring: finer dt, linear, zero padding).

    Parameters
    ----------
    records : sequence of GroundMotion
        The components, each with its own samples.

    Returns
    -------
    t : ndarray, shape (m,)
        ``arange(m) * dt`` [s], with dt the finest sample interval and ``t[-1]``
        at or after the latest end.
    acc : ndarray, shape (m, c)
        Acceleration of each record at ``t`` [m/s^2].
    """
    steps = [r.dt if r.dt is not None else float(np.min(np.diff(r.t))) for r in records]
    dt = min(steps)
    end = max(r.duration for r in records)
    m = int(math.ceil(end / dt - 1e-9)) + 1
    t = np.arange(m) * dt
    acc = np.empty((m, len(records)))
    for j, r in enumerate(records):
        same = r.dt is not None and r.dt == dt and r.t[0] == 0.0
        if same:
            # copied sample by sample: bit-identical to the record, zeros after its end
            acc[: r.t.size, j] = r.acc
            acc[r.t.size :, j] = 0.0
        else:
            acc[:, j] = np.interp(t, r.t, r.acc, left=0.0, right=0.0)
    return t, acc


def baseline_corrected(motion: GroundMotion, kind: str) -> GroundMotion:
    """The record with a least-squares polynomial of the acceleration removed.

    Parameters
    ----------
    motion : GroundMotion
    kind : str
        A key of :data:`BASELINES`: ``"none"`` (unchanged), ``"mean"``,
        ``"linear"``, ``"quadratic"`` or ``"cubic"`` (degree 0 to 3), the
        polynomial in time fitted to the acceleration samples and subtracted
        (the simple correction of SeismoSignal-type tools). Only applied when
        asked: a processed record (PEER NGA-West2) needs none.
    """
    degree = BASELINES[kind]
    if degree is None:
        return motion
    tn = motion.t / max(motion.duration, 1e-300)  # scaled time: a well-conditioned fit
    coef = np.polynomial.polynomial.polyfit(tn, motion.acc, degree)
    return replace(motion, acc=motion.acc - np.polynomial.polynomial.polyval(tn, coef))


@dataclass(frozen=True, eq=False, repr=False)
class GroundMotionPair:
    """Two orthogonal horizontal components on one time base.

    Parameters
    ----------
    first, second : GroundMotion
        The two records (their own ``angle`` is ignored: the pair sets it).
    angle : float
        Direction of the first component [degrees], counter-clockwise from
        global x; the second acts at ``angle + 90``.
    name : str
        Label; default ``"<first>+<second>"``.

    Attributes
    ----------
    t : ndarray (m,)
        Common sample times [s] (:func:`common_time_base`).
    acc : ndarray (m, 2)
        Acceleration of the two components at ``t`` [m/s^2], read-only.
    """

    first: GroundMotion
    second: GroundMotion
    angle: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        angle = float(self.angle)
        if not math.isfinite(angle):
            raise InputError(f"expected a finite angle in degrees, got {self.angle!r}", field="angle")
        object.__setattr__(self, "angle", angle)
        if not self.name:
            object.__setattr__(self, "name", f"{self.first.name}+{self.second.name}")

    def __repr__(self) -> str:
        return (f"GroundMotionPair(name={self.name!r}, n={self.t.size}, dt={self.dt:g} s, "
                f"duration={self.duration:g} s, pga={self.pga / G:.5g} g, angle={self.angle:g} deg)")

    @cached_property
    def _base(self) -> tuple[np.ndarray, np.ndarray]:
        t, acc = common_time_base((self.first, self.second))
        t.setflags(write=False)
        acc.setflags(write=False)
        return t, acc

    @property
    def t(self) -> np.ndarray:
        return self._base[0]

    @property
    def acc(self) -> np.ndarray:
        return self._base[1]

    @property
    def source(self) -> str:
        return f"{self.first.source} | {self.second.source}"

    @property
    def dt(self) -> float:
        """Sample interval of the common time base [s]."""
        return float(self.t[1] - self.t[0]) if self.t.size > 1 else float(self.t[0])

    @property
    def duration(self) -> float:
        """End of the common time base [s]."""
        return float(self.t[-1])

    @property
    def pga(self) -> float:
        """The larger component's peak |acc| [m/s^2] (what ``pga = ...`` scales)."""
        return float(np.max(np.abs(self.acc)))

    @property
    def components(self) -> tuple[GroundMotion, GroundMotion]:
        """The two components on the common time base, each with its own angle."""
        return (GroundMotion(self.t, self.acc[:, 0], self.first.name, self.first.source, self.angle),
                GroundMotion(self.t, self.acc[:, 1], self.second.name, self.second.source, self.angle + 90.0))

    def directions(self) -> np.ndarray:
        """Plan unit vectors of the two components, shape (2, 2): angle and angle + 90."""
        return np.stack([c.direction() for c in self.components])

    def piecewise_linear(self) -> tuple[np.ndarray, np.ndarray] | None:
        """(times (m,) [s], accelerations (m, c) [m/s^2]) whose linear interpolation, zero outside the
        record, :meth:`samples` is; the engine then interpolates the record in its compiled search with
        the same arithmetic. A subclass whose ``samples`` is anything else returns None."""
        return self.t, np.asarray(self.acc, dtype=float).reshape(len(self.t), -1)

    def samples(self, times: Any) -> np.ndarray:
        """Accelerations of both components at ``times`` [m/s^2]: (m, 2), or (2,) for a scalar.

        Linear between the common samples, zero before 0 and after the end.
        """
        cols = [np.interp(times, self.t, self.acc[:, j], left=0.0, right=0.0) for j in range(2)]
        return np.stack(cols, axis=-1)

    def direction(self) -> np.ndarray:
        """Direction of the first component (for code that asks one direction)."""
        return self.components[0].direction()

    # -- copies -------------------------------------------------------------

    def scaled(self, factor: float) -> "GroundMotionPair":
        """Both components multiplied by ``factor`` (> 0)."""
        return replace(self, first=self.first.scaled(factor), second=self.second.scaled(factor))

    def scaled_to_pga(self, pga_g: float) -> "GroundMotionPair":
        """Scaled by one factor so that the larger component's peak is ``pga_g`` [g]."""
        if not (isinstance(pga_g, (int, float)) and math.isfinite(pga_g) and pga_g > 0):
            raise InputError(f"target PGA must be a number > 0 g, got {pga_g!r}", field="pga")
        if self.pga == 0.0:
            raise InputError("the records are all zeros and cannot be scaled to a PGA", field="pga")
        return self.scaled(pga_g * G / self.pga)

    def with_angle(self, angle: float) -> "GroundMotionPair":
        """The same pair acting with its first component at ``angle`` [degrees]."""
        return replace(self, angle=float(angle))

    def rotated(self, angle: float) -> "GroundMotionPair":
        """The pair turned by ``angle`` degrees (counter-clockwise)."""
        return replace(self, angle=self.angle + float(angle))
