"""Third-party contact laws, as a plugin author writes them: one module, written from
:class:`pounding.contact.base.ContactLaw` alone, used by class, as ``"contact_plugins:Hertz"``
from a scene, or for one pair of buildings (``[[contact]]``).

Both are force laws: given the step's :class:`~pounding.contact.base.ContactState`, each point's
force lambda_j >= 0 [N] is solved with the step, its penetration at the step's end being
``delta = -(gap + S_q @ lambda)`` and its rate ``delta' = -(rate + S_v @ lambda)``. For each point
the force the law asks for falls as lambda grows (delta and delta' fall), so its equation has
one root in [0, delta_j / S_q[j, j]], found by bracketing (Brent); points of one step are
coupled through S_q and S_v and solved in turn until no force moves (Gauss-Seidel, which
converges for the symmetric positive definite compliances of a step).

References: Hertz contact of spheres (Goldsmith, *Impact*, 1960); the Hertzdamp model,
Muthukumar, S. and DesRoches, R. (2006), Earthquake Eng. Struct. Dyn. 35, 811-828, with the
damping of Lankarani, H. M. and Nikravesh, P. E. (1990), J. Mech. Des. 112, 369-376.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from scipy.optimize import brentq

from pounding.contact.base import ContactLaw, ContactState
from pounding.errors import InputError


class Hertz(ContactLaw):
    """Elastic Hertz contact, F = k_h delta^1.5 (no damping: restitution 1).

    Parameters
    ----------
    stiffness : float
        Hertz stiffness k_h [N/m^1.5].
    restitution : float
        Accepted (every law takes it) and unused: the contact is elastic.
    """

    name: ClassVar[str] = "hertz"
    kind: ClassVar[str] = "force"

    def __init__(self, *, stiffness: float = 2.75e9, restitution: float = 1.0):
        super().__init__(restitution=restitution)
        if not (isinstance(stiffness, (int, float)) and stiffness > 0):
            raise InputError(f"expected a positive Hertz stiffness [N/m^1.5], got {stiffness!r}", field="stiffness")
        self.stiffness = float(stiffness)

    def point_force(self, delta: float, rate: float, contact: ContactState, j: int) -> float:
        """The force [N] the law asks for at point j with penetration delta [m] and its rate [m/s]."""
        return self.stiffness * max(delta, 0.0) ** 1.5

    def forces(self, contact: ContactState) -> np.ndarray:
        c = contact
        m = len(c.gap)
        lam = np.zeros(m)
        for _ in range(100):
            change = 0.0
            for j in range(m):
                others = c.S_q[j] @ lam - c.S_q[j, j] * lam[j], c.S_v[j] @ lam - c.S_v[j, j] * lam[j]
                d0, r0 = -(c.gap[j] + others[0]), -(c.rate[j] + others[1])
                if d0 <= 0.0:  # apart with the other points' forces: no force
                    new = 0.0
                elif c.S_q[j, j] == 0.0:  # the force at a given state (forces rebuilt after a run)
                    new = self.point_force(d0, r0, c, j)
                else:
                    def residual(x):
                        return x - self.point_force(d0 - c.S_q[j, j] * x, r0 - c.S_v[j, j] * x, c, j)

                    hi = d0 / c.S_q[j, j]  # the force that closes the penetration alone
                    new = 0.0 if residual(0.0) >= 0.0 else brentq(residual, 0.0, hi, xtol=1e-14 * hi, rtol=1e-15)
                change = max(change, abs(new - lam[j]))
                lam[j] = new
            if change <= 1e-13 * max(lam.max(initial=0.0), 1e-300):
                break
        return lam


class Hertzdamp(Hertz):
    """Hertz contact with damping that depends on the contact's history:

        F = k_h delta^n (1 + xi delta' / delta'_0),   xi = 3 (1 - e^2) / 4,   F >= 0

    where delta'_0 is the closing speed when the contact began (``ContactState.approach``) and
    e the restitution; the dissipated energy per impact follows from e (Lankarani and
    Nikravesh, for e near 1).

    Parameters
    ----------
    stiffness : float
        Hertz stiffness k_h [N/m^n].
    exponent : float
        n [-] (1.5: Hertz).
    restitution : float
        Coefficient of restitution e in (0, 1].
    """

    name: ClassVar[str] = "hertzdamp"

    def __init__(self, *, stiffness: float = 2.75e9, exponent: float = 1.5, restitution: float = 0.8):
        super().__init__(stiffness=stiffness, restitution=restitution)
        self.exponent = float(exponent)
        self.xi = 0.75 * (1.0 - self.restitution**2)
        #: the approach speeds the law was given (private: describe() leaves it out of summary.json)
        self._approaches: set[float] = set()

    def point_force(self, delta: float, rate: float, contact: ContactState, j: int) -> float:
        v0 = float(contact.approach[j])
        self._approaches.add(v0)
        if delta <= 0.0 or v0 <= 0.0:
            return self.stiffness * max(delta, 0.0) ** self.exponent
        return max(self.stiffness * delta**self.exponent * (1.0 + self.xi * rate / v0), 0.0)


class NewtonInPython(ContactLaw):
    """Newton's impulse law written from the base class alone: the impulses of a group of touching
    features solve the Newton problem with restitution e (the public
    :func:`~pounding.contact.base.newton_impulses`). It does not declare ``compiled_impulses``, so
    the engine calls its ``impulses`` from Python: the same rule as the built-in ``impulse`` law,
    reached through the plugin path."""

    name: ClassVar[str] = "newton_in_python"
    kind: ClassVar[str] = "impulse"

    def impulses(self, W: np.ndarray, b: np.ndarray) -> np.ndarray:
        from pounding.contact.base import newton_impulses

        return newton_impulses(W, b, self.restitution)


class ElasticPlastic(ContactLaw):
    """An elastic-perfectly-plastic contact spring with a plastic set, a law with a state of its own
    (OpenSees' ``ImpactMaterial`` with no hardening):

        F = min(k (delta - delta_p), F_y),   F >= 0,

    delta_p [m] the point's plastic set: a committed step that presses the point beyond
    delta_p + F_y / k moves it to delta - F_y / k, and the point reloads elastically from it. The
    law keeps delta_p point by point (``ContactState.point``), reads it in every trial
    (:meth:`forces`, which changes nothing) and moves it only in :meth:`commit`, with the step the
    engine accepted.

    Parameters
    ----------
    stiffness : float
        k [N/m].
    yield_force : float
        F_y [N].
    restitution : float
        Accepted (every law takes it) and unused: the loss follows from k and F_y.
    """

    name: ClassVar[str] = "elastic_plastic"
    kind: ClassVar[str] = "force"
    keeps_state: ClassVar[bool] = True

    def __init__(self, *, stiffness: float = 1e9, yield_force: float = 1e6, restitution: float = 0.5):
        super().__init__(restitution=restitution)
        for field, value in (("stiffness", stiffness), ("yield_force", yield_force)):
            if not (isinstance(value, (int, float)) and value > 0):
                raise InputError(f"expected a positive {field.replace('_', ' ')}, got {value!r}", field=field)
        self.stiffness, self.yield_force = float(stiffness), float(yield_force)
        #: committed plastic set [m] by point (private: describe() leaves it out of summary.json)
        self._plastic: dict[tuple, float] = {}
        self._commits = self._trials = 0  # calls of commit() and of forces()

    def plastic_set(self, point) -> float:
        """The committed plastic set [m] of ``point`` (pair, striking slab, vertex)."""
        return self._plastic.get(tuple(int(x) for x in point), 0.0)

    def point_force(self, delta: float, contact: ContactState, j: int) -> float:
        """The force [N] at point j pressed to delta [m], from its committed plastic set."""
        spring = self.stiffness * (delta - self.plastic_set(contact.point[j]))
        return min(max(spring, 0.0), self.yield_force)

    def forces(self, contact: ContactState) -> np.ndarray:
        self._trials += 1
        c = contact
        share = np.ones(len(c.gap)) if c.share is None else c.share
        lam = np.zeros(len(c.gap))
        for _ in range(100):  # Gauss-Seidel over the points, each root by bracketing (as Hertz)
            change = 0.0
            for j in range(len(c.gap)):
                d0 = -(c.gap[j] + c.S_q[j] @ lam - c.S_q[j, j] * lam[j])
                hi = max(d0, 0.0) / c.S_q[j, j] if c.S_q[j, j] > 0.0 else np.inf  # the force that closes the penetration alone

                def residual(x):
                    return x - share[j] * self.point_force(d0 - c.S_q[j, j] * x, c, j)

                if d0 <= 0.0 or residual(0.0) >= 0.0:
                    new = 0.0
                elif c.S_q[j, j] == 0.0:  # the force at a given state (forces rebuilt after a run)
                    new = share[j] * self.point_force(d0, c, j)
                else:
                    new = brentq(residual, 0.0, hi, xtol=1e-14 * hi, rtol=1e-15)
                change = max(change, abs(new - lam[j]))
                lam[j] = new
            if change <= 1e-13 * max(lam.max(initial=0.0), 1e-300):
                break
        return lam

    def commit(self, contact: ContactState, forces: np.ndarray) -> None:
        self._commits += len(contact.gap) > 0  # (the commit with no point after the last let go is not counted)
        delta = -(contact.gap + contact.S_q @ forces)  # the accepted end penetrations
        for j, d in enumerate(delta):
            key = tuple(int(x) for x in contact.point[j])
            if self.stiffness * (d - self.plastic_set(key)) > self.yield_force:
                self._plastic[key] = float(d) - self.yield_force / self.stiffness
