"""The chatter test's Zeno bound (:func:`pounding.framework.engine.held.chatter_duration`).

After a rebound at opening speed r = w . q' against a closing relative acceleration a = -w . q'', a
restitution k gives impacts that accumulate within 2 r / (a (1 - k)) (the geometric series of the
rebound times); the bound of a struck pair is the shortest over its touching features that close.
Checked against that formula written with numpy at every pair the paper's pair strikes."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pounding.framework.engine import pairs as pg
from pounding.framework.engine.driver import Driver
from pounding.framework.engine.held import chatter_duration
from pounding.io.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
EPS = np.finfo(float).eps


def _numpy_bound(d: Driver, p: int, t: float, k: float):
    """The bound [s] by the formula with numpy, and its rounding allowance [s]: each dot product of n terms
    is rounded to n eps of the sum of its terms' magnitudes, so the bound moves by at most that relative to
    r and to a, plus a few roundings of the quotient."""
    m = d.model
    q = np.ascontiguousarray(d.z[:, 0])
    touching = pg.pair_features(q, p, d.tol, m.n, m.geo)
    count, W = touching.count, touching.W
    if count == 0:
        return np.inf, 0.0
    acc = d.load(t) + d.fc - m.c2 * d.z[:, 1] - m.om2 * q
    W = W[:count]
    r, a = W @ d.z[:, 1], -(W @ acc)
    close = a > 0.0
    if k >= 1.0 or not np.any(close):
        return np.inf, 0.0
    bound = 2.0 * np.maximum(r, 0.0) / (a * (1.0 - k))
    j = int(np.argmin(np.where(close, bound, np.inf)))
    rel = m.n * EPS * (np.abs(W[j] * d.z[:, 1]).sum() / max(abs(r[j]), 1e-300) + np.abs(W[j] * acc).sum() / abs(a[j])) + 8 * EPS
    return float(bound[j]), float(bound[j] * rel)


def test_the_compiled_bound_is_the_formula_at_every_struck_pair():
    """At every impact of the paper's pair (8 s of El Centro, the crossing locator), the compiled bound of the
    struck pair equals the numpy formula to its rounding, and the chatter decision (bound < dt) is the same."""
    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=8.0)
    seen = []
    original = Driver.chatters

    def checked(self, p, t):
        k = float(self.laws[self.pair_law[p]].restitution)
        new = chatter_duration(self.z, np.ascontiguousarray(self.load(t) + self.fc, dtype=float), int(p), k, float(self.tol),
                               self.model.modes, self.model.geo)
        old, allowance = _numpy_bound(self, p, t, k)
        seen.append((new, old, allowance))
        return original(self, p, t)

    Driver.chatters = checked
    try:
        result = Driver(scene).run()
    finally:
        Driver.chatters = original
    assert 10 < len(seen) <= len(result.impacts)  # (one test per struck pair; an event may strike a pair at several points)
    for new, old, allowance in seen:
        assert new == old if np.isinf(old) else abs(new - old) <= allowance, (new, old, allowance)
        assert (new < result.dt) == (old < result.dt)


def test_no_sequence_ends_without_restitution_below_one_or_a_closing_feature():
    """k = 1 never ends (inf); a pair with no touching feature has no sequence (inf); a closing acceleration
    that points apart at every feature (a <= 0) gives none either."""
    scene = load_scene(ROOT / "examples" / "paper" / "pair_gap_0.03.toml").with_analysis(duration=0.1)
    d = Driver(scene)
    d.run()
    z, m = np.ascontiguousarray(d.z), d.model
    far = np.zeros(m.n)
    assert chatter_duration(z, far, 0, 1.0, float(d.tol), m.modes, m.geo) == np.inf
    assert chatter_duration(z, far, 0, 0.5, float(d.tol), m.modes, m.geo) == np.inf  # at rest 0.03 m apart: nothing touches
