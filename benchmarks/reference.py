"""Converged reference solutions, computed once per process.

Pounding: the ``exact`` integrator (exact for the piecewise-linear record between
grid points, so the only discretisation left is the event handling), the ``root``
locator (Brent's method on the gap, to ~1e-14 s) and a tight contact tolerance
(1e-8 m instead of the default 1e-4 m), at a small dt. Its convergence is checked by
comparing two resolutions (dt_ref and 2 dt_ref, both with the tight tolerance).

No pounding: ``exact`` at dt_ref is exact (to rounding) for the linearly
interpolated record at every dt that divides the record's 0.02 s, so one
resolution would do; the same two-resolution check is reported anyway.
"""

from __future__ import annotations

import time

from common import errors, log, quiet_run, result_corners, subsample
from scenes import load, no_pounding, with_method

REF_TOL = 1e-8  # [m] contact tolerance of the reference
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


def reference(name: str, pounding: bool, dt_ref: float, duration: float | None = None) -> Reference:
    key = (name, pounding, dt_ref, duration)
    if key not in _cache:
        s = load(name)
        if not pounding:
            s = no_pounding(s)
        s = with_method(s, "exact", dt_ref, locate="root", tolerance=REF_TOL)
        if duration is not None:
            s = s.with_analysis(duration=duration)
        t0 = time.perf_counter()
        r = quiet_run(s)
        sec = time.perf_counter() - t0
        log(f"  reference {name} {'pounding' if pounding else 'no pounding'} dt={dt_ref:g}: {sec:.1f} s, "
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
