"""A base-isolated building alone, inside a moat wall, beside a fixed-base neighbour, and on a fixed base.

Usage::

    python examples/isolated_moat/run_isolated.py OUT [--duration SECONDS] [--dt SECONDS] [--stiffness N_PER_M] [--readme]

Runs four scenes of this folder (El Centro 1940 NS scaled to 0.45 g along x, the whole record unless
``--duration`` cuts it; the files' step, dt = 0.25 ms, unless ``--dt`` replaces it; the files' kelvin
contact stiffness, 1e9 N/m, unless ``--stiffness`` replaces it, to see how far the figures depend on it):

* ``alone``: ``isolated.toml``, the 4-storey frame building on lead-rubber bearings with nothing to strike;
* ``moat``: ``moat.toml``, the same inside a moat wall 0.07 m from its base slab (kelvin contact);
* ``moat_neighbour``: ``moat_neighbour.toml``, the same beside a fixed-base 6-storey neighbour 0.10 m east;
* ``fixed_base``: ``fixed_base.toml``, the same four frames and floor masses standing on the ground.

and writes into OUT:

* ``table.md`` and ``table.csv``: per scene the columns of :data:`COLUMNS`;
* ``base_displacement.png``: the base slab's x displacement over time, the moat's clearance as lines;
* ``drift_profile.png`` and ``acceleration_profile.png``: the superstructure's peak inter-storey drift
  ratio per storey and peak absolute floor acceleration per floor (contact forces included), every scene;
* ``isolator_loop.png``: the x isolators' total force against the base slab's displacement.

"Superstructure" is the isolated building's storeys 2-5 and floors 2-5 (its frames stand on the base
slab, floor 1) and the fixed-base building's storeys and floors 1-4: the same frames and floors.

``--readme`` also writes the table into examples/isolated_moat/README.md (between its markers) and the
plots into examples/isolated_moat/images/. Every figure comes from this one run.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pounding import load_scene, run
from pounding.framework.post.contact_forces import contact_force_history
from pounding.io.results import response_histories, summary

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the examples' shared table helpers
from readme_table import markers, update_readme, write_table  # noqa: E402
#: scene key -> scene file
SCENES = {
    "alone": HERE / "isolated.toml",
    "moat": HERE / "moat.toml",
    "moat_neighbour": HERE / "moat_neighbour.toml",
    "fixed_base": HERE / "fixed_base.toml",
}
#: scene key -> (the building whose superstructure is compared, 0-based index of its first superstructure storey)
SUPERSTRUCTURE = {"alone": ("isolated", 1), "moat": ("isolated", 1), "moat_neighbour": ("isolated", 1), "fixed_base": ("fixed", 0)}
NEIGHBOUR = "neighbour"
#: (header, key of a row) of the table; units in the headers
COLUMNS = (
    ("scene", "scene"),
    ("isolator D [mm]", "iso_d"),
    ("isolator F [kN]", "iso_f"),
    ("T_eff [s]", "t_eff"),
    ("beta_eff [%]", "beta_eff"),
    ("drift [%]", "drift"),
    ("floor acc. [m/s2]", "acc"),
    ("base slab acc. [m/s2]", "acc_base"),
    ("wall contacts", "wall_contacts"),
    ("wall episodes", "wall_episodes"),
    ("wall peak force [MN]", "wall_force"),
    ("neighbour contacts", "nb_contacts"),
    ("neighbour episodes", "nb_episodes"),
    ("neighbour peak force [MN]", "nb_force"),
    ("isolator energy [kJ]", "iso_energy"),
    ("contact energy [kJ]", "contact_energy"),
    ("solve time [s]", "runtime"),
)
FORMATS = {"iso_d": "{:.1f}", "iso_f": "{:.0f}", "t_eff": "{:.2f}", "beta_eff": "{:.1f}", "drift": "{:.3f}", "acc": "{:.2f}",
           "acc_base": "{:.2f}", "wall_contacts": "{:d}", "wall_episodes": "{:d}", "wall_force": "{:.2f}", "nb_contacts": "{:d}",
           "nb_episodes": "{:d}", "nb_force": "{:.2f}", "iso_energy": "{:.0f}", "contact_energy": "{:.1f}", "runtime": "{:.2f}"}
README_START, README_END = markers("run_isolated.py")


def formatted(key: str, value) -> str:
    """One table cell: the value in its column's format."""
    return FORMATS.get(key, "{}").format(value)
