"""Modal summary of an assembled building (what ``pounding info`` prints)."""

from __future__ import annotations

import numpy as np

from pounding.framework.model.assembly import System


def modal_summary(system: System, n_modes: int | None = None) -> dict:
    """Periods, mode shapes, participation and centres of one building.

    Returns
    -------
    dict
        ``periods`` [s] (n_modes,), ``frequencies`` [Hz], ``damping_ratios``,
        ``mode_shapes`` (n_modes lists of N [u, v, phi] triples, mass-normalised),
        ``effective_mass_ratio`` {x, y, rz} per mode and their sums, and per
        storey ``mass`` [kg], ``polar_inertia`` [kg m^2], ``centre_of_mass``,
        ``centre_of_rigidity`` and ``eccentricity`` [m].
    """
    n = system.n_dof if n_modes is None else min(n_modes, system.n_dof)
    N = system.n_storeys
    ex, ey, er = system.influence(np.array([1.0, 0.0])), system.influence(np.array([0.0, 1.0])), np.tile([0.0, 0.0, 1.0], N)
    total = {"x": system.mass[0::3].sum(), "y": system.mass[1::3].sum(), "rz": system.mass[2::3].sum()}
    eff = {k: system.participation(b) ** 2 / total[k] for k, b in (("x", ex), ("y", ey), ("rz", er))}
    cm = np.array([s.centre for s in system.slabs])
    cr = system.centres_of_rigidity()
    return {
        "storeys": N,
        "mass": [s.mass for s in system.slabs],
        "polar_inertia": [s.polar_inertia for s in system.slabs],
        "centre_of_mass": cm.tolist(),
        "centre_of_rigidity": cr.tolist(),
        "eccentricity": (cr - cm).tolist(),
        "periods": system.periods[:n].tolist(),
        "frequencies": (system.omega[:n] / (2 * np.pi)).tolist(),
        "damping_ratios": system.zeta[:n].tolist(),
        "mode_shapes": [system.modes[:, i].reshape(N, 3).tolist() for i in range(n)],
        "effective_mass_ratio": {k: v[:n].tolist() for k, v in eff.items()},
        "effective_mass_ratio_sum": {k: float(v[:n].sum()) for k, v in eff.items()},
    }
