"""Contact episodes that converge with the time step: a pair's chatter counted as one contact.

Two slabs that strike often rebound a little and strike again, ever more softly, before they
part (chatter; for the impulse law, a Zeno sequence of micro-impacts whose rebound speeds fall by
the restitution at each). How many of those micro-impacts a run resolves depends on its step:
the impulse law holds a sequence in contact once its remaining duration is shorter than a step
(on the paper's pair, 61, 67, 84, 93 and 102 impacts at dt = 0.01, 0.005, 0.002, 0.001 and
0.0005 s), while the response, the impulse the slabs exchange and the energy lost converge. The
quantity that converges with them is the *contact episode*: a maximal stretch of time in which
a pair is in contact or chattering.

The rule (one for every contact law): a pair's strikes (an impulse law's impacts, each an
instant, and a force law's stretches of touching) form one episode while each begins less than
``CHATTER_FRACTION`` of the pair's faster fundamental period after the previous one ended:

    tau = CHATTER_FRACTION * min(T1 of the pair's two buildings)

Why that scale: a fresh approach needs the slabs to part and come back through the buildings'
own vibration, which takes about half a fundamental period of the faster building (0.29 s on the
paper's pair); a strike much sooner than that is the previous one's rebound pulled back. Chatter
intervals shrink geometrically (by the restitution, for a steady pull), so once one interval is
below tau the rest of the sequence merges, and the micro-impacts that a finer step resolves all
fall inside it. On the paper's pair at 0.03 m the intervals between one pair's impacts are either
below 52 ms (chatter) or above 119 ms (fresh approaches) at every step from 0.01 to 0.0005 s;
tau = T1 / 8 = 73 ms (T1 = 0.58 s) sits between them, and the episodes number 19 at every one of
those steps. The count changes with dt only when an interval crosses tau, that is when an impact
instant moves by the interval's distance to tau (here at least 21 ms, against impact instants
that move by less than 1 ms between those steps).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

#: the merge interval as a fraction of the pair's faster fundamental period (see the module docstring)
CHATTER_FRACTION = 1.0 / 8.0

#: what converges with the time step and what does not (summary.json ``convergence``, ``pounding run``)
CONVERGES_WITH_DT = ("peak displacements", "drift ratios", "storey shears", "floor accelerations",
                     "impulse totals", "energy lost in contact", "contact episodes")
#: and what does not
DEPENDS_ON_DT = ("number of impacts (the micro-impacts of a chatter: more as dt falls)",)


def merge_intervals(systems, pairs: list) -> np.ndarray:
    """tau [s] (P,) of every pair: CHATTER_FRACTION of the faster fundamental period of its two
    buildings (``pairs``: (building a, storey a, building b, storey b, rest gap); ``systems``: the
    buildings' modal systems, each with ``periods`` (longest first))."""
    t1 = [float(np.max(s.periods)) if len(s.periods) else math.inf for s in systems]
    return np.array([CHATTER_FRACTION * min(t1[a], t1[b]) for a, _, b, _, _ in pairs], dtype=float)


def merge_chatter(strikes: list, tau: np.ndarray) -> list:
    """The contact episodes (:class:`~pounding.framework.engine.results.ContactEpisode`) of a run's
    strikes: the strikes of one pair merged while each begins less than ``tau[pair]`` [s] after
    the previous one ended (see the module docstring); by start time.

    A merged episode starts with its first strike and ends with the last one's end; its point,
    normal and approach speed are its first strike's; its peak force and penetration the largest
    of its strikes' (nan when none has a force: impulses); its impulse and the energy it
    dissipated the sums; ``strikes`` counts what it merged.
    """
    by_pair: dict[int, list] = {}
    for e in sorted(strikes, key=lambda e: (e.start, e.end)):
        by_pair.setdefault(int(e.pair), []).append(e)
    out = []
    for p, seq in by_pair.items():
        group = [seq[0]]
        end = seq[0].end
        for e in seq[1:]:
            if e.start - end < tau[p]:
                group.append(e)
            else:
                out.append(_merged(group))
                group = [e]
            end = max(end, e.end)
        out.append(_merged(group))
    return sorted(out, key=lambda e: (e.start, e.pair))


def _merged(group: list):
    """One episode of the strikes ``group`` (by start) of one pair."""
    first = group[0]
    if len(group) == 1:
        return first
    forces = [e.peak_force for e in group if not math.isnan(e.peak_force)]
    return replace(first, end=max(e.end for e in group), peak_force=max(forces) if forces else math.nan,
                   peak_penetration=max(e.peak_penetration for e in group), impulse=float(sum(e.impulse for e in group)),
                   energy_dissipated=float(sum(e.energy_dissipated for e in group)), strikes=int(sum(e.strikes for e in group)))
