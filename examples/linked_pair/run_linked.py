"""The paper's pair at 0.03 m, unlinked, linked at the lower building's roof (dampers, a rigid tie) and with a bumper.

Usage::

    python examples/linked_pair/run_linked.py OUT [--duration SECONDS] [--refine N] [--readme]

Runs six scenes, each with its file's [analysis] and the whole El Centro record unless ``--duration``
cuts it (``--refine N`` divides every scene's step by N, to see how far the table moves with it):

* ``unlinked``: ``examples/paper/pair_gap_0.03.toml`` as it is (``hht`` alpha = -0.05, dt = 5 ms, the
  impulse contact law with e = 0.5, as the next three);
* ``viscous``: ``pair_viscous.toml``, two linear viscous dampers from the roof of "low" (storey 3) to
  the slab of "high" at the same level;
* ``maxwell``: ``pair_maxwell.toml``, the same dampers each in series with a steel brace;
* ``tie``: ``pair_tie.toml``, two stiff elastic ties in their place (the rigid limit);
* ``unlinked_force``: ``pair_bumper.toml`` without its ``[[contact]]`` table: the paper's pair under
  Jankowski's force law for the slabs (e = 0.5, dt = 0.25 ms), the bumper's reference;
* ``bumper``: ``pair_bumper.toml``, a rubber bumper on the roof slab of "low" facing "high" (a bumper
  needs a force law for the slabs, hence the reference above).

and writes into OUT:

* ``table.md`` and ``table.csv``: per scene the columns of :data:`COLUMNS`;
* ``top_displacement.png``: the top floor's x displacement of each building, each linked scene over
  the unlinked one;
* ``drift_profile.png`` and ``acceleration_profile.png``: per storey the peak inter-storey drift
  ratio and per floor the peak absolute floor acceleration, every scene on one axis per building;
* ``damper_loop.png``: force against stroke of one damper of each damped scene, and the bumper's
  contact force against its layer's compression.

It also prints the figures the scenes' parameters were chosen from: the added damping ratio the
dampers' coefficient gives each building's x mode (:func:`added_damping`), and the tied pair's
period against the rigid ties' (:func:`tie_periods`).

``--readme`` also writes the table into examples/linked_pair/README.md (between its markers) and the
plots into examples/linked_pair/images/. Every figure comes from this one run.
"""

from __future__ import annotations

import argparse
import sys
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from pounding import assemble, load_scene, run
from pounding.framework.post.contact_forces import contact_force_history, run_laws
from pounding.io.results import summary

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the examples' shared table helpers
from readme_table import markers, update_readme, write_table  # noqa: E402
#: scene key -> scene file
SCENES = {
    "unlinked": HERE.parent / "paper" / "pair_gap_0.03.toml",
    "viscous": HERE / "pair_viscous.toml",
    "maxwell": HERE / "pair_maxwell.toml",
    "tie": HERE / "pair_tie.toml",
    "unlinked_force": HERE / "pair_bumper.toml",
    "bumper": HERE / "pair_bumper.toml",
}
#: scenes run without their file's [[contact]] tables (the bumper's reference: its slabs' law alone)
WITHOUT_CONTACT_TABLES = {"unlinked_force"}
#: scene key -> the scene it is drawn over and compared with
REFERENCE = {"viscous": "unlinked", "maxwell": "unlinked", "tie": "unlinked", "bumper": "unlinked_force"}
BUILDINGS = ("low", "high")
#: (header, key of a row) of the table; units in the headers
COLUMNS = (
    ("scene", "scene"),
    ("top u low [mm]", "top_low"),
    ("top u high [mm]", "top_high"),
    ("drift low [%]", "drift_low"),
    ("drift high [%]", "drift_high"),
    ("impacts", "impacts"),
    ("episodes", "episodes"),
    ("floor acc. low [m/s2]", "acc_low"),
    ("floor acc. high [m/s2]", "acc_high"),
    ("impact spike [m/s2]", "spike"),
    ("contact peak force [kN]", "contact_force"),
    ("peak penetration [mm]", "penetration"),
    ("contact energy [kJ]", "contact_energy"),
    ("link peak force [kN]", "link_force"),
    ("link peak stroke [mm]", "link_stroke"),
    ("link energy [kJ]", "link_energy"),
    ("solve time [s]", "runtime"),
)
FORMATS = {"top_low": "{:.1f}", "top_high": "{:.1f}", "drift_low": "{:.3f}", "drift_high": "{:.3f}", "impacts": "{:d}",
           "episodes": "{:d}", "acc_low": "{:.2f}", "acc_high": "{:.2f}", "spike": "{:.1f}", "contact_force": "{:.0f}",
           "penetration": "{:.2f}", "contact_energy": "{:.1f}", "link_force": "{:.0f}",
           "link_stroke": "{:.2f}", "link_energy": "{:.0f}", "runtime": "{:.2f}"}
