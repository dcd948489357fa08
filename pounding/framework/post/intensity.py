"""Intensity measures of ground motions: PGA, Sa(T), geometric mean, RotD50/RotD100, Arias intensity.

Glossary (SI units throughout; results in g only where a name says so):

``SD(T)``
    Peak |u| [m] of the 5 %-damped linear oscillator of period T under the
    record, ``u'' + 2 zeta omega u' + omega**2 u = -a(t)``, ``omega = 2 pi / T``.
``PSA(T) = omega**2 SD(T)``
    Pseudo-spectral acceleration [m/s^2] (the Sa(T) of design codes).
Geometric mean
    ``sqrt(X1 X2)`` of the two horizontal components' values (PGA or PSA).
``RotD50``, ``RotD100``
    Orientation-independent measures (Boore, 2010, Bull. Seismol. Soc. Am.
    100(4), 1830-1835): the oscillator responses of the two components
    ``u1(t), u2(t)`` are combined for every non-redundant angle
    ``theta = 0, 1, ..., 179`` degrees, ``u(t; theta) = u1 cos theta + u2 sin theta``,
    the peak ``max_t |u|`` is taken per angle, and RotDnn is the nn-th
    percentile of those 180 peaks (linear interpolation between order
    statistics, numpy's default): RotD100 the largest, RotD50 the median.
    At T = 0 the same is done with the accelerations (PGA-RotD).
Arias intensity ``I_A(t) = pi / (2 g) * int_0^t sum_j a_j(s)**2 ds``
    [m/s] (Arias, 1970, in *Seismic Design for Nuclear Power Plants*, MIT
    Press, 438-483): the energy per unit weight dissipated by a population of
    undamped oscillators of all frequencies. Of two horizontal components it is
    the sum of theirs (the trace of Arias's intensity tensor, the same in every
    plan orientation). The time at which it reaches 95 % of its total marks the
    end of the strong motion (Trifunac & Brady, 1975, Bull. Seismol. Soc. Am.
    65(3), 581-626, take 5 % to 95 % as the significant duration).

The oscillator is integrated exactly for an acceleration linear between
samples (Nigam & Jennings, 1969): the per-period one-step maps are those of the
``exact`` integrator (:mod:`pounding.solvers.exact`), accurate to ~1e-14 for any
``omega dt``, so a spectrum needs no sub-stepping at short periods.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.compiler import njit
from pounding.errors import InputError

__all__ = [
    "DAMPING", "ANGLES", "MEASURES", "Spectra", "spectra", "oscillator_peaks", "intensity",
    "scale_factor", "default_periods", "arias_history", "arias_time", "StrongMotion", "strong_motion",
]

#: Damping ratio of the response spectra (5 %, the codes' and the GMPEs' value).
DAMPING = 0.05
#: Non-redundant rotation angles of RotDnn [deg] (Boore 2010: 1-degree steps over 0..179).
ANGLES = np.arange(180.0)
#: Intensity measures a record or a pair can be scaled to (``intensity`` key).
MEASURES = ("pga", "sa", "geomean", "rotd50", "rotd100")


def default_periods() -> np.ndarray:
    """Periods of a spectrum [s]: 0.02 s to 10 s, 100 points evenly spaced in log."""
    return np.geomspace(0.02, 10.0, 100)


@njit
def _peaks(A, B, acc, cosines, sines, sd, rot):
    """Peak oscillator displacements of each component and of each rotation.

    A (nT, 3, 3), B (nT, 3, 2): one-step maps of each period's oscillator for the
    state (u, u', u''); acc (m, c) ground acceleration [m/s^2]; cosines, sines (na,).
    Fills sd (nT, c) with max_t |u_j| and, when c == 2, rot (nT, na) with
    max_t |u_1 cos + u_2 sin| for every angle.
    """
    nT = A.shape[0]
    m, c = acc.shape
    na = cosines.shape[0]
    u = np.empty((c, m))
    for p in range(nT):
        for j in range(c):
            z0 = 0.0
            z1 = 0.0
            z2 = -acc[0, j]
            u[j, 0] = 0.0
            peak = 0.0
            for k in range(m - 1):
                p0 = -acc[k, j]
                p1 = -acc[k + 1, j]
                n0 = A[p, 0, 0] * z0 + A[p, 0, 1] * z1 + A[p, 0, 2] * z2 + B[p, 0, 0] * p0 + B[p, 0, 1] * p1
                n1 = A[p, 1, 0] * z0 + A[p, 1, 1] * z1 + A[p, 1, 2] * z2 + B[p, 1, 0] * p0 + B[p, 1, 1] * p1
                n2 = A[p, 2, 0] * z0 + A[p, 2, 1] * z1 + A[p, 2, 2] * z2 + B[p, 2, 0] * p0 + B[p, 2, 1] * p1
                z0, z1, z2 = n0, n1, n2
                u[j, k + 1] = z0
                if abs(z0) > peak:
                    peak = abs(z0)
            sd[p, j] = peak
        if c == 2:
            for a in range(na):
                peak = 0.0
                ca = cosines[a]
                sa = sines[a]
                for k in range(m):
                    v = abs(u[0, k] * ca + u[1, k] * sa)
                    if v > peak:
                        peak = v
                rot[p, a] = peak


def _acc_matrix(motion) -> tuple[np.ndarray, float]:
    """(acc (m, c) [m/s^2], dt [s]) of a GroundMotion or GroundMotionPair on its own samples."""
    acc = np.asarray(motion.acc, dtype=float)
    acc = acc.reshape(acc.shape[0], -1)
    dt = motion.dt
    if dt is None:
        raise InputError("response spectra need uniformly sampled records; this one has non-uniform "
                         "times (put it on a uniform grid first)", file=motion.source or None, field="t")
    return np.ascontiguousarray(acc), float(dt)


def _rotation(n_angles: int) -> tuple[np.ndarray, np.ndarray]:
    r = np.radians(ANGLES[:n_angles])
    c, s = np.cos(r), np.sin(r)
    # exact at 0 and 90 degrees, so RotD at those angles is the component itself
    c[90], s[90], s[0] = 0.0, 1.0, 0.0
    return c, s


def oscillator_peaks(acc: np.ndarray, dt: float, periods, zeta: float = DAMPING):
    """Peak responses of damped oscillators to one or two components.

    Parameters
    ----------
    acc : ndarray, shape (m,) or (m, c), c = 1 or 2
        Ground acceleration sampled every ``dt`` from t = 0 [m/s^2], linear
        between samples.
    dt : float
        Sample interval [s].
    periods : array_like, shape (nT,)
        Oscillator periods [s], > 0.
    zeta : float
        Damping ratio.

    Returns
    -------
    sd : ndarray, shape (nT, c)
        Peak |u| of each component [m].
    rot : ndarray, shape (nT, 180)
        Peak |u1 cos theta + u2 sin theta| for theta = 0..179 deg [m] (zeros for c = 1).
    """
    from pounding.solvers.exact import Exact

    acc = np.ascontiguousarray(np.asarray(acc, dtype=float).reshape(np.shape(acc)[0], -1))
    periods = np.atleast_1d(np.asarray(periods, dtype=float))
    if np.any(~(periods > 0)):
        raise InputError(f"oscillator periods must be > 0 s, got {periods[~(periods > 0)][0]:g}", field="period")
    omega = 2.0 * np.pi / periods
    tr = Exact().transition(omega, np.full_like(omega, zeta), float(dt))
    A = np.ascontiguousarray(tr.A)
    B = np.ascontiguousarray(tr.B)
    c = acc.shape[1]
    sd = np.zeros((periods.size, c))
    rot = np.zeros((periods.size, ANGLES.size))
    cosines, sines = _rotation(ANGLES.size)
    _peaks(A, B, acc, cosines, sines, sd, rot)
    return sd, rot


def _rotd(rot: np.ndarray, percentile: float) -> np.ndarray:
    return np.percentile(rot, percentile, axis=-1, method="linear")


def _rotated_pga(acc: np.ndarray) -> np.ndarray:
    """max_t |a1 cos theta + a2 sin theta| for theta = 0..179 deg, shape (180,) [m/s^2]."""
    c, s = _rotation(ANGLES.size)
    return np.max(np.abs(acc[:, :1] * c + acc[:, 1:2] * s), axis=0)


@dataclass(frozen=True)
class Spectra:
    """5 %-damped response spectra of one record or a pair.

    Attributes
    ----------
    periods : ndarray (nT,)
        [s].
    sd : ndarray (nT, c)
        Spectral displacement of each component [m].
    psa : ndarray (nT, c)
        Pseudo-spectral acceleration of each component [m/s^2].
    rotd50_sd, rotd100_sd, rotd50_psa, rotd100_psa : ndarray (nT,) or None
        RotD50/RotD100 of SD [m] and PSA [m/s^2] (pairs only).
    pga : ndarray (c,)
        Peak |acc| of each component [m/s^2].
    names : tuple of str
        Component labels.
    zeta : float
        Damping ratio.
    """

    periods: np.ndarray
    sd: np.ndarray
    psa: np.ndarray
    rotd50_sd: np.ndarray | None
    rotd100_sd: np.ndarray | None
    rotd50_psa: np.ndarray | None
    rotd100_psa: np.ndarray | None
    pga: np.ndarray
    names: tuple[str, ...]
    zeta: float = DAMPING


def spectra(motion, periods=None, zeta: float = DAMPING) -> Spectra:
    """Response spectra of a GroundMotion (one component) or a GroundMotionPair.

    Parameters
    ----------
    motion : GroundMotion or GroundMotionPair
        Accelerations on uniform samples (a pair is on its common time base).
    periods : array_like (nT,), optional
        [s]; default :func:`default_periods`.
    zeta : float
        Damping ratio (0.05).
    """
    periods = default_periods() if periods is None else np.atleast_1d(np.asarray(periods, dtype=float))
    acc, dt = _acc_matrix(motion)
    sd, rot = oscillator_peaks(acc, dt, periods, zeta)
    w2 = (2.0 * np.pi / periods) ** 2
    names = tuple(c.name for c in motion.components)
    two = acc.shape[1] == 2
    r50 = _rotd(rot, 50.0) if two else None
    r100 = _rotd(rot, 100.0) if two else None
    return Spectra(
        periods=periods, sd=sd, psa=sd * w2[:, None],
        rotd50_sd=r50, rotd100_sd=r100,
        rotd50_psa=None if r50 is None else r50 * w2, rotd100_psa=None if r100 is None else r100 * w2,
        pga=np.max(np.abs(acc), axis=0), names=names, zeta=zeta,
    )


def intensity(motion, measure: str, period: float | None = None, zeta: float = DAMPING) -> float:
    """One intensity measure of a record or a pair [m/s^2].

    Parameters
    ----------
    motion : GroundMotion or GroundMotionPair
    measure : str
        ``"pga"`` (peak |acc|; of a pair, the larger component's), ``"sa"``
        (PSA(T); of a pair, the larger component's), ``"geomean"`` (geometric
        mean of the two components' PSA(T), or of their PGAs when ``period`` is
        0), ``"rotd50"``, ``"rotd100"`` (of PSA(T), or of the acceleration when
        ``period`` is 0). For one component, geomean, RotD50 and RotD100 are the
        component's own value (a single record has no orientation to vary).
    period : float, optional
        T [s] for the spectral measures (>= 0; 0 means the peak ground value).
    """
    if measure not in MEASURES:
        raise InputError(f"unknown intensity measure {measure!r}; expected one of {', '.join(MEASURES)}",
                         field="intensity")
    acc, dt = _acc_matrix(motion)
    if measure == "pga":
        return float(np.max(np.abs(acc)))
    if period is None:
        raise InputError(f"intensity {measure!r} needs a period T [s]", field="period")
    period = float(period)
    if not period >= 0.0:
        raise InputError(f"expected a period >= 0 s, got {period:g}", field="period")
    two = acc.shape[1] == 2
    if period == 0.0:
        comp = np.max(np.abs(acc), axis=0)
        rot = _rotated_pga(acc) if two else None
    else:
        sd, rot = oscillator_peaks(acc, dt, [period], zeta)
        w2 = (2.0 * np.pi / period) ** 2
        comp = sd[0] * w2
        rot = rot[0] * w2 if two else None
    if measure == "sa":
        return float(np.max(comp))
    if measure == "geomean":
        return float(np.sqrt(np.prod(comp))) if two else float(comp[0])
    if not two:
        return float(comp[0])
    return float(_rotd(rot, 50.0 if measure == "rotd50" else 100.0))


def scale_factor(motion, measure: str, target_g: float, period: float | None = None, zeta: float = DAMPING) -> float:
    """The factor that brings ``intensity(motion, measure, period)`` to ``target_g`` [g].

    Every measure is linear in the record (a factor f scales every response by f),
    so the factor is target / measured.
    """
    from pounding.framework.model.units import G

    target_g = float(target_g)
    if not target_g > 0.0:
        raise InputError(f"expected a target > 0 g, got {target_g:g}", field="target")
    value = intensity(motion, measure, period, zeta)
    if value == 0.0:
        raise InputError(f"the record's {measure} is zero and cannot be scaled to a target", field="target")
    return target_g * G / value


# =============================================================================
# Arias intensity and the end of the strong motion
# =============================================================================


def _record_arrays(t, acc) -> tuple[np.ndarray, np.ndarray]:
    """(t (m,) [s], acc (m, c) [m/s^2]) as float arrays, one column per component."""
    t = np.asarray(t, dtype=float)
    acc = np.asarray(acc, dtype=float).reshape(t.size, -1)
    return t, acc


def arias_history(t, acc) -> np.ndarray:
    """Arias intensity accumulated up to each sample, ``I_A(t_k)`` [m/s].

    Parameters
    ----------
    t : array_like, shape (m,)
        Sample times [s], increasing (not necessarily uniform).
    acc : array_like, shape (m,) or (m, c)
        Ground acceleration of c components [m/s^2], linear between samples
        (the record the analysis applies); the components' intensities add.

    Returns
    -------
    ndarray, shape (m,)
        ``I_A`` from ``t[0]`` (0 there) to each sample. Each interval of length
        h adds ``pi / (2 g) * h / 3 * (a0**2 + a0 a1 + a1**2)`` per component,
        the exact integral of the square of the linear piece, so the history is
        exact to rounding for the piecewise-linear record (no quadrature error).
    """
    from pounding.framework.model.units import G

    t, acc = _record_arrays(t, acc)
    a0, a1 = acc[:-1], acc[1:]
    pieces = np.diff(t) / 3.0 * np.sum(a0 * a0 + a0 * a1 + a1 * a1, axis=1)
    return np.concatenate(([0.0], np.cumsum(pieces))) * (np.pi / (2.0 * G))


def arias_time(t, acc, fraction: float) -> float:
    """The time [s] at which the Arias intensity reaches ``fraction`` of its total.

    Parameters
    ----------
    t, acc : as :func:`arias_history`
    fraction : float
        In (0, 1]; 0.95 gives the end of the strong motion.

    Returns
    -------
    float
        Exact to rounding for the piecewise-linear record: inside the interval
        where the history crosses the level, the accumulated intensity is the
        cubic ``A s + B s**2 / 2 + C s**3 / 3`` of the time s into the interval
        (``sum_j (a0_j + m_j s)**2 = A + B s + C s**2``), increasing, solved by
        Brent's method to a few units of rounding of the interval. ``t[0]`` for
        a record of zeros.
    """
    from scipy.optimize import brentq

    if not 0.0 < fraction <= 1.0:
        raise InputError(f"expected a fraction of the Arias intensity in (0, 1], got {fraction:g}", field="fraction")
    t, acc = _record_arrays(t, acc)
    history = arias_history(t, acc)
    level = fraction * history[-1]
    if level == 0.0:
        return float(t[0])
    k = min(int(np.searchsorted(history, level, side="left")), t.size - 1)  # history[k-1] < level <= history[k]
    h = t[k] - t[k - 1]
    a0 = acc[k - 1]
    m = (acc[k] - a0) / h
    A, B, C = np.sum(a0 * a0), 2.0 * np.sum(a0 * m), np.sum(m * m)
    need = (level - history[k - 1]) / (history[k] - history[k - 1]) * (A * h + B * h * h / 2.0 + C * h**3 / 3.0)
    s = brentq(lambda x: x * (A + x * (B / 2.0 + x * C / 3.0)) - need, 0.0, h, xtol=4.0 * np.finfo(float).eps * max(t[k], h))
    return float(t[k - 1] + s)


@dataclass(frozen=True)
class StrongMotion:
    """Where the shaking of a record lies in time.

    Attributes
    ----------
    arias : float
        Arias intensity of the whole record [m/s] (components summed).
    arias95_time : float
        Time at which the Arias intensity reaches 95 % of ``arias`` [s]: the
        end of the strong motion.
    peak_time : float
        Time of the largest |acceleration| of any component [s] (the first, on
        a tie): where the record's PGA is.
    """

    arias: float
    arias95_time: float
    peak_time: float


def strong_motion(motion) -> StrongMotion:
    """:class:`StrongMotion` of a GroundMotion or a GroundMotionPair, on its own samples (as scaled)."""
    t, acc = _record_arrays(motion.t, motion.acc)
    peak = int(np.argmax(np.max(np.abs(acc), axis=1)))
    return StrongMotion(arias=float(arias_history(t, acc)[-1]), arias95_time=arias_time(t, acc, 0.95),
                        peak_time=float(t[peak]))
