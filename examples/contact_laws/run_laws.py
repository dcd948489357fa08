"""The paper's pair at 0.03 m with every contact law of the package, side by side.

Usage::

    python examples/contact_laws/run_laws.py OUT [--duration SECONDS] [--readme]

Runs ``examples/paper/pair_gap_0.03.toml`` (El Centro 1940 NS at 0.32 g) once per law, every law
at its default parameters with restitution 0.5, the integrator and the time step left to the
run's defaults (the scene's own ``dt`` and ``integrator`` are dropped), and writes into OUT:

* ``table.md`` and ``table.csv``: per law the peaks and contact figures (columns in :data:`COLUMNS`);
* ``top_displacement.png``: the top floor's x displacement of both buildings, per law;
* ``contact_force.png``: the force history of the strongest contact episode of each force law
  (rebuilt from the recorded states with the law's own force function,
  :mod:`pounding.framework.post.contact_forces`), and the impulse law's impulses over the same
  stretch;
* ``floor_acceleration.png``: the top floor's absolute x acceleration of the lower building, with
  the contact forces' spikes.

``--readme`` also writes the table into examples/contact_laws/README.md (between its markers) and
the plots into examples/contact_laws/images/, so that the README shows this run's figures.
Every figure comes from this one run: nothing is copied by hand.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pounding import load_scene, run
from pounding.framework.post.contact_forces import contact_force_history
from pounding.framework.post.response import impact_forces
from pounding.io.results import response_histories, summary

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the examples' shared table helpers
from readme_table import markers, update_readme, write_table  # noqa: E402
SCENE = HERE.parent / "paper" / "pair_gap_0.03.toml"
#: the laws compared, every one at its defaults with this restitution
LAWS = ("impulse", "kelvin", "hertz", "hertzdamp", "jankowski")
RESTITUTION = 0.5
#: (header, key of a row) of the table; units in the headers
COLUMNS = (
    ("law", "law"),
    ("dt [s]", "dt"),
    ("top u low [m]", "top_low"),
    ("top u high [m]", "top_high"),
    ("drift low [%]", "drift_low"),
    ("drift high [%]", "drift_high"),
    ("storey shear low [MN]", "shear_low"),
    ("storey shear high [MN]", "shear_high"),
    ("floor acc. low [m/s2]", "acc_low"),
    ("floor acc. high [m/s2]", "acc_high"),
    ("impacts", "impacts"),
    ("episodes", "episodes"),
    ("peak contact force [MN]", "force"),
    ("energy lost in contact [kJ]", "energy"),
    ("solve time [s]", "runtime"),
)
FORMATS = {"dt": "{:.2g}", "top_low": "{:.4f}", "top_high": "{:.4f}", "drift_low": "{:.3f}", "drift_high": "{:.3f}",
           "shear_low": "{:.3f}", "shear_high": "{:.3f}", "acc_low": "{:.1f}", "acc_high": "{:.1f}", "impacts": "{:d}",
           "episodes": "{:d}", "force": "{:.2f}", "energy": "{:.1f}", "runtime": "{:.2f}"}
README_START, README_END = markers("run_laws.py")


def formatted(key: str, value) -> str:
    """One table cell: the value in its column's format."""
    return FORMATS.get(key, "{}").format(value)


@dataclass
class LawRun:
    """One law's run and what the table and plots read from it."""

    law: str
    result: object
    summary: dict
    row: dict
    contact_forces: object  # ContactForces (force laws) or None (impulse law)
    acceleration: np.ndarray  # (nt,) top floor of "low", absolute x acceleration with contact forces [m/s^2]


def scene_for(law: str, duration: float | None):
    """The paper pair with ``law`` at its defaults (restitution :data:`RESTITUTION`), default step and integrator."""
    scene = load_scene(SCENE).with_analysis(dt=None, integrator=None, integrator_params={}, contact=law,
                                            contact_params={"restitution": RESTITUTION})
    return scene.with_analysis(duration=duration) if duration else scene


def episode_count(summ: dict) -> int:
    """Contact episodes as summary.json reports them (``n_contact_episodes``: a pair's strikes in one
    chatter merged, the count that converges as the step falls; docs/outputs.md)."""
    return int(summ["n_contact_episodes"])


def floor_accelerations(result, hist: dict, forces) -> dict[str, np.ndarray]:
    """Per building, absolute floor accelerations (nt, N, 3) with the contact forces' part added
    (force laws; the impulse law's impacts are instants, reported as half-sine spikes instead)."""
    out = {}
    for name in result.names:
        acc = hist[name]["floor_acceleration"]
        out[name] = acc + forces.floor_acceleration(result, name) if forces is not None else acc
    return out


def run_law(law: str, duration: float | None) -> LawRun:
    """Run one law and collect its row of the table."""
    result = run(scene_for(law, duration))
    summ = summary(result)
    hist = response_histories(result)
    forces = contact_force_history(result) if result.contacts else None
    acc = floor_accelerations(result, hist, forces)
    row = {"law": law, "dt": result.dt, "runtime": result.runtime_s, "impacts": int(summ["n_impacts"]),
           "episodes": episode_count(summ), "energy": summ["contacts"]["energy_dissipated"] / 1e3}
    for name, key in (("low", "low"), ("high", "high")):
        b = summ["buildings"][name]
        row[f"top_{key}"] = b["peak_u"][-1]
        row[f"drift_{key}"] = 100.0 * max(b["peak_drift_ratio_corner"])
        row[f"shear_{key}"] = max(b["peak_storey_shear"]) / 1e6
        plan = np.linalg.norm(acc[name][:, :, :2], axis=-1).max()
        row[f"acc_{key}"] = float(max(plan, max(b["peak_floor_acceleration_impact"], default=0.0)))
    if result.impacts:  # the impulse law: the equivalent Hertz peak force of its strongest impact
        row["force"] = float(impact_forces(result)[0].max()) / 1e6
    else:
        row["force"] = summ["contacts"]["peak_force"] / 1e6
    return LawRun(law, result, summ, row, forces, acc["low"][:, -1, 0])