README_START, README_END = markers("run_linked.py")
COLOURS = {"unlinked": "0.55", "viscous": "C0", "maxwell": "C2", "tie": "C3", "unlinked_force": "0.2", "bumper": "C1"}


@dataclass
class SceneRun:
    """One scene's run and what the table and plots read from it."""

    key: str
    result: object
    summary: dict
    row: dict
    #: the force laws' contact forces at the recorded steps in contact (:func:`contact_forces`; None when no
    #: pair acts by forces or nothing touched)
    forces: object = None
    #: the indices (k,) into ``result.t`` of those steps
    force_steps: np.ndarray | None = None


def scene_for(key: str, duration: float | None, refine: int = 1):
    """The scene ``key`` of :data:`SCENES` (without its [[contact]] tables for the keys of
    :data:`WITHOUT_CONTACT_TABLES`), cut to ``duration`` [s] when given, its file's step divided by ``refine``."""
    scene = load_scene(SCENES[key])
    scene = replace(scene, contacts=()) if key in WITHOUT_CONTACT_TABLES else scene
    scene = scene.with_analysis(duration=duration) if duration else scene
    return scene.with_analysis(dt=scene.analysis.dt / refine) if refine != 1 else scene


def link_row_x(building, storey: int, point) -> np.ndarray:
    """Row (3N,) of a slab point's x displacement over a building's slab DOFs (u, v, phi per floor,
    phi about the slab's centre of mass): x = u - (y_p - y_c) phi."""
    centre = np.asarray(building.slabs[storey - 1].centre, dtype=float)
    row = np.zeros(3 * building.n_storeys)
    row[3 * (storey - 1)] = 1.0
    row[3 * (storey - 1) + 2] = -(float(point[1]) - centre[1])
    return row


def added_damping(scene) -> dict[str, np.ndarray]:
    """Per building, the damping ratio (n_modes,) [-] its linear dampers add to each of its own modes
    with the other building held still (FEMA 356's estimate): zeta_j = sum_d c_d (t_d . phi_j)^2 / (2 w_j),
    phi_j mass-normalised, t_d the row of damper d's end on that building (:func:`link_row_x`; the links
    here lie along x). Links of other laws (or with an exponent other than 1) are left out."""
    systems = {b.name: assemble(b) for b in scene.buildings}
    out = {name: np.zeros(len(s.periods)) for name, s in systems.items()}
    for link in scene.links:
        law = link.law.describe()
        if law.get("name") not in ("viscous", "maxwell") or law.get("exponent", 1.0) != 1.0:
            continue
        for name, storey, point in zip(link.between, link.storeys, link.points):
            s = systems[name]
            t_phi = link_row_x(s, storey, point) @ s.modes
            out[name] += law["coefficient"] * t_phi**2 / (2.0 * 2.0 * np.pi / s.periods)
    return out


def x_effective_mass(building_system) -> np.ndarray:
    """Share (n_modes,) [-] of a building's mass each mode moves along x (sums to 1)."""
    s = building_system
    r = np.zeros(3 * s.n_storeys)
    r[0::3] = 1.0
    gamma = s.modes.T @ s.M @ r
    return gamma**2 / (r @ s.M @ r)


