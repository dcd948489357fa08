"""How much of the pair checking the cheap bound saves: a count over a run's recorded states.

After every step the compiled core checks each slab pair that could touch: first the
clearance bound (:func:`pounding.contact.geometry.clearance_bound`: the rest gap minus the
slabs' relative motion), and only when that bound is within the contact tolerance the axis
bound and the polygon test. :func:`bound_screening` applies the same first bound to the
recorded states of a run, every pair at every output step, and counts the checks it settles
(summary.json ``pair_checks``). With ``output_every = 1`` the recorded states are the states
the core checked, so the count is the run's own; with thinned output, a sample of it.
"""

from __future__ import annotations

import numpy as np

from pounding.compiler import njit
from pounding.contact.geometry import clearance_bound
from pounding.framework.engine.pairs import slab_dofs


def bound_screening(geo, q: np.ndarray, tol: float) -> dict:
    """Count of pair checks the clearance bound settles over modal displacement histories q (nt, n).

    geo: the run's :class:`~pounding.framework.engine.bundles.PairArrays`; tol: the contact tolerance [m].
    Returns ``{"checks": nt * P, "skipped_by_bound": ..., "beyond_bound": ...}``: every check,
    those the bound settles (bound > tol: no further work), and those that went on to the axis
    bound or the polygon test. Facade pairs count like the others.
    """
    P = geo.pa.shape[0]
    nt = q.shape[0]
    if P == 0 or nt == 0:
        return {"checks": 0, "skipped_by_bound": 0, "beyond_bound": 0}
    skipped = int(settled_by_bound(np.ascontiguousarray(q, dtype=float), float(tol), geo))
    return {"checks": int(nt * P), "skipped_by_bound": skipped, "beyond_bound": int(nt * P - skipped)}


@njit
def settled_by_bound(q, tol, geo):
    """How many of the checks of every pair at every state of q (nt, n) the clearance bound settles
    (bound > tol [m]), with the core's own slab motion and bound (:func:`pounding.framework.engine.pairs.slab_dofs`,
    :func:`pounding.contact.geometry.clearance_bound`)."""
    pa, pb, rows, off, n_modes, radii, rest = geo.pa, geo.pb, geo.rows, geo.off, geo.n_modes, geo.radii, geo.rest
    da, db = np.empty(3), np.empty(3)
    count = 0
    for k in range(q.shape[0]):
        x = q[k]
        for p in range(pa.shape[0]):
            slab_dofs(rows, off, n_modes, pa[p, 0], pa[p, 1], x, da)
            slab_dofs(rows, off, n_modes, pb[p, 0], pb[p, 1], x, db)
            sa, sb = off[pa[p, 0]] + pa[p, 1], off[pb[p, 0]] + pb[p, 1]
            if clearance_bound(rest[p], da[0], da[1], da[2], radii[sa], db[0], db[1], db[2], radii[sb]) > tol:
                count += 1
    return count
