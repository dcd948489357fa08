"""Write a run's results: response.npz, summary.json, impacts.csv (a contract people script against).

Files are written into a temporary folder beside the target and moved into
place only when complete (:mod:`pounding.io.outputs`), so an interrupted or
failed run leaves the previous results, never a half-written folder; files
other commands wrote there (plots, renders) and files pounding did not write
are kept.

* ``response.npz``: ``t`` (nt,) [s]; for every building B, ``B_cm`` (nt, storeys, 3)
  = u [m], v [m], phi [rad] of every slab's centre of mass relative to the
  ground, and ``B_vertices`` (nt, storeys, vertices, 2) = x and y displacement
  of every slab vertex in the scene's order (NaN-padded when storeys have
  polygons with fewer vertices); and the response histories of
  :mod:`pounding.framework.post.response` as ``B_<quantity>`` (drift ratios, storey
  and element shears, overturning moments, floor accelerations, the impacts'
  floor velocity jumps; units and definitions in docs/outputs.md).
* ``summary.json``: steps, runtime_s (solver time; ``timings_s`` adds the time spent loading
  and compiling the compiled core, ``load_and_compile`` of which ``compile``), integrator, dt,
  per building periods, peak |u|, |v|, |phi| and the peak response quantities per
  storey, its own energy account (:mod:`pounding.framework.post.energy_account`),
  n_impacts, impacts per storey, the pair's energy balance with the flag of a
  contact rule that creates energy.
* ``impacts.csv``: one row per impact (header only while there is none), units
  in the header, with the equivalent peak force and contact duration, and what was
  struck: the building, storey, height and element, and for a slab striking a
  neighbour between its floors the local stiffness and shear demand of the struck
  element (:func:`pounding.framework.model.facade.impact_sites`).
* ``contacts.csv``: one row per contact episode of any contact law (:data:`CONTACT_COLUMNS`):
  a force law's stretch of touching (start, end, its peak force and penetration, the
  integral of its force and the energy it took out), and an impulse law's impact (an instant:
  end = start, no penetration, the impulse and the kinetic energy lost, and the equivalent
  peak force of ``[analysis.impact_force]``), so runs with either kind of law compare on one
  table; summary.json has ``n_contacts`` and their totals under ``contacts``.
* ``modal.npz`` and ``scene.toml``: what :func:`load_result` needs to rebuild
  the full :class:`Result` (modal histories, impact log, states at impact
  instants) for ``pounding plot`` and ``pounding render``. scene.toml is the scene
  file's text when given, else the run's scene written back
  (:func:`pounding.io.scene_writer.write_scene`, with its ground motion in
  ``scene.ground_motion.txt``), so every run folder can be plotted.
"""

from __future__ import annotations

import csv
import json
from collections import Counter
from pathlib import Path

import numpy as np

from pounding.framework.engine.results import ContactEpisode, Result
from pounding.framework.post.energy_account import energy_balance

IMPACT_COLUMNS = [
    "time [s]", "storey", "striking_building", "vertex", "impulse [N s]", "normal_x", "normal_y", "approach_velocity [m/s]",
    "energy_loss [J]", "peak_force [N]", "contact_duration [s]",
    # what was struck (pounding.framework.model.facade.impact_sites): a slab, or a facade between floors
    "struck_building", "struck_storey", "struck_height [m]", "struck_element", "struck_fraction",
    "local_stiffness [N/m]", "struck_shear_below [N]", "struck_shear_above [N]",
]


CONTACT_COLUMNS = [
    "start [s]", "end [s]", "law", "building_a", "storey_a", "building_b", "storey_b", "point_x [m]", "point_y [m]",
    "normal_x", "normal_y", "approach_velocity [m/s]", "peak_force [N]", "peak_penetration [m]", "impulse [N s]",
    "energy_dissipated [J]", "episode",
]


