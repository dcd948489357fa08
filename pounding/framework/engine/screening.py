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
    skipped = 0
    for p in range(P):
        d = []
        for bld, st in (geo.pa[p], geo.pb[p]):
            s = int(geo.off[bld] + st)
            i0, nb = int(geo.n_modes[bld, 0]), int(geo.n_modes[bld, 1])
            d.append((q[:, i0 : i0 + nb] @ geo.rows[s, :, :nb].T, float(geo.radii[s])))
        (da, ra), (db, rb) = d
        bound = geo.rest[p] - np.hypot(da[:, 0] - db[:, 0], da[:, 1] - db[:, 1]) - np.abs(da[:, 2]) * ra - np.abs(db[:, 2]) * rb
        skipped += int(np.count_nonzero(bound > tol))
    return {"checks": int(nt * P), "skipped_by_bound": skipped, "beyond_bound": int(nt * P - skipped)}
