"""The response quantities of practice, per building and storey, from a run's histories.

Everything here is post-processing of a :class:`~pounding.framework.engine.results.Result`
and the buildings' assembled systems; nothing changes the analysis.

* **Drift.** The inter-storey drift at plan point r of storey s is the relative
  displacement ``U_s(r) - U_{s-1}(r)`` of the two floors (each a rigid body,
  ``U_f(r) = (u_f - phi_f (r_y - c_fy), v_f + phi_f (r_x - c_fx))``; the ground
  below storey 1 does not move), its plan magnitude divided by the storey
  height. At the centre of mass r = c_s; at the corners r = every vertex of
  slab s (the vertical line through the corner).
* **Storey forces.** Each element's floor forces along its line are ``k T x``
  (:func:`pounding.framework.model.assembly.placed_elements`, kept on the System: the same matrices the
  stiffness is assembled from, stiffness modifiers included); its storey shear
  is their sum over the floors at and above the storey. The building's storey
  shear (x, y) [N] is the sum of the elements' storey shears along their
  directions, the base shear that of storey 1, and the overturning moment at
  the foot of storey s the moment of the floor forces above about that level,
  ``M = sum_f (z_f - z_{s-1}) (-F_y, F_x)`` [N m]. These are the elastic forces
  of the elements: viscous damping (a modal matrix tied to no element) and the
  P-Delta shear of gravity loads are not in them.
* **Floor accelerations, absolute.** Smooth part: ``a = -M^-1 (K x + C v)``
  (exact in modal coordinates, ``-Phi (omega^2 q + 2 zeta omega q')``, the
  ground acceleration included since ``Phi L = b``) at the output instants.
  Forces of sustained or penalty contact are not recorded by a run and are not
  included (``summary.json`` says so when such forces acted). Impacts: an
  impulse changes the floor velocities by ``dv = Phi (w I)`` at one instant, a
  Dirac spike ``dv delta(t - t_i)`` in acceleration; reported apart as the
  velocity jump [m/s] and as the peak of an equivalent half-sine pulse of the
  impact's contact duration tau, ``pi |dv| / (2 tau)`` [m/s^2].
* **Equivalent impact force.** A contact-duration model turns each impulse I
  into a peak force: ``duration`` (a half-sine pulse of given tau: F = pi I /
  (2 tau)) or ``hertz`` (elastic Hertz contact F = k_h delta^1.5 of the
  effective mass m = 1/(w . w) at the approach velocity b: delta_max =
  (5 m b^2 / (4 k_h))^(2/5), F = k_h delta_max^1.5, tau = 2.943 delta_max / b,
  the 2.943 being (4/5) B(2/5, 1/2);
  Goldsmith, *Impact*, 1960; k_h = 2.75e9 N/m^1.5 for concrete, Jankowski,
  EESD 34 (2005) 595-611).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pounding.framework.engine.event_record import contact_row, impact_velocity_changes

HERTZ_CONCRETE = 2.75e9  # [N/m^1.5] Jankowski (2005)
DEFAULT_DURATION = 0.005  # [s]
#: Hertz contact time in units of delta_max / b: 2 int_0^1 (1 - x^2.5)^-1/2 dx = (4/5) B(2/5, 1/2)
HERTZ_TIME = 2.9432751843247047


# --------------------------------------------------------------------------- drift
def drift_at(cm: np.ndarray, centres: np.ndarray, heights, points: np.ndarray) -> np.ndarray:
    """Inter-storey drift ratio vectors at plan points, shape (nt, N, k, 2) [-].

    Parameters
    ----------
    cm : (nt, N, 3)
        u [m], v [m], phi [rad] of every slab's centre of mass.
    centres : (N, 2)
        Centres of mass at rest [m].
    heights : (N,)
        Storey heights [m].
    points : (N, k, 2)
        Plan points of every storey [m] (NaN rows are carried through).
    """
    nt, n = cm.shape[0], cm.shape[1]

    def at(f: int, r: np.ndarray) -> np.ndarray:  # U_f(r), (nt, k, 2)
        d = r - centres[f]
        u, v, phi = cm[:, f, 0:1], cm[:, f, 1:2], cm[:, f, 2:3]
        return np.stack([u - phi * d[:, 1], v + phi * d[:, 0]], axis=-1)

    out = np.empty((nt, n, points.shape[1], 2))
    for s in range(n):
        rel = at(s, points[s]) - (at(s - 1, points[s]) if s > 0 else 0.0)
        out[:, s] = rel / heights[s]
    return out


def drift_ratios(system, cm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drift ratio magnitude histories at the centre of mass (nt, N) and the worst corner (nt, N) [-],
    for a building's :class:`~pounding.framework.model.assembly.System` and its slab histories cm (nt, N, 3)."""
    centres = np.array([s.centre for s in system.slabs])
    h = np.asarray(system.storey_heights, dtype=float)
    at_cm = np.linalg.norm(drift_at(cm, centres, h, centres[:, None, :]), axis=-1)[:, :, 0]
    kmax = max(len(s.vertices) for s in system.slabs)
    verts = np.full((system.n_storeys, kmax, 2), np.nan)
    for f, s in enumerate(system.slabs):
        verts[f, : len(s.vertices)] = s.vertices
    corner = np.nanmax(np.linalg.norm(drift_at(cm, centres, h, verts), axis=-1), axis=2)
    return at_cm, corner