def episodes_with_forces(result: Result) -> list[tuple[ContactEpisode, float]]:
    """Every contact episode (:meth:`Result.episodes`'s, unsorted) with its peak force [N]: a force law's
    own, and for an impulse law's impact the equivalent peak force of ``[analysis.impact_force]``
    (:func:`pounding.framework.post.response.impact_forces`): what contacts.csv and summary.json report."""
    from pounding.framework.post.response import impact_forces

    equivalent = impact_forces(result)[0] if result.impacts else []
    return [(ContactEpisode.of_impact(imp), float(f)) for imp, f in zip(result.impacts, equivalent)] + [
        (e, e.peak_force) for e in result.contacts]


def contact_rows(result: Result) -> list[list]:
    """contacts.csv rows (:data:`CONTACT_COLUMNS`), by start time: storeys 1-based; each with its peak
    force (:func:`episodes_with_forces`)."""
    laws = result.pair_law_names
    episodes = episodes_with_forces(result)
    merged = result.contact_episodes()
    rows = []
    for e, force in sorted(episodes, key=lambda x: (x[0].start, x[0].pair)):
        a, fa, b, fb, _ = result.pairs[e.pair]
        # the 1-based contact episode (chatter merged: Result.contact_episodes) the row belongs to
        episode = next(k + 1 for k, m in enumerate(merged) if m.pair == e.pair and m.start <= e.start <= m.end)
        rows.append([e.start, e.end, laws[e.pair], result.names[a], fa + 1, *result.second_body(e.pair), e.point[0], e.point[1],
                     e.normal[0], e.normal[1], e.approach_velocity, force, e.peak_penetration, e.impulse, e.energy_dissipated,
                     episode])
    return rows


def episodes_summary(result: Result) -> dict:
    """summary.json's ``contact_episodes``: the contact episodes with each pair's chatter merged
    (:meth:`Result.contact_episodes`, the count that converges with dt), how many per storey, how
    many impacts or force contacts they hold, and the merge interval of every pair [s]."""
    from pounding.framework.engine.chatter import CHATTER_FRACTION, merge_intervals

    eps = result.contact_episodes()
    tau = merge_intervals(result.systems, result.pairs)
    return {
        "n": len(eps),
        "per_storey": {str(k): v for k, v in sorted(Counter(result.pairs[e.pair][1] + 1 for e in eps).items())},
        "strikes": int(sum(e.strikes for e in eps)),
        "most_strikes": int(max((e.strikes for e in eps), default=0)),
        "merge_interval_s": {"{}.{}-{}.{}".format(result.names[a], fa + 1, *result.second_body(p)): float(t)
                             for p, ((a, fa, _, _, _), t) in enumerate(zip(result.pairs, tau))},
        "rule": (f"a pair's impacts (or force contacts) form one episode while each begins less than {CHATTER_FRACTION:g} "
                 "of the faster fundamental period of the pair's two buildings after the previous one ended"),
    }


def convergence_note() -> dict:
    """summary.json's ``convergence``: which results converge as dt falls and which do not."""
    from pounding.framework.engine.chatter import CONVERGES_WITH_DT, DEPENDS_ON_DT

    return {"converge_with_dt": list(CONVERGES_WITH_DT), "depend_on_dt": list(DEPENDS_ON_DT)}


def contacts_summary(result: Result) -> dict:
    """The contact episodes in summary.json: how many, per storey (the pair's first slab's), and their
    totals (impulse, energy dissipated), largest peak force (contacts.csv's: :func:`episodes_with_forces`)
    and largest penetration (force laws')."""
    eps = result.episodes()
    storeys = Counter(result.pairs[e.pair][1] + 1 for e in eps)
    forces = [f for _, f in episodes_with_forces(result) if np.isfinite(f)]
    return {
        "n": len(eps),
        "per_storey": {str(k): v for k, v in sorted(storeys.items())},
        "impulse": float(sum(e.impulse for e in eps)),
        "energy_dissipated": float(sum(e.energy_dissipated for e in eps)),
        "peak_force": float(max(forces, default=0.0)),
        "peak_penetration": float(max((e.peak_penetration for e in eps), default=0.0)),
        "longest": float(max((e.duration for e in eps), default=0.0)),
    }