COLOURS = {"alone": "0.45", "moat": "C0", "moat_neighbour": "C3", "fixed_base": "C2"}


@dataclass
class SceneRun:
    """One scene's run and what the table and plots read from it."""

    key: str
    result: object
    summary: dict
    floor_acceleration: np.ndarray  # (nt, N, 3) absolute, contact forces included [m/s2, m/s2, rad/s2]
    row: dict


def scene_for(key: str, duration: float | None, dt: float | None = None, stiffness: float | None = None):
    """The scene ``key`` of :data:`SCENES`, cut to ``duration`` [s], stepped at ``dt`` [s] and with the
    contact law's ``stiffness`` [N/m] (every pair's, walls included) when given and the scene has one."""
    scene = load_scene(SCENES[key])
    scene = scene.with_analysis(duration=duration) if duration else scene
    scene = scene.with_analysis(dt=dt) if dt else scene
    if stiffness and "stiffness" in scene.analysis.contact_params:  # (the fixed-base scene has nothing to strike)
        scene = scene.with_analysis(contact_params={**scene.analysis.contact_params, "stiffness": stiffness})
    return scene


def clearance(scene) -> float:
    """The moat's clearance [m]: the least distance from the base slab's edges (x = 0 and the slab's
    largest x) to the walls' faces, which here run along y."""
    slab = np.asarray(scene.buildings[0].slabs[0].vertices, dtype=float)
    x0, x1 = float(slab[:, 0].min()), float(slab[:, 0].max())
    faces = [float(np.mean(w.face[:, 0])) for w in scene.walls]
    return min(min(abs(x - x0), abs(x - x1)) for x in faces)


def floor_accelerations(result, name: str, hist: dict, forces) -> np.ndarray:
    """Absolute floor accelerations (nt, N, 3) of building ``name``: the recorded smooth part
    (-M^-1 (K x + C v) + the ground's) plus the contact forces' part M^-1 f_c, which a run does not
    record (rebuilt from the recorded states, :func:`contact_force_history`)."""
    acc = hist[name]["floor_acceleration"]
    return acc + forces.floor_acceleration(result, name) if forces is not None else acc


def contact_figures(result, target) -> dict:
    """Contacts of the run whose second body satisfies ``target(name)`` (a wall's or a building's
    name): their number (``Result.episodes``), the episodes with each pair's chatter merged
    (``Result.contact_episodes``), the largest peak force [N] and the energy they dissipated [J]."""
    def hits(e) -> bool:
        return target(result.second_body(e.pair)[0])

    eps = [e for e in result.episodes() if hits(e)]
    return {"contacts": len(eps), "episodes": sum(1 for e in result.contact_episodes() if hits(e)),
            "force": max((float(e.peak_force) for e in eps), default=0.0),
            "energy": float(sum(e.energy_dissipated for e in eps)),
            "durations": [float(e.end - e.start) for e in eps]}


def isolator_figures(summ: dict, building: str) -> dict:
    """From summary.json's ``isolators`` and ``yielding_springs`` of ``building``: the x lines' peak
    displacement D [m] and force F [N] (the largest line's), the effective period [s] and damping [-]
    along x, and the energy the isolators dissipated [J] (all lines); zeros without isolators."""
    b = summ["buildings"][building]
    iso = b.get("isolators")
    if iso is None:
        return {"d": 0.0, "f": 0.0, "t_eff": 0.0, "beta_eff": 0.0, "energy": 0.0}
    lines = [line for line in iso["lines"] if abs(line["direction"][0]) > 0.5]  # the lines along x
    elements = {line["element"] for line in iso["lines"]}
    energy = sum(sum(s["hysteretic_energy"]) for s in b.get("yielding_springs", []) if s["element"] in elements)
    return {"d": max(line["peak_displacement"] for line in lines), "f": max(line["peak_force"] for line in lines),
            "t_eff": iso["effective_period"]["x"], "beta_eff": iso["effective_damping"]["x"], "energy": float(energy)}