def corner_drift_ratios(system, cm: np.ndarray) -> np.ndarray:
    """Inter-storey drift ratio magnitude at every corner of every slab, shape (nt, N, kmax) [-].

    Corner j of storey s is vertex j of slab s's polygon (scene order); the drift there is the
    relative plan displacement of that material point of floor s and the floor below (rigid slabs:
    ``(u - phi dy, v + phi dx)`` about each floor's centre; the ground below floor 1) over the storey
    height. NaN-padded where storeys have fewer than kmax vertices.
    """
    centres = np.array([s.centre for s in system.slabs])
    h = np.asarray(system.storey_heights, dtype=float)
    kmax = max(len(s.vertices) for s in system.slabs)
    verts = np.full((system.n_storeys, kmax, 2), np.nan)
    for f, s in enumerate(system.slabs):
        verts[f, : len(s.vertices)] = s.vertices
    return np.linalg.norm(drift_at(cm, centres, h, verts), axis=-1)


# --------------------------------------------------------------------------- storey forces
@dataclass(frozen=True)
class StoreyForces:
    """Elastic storey forces of one building over time (see the module docstring).

    element_shear : (nt, n_elements, N) [N]
        Storey shear of every element along its line (0 above the storeys it spans).
    shear : (nt, N, 2) [N]
        Storey shear (x, y) of the building.
    overturning : (nt, N, 2) [N m]
        Overturning moment (about x, about y) at the foot of every storey.
    """

    element_shear: np.ndarray
    shear: np.ndarray
    overturning: np.ndarray


def storey_forces(system, cm: np.ndarray, springs: dict | None = None) -> StoreyForces:
    """Storey shears and overturning moments of a building (its :class:`~pounding.framework.model.assembly.System`)
    from its slab histories cm (nt, N, 3); ``springs`` (:func:`pounding.framework.engine.yielding.spring_record`):
    the yielding storey springs, whose storey shear is their own force, not the elastic k0 u."""
    nt, n = cm.shape[0], system.n_storeys
    x = cm.reshape(nt, 3 * n)
    eshear = np.zeros((nt, len(system.elements), n))
    floor_force = np.zeros((nt, n, 2))
    yielding = set() if not springs else {int(j) for j in springs["element"]}
    for j, e in enumerate(system.elements):
        per_floor = np.zeros((nt, n))
        if j in yielding:
            sel = springs["element"] == j
            eshear[:, j, springs["storey"][sel] - 1] = springs["force"][:, sel]
            # floor force = the shear of the storey below the floor minus that of the storey above
            per_floor = eshear[:, j] - np.concatenate([eshear[:, j, 1:], np.zeros((nt, 1))], axis=1)
        else:
            f = (x @ e.T.T) @ e.k  # (nt, n_e) floor forces along the element line [N] (k symmetric)
            per_floor[:, np.asarray(e.floors) - 1] = f
            eshear[:, j] = np.cumsum(per_floor[:, ::-1], axis=1)[:, ::-1]
        floor_force += per_floor[:, :, None] * e.direction
    shear = np.cumsum(floor_force[:, ::-1], axis=1)[:, ::-1]
    z = np.cumsum(system.storey_heights)
    base = np.concatenate([[0.0], z[:-1]])
    ot = np.zeros((nt, n, 2))
    for s in range(n):
        lever = z[s:] - base[s]
        ot[:, s, 0] = -np.einsum("tf,f->t", floor_force[:, s:, 1], lever)
        ot[:, s, 1] = np.einsum("tf,f->t", floor_force[:, s:, 0], lever)
    return StoreyForces(eshear, shear, ot)


