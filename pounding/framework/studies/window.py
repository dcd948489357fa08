"""Does a study's analysis window hold each record's strong motion?

A study scales a record by an intensity measure of the *whole* record (its PGA,
its Sa(T1)...), then analyses the scene for ``analysis.duration`` seconds (the
record's own length when none is set). When that window ends before the
record's strong motion is over, the run sees a record scaled for shaking it
never applies: the required gaps and drifts of such runs answer another
question. ``pounding fragility --duration 15`` on 90 s records reported required
gaps of 4e-6 m that way.

A window *cuts* a record when it ends before either

* the time at which the record's Arias intensity reaches 95 % of its total (the
  end of the strong motion, :func:`pounding.framework.post.intensity.strong_motion`;
  both components of a pair count), or
* the time of the record's peak acceleration (what a PGA scaling was set by).

The window used is the requested duration; the analysis covers it (its last
step ends at or after it), so a record that fits is never cut by the steps.
Both times are independent of the scale factor (a positive factor scales a**2
everywhere alike), so the check is made once per record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pounding.errors import AnalysisWarning

__all__ = ["WindowCheck", "WindowWarning", "check_window", "window_columns", "window_warning", "analysis_window"]


class WindowWarning(AnalysisWarning):
    """A study's analysis window ends before some records' strong motion or peak."""


@dataclass(frozen=True)
class WindowCheck:
    """One record against the analysis window.

    Attributes
    ----------
    record : str
        The record's name in the study.
    window : float
        End of the analysis window [s] (the analysis starts at 0).
    arias : float
        Arias intensity of the record as scaled [m/s].
    arias95_time : float
        Time at which the Arias intensity reaches 95 % [s].
    peak_time : float
        Time of the record's peak |acceleration| [s].
    """

    record: str
    window: float
    arias: float
    arias95_time: float
    peak_time: float

    @property
    def missed(self) -> list[str]:
        """The times after the window's end, in words (empty when it holds both)."""
        missed = []
        if self.window < self.arias95_time:
            missed.append(f"95 % Arias intensity at {self.arias95_time:.3g} s")
        if self.window < self.peak_time:
            missed.append(f"peak at {self.peak_time:.3g} s")
        return missed

    @property
    def cut(self) -> str | None:
        """What the window misses, in words (None when it holds both times): a row's ``window_cut``."""
        return f"window {self.window:.3g} s ends before the " + " and the ".join(self.missed) if self.missed else None

    def as_dict(self) -> dict:
        """The check as a study's JSON file states it (times in s)."""
        return {"record": self.record, "window_s": self.window, "arias95_s": self.arias95_time, "peak_time_s": self.peak_time,
                "cut": self.cut}

    @property
    def needed(self) -> float:
        """The shortest window that holds both times [s]."""
        return max(self.arias95_time, self.peak_time)


def analysis_window(scene) -> float:
    """End of the analysis window of ``scene`` [s]: its ``analysis.duration``, or its record's length."""
    return float(scene.analysis.duration or scene.ground_motion.duration)


def check_window(record: str, scene) -> WindowCheck:
    """The check of ``scene``'s ground motion (as scaled) against ``scene``'s window."""
    from pounding.framework.post.intensity import strong_motion

    sm = strong_motion(scene.ground_motion)
    return WindowCheck(record, analysis_window(scene), sm.arias, sm.arias95_time, sm.peak_time)


def window_columns(check: WindowCheck) -> dict:
    """The columns a study's row gets from a check: ``window_s, arias_m_s, arias95_s, peak_time_s, window_cut``."""
    return {"window_s": check.window, "arias_m_s": check.arias, "arias95_s": check.arias95_time,
            "peak_time_s": check.peak_time, "window_cut": check.cut}


def window_warning(checks, scaled_by: str, table: str) -> str | None:
    """The warning for the records a window cuts, naming each; None when none is cut.

    Parameters
    ----------
    checks : iterable of WindowCheck
    scaled_by : str
        How the records were scaled, e.g. ``"their whole-record PGA"``.
    table : str
        The file whose ``window_cut`` column marks the runs.
    """
    checks = list(checks)
    cut = [c for c in checks if c.missed]
    if not cut:
        return None
    windows = ", ".join(f"{w:.3g} s" for w in sorted({c.window for c in cut}))
    names = "; ".join(f"{c.record} ({', '.join(c.missed)})" for c in cut)
    need = max(c.needed for c in cut)
    return (f"the analysis window ({windows}) ends before the strong motion or the peak of {len(cut)} of {len(checks)} "
            f"records, scaled by {scaled_by}: {names}. Their runs miss part of the shaking ({table} marks them in "
            f"window_cut); a duration of at least {math.ceil(need * 10.0) / 10.0:g} s holds every record's strong motion and peak")
