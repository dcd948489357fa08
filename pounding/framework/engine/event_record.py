"""What a run's impulses did: its impacts grouped by instant and the modal velocity change of each.

Read from a :class:`~pounding.framework.engine.results.Result`'s event log (the state before every
instant's impulses, ``event_t``, ``event_q``, ``event_qd``) and its impacts; used by the true peaks
(:mod:`pounding.framework.engine.peaks`), the energy account and the impact forces.
"""

from __future__ import annotations

import numpy as np


def contact_row(result, q: np.ndarray, pair: int, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Modal row w (ntot,) of a contact at ``point`` [m] with unit ``normal`` (slab a -> b), modal state q.

    d gap = w . dq, and an impulse I pushing the slabs apart changes q' by w I
    (mass-normalised modes: w . w = sum(1/m + h^2/J), the paper's a). The run's own row
    (:func:`pounding.framework.engine.pairs.contact_row`, on the pair geometry ``result.geo``), so a
    facade pair's row is its storey shape's.
    """
    from pounding.framework.engine.pairs import pair_row

    if result.geo is None:
        raise ValueError("the result carries no pair geometry (Result.geo): build it with Driver.result or load_result")
    return pair_row(np.ascontiguousarray(q, dtype=float), int(pair), float(point[0]), float(point[1]), float(normal[0]), float(normal[1]),
                    result.geo)


def impact_instants(result) -> list[tuple[float, int, list[int]]]:
    """Impacts grouped by instant: (time [s], index into result.event_t, impact indices)."""
    where = {float(t): j for j, t in enumerate(result.event_t)}
    groups: dict[float, list[int]] = {}
    for i, imp in enumerate(result.impacts):
        groups.setdefault(float(imp.time), []).append(i)
    out = []
    for t, idx in groups.items():
        if t not in where:
            raise RuntimeError(f"no state recorded before the impulses at t = {t!r} s (driver contract: Result.event_t)")
        out.append((t, where[t], idx))
    return out


def impact_velocity_changes(result) -> list[tuple[float, np.ndarray, list[int], np.ndarray]]:
    """Per impact instant: (time, modal state before (q, q') as (2, ntot), impacts, modal velocity change (ntot,)).

    The change is the sum of ``w_j I_j`` over the instant's impacts (solved together or group by
    group, their velocity changes add).
    """
    out = []
    for t, j, idx in impact_instants(result):
        q, qd = result.event_q[j], result.event_qd[j]
        dv = np.zeros_like(qd)
        for i in idx:
            imp = result.impacts[i]
            dv += contact_row(result, q, imp.pair, imp.point, imp.normal) * imp.impulse
        out.append((t, np.stack([q, qd]), idx, dv))
    return out