def walls_summary(result: Result) -> dict:
    """summary.json's ``walls``: per retaining wall, its contacts (impacts of impulse laws, episodes of
    force laws), their total impulse [N s] and dissipated energy [J], its largest contact force [N]
    (contacts.csv's: :func:`episodes_with_forces`) and the buildings that struck it."""
    out = {}
    with_forces = episodes_with_forces(result)
    for wall in dict.fromkeys(w.name for w in result.walls.values()):
        mine = [(e, f) for e, f in with_forces if e.pair in result.walls and result.walls[e.pair].name == wall]
        eps = [e for e, _ in mine]
        forces = [f for _, f in mine if np.isfinite(f)]
        out[wall] = {"n_contacts": len(eps), "impulse": float(sum(e.impulse for e in eps)),
                     "energy_dissipated": float(sum(e.energy_dissipated for e in eps)), "peak_force": float(max(forces, default=0.0)),
                     "struck_by": sorted({result.names[result.pairs[e.pair][0]] for e in eps})}
    return out


def response_histories(result: Result) -> dict[str, dict[str, np.ndarray]]:
    """Per building, the response histories of :func:`pounding.framework.post.response.building_response`."""
    from pounding.framework.post.response import building_response, impact_forces

    _, durations = impact_forces(result)
    return {name: building_response(result, name, durations) for name in result.names}


def summary(result: Result, histories: dict | None = None) -> dict:
    """The summary.json content as a dict (``histories``: :func:`response_histories`, computed when None)."""
    from pounding.framework.post.energy_account import building_balances, energy_creating_rule
    from pounding.framework.post.response import peaks as response_peaks

    histories = response_histories(result) if histories is None else histories
    storeys = Counter(result.impact_storey(i) for i in result.episodes())
    balances = building_balances(result)
    contact_forces = any(abs(result.energy[n]["contact_forces"]) > 0.0 for n in result.names)
    buildings = {}
    for s in result.systems:
        peaks = result.peaks(s.name)
        buildings[s.name] = {
            "periods": s.periods.tolist(),
            "damping_ratios": s.zeta.tolist(),
            "peak_u": peaks[:, 0].tolist(),
            "peak_v": peaks[:, 1].tolist(),
            "peak_phi": peaks[:, 2].tolist(),
            **_true_drift_peaks(result, s.name, response_peaks(histories[s.name])),
            # the smooth part omits forces of sustained/penalty contact, which a run does not record
            "floor_acceleration_includes_contact_forces": not contact_forces,
            # storey and base shears and overturning moments are the elements' forces: the damping matrix is tied to no
            # element (docs/outputs.md; said next to every storey shear: pounding.io.frames.STOREY_FORCES_NOTE)
            "storey_shear_includes_damping_forces": False,
            "energy": balances[s.name],
            **_isolators(result, s),
        }
    balance = energy_balance(result)
    balance["energy_creating_rule"] = energy_creating_rule(result)
    episodes = episodes_summary(result)
    from pounding.version import package_version

    return {
        "pounding_version": package_version(),  # which code computed these numbers
        "steps": result.steps,
        "runtime_s": result.runtime_s,
        "timings_s": {"solve": result.runtime_s, **{k[:-2]: v for k, v in getattr(result, "timings", {}).items() if k != "solve_s"}},
        "integrator": result.integrator,
        "contact": result.contact,
        "dt": result.dt,
        "duration": float(result.steps * result.dt),
        "ground_motion": result.ground_motion,
        "buildings": buildings,
        "n_impacts": result.n_impacts,
        "impacts_per_storey": {str(k): v for k, v in sorted(storeys.items())},
        "impact_energy_loss": float(sum(i.energy_loss for i in result.impacts)),
        "n_contacts": result.n_impacts,
        "contacts": contacts_summary(result),
        **({"walls": walls_summary(result)} if getattr(result, "walls", None) else {}),
        "n_contact_episodes": episodes["n"],
        "contact_episodes": episodes,
        "convergence": convergence_note(),
        "energy_balance": balance,
        **_links(result),
        "peaks_over": _peaks_over(result),
        **result.info,
    }