# --------------------------------------------------------------------------- accelerations
def floor_acceleration(system, q: np.ndarray, qd: np.ndarray, springs: dict | None = None,
                       links: np.ndarray | None = None) -> np.ndarray:
    """Absolute floor acceleration, smooth part, (nt, N, 3) [m/s^2, m/s^2, rad/s^2]: -M^-1 (K x + C v),
    plus, with yielding springs (``springs``), their remainders' share -M^-1 T^T (r - k0 u), and with
    links between slabs, their forces' share (``links``: their modal load (nt, n_b), :func:`link_loads`)."""
    modal = q * system.omega**2 + qd * (2.0 * system.zeta * system.omega)
    if springs:
        modal = modal + (springs["force"] - springs["k0"] * springs["deformation"]) @ springs["G"]
    if links is not None:
        modal = modal + links
    acc = -modal @ system.modes.T
    return acc.reshape(q.shape[0], system.n_storeys, 3)


def link_loads(result, name: str) -> np.ndarray | None:
    """The modal load (nt, n_b) of the links between slabs on building ``name`` (force x its row over
    the building's modes, summed over its links), or None when no link acts on it."""
    out = None
    for rec in getattr(result, "links", {}).values():
        row = rec["rows"].get(name)
        if row is not None:
            out = (0.0 if out is None else out) + np.outer(rec["force"], row)
    return out


# --------------------------------------------------------------------------- impacts
def impact_force_model(table: dict | None) -> dict:
    """The ``[analysis.impact_force]`` table with its defaults filled in (what summary.json states)."""
    table = dict(table or {})
    if table.get("model", "hertz") == "duration":
        return {"model": "duration", "duration": float(table.get("duration", DEFAULT_DURATION))}
    return {"model": "hertz", "stiffness": float(table.get("stiffness", HERTZ_CONCRETE))}