def strongest_episode(r: LawRun):
    """The episode with the largest peak force (force laws) or impulse (impulse law)."""
    eps = r.result.episodes()
    if not eps:
        return None
    return max(eps, key=lambda e: e.impulse if r.contact_forces is None else e.peak_force)


def pulse(forces, episode, pad: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """(t [s], force [N]) of an episode's strongest pulse: from the last recorded zero force before its
    peak to the first after it (within the episode), ``pad`` recorded steps either side. An episode
    may hold several pulses (the slabs stay within the contact tolerance between them)."""
    t, f = forces.t, forces.pair_force[:, episode.pair]
    inside = np.flatnonzero((t >= episode.start) & (t <= episode.end + (t[1] - t[0])))
    k = inside[np.argmax(f[inside])]
    lo = k
    while lo > 0 and f[lo] > 0.0:
        lo -= 1
    hi = k
    while hi < len(t) - 1 and f[hi] > 0.0:
        hi += 1
    sel = slice(max(lo - pad, 0), min(hi + pad + 1, len(t)))
    return t[sel], f[sel]


def plot_all(runs: list[LawRun], out: Path) -> list[Path]:
    """The three figures of the module docstring; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    fig, axes = plt.subplots(len(runs), 1, sharex=True, figsize=(9, 1.8 * len(runs)))
    for ax, r in zip(np.atleast_1d(axes), runs):
        for name, colour in (("low", "C0"), ("high", "C1")):
            ax.plot(r.result.t, r.result.cm(name)[:, -1, 0], colour, lw=0.8, label=f"{name}, top floor")
        ax.set_ylabel("u [m]")
        ax.set_title(f"{r.law} (dt = {r.result.dt:.2g} s)", fontsize=9, loc="left")
    np.atleast_1d(axes)[0].legend(fontsize=8, loc="upper right")
    np.atleast_1d(axes)[-1].set_xlabel("t [s]")
    fig.tight_layout()
    paths.append(out / "top_displacement.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(runs), figsize=(2.6 * len(runs), 2.8))
    for ax, r in zip(np.atleast_1d(axes), runs):
        e = strongest_episode(r)
        if e is None:
            ax.set_title(f"{r.law}: no contact", fontsize=9)
            continue
        a, fa, b, fb, _ = r.result.pairs[e.pair]
        where = f"storey {fa + 1}, t = {e.start:.3f} s"
        if r.contact_forces is None:
            near = [i for i in r.result.impacts if i.pair == e.pair and abs(i.time - e.start) < 0.05]
            ax.stem([1e3 * (i.time - e.start) for i in near], [i.impulse / 1e3 for i in near])
            ax.set_ylabel("impulse [kN s]")
        else:
            t, f = pulse(r.contact_forces, e)
            ax.plot(1e3 * (t - e.start), f / 1e6, ".-", lw=0.8, ms=3)
            ax.set_ylabel("force [MN]")
        ax.set_xlabel("t - start [ms]")
        ax.set_title(f"{r.law}\n{where}", fontsize=8)
    fig.tight_layout()
    paths.append(out / "contact_force.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(len(runs), 1, sharex=True, sharey=True, figsize=(9, 1.8 * len(runs)))
    for ax, r in zip(np.atleast_1d(axes), runs):
        ax.plot(r.result.t, r.acceleration, "C0", lw=0.6)
        if r.contact_forces is None:  # impacts: the half-sine pulse's peak at each instant
            hist = response_histories(r.result)["low"]
            sign = np.sign(hist["floor_velocity_jump"][:, -1, 0])
            ax.plot(hist["impact_time"], sign * hist["floor_acceleration_impact"][:, -1], "rv", ms=3,
                    label="impact spike (half-sine equivalent, signed as the x velocity change)")
            ax.legend(fontsize=7, loc="upper right")
        ax.set_ylabel("a [m/s2]")
        ax.set_title(f"{r.law}: top floor of 'low', absolute x acceleration", fontsize=9, loc="left")
    np.atleast_1d(axes)[-1].set_xlabel("t [s]")
    fig.tight_layout()
    paths.append(out / "floor_acceleration.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)
    return paths




def main(out: Path, duration: float | None = None, readme: bool = False) -> list[LawRun]:
    out.mkdir(parents=True, exist_ok=True)
    runs = []
    for law in LAWS:
        t0 = time.perf_counter()
        runs.append(run_law(law, duration))
        print(f"{law}: {time.perf_counter() - t0:.1f} s", flush=True)
    md = write_table(COLUMNS, [r.row for r in runs], out, formatted)
    print(md)
    plots = plot_all(runs, out)
    if readme:
        update_readme(HERE, "run_laws.py", md, plots)
    return runs


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--duration", type=float, default=None, help="seconds of the record to run (default: all of it)")
    p.add_argument("--readme", action="store_true", help="write the table and plots into this example's README")
    a = p.parse_args()
    main(a.out, a.duration, a.readme)