def describe_damping(scene) -> str:
    """One line per building: the x-dominant mode's period, its share of mass along x, the added damping ratio."""
    zeta = added_damping(scene)
    lines = []
    for b in scene.buildings:
        s = assemble(b)
        j = int(np.argmax(x_effective_mass(s)))
        lines.append(f"{b.name}: mode {j + 1} (T = {s.periods[j]:.3f} s, {100 * x_effective_mass(s)[j]:.0f} % of the mass "
                     f"along x): added damping {100 * zeta[b.name][j]:.1f} %")
    return "; ".join(lines)


def pair_matrices(scene) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The two buildings as one system over their stacked slab DOFs (n = 3 (N_low + N_high)): mass M and
    stiffness K (n, n) with the stiffness of the scene's elastic links added (k t t^T), the links' rows
    T (n_links, n) (the x displacement of the second end minus the first's: the links lie along +x), and
    the x influence vector r (n,)."""
    systems = [assemble(b) for b in scene.buildings]
    sizes = [s.M.shape[0] for s in systems]
    start = dict(zip((b.name for b in scene.buildings), np.cumsum([0] + sizes[:-1])))
    by_name = {b.name: s for b, s in zip(scene.buildings, systems)}
    n = sum(sizes)
    M, K, r = np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
    for name, s in by_name.items():
        sl = slice(start[name], start[name] + s.M.shape[0])
        M[sl, sl], K[sl, sl] = s.M, s.K
    r[0::3] = 1.0
    rows = []
    for link in scene.links:
        t = np.zeros(n)
        for sign, name, storey, point in zip((-1.0, 1.0), link.between, link.storeys, link.points):
            s = by_name[name]
            t[start[name] : start[name] + s.M.shape[0]] += sign * link_row_x(s, storey, point)
        rows.append(t)
        law = link.law.describe()
        if law.get("name") == "elastic":
            K += law["stiffness"] * np.outer(t, t)
    return M, K, np.array(rows), r


def tie_periods(scene) -> dict[str, float]:
    """Of the pair joined by the scene's elastic links: ``first`` the period [s] of the mode that moves the
    most mass along x, ``rigid`` the same with the links rigid (the motion kept in the null space of
    their rows), and ``highest_w`` the highest circular frequency [rad/s] with the links."""
    import scipy.linalg

    M, K, T, r = pair_matrices(scene)
    w2, phi = scipy.linalg.eigh(K, M)
    first = 2.0 * np.pi / np.sqrt(w2[np.argmax((phi.T @ M @ r) ** 2)])
    N = scipy.linalg.null_space(T)  # (n, n - n_links): the motions the rigid links allow
    w2r, psi = scipy.linalg.eigh(N.T @ K @ N, N.T @ M @ N)  # K's link terms vanish on N
    rigid = 2.0 * np.pi / np.sqrt(w2r[np.argmax((psi.T @ N.T @ M @ r) ** 2)])
    return {"first": float(first), "rigid": float(rigid), "highest_w": float(np.sqrt(w2[-1]))}


def link_figures(result) -> dict:
    """Over the run's links: the largest peak |force| [N] and peak |stroke| [m] of one link, the energy
    all of them dissipated [J] (0 for a scene without links)."""
    links = result.links.values()
    return {"force": max((float(np.max(np.abs(r["force"]))) for r in links), default=0.0),
            "stroke": max((float(r["peak"]) for r in links), default=0.0),
            "energy": sum(float(r["energy_dissipated"]) for r in links)}


def by_forces(result) -> bool:
    """Whether the run's slab pairs act by forces solved with the step (their laws' ``with_step``),
    not by impulses."""
    laws, which = run_laws(result)
    return all(laws[k].with_step for k in which)


def contact_figures(result) -> dict:
    """Over the run's contacts (``Result.episodes``: the impacts of an impulse law, the contact episodes
    of a force law): the largest peak force [N] and penetration [m] (NaN under an impulse law, whose
    contacts are instants without either) and the energy they dissipated [J]."""
    eps = result.episodes()
    forced = by_forces(result)
    return {"force": max((float(e.peak_force) for e in eps), default=0.0) if forced else math.nan,
            "penetration": max((float(e.peak_penetration) for e in eps), default=0.0) if forced else math.nan,
            "energy": float(sum(e.energy_dissipated for e in eps))}


def contact_forces(result) -> tuple[object, np.ndarray]:
    """The force laws' contact forces (:func:`~pounding.framework.post.contact_forces.contact_force_history`)
    at the recorded steps within the run's contact episodes, one step either side, and the indices (k,)
    of those steps into ``result.t``. Elsewhere no pair touches and every contact force is zero, so the
    peaks are the whole run's; the rebuild, one contact solve per step, then costs a fraction."""
    t, margin = result.t, 1.5 * result.dt
    keep = np.zeros(len(t), dtype=bool)
    for e in result.contacts:
        keep |= (t >= e.start - margin) & (t <= e.end + margin)
    steps = np.flatnonzero(keep)
    return contact_force_history(replace(result, t=t[steps], q=result.q[steps], qd=result.qd[steps])), steps