def run_scene(key: str, duration: float | None, dt: float | None = None, stiffness: float | None = None) -> SceneRun:
    """Run one scene and collect its row of the table."""
    result = run(scene_for(key, duration, dt, stiffness))
    hist = response_histories(result)
    summ = summary(result, hist)
    forces = contact_force_history(result) if result.contacts else None
    name, first = SUPERSTRUCTURE[key]
    acc = floor_accelerations(result, name, hist, forces)
    plan = np.linalg.norm(acc[:, :, :2], axis=-1).max(axis=0)  # (N,) peak per floor, in plan
    pga = float(np.max(np.abs(result.scene.ground_motion.acc)))
    iso = isolator_figures(summ, name)
    wall = contact_figures(result, lambda body: body not in result.names)
    nb = contact_figures(result, lambda body: body == NEIGHBOUR)
    row = {"scene": key, "iso_d": 1e3 * iso["d"], "iso_f": iso["f"] / 1e3, "t_eff": iso["t_eff"], "beta_eff": 100.0 * iso["beta_eff"],
           "drift": 100.0 * max(summ["buildings"][name]["peak_drift_ratio_corner"][first:]),
           "acc": float(plan[first:].max()), "acc_base": float(plan[first - 1]) if first else pga,
           "wall_contacts": wall["contacts"], "wall_episodes": wall["episodes"], "wall_force": wall["force"] / 1e6,
           "nb_contacts": nb["contacts"], "nb_episodes": nb["episodes"], "nb_force": nb["force"] / 1e6,
           "iso_energy": iso["energy"] / 1e3, "contact_energy": (wall["energy"] + nb["energy"]) / 1e3, "runtime": result.runtime_s}
    if wall["durations"] or nb["durations"]:
        print(f"{key}: contact durations {describe_durations(wall['durations'], nb['durations'])} (dt = {1e3 * result.dt:.3f} ms)",
              flush=True)
    return SceneRun(key, result, summ, acc, row)


def describe_durations(wall: list[float], neighbour: list[float]) -> str:
    """The shortest and longest contact [ms] on the wall and on the neighbour, as one phrase."""
    return ", ".join(f"{what} {1e3 * min(d):.1f}-{1e3 * max(d):.1f} ms" for what, d in (("wall", wall), ("neighbour", neighbour)) if d)






def profiles(r: SceneRun) -> tuple[np.ndarray, np.ndarray]:
    """The superstructure's peak drift ratio per storey (4,) [-] and peak floor acceleration per level
    (5,) [m/s2], level 0 the floor it stands on (the base slab; the ground, at the PGA, for a fixed base)."""
    name, first = SUPERSTRUCTURE[r.key]
    drift = np.asarray(r.summary["buildings"][name]["peak_drift_ratio_corner"][first:])
    plan = np.linalg.norm(r.floor_acceleration[:, :, :2], axis=-1).max(axis=0)
    return drift, np.concatenate([[r.row["acc_base"]], plan[first:]])


