"""Lognormal fragility curves fitted by maximum likelihood to multiple-stripe data.

A fragility curve gives the probability of an event (here: the two buildings
pound) given the intensity measure x of the shaking,

    P(event | IM = x) = Phi(ln(x / theta) / beta),

with median ``theta`` (in the units of x) and logarithmic dispersion
``beta`` (> 0). In a multiple-stripe analysis every record is scaled to each
of the levels x_j and the event is observed in z_j of the n_j runs at level
j. The counts are binomial, so the parameters maximise (Baker 2015, eq. 11)

    L(theta, beta) = prod_j  C(n_j, z_j) p_j^z_j (1 - p_j)^(n_j - z_j),
    p_j = Phi(ln(x_j / theta) / beta).

Written as a probit regression, p_j = Phi(a + b ln x_j) with b = 1 / beta and
a = -ln(theta) / beta, the log-likelihood is concave in (a, b): it has at most
one maximum, found here by a trust-region Newton method
(:func:`scipy.optimize.minimize`, ``trust-exact``) on the analytic gradient
and Hessian. The maximum is finite if and only if the data are not
separated: when every level with an event lies at or above every level with a
non-event, the likelihood keeps growing as beta -> 0 and no finite MLE exists
(:func:`separation` names the case; the fit is then not reported).

Confidence bounds: Wald intervals from the observed information (the
negative Hessian of the log-likelihood at the maximum, inverted), carried to
``ln theta = -a / b`` and ``ln beta = -ln b`` by the delta method and
exponentiated, so the bounds of theta and beta are positive and asymmetric.
They are asymptotic (many runs per level); with few records they are
indicative only.

Reference: J. W. Baker (2015), Efficient analytical fragility function
fitting using dynamic structural analysis, Earthquake Spectra 31(1), 579-599.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["LognormalFit", "fit_lognormal", "log_likelihood", "separation"]


@dataclass(frozen=True)
class LognormalFit:
    """A fitted lognormal fragility; NaN parameters unless ``status == "ok"``.

    ``median`` and its bounds in the units of the intensity measure,
    ``beta`` and its bounds dimensionless; ``level`` is the confidence level
    of the bounds (two-sided). ``status``: ``"ok"``, ``"none"`` (no event at
    any level), ``"all"`` (events in every run), ``"separated"`` (events only
    at levels above all non-events: beta -> 0, no finite maximum),
    ``"decreasing"`` (the maximum has beta < 0: fewer events at higher
    intensity), ``"flat"`` (the same fraction at every level: beta -> inf), ``"one level"`` (two parameters cannot be fitted to one level)
    or ``"failed"`` (the optimiser did not converge).
    """

    median: float
    beta: float
    median_lo: float
    median_hi: float
    beta_lo: float
    beta_hi: float
    status: str
    level: float = 0.95
    log_likelihood: float = math.nan

    def probability(self, x) -> np.ndarray:
        """P(event | IM = x) of the fitted curve, x > 0 (array_like)."""
        from scipy.special import ndtr

        x = np.asarray(x, dtype=float)
        return ndtr(np.log(x / self.median) / self.beta)


def _exp(v: float) -> float:
    """exp, inf beyond the float range (a bound of a nearly separated fit)."""
    return math.exp(v) if v < 709.0 else math.inf


def _nan_fit(status: str, level: float) -> LognormalFit:
    nan = math.nan
    return LognormalFit(nan, nan, nan, nan, nan, nan, status, level)


def separation(x, n, z) -> str | None:
    """Why no finite MLE exists for the counts, or None if one does.

    Parameters
    ----------
    x : array_like (m,)
        Intensity levels (> 0).
    n, z : array_like (m,)
        Runs and events per level (0 <= z <= n, n >= 1).
    """
    x, n, z = (np.asarray(v, dtype=float) for v in (x, n, z))
    if len(np.unique(x)) < 2:
        return "one level"
    if np.all(z == 0):
        return "none"
    if np.all(z == n):
        return "all"
    with_event = x[z > 0]
    with_non_event = x[z < n]
    if with_non_event.max() <= with_event.min():
        return "separated"
    if with_event.max() <= with_non_event.min():
        return "decreasing"
    return None


def _parts(theta: np.ndarray, t: np.ndarray, n: np.ndarray, z: np.ndarray):
    """Log-likelihood (without the binomial constants), gradient and Hessian in (a, b), eta = a + b t."""
    from scipy.special import log_ndtr

    eta = theta[0] + theta[1] * t
    lp, lq = log_ndtr(eta), log_ndtr(-eta)
    logphi = -0.5 * eta * eta - 0.5 * math.log(2.0 * math.pi)
    lam_p = np.exp(logphi - lp)  # phi / Phi(eta), the inverse Mills ratio
    lam_q = np.exp(logphi - lq)  # phi / Phi(-eta)
    ll = float(np.sum(z * lp + (n - z) * lq))
    d1 = z * lam_p - (n - z) * lam_q
    d2 = -z * lam_p * (eta + lam_p) - (n - z) * lam_q * (lam_q - eta)  # <= 0: concave
    X = np.stack([np.ones_like(t), t])
    grad = X @ d1
    hess = (X * d2) @ X.T
    return ll, grad, hess


def log_likelihood(x, n, z, median: float, beta: float) -> float:
    """The binomial log-likelihood of the counts under a lognormal fragility, with the binomial constants."""
    from scipy.special import gammaln

    x, n, z = (np.asarray(v, dtype=float) for v in (x, n, z))
    ll, _, _ = _parts(np.array([-math.log(median) / beta, 1.0 / beta]), np.log(x), n, z)
    return ll + float(np.sum(gammaln(n + 1) - gammaln(z + 1) - gammaln(n - z + 1)))


def fit_lognormal(x, n, z, *, level: float = 0.95) -> LognormalFit:
    """Maximum-likelihood lognormal fragility from multiple-stripe counts (Baker 2015).

    Parameters
    ----------
    x : array_like (m,)
        Intensity levels, > 0, in any unit (the median comes back in it).
    n : array_like (m,)
        Number of runs at each level, >= 1.
    z : array_like (m,)
        Number of runs with the event at each level, 0 <= z <= n.
    level : float
        Two-sided confidence level of the Wald bounds.

    Returns
    -------
    LognormalFit
        See the module docstring for the method and the bounds.
    """
    from scipy.optimize import minimize
    from scipy.special import gammaln, ndtri

    x, n, z = (np.asarray(v, dtype=float) for v in (x, n, z))
    if x.ndim != 1 or not (x.shape == n.shape == z.shape) or np.any(x <= 0) or np.any(n < 1) or np.any((z < 0) | (z > n)):
        raise ValueError("expected levels x > 0, runs n >= 1 and events 0 <= z <= n, one of each per level")
    why = separation(x, n, z)
    if why is not None:
        return _nan_fit(why, level)
    lx = np.log(x)
    centre = float(np.average(lx, weights=n))
    scale = float(np.sqrt(np.average((lx - centre) ** 2, weights=n)))
    t = (lx - centre) / scale  # centred and scaled: the Hessian is well conditioned
    # start: a straight line through the probits of the (shrunk) observed fractions
    p0 = (z + 0.5) / (n + 1.0)
    slope, icpt = np.polyfit(t, ndtri(p0), 1, w=np.sqrt(n))
    start = np.array([icpt, max(slope, 0.1)])

    def neg(th):
        ll, g, h = _parts(th, t, n, z)
        return -ll, -g, -h

    res = minimize(lambda th: neg(th)[0], start, jac=lambda th: neg(th)[1], hess=lambda th: neg(th)[2], method="trust-exact",
                   options={"gtol": 1e-10, "maxiter": 200})
    a_c, b_c = res.x
    ll, g, h = _parts(res.x, t, n, z)
    if not np.all(np.isfinite(res.x)) or np.max(np.abs(g)) > 1e-6 * max(1.0, float(n.sum())):
        return _nan_fit("failed", level)
    if b_c <= 0:
        return _nan_fit("decreasing", level)
    if b_c < 1e-8:  # the fraction does not change with the intensity: theta -> 0 or inf, beta -> inf
        return _nan_fit("flat", level)
    # back to eta = a + b ln x: b = b_c / scale, a = a_c - b centre
    b = b_c / scale
    a = a_c - b * centre
    cov_c = np.linalg.inv(-h)  # covariance of (a_c, b_c)
    # (ln theta, ln beta) = (-a/b, -ln b) = (centre - a_c scale / b_c, ln scale - ln b_c)
    J = np.array([[-scale / b_c, a_c * scale / b_c**2], [0.0, -1.0 / b_c]])
    cov = J @ cov_c @ J.T
    zq = float(ndtri(0.5 + level / 2.0))
    ln_theta, ln_beta = -a / b, -math.log(b)
    se_t, se_b = math.sqrt(max(cov[0, 0], 0.0)), math.sqrt(max(cov[1, 1], 0.0))
    median, beta = math.exp(ln_theta), math.exp(ln_beta)
    return LognormalFit(median, beta, _exp(ln_theta - zq * se_t), _exp(ln_theta + zq * se_t),
                        _exp(ln_beta - zq * se_b), _exp(ln_beta + zq * se_b), "ok", level,
                        ll + float(np.sum(gammaln(n + 1) - gammaln(z + 1) - gammaln(n - z + 1))))


def pounding_probability(required, gaps) -> np.ndarray:
    """Fraction of runs that pound at each gap: ``mean(required >= g)``.

    Parameters
    ----------
    required : array_like (n,)
        Required gaps of the contact-free runs [m].
    gaps : array_like (m,)
        Clear distances [m].

    Returns
    -------
    ndarray (m,)
    """
    r = np.sort(np.asarray(required, dtype=float))
    g = np.asarray(gaps, dtype=float)
    if r.size == 0:
        return np.full(g.shape, np.nan)
    return (r.size - np.searchsorted(r, g, side="left")) / r.size