def contact_acceleration(result, forces, name: str) -> np.ndarray:
    """Peak in plan (N,) [m/s2] per floor of building ``name`` of the contact forces' own part of its
    floor acceleration, M^-1 f_c (:meth:`~pounding.framework.post.contact_forces.ContactForces.floor_acceleration`),
    which summary.json's smooth part leaves out; zeros when no pair acts by forces."""
    n = result.systems[result.names.index(name)].n_storeys
    if forces is None:
        return np.zeros(n)
    return np.linalg.norm(forces.floor_acceleration(result, name)[:, :, :2], axis=-1).max(axis=0)


def impact_spikes(r: SceneRun, name: str) -> np.ndarray:
    """Per floor (N,) [m/s2] of building ``name``: the contacts' own peak floor acceleration, the
    impulse law's half-sine estimate (summary.json) or the force laws' resolved M^-1 f_c."""
    spikes = np.asarray(r.summary["buildings"][name]["peak_floor_acceleration_impact"], dtype=float)
    return np.maximum(spikes, contact_acceleration(r.result, r.forces, name))


def run_scene(key: str, duration: float | None, refine: int = 1) -> SceneRun:
    """Run one scene and collect its row of the table."""
    result = run(scene_for(key, duration, refine))
    summ = summary(result)
    links = link_figures(result)
    contacts = contact_figures(result)
    forces, steps = contact_forces(result) if by_forces(result) and result.contacts else (None, None)
    row = {"scene": key, "runtime": result.runtime_s, "impacts": int(result.n_impacts), "episodes": int(summ["n_contact_episodes"]),
           "contact_force": contacts["force"] / 1e3, "penetration": 1e3 * contacts["penetration"],
           "contact_energy": contacts["energy"] / 1e3,
           "link_force": links["force"] / 1e3, "link_stroke": links["stroke"] * 1e3, "link_energy": links["energy"] / 1e3}
    for name in BUILDINGS:
        b = summ["buildings"][name]
        row[f"top_{name}"] = 1e3 * b["peak_u"][-1]
        row[f"drift_{name}"] = 100.0 * max(b["peak_drift_ratio_corner"])
        row[f"acc_{name}"] = max(b["peak_floor_acceleration"])
    out = SceneRun(key, result, summ, row, forces, steps)
    row["spike"] = float(max(np.max(impact_spikes(out, name), initial=0.0) for name in BUILDINGS))
    return out


def cell(key: str, value) -> str:
    """One table cell: the value in its format, "-" for a figure the scene's contact law does not have (NaN)."""
    if isinstance(value, float) and math.isnan(value):
        return "-"
    return FORMATS.get(key, "{}").format(value)