def impact_forces(result, model: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Equivalent peak force [N] and contact duration [s] of every impact, shape (n_impacts,) each.

    ``model``: ``{"model": "hertz", "stiffness": k_h [N/m^1.5]}`` (default, concrete) or
    ``{"model": "duration", "duration": tau [s]}`` (see the module docstring).
    """
    model = impact_force_model(model if model is not None else result.info.get("impact_force"))
    kind = model["model"]
    n = len(result.impacts)
    force, tau = np.zeros(n), np.zeros(n)
    if kind == "duration":
        tau[:] = model["duration"]
        force[:] = np.pi * np.array([i.impulse for i in result.impacts]) / (2.0 * tau) if n else 0.0
        return force, tau
    kh = model["stiffness"]
    for _, state, idx, _ in impact_velocity_changes(result):
        for i in idx:
            imp = result.impacts[i]
            b = float(imp.approach_velocity)
            if b <= 0.0:
                continue  # an end pushed in without approaching: it takes its instant's duration below
            w = contact_row(result, state[0], imp.pair, imp.point, imp.normal)
            m_eff = 1.0 / float(w @ w)
            delta = (5.0 * m_eff * b * b / (4.0 * kh)) ** 0.4
            force[i], tau[i] = kh * delta**1.5, HERTZ_TIME * delta / b
        tmax = max(tau[i] for i in idx)
        for i in idx:
            if tau[i] == 0.0 and tmax > 0.0:
                tau[i] = tmax
                force[i] = np.pi * result.impacts[i].impulse / (2.0 * tmax)
    return force, tau


def floor_velocity_jumps(result, name: str, durations: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Impacts seen by the floors of building ``name``.

    Returns
    -------
    times : (ni,) [s]
        The impact instants.
    jumps : (ni, N, 3)
        Velocity change of every floor's centre of mass (u', v' [m/s], phi' [rad/s]).
    spikes : (ni, N)
        Peak horizontal acceleration [m/s^2] of the equivalent half-sine pulse
        ``pi |dv| / (2 tau)``, tau the shortest contact duration of the instant.
    """
    b = result.names.index(name)
    s = result.systems[b]
    i0 = int(result.mode_start[b])
    times, jumps, spikes = [], [], []
    for t, _, idx, dv in impact_velocity_changes(result):
        jump = (s.modes @ dv[i0 : i0 + s.n_dof]).reshape(s.n_storeys, 3)
        tau = min(durations[i] for i in idx)
        times.append(t)
        jumps.append(jump)
        spikes.append(np.pi * np.hypot(jump[:, 0], jump[:, 1]) / (2.0 * tau) if tau > 0 else np.full(s.n_storeys, np.inf))
    n = s.n_storeys
    return np.array(times), np.array(jumps).reshape(-1, n, 3), np.array(spikes).reshape(-1, n)


# --------------------------------------------------------------------------- all of it
def building_response(result, name: str, durations: np.ndarray) -> dict[str, np.ndarray]:
    """Histories of one building (the arrays response.npz holds for it, without the prefix)."""
    s = result.systems[result.names.index(name)]
    cm = result.cm(name)
    d_cm, d_corner = drift_ratios(s, cm)
    sp = getattr(result, "springs", {}).get(name)
    sf = storey_forces(s, cm, sp)
    acc = floor_acceleration(s, result.modal(name), result.modal(name, velocity=True), sp, link_loads(result, name))
    times, jumps, spikes = floor_velocity_jumps(result, name, durations)
    extra = {}
    if sp:
        extra = {"spring_element": sp["element"], "spring_storey": sp["storey"], "spring_deformation": sp["deformation"],
                 "spring_force": sp["force"], "spring_dissipated": sp["dissipated"], "spring_peak": sp["peak"],
                 "spring_yield_deformation": sp["yield_deformation"], "spring_height": sp["height"]}
    return {
        **extra,
        "drift_ratio_cm": d_cm,
        "drift_ratio_corner": d_corner,
        "drift_ratio_corners": corner_drift_ratios(s, cm),
        "storey_shear": sf.shear,
        "element_shear": sf.element_shear,
        "overturning_moment": sf.overturning,
        "floor_acceleration": acc,
        "impact_time": times,
        "floor_velocity_jump": jumps,
        "floor_acceleration_impact": spikes,
    }


def peaks(hist: dict[str, np.ndarray]) -> dict[str, list]:
    """The per-storey peaks summary.json reports for one building (units and definitions in docs/outputs.md)."""
    mag = lambda a: np.linalg.norm(a, axis=-1)  # noqa: E731  plan magnitude of (x, y)
    acc = hist["floor_acceleration"]
    spikes = hist["floor_acceleration_impact"]
    jumps = hist["floor_velocity_jump"]
    n = acc.shape[1]
    shear = mag(hist["storey_shear"]).max(axis=0)
    return {
        "peak_drift_ratio_cm": hist["drift_ratio_cm"].max(axis=0).tolist(),
        "peak_drift_ratio_corner": hist["drift_ratio_corner"].max(axis=0).tolist(),
        **({"peak_drift_ratio_corners": _nan_to_none(hist["drift_ratio_corners"].max(axis=0))} if "drift_ratio_corners" in hist else {}),
        "peak_storey_shear": shear.tolist(),
        "peak_storey_shear_x": np.abs(hist["storey_shear"][:, :, 0]).max(axis=0).tolist(),
        "peak_storey_shear_y": np.abs(hist["storey_shear"][:, :, 1]).max(axis=0).tolist(),
        "peak_base_shear": float(shear[0]),
        "peak_overturning_moment": mag(hist["overturning_moment"]).max(axis=0).tolist(),
        "peak_floor_acceleration": mag(acc[:, :, :2]).max(axis=0).tolist(),
        "peak_floor_velocity_jump": (mag(jumps[:, :, :2]).max(axis=0) if len(jumps) else np.zeros(n)).tolist(),
        "peak_floor_acceleration_impact": (spikes.max(axis=0) if len(spikes) else np.zeros(n)).tolist(),
        **({"yielding_springs": spring_summary(hist)} if "spring_force" in hist else {}),
    }


def _nan_to_none(a: np.ndarray) -> list:
    """Nested lists of a float array with NaN (padding) as None (JSON null)."""
    return [[None if np.isnan(x) else float(x) for x in row] for row in a]


def spring_summary(hist: dict[str, np.ndarray]) -> list[dict]:
    """Per yielding spring line (element), per storey it spans, bottom first: ``element`` (0-based
    index in the building's list), ``storeys`` (1-based), ``peak_drift_ratio`` = peak |u| / h,
    ``ductility`` = peak |u| / u_y, ``residual_drift`` [m] and ``residual_drift_ratio`` (signed u at
    the record's end), ``peak_force`` [N], ``hysteretic_energy`` [J] (the law's own dissipation)."""
    out = []
    el = hist["spring_element"]
    for j in sorted({int(e) for e in el}):
        sel = np.flatnonzero(el == j)
        sel = sel[np.argsort(hist["spring_storey"][sel])]
        peak, h = hist["spring_peak"][sel], hist["spring_height"][sel]
        res = hist["spring_deformation"][-1, sel]
        out.append({
            "element": j,
            "storeys": hist["spring_storey"][sel].tolist(),
            "peak_drift_ratio": (peak / h).tolist(),
            # None for a link that has no yield deformation (a damper, a linear spring): not "did not yield"
            "ductility": [float(d) if np.isfinite(y) else None for d, y in zip(peak / hist["spring_yield_deformation"][sel],
                                                                                 hist["spring_yield_deformation"][sel])],
            "residual_drift": res.tolist(),
            "residual_drift_ratio": (res / h).tolist(),
            "peak_force": np.abs(hist["spring_force"][:, sel]).max(axis=0).tolist(),
            "hysteretic_energy": hist["spring_dissipated"][-1, sel].tolist(),
        })
    return out
