"""Two free bodies on a line meeting at a contact, stepped with a force law's own solve.

The test harness of the contact laws (tests/test_contact_laws.py): body 1 (mass m1, at x1,
velocity v1) approaches body 2 (m2, x2, v2) from the left; the gap is x2 - x1. Each step is
Newmark's average acceleration (trapezoidal) on the two free masses, with the contact force
lambda (pushing them apart) at the step's end solved implicitly by the law, exactly as the
engine gives it (the contact state of the contact-law contract, :class:`Contact`): the step's
end gap and rate without the end force, and their compliances

    S_q = h^2 / 4 * a,    S_v = h / 2 * a,    a = 1/m1 + 1/m2 = W (the Delassus entry).

The contact's approach speed is the closing speed when the gap first closes (constant before:
the bodies fly freely). A law that keeps a state of its own (``keeps_state``: a plastic set) is
given the contact point's identity and committed as the driver commits it
(:func:`pounding.framework.engine.contact_laws.commit_laws`): at every step that presses the
point, with the forces solved, and once with no point at the first step after it let go; its state
carries over to a later call with the same law instance (a second collision).
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np


@dataclass
class Stepped:
    """Histories of a stepped contact: t (N,) [s], gap (N,) [m], force (N,) [N], v1, v2 (N,) [m/s]."""

    t: np.ndarray
    gap: np.ndarray
    force: np.ndarray
    v1: np.ndarray
    v2: np.ndarray

    def rebound(self) -> float:
        """Separation speed over approach speed [-]: (v2 - v1) at the end over (v1 - v2) at the start."""
        return float((self.v2[-1] - self.v1[-1]) / (self.v1[0] - self.v2[0]))


#: the identity (pair, striking slab, vertex) of the one contact point, for a law that keeps a state
POINT = (0, 0, 0)


def contact(gap, rate, S_q, S_v, W, pair, approach, share=None, *, t=0.0, dt=0.0, point=None):
    """The contact state a force law is given (the fields of the contact-law contract it reads);
    ``share`` (m,) the share of a whole contact of each point (None: every point a whole contact);
    ``t`` [s] the step's end and ``dt`` [s] its length; ``point`` (m, 3) the points' identities
    (None: no law of the run keeps a state)."""
    arr = lambda x: np.atleast_1d(np.asarray(x, dtype=float))  # noqa: E731
    mat = lambda x: np.atleast_2d(np.asarray(x, dtype=float))  # noqa: E731
    return SimpleNamespace(gap=arr(gap), rate=arr(rate), S_q=mat(S_q), S_v=mat(S_v), W=mat(W),
                           pair=np.atleast_1d(np.asarray(pair, dtype=np.int64)), approach=arr(approach),
                           share=None if share is None else arr(share), t=float(t), dt=float(dt),
                           point=None if point is None else np.atleast_2d(np.asarray(point, dtype=np.int64)))


def step_two_bodies(law, *, m1: float, m2: float, v1: float, v2: float, h: float, gap0: float = 0.0,
                    t_max: float = 1.0) -> Stepped:
    """Step the two bodies from gap ``gap0`` [m] (>= 0) until they are apart again after a contact
    (or ``t_max`` [s]); ``h`` the step [s]. A law that keeps a state is committed every step
    (module docstring)."""
    from pounding.contact.base import ContactState

    keeps = bool(getattr(law, "keeps_state", False))
    a = 1.0 / m1 + 1.0 / m2
    x1, x2 = 0.0, gap0
    lam0, approach, touched = 0.0, 0.0, False
    t_hist, g_hist, f_hist, v1_hist, v2_hist = [0.0], [gap0], [0.0], [v1], [v2]
    t, pressed = 0.0, False
    while t < t_max:
        # the free step (the start force lam0 in it, none at the end)
        v1f, v2f = v1 - 0.5 * h * lam0 / m1, v2 + 0.5 * h * lam0 / m2
        x1f, x2f = x1 + h * v1 - 0.25 * h * h * lam0 / m1, x2 + h * v2 + 0.25 * h * h * lam0 / m2
        gap, rate = x2f - x1f, v2f - v1f
        lam = 0.0
        if gap < 0.0:
            if not touched:
                touched, approach = True, v1 - v2
            c = contact(gap, rate, 0.25 * h * h * a, 0.5 * h * a, a, 0, approach, t=t + h, dt=h,
                        point=[POINT] if keeps else None)
            lam = float(law.forces(c)[0])
            if keeps:  # the step is accepted: the law keeps its point's state at the forces solved
                law.commit(c, np.array([lam]))
        elif keeps and pressed:  # the first step after the point let go: one commit with no point
            law.commit(ContactState.empty(t + h, h), np.zeros(0))
        pressed = gap < 0.0
        v1, v2 = v1f - 0.5 * h * lam / m1, v2f + 0.5 * h * lam / m2
        x1, x2 = x1f - 0.25 * h * h * lam / m1, x2f + 0.25 * h * h * lam / m2
        t += h
        lam0 = lam
        t_hist.append(t), g_hist.append(x2 - x1), f_hist.append(lam), v1_hist.append(v1), v2_hist.append(v2)
        if touched and x2 - x1 > 0.0 and lam == 0.0:
            break
    return Stepped(np.array(t_hist), np.array(g_hist), np.array(f_hist), np.array(v1_hist), np.array(v2_hist))