def plot_base_displacement(runs: list[SceneRun], plt, path: Path, gap: float) -> None:
    """The base slab's x displacement [mm] of each isolated scene, the moat's faces at +- ``gap``."""
    isolated = [r for r in runs if SUPERSTRUCTURE[r.key][1] == 1]
    fig, ax = plt.subplots(figsize=(8, 3.0))
    for r in isolated:
        ax.plot(r.result.t, 1e3 * r.result.cm("isolated")[:, 0, 0], color=COLOURS[r.key], lw=0.6, label=r.key)
    for sign in (-1.0, 1.0):
        ax.axhline(sign * 1e3 * gap, color="k", ls="--", lw=0.8)
    ax.text(0.0, 1e3 * gap, "moat, east face", fontsize=7, va="bottom", ha="left")
    ax.text(0.0, -1e3 * gap, "moat, west face", fontsize=7, va="top", ha="left")
    ax.set_xlabel("t [s]", fontsize=8)
    ax.set_ylabel("base slab u [mm]", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def plot_profiles(runs: list[SceneRun], plt, path: Path, quantity: str) -> None:
    """The superstructure's peak drift ratio [%] per storey (``quantity = "drift"``) or peak absolute
    floor acceleration [m/s2] per level (``"acceleration"``) of every scene."""
    fig, ax = plt.subplots(figsize=(4.2, 3.4))
    for r in runs:
        drift, acc = profiles(r)
        values = 100.0 * drift if quantity == "drift" else acc
        levels = np.arange(1, 5) if quantity == "drift" else np.arange(0, 5)
        ax.plot(values, levels, "o-", color=COLOURS[r.key], ms=3, lw=1, label=r.key)
    ax.set_yticks(levels)
    if quantity == "drift":
        ax.set_ylabel("superstructure storey", fontsize=8)
        ax.set_xlabel("peak drift ratio [%]", fontsize=8)
    else:
        ax.set_yticklabels(["base"] + [str(k) for k in range(1, 5)])
        ax.set_ylabel("superstructure floor (base: base slab, or ground)", fontsize=7)
        ax.set_xlabel("peak floor acceleration [m/s2]", fontsize=8)
    ax.set_xlim(left=0.0)
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def x_lines(result) -> np.ndarray:
    """Indices into ``result.springs["isolated"]`` of the isolator lines along x (elements 0 and 1)."""
    return np.flatnonzero(np.isin(result.springs["isolated"]["element"], (0, 1)))


def plot_isolator_loop(runs: list[SceneRun], plt, path: Path) -> None:
    """The x isolator lines' total force [kN] against their deformation [mm] (the base slab's x
    displacement), per isolated scene."""
    isolated = [r for r in runs if SUPERSTRUCTURE[r.key][1] == 1]
    fig, axes = plt.subplots(1, len(isolated), figsize=(3.0 * len(isolated), 2.8), sharex=True, sharey=True, squeeze=False)
    for ax, r in zip(axes[0], isolated):
        rec, sel = r.result.springs["isolated"], x_lines(r.result)
        ax.plot(1e3 * rec["deformation"][:, sel[0]], rec["force"][:, sel].sum(axis=1) / 1e3, color=COLOURS[r.key], lw=0.5)
        ax.set_title(r.key, fontsize=9)
        ax.set_xlabel("isolator deformation [mm]", fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0][0].set_ylabel("force of the x lines [kN]", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def plot_all(runs: list[SceneRun], out: Path, gap: float) -> list[Path]:
    """The figures of the module docstring; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = [out / n for n in ("base_displacement.png", "drift_profile.png", "acceleration_profile.png", "isolator_loop.png")]
    plot_base_displacement(runs, plt, paths[0], gap)
    plot_profiles(runs, plt, paths[1], "drift")
    plot_profiles(runs, plt, paths[2], "acceleration")
    plot_isolator_loop(runs, plt, paths[3])
    return paths




def main(out: Path, duration: float | None = None, readme: bool = False, dt: float | None = None,
         stiffness: float | None = None) -> list[SceneRun]:
    out.mkdir(parents=True, exist_ok=True)
    gap = clearance(load_scene(SCENES["moat"]))
    print(f"moat clearance {1e3 * gap:.0f} mm", flush=True)
    runs = []
    for key in SCENES:
        runs.append(run_scene(key, duration, dt, stiffness))
        print(f"{key}: solved in {runs[-1].row['runtime']:.2f} s", flush=True)
    md = write_table(COLUMNS, [r.row for r in runs], out, formatted)
    print(md)
    plots = plot_all(runs, out, gap)
    if readme:
        update_readme(HERE, "run_isolated.py", md, plots)
    return runs


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--duration", type=float, default=None, help="seconds of the record to run (default: all of it)")
    p.add_argument("--dt", type=float, default=None, help="time step [s] (default: the scene files', 0.00025)")
    p.add_argument("--stiffness", type=float, default=None, help="kelvin contact stiffness [N/m] (default: the files', 1e9)")
    p.add_argument("--readme", action="store_true", help="write the table and plots into this example's README")
    a = p.parse_args()
    main(a.out, a.duration, a.readme, a.dt, a.stiffness)