def plot_top_displacement(runs: list[SceneRun], plt, path: Path) -> None:
    """Top floor x displacement [mm] of each building: one row per scene of :data:`REFERENCE`, its
    reference run behind it."""
    by = {r.key: r for r in runs}
    shown = [r for r in runs if REFERENCE.get(r.key) in by]
    fig, axes = plt.subplots(len(shown), 2, sharex=True, sharey="col", figsize=(9, 1.7 * len(shown) + 0.4), squeeze=False)
    for row_axes, r in zip(axes, shown):
        base = by[REFERENCE[r.key]]
        for ax, name in zip(row_axes, BUILDINGS):
            ax.plot(base.result.t, 1e3 * base.result.cm(name)[:, -1, 0], color="0.55", lw=0.6, label=base.key)
            ax.plot(r.result.t, 1e3 * r.result.cm(name)[:, -1, 0], color=COLOURS[r.key], lw=0.6, label=r.key)
            ax.set_title(f"{name}, top floor: {r.key}", fontsize=8, loc="left")
            ax.tick_params(labelsize=7)
            ax.legend(fontsize=6, loc="upper right")
        row_axes[0].set_ylabel("u [mm]", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("t [s]", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def plot_profiles(runs: list[SceneRun], plt, path: Path, quantity: str) -> None:
    """Peak drift ratio [%] per storey (``quantity = "drift"``) or peak absolute floor acceleration
    [m/s2] per floor (``"acceleration"``: the smooth part as dots, the contacts' own spikes as crosses,
    :func:`impact_spikes`), per building; the scenes under a force law dashed."""
    fig, axes = plt.subplots(1, 2, figsize=(7.5, 4.2), sharey=False)
    for ax, name in zip(axes, BUILDINGS):
        for r in runs:
            b = r.summary["buildings"][name]
            if quantity == "drift":
                values = 100.0 * np.asarray(b["peak_drift_ratio_corner"])
            else:
                values = np.asarray(b["peak_floor_acceleration"])
            levels = np.arange(1, len(values) + 1)
            style = "s--" if np.isfinite(r.row["contact_force"]) else "o-"  # a force law's scene dashed
            ax.plot(values, levels, style, color=COLOURS[r.key], ms=3, lw=1, label=r.key)
            spikes = impact_spikes(r, name)
            # floors not struck report the rounding of a velocity jump (~1e-15 m/s2): not marked
            hit = spikes > 1e-9 * np.max(spikes, initial=0.0)
            if quantity == "acceleration" and np.any(hit):
                ax.plot(spikes[hit], levels[hit], "x", color=COLOURS[r.key], ms=6, label=f"{r.key}: contact spike")
        ax.set_yticks(levels)
        ax.set_ylabel("storey" if quantity == "drift" else "floor", fontsize=8)
        ax.set_xlabel("peak drift ratio [%]" if quantity == "drift" else "peak floor acceleration [m/s2]", fontsize=8)
        ax.set_title(name, fontsize=9)
        ax.set_xlim(left=0.0)
        ax.tick_params(labelsize=7)
    handles, labels = axes[-1].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=6, loc="lower center", ncol=4)
    fig.tight_layout(rect=(0.0, 0.05 + 0.035 * ((len(labels) + 3) // 4), 1.0, 1.0))  # room for the legend below
    fig.savefig(path, dpi=80)
    plt.close(fig)


def pair_penetration(result, pair: int, steps: np.ndarray) -> np.ndarray:
    """The deepest penetration [m] of slab pair ``pair`` at the recorded steps ``steps`` (k,) (0 where
    it does not touch): the contact geometry's gaps at the recorded states. For a bumper's pair it is
    the layer's compression."""
    from pounding.framework.engine.face_shares import rest_face_ends, touching_with_shares

    laws, _ = run_laws(result)
    tol = max(float(law.tolerance) for law in laws)
    ends = rest_face_ends(result.geo)
    plist = np.array([pair], dtype=np.int64)
    out = np.zeros(len(steps))
    for j, k in enumerate(steps):
        _, gap, *_ = touching_with_shares(np.ascontiguousarray(result.q[k]), plist, tol, result.q.shape[1], result.geo, ends)
        out[j] = max(float(-np.min(gap, initial=0.0)), 0.0)
    return out


def bumper_pair(result) -> tuple[int, object] | None:
    """(index of the slab pair a bumper stands in, its :class:`~pounding.framework.model.scene.Bumper`)
    of the first such pair of the run (:func:`pounding.framework.model.bumpers.bumper_pairs`), or None."""
    from pounding.framework.model.bumpers import bumper_pairs

    found = sorted(bumper_pairs(result.systems, result.pairs, result.scene.contacts).items())
    return (found[0][0], found[0][1].bumper) if found else None


def plot_loops(runs: list[SceneRun], plt, path: Path) -> None:
    """Force [kN] against stroke [mm] of the first link of each damped scene (not the tie), and the
    bumper's contact force [kN] against its layer's compression [mm] (the slabs' law acts beyond the
    dotted line, ``compressible`` t)."""
    damped = [r for r in runs if r.result.links and r.row["link_energy"] > 0.0]
    bumpers = [r for r in runs if r.forces is not None and bumper_pair(r.result) is not None]
    panels = len(damped) + len(bumpers)
    fig, axes = plt.subplots(1, max(panels, 1), figsize=(3.4 * max(panels, 1), 3.0), squeeze=False)
    for ax, r in zip(axes[0], damped):
        name, rec = next(iter(r.result.links.items()))
        ax.plot(1e3 * rec["deformation"], rec["force"] / 1e3, color=COLOURS[r.key], lw=0.5)
        ax.set_xlabel("stroke [mm] (+: the points move apart)", fontsize=8)
        ax.set_ylabel("force [kN] (+: tension)", fontsize=8)
        ax.set_title(f"{r.key}: {name}", fontsize=9)
        ax.tick_params(labelsize=7)
    for ax, r in zip(axes[0][len(damped):], bumpers):
        p, bumper = bumper_pair(r.result)
        pressed = np.flatnonzero(r.forces.pair_force[:, p] > 0.0)
        compression = pair_penetration(r.result, p, r.force_steps[pressed])
        ax.plot(1e3 * compression, r.forces.pair_force[pressed, p] / 1e3, ".", color=COLOURS[r.key], ms=1)
        ax.axvline(1e3 * bumper.compressible * bumper.thickness, color="0.4", ls=":", lw=0.8)
        ax.set_xlabel("layer compression [mm]", fontsize=8)
        ax.set_ylabel("contact force [kN]", fontsize=8)
        ax.set_title(f"{r.key}: roof of low", fontsize=9)
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def plot_all(runs: list[SceneRun], out: Path) -> list[Path]:
    """The figures of the module docstring; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = [out / n for n in ("top_displacement.png", "drift_profile.png", "acceleration_profile.png", "damper_loop.png")]
    plot_top_displacement(runs, plt, paths[0])
    plot_profiles(runs, plt, paths[1], "drift")
    plot_profiles(runs, plt, paths[2], "acceleration")
    plot_loops(runs, plt, paths[3])
    return paths




def layer_design(scene, approach_speed: float) -> dict:
    """The first bumper of ``scene`` struck by its facing slab at ``approach_speed`` [m/s], both slabs
    free (masses of the two slabs it stands between: the layer's storey and the other building's slab
    at its level): the layer law's own contact (:func:`pounding.contact.rebound.rebound`, integrated to
    rtol 1e-12), ``penetration`` [m] and ``force`` [N] at its deepest, ``rebound`` [-], ``duration`` [s],
    the layer's ``reach`` c t [m], beyond which the slabs' law would act, and ``slabs_force`` [N], the
    peak force of the slabs' law alone (the bare slabs meeting at the same speed)."""
    from pounding.contact.rebound import rebound
    from pounding.framework.model.levels import common_levels
    from pounding.framework.model.registry import CONTACT_LAWS

    rule = next(rule for rule in scene.contacts if rule.bumper is not None)
    bumper = rule.bumper
    by_name = {b.name: b for b in scene.buildings}
    on = by_name[bumper.on]
    other = by_name[next(n for n in rule.between if n != bumper.on)]
    storey = bumper.storeys[0] - 1
    level = next(fo for fa, fo in common_levels(on, other) if fa == storey)
    m1, m2 = assemble(on).mass[3 * storey], assemble(other).mass[3 * level]
    r = rebound(CONTACT_LAWS.get(bumper.law)(**bumper.params), approach_speed=approach_speed, m1=m1, m2=m2)
    bare = rebound(CONTACT_LAWS.get(rule.law)(**rule.params), approach_speed=approach_speed, m1=m1, m2=m2)
    return {"penetration": r.peak_penetration, "force": r.peak_force, "rebound": r.ratio, "duration": r.duration,
            "reach": bumper.compressible * bumper.thickness, "masses": (float(m1), float(m2)), "slabs_force": bare.peak_force}


def describe_layer(scene, approach_speed: float) -> str:
    """One line: the bumper's layer struck at ``approach_speed`` [m/s] (:func:`layer_design`)."""
    d = layer_design(scene, approach_speed)
    return (f"struck at {approach_speed:.3f} m/s by free slabs of {d['masses'][0] / 1e3:.0f} and {d['masses'][1] / 1e3:.0f} t, "
            f"the layer compresses {1e3 * d['penetration']:.1f} mm (c t = {1e3 * d['reach']:.1f} mm), "
            f"peak force {d['force'] / 1e3:.0f} kN (the bare slabs' law: {d['slabs_force'] / 1e3:.0f} kN), "
            f"rebound {d['rebound']:.3f}, contact {1e3 * d['duration']:.0f} ms")


def fastest_approach(result) -> float:
    """The largest closing speed [m/s] at the start of the run's contacts (``Result.episodes``), 0 without any."""
    return max((float(e.approach_velocity) for e in result.episodes()), default=0.0)


def describe_durations(r: SceneRun) -> str:
    """", contacts A-B ms at dt = C ms": the shortest and longest contact of a force law's run, "" otherwise."""
    durations = [e.end - e.start for e in r.result.episodes()] if np.isfinite(r.row["contact_force"]) else []
    if not durations:
        return ""
    return f", contacts {1e3 * min(durations):.1f}-{1e3 * max(durations):.1f} ms at dt = {1e3 * r.result.dt:.3g} ms"


def main(out: Path, duration: float | None = None, readme: bool = False, refine: int = 1) -> list[SceneRun]:
    out.mkdir(parents=True, exist_ok=True)
    print("dampers of pair_viscous.toml:", describe_damping(load_scene(SCENES["viscous"])), flush=True)
    tie = load_scene(SCENES["tie"])
    periods = tie_periods(tie)
    print(f"ties of pair_tie.toml: first period along x {periods['first']:.4f} s (rigid ties: {periods['rigid']:.4f} s), "
          f"highest w dt = {periods['highest_w'] * tie.analysis.dt:.2f}", flush=True)
    runs = []
    for key in SCENES:
        runs.append(run_scene(key, duration, refine))
        r = runs[-1]
        print(f"{key}: solved in {r.row['runtime']:.2f} s, fastest approach {fastest_approach(r.result):.3f} m/s"
              f"{describe_durations(r)}", flush=True)
        if key == "unlinked_force" and r.result.episodes():
            print("bumper of pair_bumper.toml at that approach:", describe_layer(load_scene(SCENES["bumper"]),
                                                                          fastest_approach(r.result)), flush=True)
    md = write_table(COLUMNS, [r.row for r in runs], out, cell)
    print(md)
    plots = plot_all(runs, out)
    if readme:
        update_readme(HERE, "run_linked.py", md, plots)
    return runs


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--duration", type=float, default=None, help="seconds of the record to run (default: all of it)")
    p.add_argument("--refine", type=int, default=1, help="divide every scene file's time step by this (default 1)")
    p.add_argument("--readme", action="store_true", help="write the table and plots into this example's README")
    a = p.parse_args()
    main(a.out, a.duration, a.readme, a.refine)
