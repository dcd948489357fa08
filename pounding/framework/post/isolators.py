"""Isolator outputs of a base-isolated building: per line of isolators and along x and y.

For each line i of the isolation layer (:func:`pounding.framework.model.isolation.isolator_lines`:
one-storey storey springs in storey 1 with the superstructure standing on floor 1), with u_i its
deformation (the base slab's displacement along the line at the line's position) and r_i its force:

* D_i = peak |u_i| [m] and F_i = peak |r_i| [N];
* K_eff,i = F_i / D_i [N/m], the secant stiffness at the peak;
* E_D,i [J]: what the line's law dissipates in one quasi-static cycle of amplitude D_i, the loop
  D -> -D -> D after a first loading to D (the law driven alone; 4 Q (D - D_y) for a bilinear law
  with Q = F_y (1 - b), as the AASHTO Guide Specifications for Seismic Isolation Design write it),
  0 for an elastic line;
* beta_eff,i = E_D,i / (2 pi K_eff,i D_i^2) [-].

For the building along the plan unit vector e (x and y), the superstructure and the base slab moving
as one body of mass M (every slab's) on the lines, each counted by (d_i . e)^2 (d_i its direction):

    T_eff = 2 pi sqrt(M / sum_i K_eff,i (d_i . e)^2),
    beta_eff = sum_i E_D,i (d_i . e)^2 / (2 pi sum_i K_eff,i D_i^2 (d_i . e)^2).

These are the design quantities of an equivalent linear isolation system (effective period and
damping at the peak displacement); they describe the run, they are not fed back into it.
"""

from __future__ import annotations

import numpy as np

#: deformation increments per half cycle when driving a law through its loop (a smooth law's loop
#: area converges with the increment; the bilinear law is exact for any increment)
CYCLE_STEPS = 2000


def cycle_energy(law, params: np.ndarray, amplitude: float, steps: int = CYCLE_STEPS) -> float:
    """Energy [J] a hysteresis law (an instance or class of :mod:`pounding.hysteresis`) with ``params``
    (n_params,) dissipates in the quasi-static cycle amplitude -> -amplitude -> amplitude [m], after a
    first loading from rest to amplitude (the law's own dissipated energy, state slot 2)."""
    # the class's function: an instance would bind a plain function (the compiler off) as a method
    update = (law if isinstance(law, type) else type(law)).update
    params = np.asarray(params, dtype=float).reshape(1, -1)
    state = np.zeros((1, law.n_state))
    trial = np.zeros((1, law.n_state))
    path = np.concatenate([np.linspace(0.0, amplitude, steps + 1)[1:], np.linspace(amplitude, -amplitude, steps + 1)[1:],
                           np.linspace(-amplitude, amplitude, steps + 1)[1:]])
    at_first_peak = 0.0
    for k, u in enumerate(path):
        update(float(u), 0.0, state, params, trial, 0)
        state[:] = trial
        if k == steps - 1:
            at_first_peak = float(state[0, 2])
    return float(state[0, 2]) - at_first_peak


def isolator_summary(building, system, cm: np.ndarray, springs: dict | None) -> dict | None:
    """The isolation layer's outputs (module docstring) of a scene ``building`` with its assembled
    ``system``, slab histories ``cm`` (nt, N, 3) and yielding-spring record ``springs``
    (:func:`pounding.framework.engine.yielding.spring_record`, or None); None without isolators.

    Returns ``{"lines": [{"element", "direction", "peak_displacement", "peak_force", "effective_stiffness",
    "loop_energy", "effective_damping"}], "mass", "effective_period": {"x", "y"}, "effective_damping": {"x", "y"}}``.
    """
    from pounding.framework.model.isolation import isolator_lines

    indices = isolator_lines(building)
    if not indices:
        return None
    x = cm.reshape(len(cm), -1)
    lines = []
    for i in indices:
        e, placed = building.elements[i], system.elements[i]
        sel = np.flatnonzero(springs["element"] == i) if springs else np.zeros(0, dtype=int)
        if len(sel):  # yielding: its own record (peak over every step, force from its law)
            s = int(sel[0])
            D, F = float(springs["peak"][s]), float(np.abs(springs["force"][:, s]).max())
            energy = cycle_energy(e.law, e.spring_parameters()[0], D) if D > 0 else 0.0
        else:  # elastic: k u along its row, dissipating nothing
            u = x @ placed.T[0]
            D = float(np.abs(u).max())
            F = float(abs(placed.k[0, 0]) * D)
            energy = 0.0
        K = F / D if D > 0 else float(placed.k[0, 0])
        lines.append({"element": int(i), "direction": [float(c) for c in e.direction], "peak_displacement": D,
                      "peak_force": F, "effective_stiffness": K, "loop_energy": energy,
                      "effective_damping": energy / (2 * np.pi * K * D * D) if D > 0 else 0.0})
    mass = float(sum(s.mass for s in building.slabs))
    period, damping = {}, {}
    for axis, unit in (("x", (1.0, 0.0)), ("y", (0.0, 1.0))):
        w = [float(np.dot(line["direction"], unit)) ** 2 for line in lines]
        K = sum(wi * line["effective_stiffness"] for wi, line in zip(w, lines))
        KD2 = sum(wi * line["effective_stiffness"] * line["peak_displacement"] ** 2 for wi, line in zip(w, lines))
        period[axis] = float(2 * np.pi * np.sqrt(mass / K)) if K > 0 else None
        damping[axis] = float(sum(wi * line["loop_energy"] for wi, line in zip(w, lines)) / (2 * np.pi * KD2)) if KD2 > 0 else None
    return {"lines": lines, "mass": mass, "effective_period": period, "effective_damping": damping}
