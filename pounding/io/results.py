"""Write a run's results: response.npz, summary.json, impacts.csv (a contract people script against).

Files are written into a temporary folder beside the target and moved into
place only when complete, so an interrupted or failed run leaves either the
previous results or nothing, never a half-written folder.

* ``response.npz``: ``t`` (nt,) [s]; for every building B, ``B_cm`` (nt, storeys, 3)
  = u [m], v [m], phi [rad] of every slab's centre of mass relative to the
  ground, and ``B_vertices`` (nt, storeys, vertices, 2) = x and y displacement
  of every slab vertex in the scene's order (NaN-padded when storeys have
  polygons with fewer vertices).
* ``summary.json``: steps, runtime_s (solver time), integrator, dt, per
  building periods and peak |u|, |v|, |phi| per storey, n_impacts, impacts per
  storey, energy terms and balance.
* ``impacts.csv``: one row per impact (header only while there is none).
"""

from __future__ import annotations

import contextlib
import csv
import json
import os
import shutil
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

from pounding.framework.results import Result

IMPACT_COLUMNS = ["time", "storey", "striking_building", "vertex", "impulse", "normal_x", "normal_y", "approach_velocity", "energy_loss"]


@contextlib.contextmanager
def atomic_dir(target: str | Path):
    """Yield a temporary folder beside ``target``; on success it replaces ``target``.

    On any exception (KeyboardInterrupt included) the temporary folder is
    removed and ``target`` is left as it was.
    """
    target = Path(target).resolve()
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent))
    try:
        yield tmp
        old = None
        if target.exists():
            old = target.parent / f".{target.name}.old-{os.getpid()}"
            os.replace(target, old)
        os.replace(tmp, target)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def summary(result: Result) -> dict:
    """The summary.json content as a dict."""
    storeys = Counter(result.impact_storey(i) for i in result.impacts)
    buildings = {}
    for s in result.systems:
        peaks = result.peaks(s.name)
        buildings[s.name] = {
            "periods": s.periods.tolist(),
            "damping_ratios": s.zeta.tolist(),
            "peak_u": peaks[:, 0].tolist(),
            "peak_v": peaks[:, 1].tolist(),
            "peak_phi": peaks[:, 2].tolist(),
            "energy": result.energy[s.name],
        }
    balance = result.energy_balance()
    return {
        "steps": result.steps,
        "runtime_s": result.runtime_s,
        "integrator": result.integrator,
        "contact": result.contact,
        "dt": result.dt,
        "duration": float(result.steps * result.dt),
        "ground_motion": result.ground_motion,
        "buildings": buildings,
        "n_impacts": result.n_impacts,
        "impacts_per_storey": {str(k): v for k, v in sorted(storeys.items())},
        "impact_energy_loss": float(sum(i.energy_loss for i in result.impacts)),
        "energy_balance": balance,
        **result.info,
    }


def impact_rows(result: Result) -> list[list]:
    return [
        [i.time, result.impact_storey(i), result.striking_building(i), i.vertex, i.impulse, i.normal[0], i.normal[1], i.approach_velocity, i.energy_loss]
        for i in result.impacts
    ]


def write_files(result: Result, folder: Path, scene_text: str | None = None) -> None:
    """Write the three result files (and a copy of the scene) into an existing folder."""
    arrays = {"t": result.t}
    for name in result.names:
        arrays[f"{name}_cm"] = result.cm(name)
        arrays[f"{name}_vertices"] = result.vertices(name)
    np.savez_compressed(folder / "response.npz", **arrays)
    (folder / "summary.json").write_text(json.dumps(summary(result), indent=1, default=_jsonable) + "\n")
    with open(folder / "impacts.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(IMPACT_COLUMNS)
        w.writerows(impact_rows(result))
    if scene_text is not None:
        (folder / "scene.toml").write_text(scene_text)


def write_results(result: Result, out: str | Path, scene_text: str | None = None, extra=None) -> Path:
    """Write all result files into ``out`` atomically; ``extra(folder)`` may add more (VTK, plots)."""
    with atomic_dir(out) as tmp:
        write_files(result, tmp, scene_text)
        if extra is not None:
            extra(tmp)
    return Path(out)


def _jsonable(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
