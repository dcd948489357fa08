"""Converged reference solutions, computed once per process.

Pounding: the ``exact`` integrator (exact for the piecewise-linear record between
grid points, so the only discretisation left is the event handling) with the
``crossing`` locator (every impulse where the gap is zero to rounding; the contact
tolerance decides resting contact only), at a small dt. Its convergence is checked by
comparing two resolutions (dt_ref and 2 dt_ref) and, where a benchmark asks, against
Newmark with the same locator at dt_ref (an independent time-stepping of the same
rigid-impact model).

Until 2026-11-24 the reference was ``exact`` + ``root`` + tolerance 1e-8 m (``method =
"root"``, kept for comparison). That family strikes a closing pair as soon as its gap is
within the tolerance, so an impact comes early by tolerance / approach speed; in a chatter
sequence the approach speeds fall to ~1e-4 m/s and the error in the instants reaches
~1e-4 s, the order of dt. It converges, but slowly: on the paper pair its largest peak
moved by 2.5e-4 between dt = 0.00025 s and 6.25e-5 s while the crossing family moved
by 8e-5, 2.4e-5 and (exact against Newmark at 6.25e-5 s) 7e-6.

No pounding: ``exact`` at dt_ref is exact (to rounding) for the linearly
interpolated record at every dt that divides the record's 0.02 s, so one
resolution would do; the same two-resolution check is reported anyway.
"""

from __future__ import annotations

import time

from common import errors, log, quiet_run, result_corners, subsample
from scenes import load, no_pounding, with_method

REF_TOL = 1e-8  # [m] contact tolerance of the old (``root``) reference family
REF_LOCATE = "crossing"  # the reference's locator (the contact tolerance is then the scene's: resting contact only)
WINDOW_AFTER_FIRST_IMPACT = 1.0  # [s] the error window ends this long after the first impact

_cache: dict = {}


class Reference:
    def __init__(self, scene, result, seconds: float):
        self.scene = scene
        self.result = result
        self.dt = result.dt
        self.t = result.t
        self.corners = result_corners(result, scene)
        self.seconds = seconds

    @property
    def first_impact(self) -> float | None:
        return self.result.impacts[0].time if self.result.impacts else None


def reference(name: str, pounding: bool, dt_ref: float, duration: float | None = None, method: str = REF_LOCATE,
              integrator: str = "exact") -> Reference:
    """The reference run of a benchmark scene: ``integrator`` at dt_ref with the ``crossing`` locator, or with
    ``method = "root"`` the old family (``root`` locator, tolerance REF_TOL)."""
    key = (name, pounding, dt_ref, duration, method, integrator)
    if key not in _cache:
        s = load(name)
        if not pounding:
            s = no_pounding(s)
        if method == "root":
            s = with_method(s, integrator, dt_ref, locate="root", tolerance=REF_TOL)
        else:
            s = with_method(s, integrator, dt_ref, locate=method)
        if duration is not None:
            s = s.with_analysis(duration=duration)
        t0 = time.perf_counter()
        r = quiet_run(s)
        sec = time.perf_counter() - t0
        log(f"  reference {name} {'pounding' if pounding else 'no pounding'} {integrator}/{method} dt={dt_ref:g}: {sec:.1f} s, "
            f"{r.n_impacts} impacts, {r.info.get('located_events')} located events")
        _cache[key] = Reference(s, r, sec)
    return _cache[key]


def window_end(ref: Reference) -> float | None:
    """End of the error window: WINDOW_AFTER_FIRST_IMPACT after the reference's first impact."""
    t1 = ref.first_impact
    return None if t1 is None else t1 + WINDOW_AFTER_FIRST_IMPACT


def convergence(fine: Reference, coarse: Reference, t_window: float | None) -> dict:
    """Error measures of the coarser reference against the finer one (on the coarse grid)."""
    R = subsample(fine.corners, fine.dt, coarse.dt, len(coarse.t))
    e = errors(coarse.corners, R, coarse.t, t_window)
    e.update(dt_fine=fine.dt, dt_coarse=coarse.dt, impacts_fine=fine.result.n_impacts, impacts_coarse=coarse.result.n_impacts,
             seconds_fine=fine.seconds, seconds_coarse=coarse.seconds)
    return e