def _links(result: Result) -> dict:
    """``{"links": ...}`` with the links between slabs (:func:`pounding.io.link_outputs.links_summary`), else {}."""
    from pounding.io.link_outputs import links_summary

    return {"links": links_summary(result)} if getattr(result, "links", None) else {}


def _isolators(result: Result, system) -> dict:
    """``{"isolators": ...}`` for a base-isolated building (:mod:`pounding.framework.post.isolators`), else {}."""
    from pounding.framework.post.isolators import isolator_summary

    if getattr(result, "scene", None) is None:
        return {}
    iso = isolator_summary(result.scene.building(system.name), system, result.cm(system.name), getattr(result, "springs", {}).get(system.name))
    return {"isolators": iso} if iso else {}


def _peaks_over(result: Result) -> str:
    """What the peaks of displacements and drifts are taken over (:mod:`pounding.framework.engine.peaks`)."""
    if len(result.t) != result.steps + 1:
        return "continuous trajectory of the slabs (cubic Hermite in every step, tracked during the run); drifts over the output steps"
    if getattr(result, "intra_step", None) is not None:
        return "continuous trajectory (the exact integrator's intra-step solution)"
    return "continuous trajectory (cubic Hermite through (q, q') at both ends of every step)"


def _true_drift_peaks(result: Result, name: str, peaks: dict) -> dict:
    """The response peaks with the drift ratios' taken over the continuous trajectory (where every step
    is in the output; else over the output steps)."""
    from pounding.framework.engine.peaks import drift_peaks

    dp = drift_peaks(result, name)
    if dp is not None:
        peaks = {**peaks, "peak_drift_ratio_cm": dp[0].tolist(), "peak_drift_ratio_corner": dp[1].tolist()}
    return peaks


def impact_rows(result: Result) -> list[list]:
    """impacts.csv rows (:data:`IMPACT_COLUMNS`): ``storey`` is the pair's first slab's storey (1-based; for a
    facade pair, the striking slab's), the struck side follows in the ``struck_*`` columns."""
    from pounding.framework.model.facade import impact_sites
    from pounding.framework.post.response import impact_forces

    force, tau = impact_forces(result)
    sites = impact_sites(result, force)
    return [
        [i.time, result.impact_storey(i), result.striking_building(i), i.vertex, i.impulse, i.normal[0], i.normal[1], i.approach_velocity,
         i.energy_loss, f, d, *site]
        for i, f, d, site in zip(result.impacts, force, tau, sites)
    ]



