"""Contact episodes of force laws: each pair's history, given to the law, and what it reports.

A slab pair under a force law is *in contact* from the step its gap first closes until the
first step that ends with its slabs apart and pushing on nothing: one *episode*
(:class:`~pounding.framework.engine.results.ContactEpisode`). While it lasts, the law is given the
episode's history with every step's state (:class:`~pounding.contact.base.ContactState`:
when it began, the closing speed then, the pair); when it ends, the episode's figures are
what the law reports, in the same table as an impulse law's impacts.

The start is where the gap crosses zero inside the step it first closed, interpolated
linearly between the step's start and its end without contact forces (the trajectory before
the crossing carries no contact force); the closing speed there likewise. The end is
interpolated the same way between the last penetration and the first opening gap.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.engine.results import ContactEpisode


@dataclass
class _Open:
    """An episode that has not ended yet (figures so far)."""

    start: float
    approach: float
    peak_force: float = 0.0
    peak_penetration: float = 0.0
    impulse: float = 0.0
    work: float = 0.0  # work of the pair's forces on the buildings so far [J]
    at_peak: tuple | None = None  # (forces (k,), points (k, 2), normals (k, 2)) of the pair's points at the peak
    force: float = 0.0  # total force at the last step end [N]
    modal: np.ndarray | None = None  # modal force (n,) at the last step end
    penetration: float = 0.0  # deepest overlap at the last step end [m]


@dataclass
class StepContacts:
    """What a trial step of a force law found, kept with it until it is committed.

    pair (m,) int, forces (m,) [N], end gaps with the forces (m,) [m], points and normals (m, 2),
    modal rows (m, n), the history given to the law (start, approach (m,)), and the pairs and end
    gaps without forces of every feature within the watch tolerance (``near``, ``near_gap`` (k,)).
    """

    pair: np.ndarray
    force: np.ndarray
    gap: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    rows: np.ndarray
    start: np.ndarray
    approach: np.ndarray
    near: np.ndarray
    near_gap: np.ndarray
    modal: np.ndarray | None = None  # the modal force of all the points (n,): rows.T @ force
    #: the :class:`~pounding.contact.base.ContactState` the forces were solved from (None: no point pressed)
    state: object = None

    @classmethod
    def empty(cls, near: np.ndarray, near_gap: np.ndarray, n: int) -> "StepContacts":
        """A step where no point overlaps (near, near_gap: the features within the watch tolerance; n modes)."""
        z = np.zeros(0)
        return cls(np.zeros(0, dtype=np.int64), z, z, np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, n)), z, z, near, near_gap)

    def end_gap(self, p: int) -> float:
        """Pair p's smallest gap at the step's end [m] among the features within the watch tolerance (inf: none)."""
        sel = self.near == p
        return float(self.near_gap[sel].min()) if np.any(sel) else np.inf


def _by_pair(pair: np.ndarray):
    """(pair, selector) of every pair among the points ``pair`` (m,): a slice over all of them when
    there is one pair (the common case, without masks), else a boolean mask."""
    ids = pair.tolist()  # a handful of points: Python's set is cheaper than numpy's reductions here
    if not ids:
        return []
    if len(set(ids)) == 1:
        return [(ids[0], slice(None))]
    return [(p, pair == p) for p in dict.fromkeys(ids)]


def crossing(t: float, h: float, g0: float, g1: float) -> tuple[float, float]:
    """(time [s], fraction of the step) where a gap going linearly from g0 [m] at t to g1 at t + h
    crosses zero (the step's start when it is already <= 0 there, its end when it never does)."""
    if g0 <= 0.0:
        return t, 0.0
    if g1 >= 0.0:
        return t + h, 1.0
    s = g0 / (g0 - g1)
    return t + s * h, s


class Episodes:
    """The force-law episodes of a run: the open ones by pair, and the ended ones."""

    def __init__(self):
        self.open: dict[int, _Open] = {}
        self.ended: list[ContactEpisode] = []

    def history(self, t: float, h: float, pair: np.ndarray, closing) -> tuple[np.ndarray, np.ndarray]:
        """Start [s] and closing speed at the start [m/s] (m,) of each point's episode, for a step
        from t [s] of h [s]: an open episode's own, or for a pair that closes in this step, the
        crossing of its deepest point, from ``closing()`` = (gap0, gap1, b0, b1) (m,) each: the
        points' gaps at the step's start and at its end without contact forces, and their closing
        speeds there (asked for only when a pair closes)."""
        start, approach = np.empty(len(pair)), np.empty(len(pair))
        for p, sel in _by_pair(pair):
            ep = self.open.get(p)
            if ep is None:
                gap0, gap1, b0, b1 = closing()
                j = int(np.arange(len(pair))[sel][np.argmin(gap1[sel])])
                ts, s = crossing(t, h, float(gap0[j]), float(gap1[j]))
                start[sel], approach[sel] = ts, b0[j] + s * (b1[j] - b0[j])
            else:
                start[sel], approach[sel] = ep.start, ep.approach
        return start, approach

    def commit(self, t: float, h: float, contacts: StepContacts | None, dq: np.ndarray, gap_at=None) -> None:
        """Book a committed step from t [s] of h [s] that moved the modal displacements by dq (n,):
        open the episodes of pairs that press, add to the open ones, end those whose slabs parted
        (``gap_at(p)``: pair p's gap [m] at the step's end, asked for a pair that opened beyond the
        watch tolerance in the step, to interpolate its end).

        A step's work of a pair's forces is their mean over the step times its displacement,
        (f0 + f1) . dq / 2: the rule of the energy account of average acceleration (Newmark's
        default, the default integrator with force laws), so there the episodes' dissipation adds
        up to the account's contact work to rounding; other integrators' rules differ by O(dt^2)."""
        pressing = {} if contacts is None else self._pressing(contacts)
        for p in list(self.open):
            if p not in pressing:
                g1 = np.inf if contacts is None else contacts.end_gap(p)
                if not np.isfinite(g1) and gap_at is not None:
                    g1 = float(gap_at(p))
                self._end(p, t, h, g1, dq)
        for p, (idx, force, modal, pen) in pressing.items():
            ep = self.open.get(p)
            if ep is None:
                ep = self.open[p] = _Open(float(contacts.start[idx][0]), float(contacts.approach[idx][0]))
                f0 = 0.0
                m0 = None
            else:
                f0, m0 = ep.force, ep.modal
            ep.impulse += 0.5 * (f0 + force) * h
            ep.work += 0.5 * float(((0.0 if m0 is None else m0) + modal) @ dq)
            if force >= ep.peak_force:  # the point and normal are formed when the episode ends
                ep.peak_force = force
                ep.at_peak = (contacts.force[idx], contacts.point[idx], contacts.normal[idx])
            ep.peak_penetration = max(ep.peak_penetration, pen)
            ep.force, ep.modal, ep.penetration = force, modal, pen

    def close_all(self, t: float) -> None:
        """End the episodes still open at the end of the run (t [s])."""
        for p in list(self.open):
            self._end(p, t, 0.0, np.inf, None)

    @staticmethod
    def _pressing(c: StepContacts) -> dict:
        """{pair: (point indices, total force [N], modal force (n,), deepest overlap [m])} of the pairs
        that end the step overlapping or pushing."""
        out = {}
        for p, idx in _by_pair(c.pair):
            force = sum(c.force[idx].tolist())
            pen = max(-min(c.gap[idx].tolist()), 0.0)
            if force > 0.0 or pen > 0.0:
                whole = isinstance(idx, slice) and c.modal is not None
                out[p] = (idx, force, c.modal if whole else c.rows[idx].T @ c.force[idx], pen)
        return out

    def _end(self, p: int, t: float, h: float, g1: float, dq) -> None:
        """End pair p's episode in the step from t of h (displacement dq (n,), None: the run's end),
        where its gap opens to g1 [m] (inf: unknown, the step's end)."""
        ep = self.open.pop(p)
        if ep.peak_force <= 0.0 and ep.impulse == 0.0:
            # the outlines overlapped but the law never pushed (a plastic set wider than the overlap): no
            # contact, and no work (the force was zero throughout)
            return
        # the force falls to zero in this step, linearly as the driver applies it: its last share
        ep.impulse += 0.5 * ep.force * h
        if dq is not None and ep.modal is not None:
            ep.work += 0.5 * float(ep.modal @ dq)
        # where the gap, -penetration at t, opens to g1 at t + h (linearly) crosses zero
        end = t + h * ep.penetration / (ep.penetration + g1) if 0.0 < g1 < np.inf else t + h
        point, normal = _force_weighted(ep.at_peak)
        self.ended.append(ContactEpisode(ep.start, float(end), p, point, normal, ep.approach, ep.peak_force,
                                         ep.peak_penetration, ep.impulse, -ep.work))


def _force_weighted(at_peak) -> tuple[np.ndarray, np.ndarray]:
    """Point (2,) and unit normal (2,) of a pair at its peak: its points' means weighted by their
    forces (equal weights when none pushes; nan when it never pressed)."""
    if at_peak is None:
        return np.full(2, np.nan), np.full(2, np.nan)
    lam, points, normals = at_peak
    total = float(lam.sum())
    wts = lam / total if total > 0.0 else np.full(lam.size, 1.0 / lam.size)
    n = wts @ normals
    return wts @ points, n / max(float(np.hypot(*n)), 1e-300)
