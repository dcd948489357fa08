"""Floor response spectra: the peak response of light oscillators standing on the floors.

An oscillator of period T and damping ratio zeta on floor f, along x or y,
obeys ``u'' + 2 zeta w u' + w^2 u = -a_f(t)`` with a_f the floor's absolute
acceleration. Its pseudo-acceleration ``w^2 max|u|`` [m/s^2] over the run is
the spectral ordinate. The oscillators are stepped with the ``exact``
integrator's transitions (exact for an excitation linear within each output
step; :mod:`pounding.solvers.exact`), vectorised over periods, floors and
directions.

Impacts: the floor acceleration is its smooth part (see
:mod:`pounding.framework.post.response`) plus a Dirac spike ``dv delta(t - t_i)``
at every impact. A spike changes the oscillator's relative velocity by -dv at
once; it is applied at the end of the output step that holds the impact
instant (so the instant is rounded up to the output grid: keep output_every = 1
for spectra of short periods). ``impulses=False`` gives the spectrum of the
smooth part alone, for comparison.
"""

from __future__ import annotations

import numpy as np


def floor_spectra(result, name: str, periods: np.ndarray, zeta: float = 0.05, *, impulses: bool = True) -> np.ndarray:
    """Pseudo-acceleration floor spectra of building ``name``, shape (len(periods), N, 2) [m/s^2] (x, y).

    Parameters
    ----------
    result : Result
    name : str
        Building.
    periods : (np,) [s]
        Oscillator periods, > 0.
    zeta : float
        Oscillator damping ratio [-].
    impulses : bool
        Include the impacts' velocity jumps (Dirac spikes of the floor acceleration).
    """
    from pounding.framework.model.registry import INTEGRATORS
    from pounding.framework.post.response import floor_acceleration, floor_velocity_jumps, impact_forces

    s = result.systems[result.names.index(name)]
    acc = floor_acceleration(s, result.modal(name), result.modal(name, velocity=True))[:, :, :2]  # (nt, N, 2)
    nt, n = acc.shape[0], s.n_storeys
    periods = np.asarray(periods, dtype=float)
    w = 2.0 * np.pi / periods
    # one oscillator per (period, floor, direction), flattened
    omega = np.repeat(w, 2 * n)
    tr = INTEGRATORS.get("exact")().transition(omega, np.full(omega.shape, float(zeta)), float(result.t[1] - result.t[0]))
    kicks = np.zeros((nt, n, 2))
    if impulses and result.impacts:
        _, tau = impact_forces(result)
        times, jumps, _ = floor_velocity_jumps(result, name, tau)
        k = np.searchsorted(result.t, times - 1e-12 * (result.t[1] - result.t[0]))  # the step end at or after the instant
        np.add.at(kicks, np.minimum(k, nt - 1), jumps[:, :, :2])
    z = np.zeros((omega.size, 3))
    peak = np.zeros(omega.size)
    p_prev = -np.tile(acc[0].ravel(), periods.size)
    z[:, 2] = p_prev
    for j in range(1, nt):
        p = -np.tile(acc[j].ravel(), periods.size)
        z = np.einsum("irc,ic->ir", tr.A, z) + tr.B[:, :, 0] * p_prev[:, None] + tr.B[:, :, 1] * p[:, None]
        if kicks[j].any():
            z[:, 1] -= np.tile(kicks[j].ravel(), periods.size)
        np.maximum(peak, np.abs(z[:, 0]), out=peak)
        p_prev = p
    return (omega**2 * peak).reshape(periods.size, n, 2)