def write_files(result: Result, folder: Path, scene_text: str | None = None) -> None:
    """Write the result files (and a copy of the scene) into an existing folder."""
    arrays = {"t": result.t}
    histories = response_histories(result)
    for name in result.names:
        arrays[f"{name}_cm"] = result.cm(name)
        arrays[f"{name}_vertices"] = result.vertices(name)
        arrays.update({f"{name}_{key}": val for key, val in histories[name].items()})
    from pounding.io.link_outputs import link_arrays

    arrays.update(link_arrays(result))  # the links between slabs
    np.savez(folder / "response.npz", **arrays)  # uncompressed: writing stays ~10x faster than zlib
    (folder / "summary.json").write_text(json.dumps(summary(result, histories), indent=1, default=_jsonable) + "\n")
    with open(folder / "impacts.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(IMPACT_COLUMNS)
        w.writerows(impact_rows(result))
    with open(folder / "contacts.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(CONTACT_COLUMNS)
        w.writerows(contact_rows(result))
    imp = result.impacts
    np.savez(
        folder / "modal.npz",
        t=result.t, q=result.q, qd=result.qd, mode_start=result.mode_start,
        pairs=np.array([p[:4] for p in result.pairs], dtype=np.int64).reshape(-1, 4),
        pair_rest_gap=np.array([p[4] for p in result.pairs], dtype=float),
        event_t=result.event_t, event_q=result.event_q, event_qd=result.event_qd,
        impact_time=np.array([i.time for i in imp]), impact_pair=np.array([i.pair for i in imp], dtype=np.int64),
        impact_striker=np.array([i.striker for i in imp], dtype=np.int64), impact_vertex=np.array([i.vertex for i in imp], dtype=np.int64),
        impact_impulse=np.array([i.impulse for i in imp]), impact_normal=np.array([i.normal for i in imp]).reshape(-1, 2),
        impact_b=np.array([i.approach_velocity for i in imp]), impact_loss=np.array([i.energy_loss for i in imp]),
        impact_point=np.array([i.point for i in imp]).reshape(-1, 2),
        **contact_arrays(result.contacts),
        slab_peaks=result.slab_peaks,
    )
    if scene_text is not None:
        (folder / "scene.toml").write_text(scene_text)
    elif getattr(result, "scene", None) is not None:  # a run from Python: its scene, written back (and its record)
        from pounding.io.scene_writer import write_scene

        try:
            write_scene(result.scene, folder / "scene.toml")
        except NotImplementedError as exc:  # a plugin element without to_table: the results are still written
            import warnings

            from pounding.errors import AnalysisWarning

            warnings.warn(f"scene.toml not written ({exc}): `pounding plot` cannot read this folder", AnalysisWarning, stacklevel=3)


#: the fields of a force law's contact episode in modal.npz (``contact_<field>``), in ContactEpisode's order
EPISODE_FIELDS = ("start", "end", "pair", "point", "normal", "approach_velocity", "peak_force", "peak_penetration", "impulse",
                  "energy_dissipated")


def contact_arrays(contacts: list) -> dict:
    """The force laws' contact episodes as arrays ``contact_<field>`` (n,) or (n, 2) for modal.npz."""
    out = {}
    for f in EPISODE_FIELDS:
        values = [getattr(e, f) for e in contacts]
        out[f"contact_{f}"] = (np.array(values, dtype=float).reshape(-1, 2) if f in ("point", "normal")
                               else np.array(values, dtype=np.int64 if f == "pair" else float))
    return out


def episodes_from(data) -> list:
    """The contact episodes :func:`contact_arrays` wrote (none in older run folders)."""
    if "contact_start" not in data:
        return []
    cols = [data[f"contact_{f}"] for f in EPISODE_FIELDS]
    return [ContactEpisode(*(int(v) if f == "pair" else v.copy() if f in ("point", "normal") else float(v)
                             for f, v in zip(EPISODE_FIELDS, row))) for row in zip(*cols)]


def load_result(folder: str | Path):
    """Rebuild (scene, Result) from a run folder written by ``pounding run``.

    Raises
    ------
    InputError
        If the folder lacks scene.toml, modal.npz or summary.json.
    """
    import tomllib

    from pounding.errors import InputError
    from pounding.framework.model.assembly import assemble
    from pounding.framework.engine.results import Impact
    from pounding.io.link_outputs import load_links
    from pounding.io.scene import parse_scene

    folder = Path(folder)
    if not folder.is_dir():
        what = "it is a file" if folder.exists() else "no such folder"
        raise InputError(f"not a run folder: {what} (write one with `pounding run SCENE --out DIR`)", file=str(folder))
    for name in ("scene.toml", "modal.npz", "summary.json"):
        if not (folder / name).is_file():
            raise InputError(f"not a run folder: {name} is missing (write one with `pounding run SCENE --out DIR`)", file=str(folder))
    summ = json.loads((folder / "summary.json").read_text())
    source = Path(summ.get("scene_path") or folder / "scene.toml")
    try:
        scene = parse_scene(tomllib.loads((folder / "scene.toml").read_text()), source=source)
    except InputError as exc:
        raise InputError(exc.message, file=str(folder / "scene.toml"), field=exc.field) from None
    data = np.load(folder / "modal.npz")
    impacts = [
        Impact(float(t), int(p), int(s), int(v), float(i), n.copy(), float(b), float(l), pt.copy())
        for t, p, s, v, i, n, b, l, pt in zip(
            data["impact_time"], data["impact_pair"], data["impact_striker"], data["impact_vertex"], data["impact_impulse"],
            data["impact_normal"], data["impact_b"], data["impact_loss"], data["impact_point"],
        )
    ]
    pairs = [(int(a), int(fa), int(b), int(fb), float(g)) for (a, fa, b, fb), g in zip(data["pairs"], data["pair_rest_gap"])]
    terms = ("input", "damping", "contact_forces", "kinetic", "strain", "hysteretic", "links")  # as the run booked them (the rest is derived)
    energy = {name: {k: b["energy"][k] for k in terms if k in b["energy"]} for name, b in summ["buildings"].items()}
    springs = _load_springs(folder, scene, summ)
    result = Result(
        t=data["t"], names=[b.name for b in scene.buildings], q=data["q"], qd=data["qd"],
        systems=[assemble(b) for b in scene.buildings], mode_start=data["mode_start"], pairs=pairs, impacts=impacts,
        energy=energy, runtime_s=summ["runtime_s"], dt=summ["dt"], steps=summ["steps"], integrator=summ["integrator"],
        contact=summ["contact"], ground_motion=summ["ground_motion"],
        energy_tolerance=summ["energy_balance"].get("tolerance", 0.02),
        info={"impact_force": summ["impact_force"]} if "impact_force" in summ else {},
        event_t=data["event_t"], event_q=data["event_q"], event_qd=data["event_qd"],
        slab_peaks=data["slab_peaks"] if "slab_peaks" in data else None,  # older run folders: from the histories
        springs=springs,
        contacts=episodes_from(data),
        links=load_links(folder, scene),
        link_energy={k: summ["energy_balance"]["links"][k] for k in ("dissipated", "stored")} if "links" in summ["energy_balance"] else None,
    )
    from pounding.framework.engine.stacked_model import Model

    model = Model(scene, result.systems)  # the pair geometry, as the run built it
    result.geo, result.facades, result.buildings, result.scene = model.geo, model.facades, scene.buildings, scene
    result.walls = model.walls
    result.pair_law_names = run_law_names(scene, model)
    return scene, result


def run_law_names(scene, model) -> list[str]:
    """The name of every slab pair's contact law of ``scene`` on the pairs of ``model``, by the rule
    the run resolves them with (:func:`pounding.contact.rules.scene_laws`)."""
    from pounding.contact.rules import law_name, scene_laws

    laws, which = scene_laws(scene, model.pairs, model.walls)
    return [law_name(laws[j]) for j in which]


def _load_springs(folder: Path, scene, summ: dict) -> dict:
    """The yielding springs' histories of a run folder (response.npz), as the run kept them."""
    from pounding.framework.model.assembly import assemble
    from pounding.framework.engine.inelastic import spring_set

    path = folder / "response.npz"
    if not path.exists():
        return {}
    out = {}
    with np.load(path) as data:
        for i, b in enumerate(scene.buildings):
            if f"{b.name}_spring_force" not in data:
                continue
            sset = spring_set(b, i)
            G = sset.T @ assemble(b).modes
            d = data
            out[b.name] = {"element": sset.element, "storey": sset.storey, "height": sset.height, "k0": sset.k0,
                           "yield_deformation": sset.yield_deformation, "G": G,
                           "deformation": d[f"{b.name}_spring_deformation"], "force": d[f"{b.name}_spring_force"],
                           "dissipated": d[f"{b.name}_spring_dissipated"], "peak": d[f"{b.name}_spring_peak"]}
    return out


def write_results(result: Result, out: str | Path, scene_text: str | None = None, extra=None, scene_path=None, *, overwrite: bool = True) -> Path:
    """Write all result files into ``out`` through a temporary folder; ``extra(folder)`` may add more (VTK).

    The files are recorded as the ``run`` command's in ``out``'s manifest
    (:mod:`pounding.io.outputs`): files the previous run wrote there and this
    one did not are removed, every other file stays. With ``overwrite=False``
    a folder holding files pounding did not write is refused (InputError).
    """
    from pounding.io.outputs import check_target, write_folder

    check_target(Path(out), overwrite=overwrite)
    if scene_path is not None:
        result.info["scene_path"] = str(Path(scene_path).resolve())

    def write(tmp: Path) -> None:
        write_files(result, tmp, scene_text)
        if extra is not None:
            extra(tmp)

    write_folder(out, "run", write)
    return Path(out)


def _jsonable(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
