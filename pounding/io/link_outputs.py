"""What a run writes of its links between slabs (the ``[[link]]`` tables), and reads back.

* response.npz: ``link_<name>_deformation``, ``link_<name>_force``, ``link_<name>_dissipated`` (nt,)
  [m, N, J] at the output times (the deformation is the second point's displacement minus the
  first's along the link's line; the dissipated energy is the law's own, cumulative), and
  ``link_<name>_peak`` [m], the peak |deformation| over every step;
* summary.json ``links``: per link its ``between``, ``storeys``, ``law``, ``peak_force`` [N] (over
  the output times), ``peak_stroke`` [m] (over every step) and ``energy_dissipated`` [J].
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: the histories of a link kept in response.npz, as ``link_<name>_<key>``
HISTORY_KEYS = ("deformation", "force", "dissipated", "peak")


def link_arrays(result) -> dict[str, np.ndarray]:
    """response.npz arrays of every link between slabs (module docstring)."""
    out = {}
    for name, rec in getattr(result, "links", {}).items():
        out.update({f"link_{name}_{key}": np.asarray(rec[key]) for key in HISTORY_KEYS})
    return out


def links_summary(result) -> dict:
    """summary.json ``links``: per link name, where it is and what it did (module docstring)."""
    return {name: {"between": list(rec["between"]), "storeys": [int(s) for s in rec["storeys"]], "law": rec["law"],
                   "peak_force": float(rec["peak_force"]), "peak_stroke": float(rec["peak"]),
                   "energy_dissipated": float(rec["energy_dissipated"])}
            for name, rec in getattr(result, "links", {}).items()}


def load_links(folder: Path, scene) -> dict:
    """The links' records of a run folder (response.npz), as the run kept them (see
    :func:`pounding.framework.engine.yielding.link_record`)."""
    from pounding.framework.engine.link_table import building_rows
    from pounding.framework.model.assembly import assemble

    systems = [assemble(b) for b in scene.buildings]
    path = Path(folder) / "response.npz"
    if not scene.links or not path.exists():
        return {}
    out = {}
    with np.load(path) as data:
        for link in scene.links:
            if f"link_{link.name}_force" not in data:
                continue
            rec = {key: data[f"link_{link.name}_{key}"] for key in HISTORY_KEYS}
            force = rec["force"]
            out[link.name] = {"between": list(link.between), "storeys": list(link.storeys), "points": link.points.copy(),
                              "rows": building_rows(scene, systems, link),
                              "law": link.law.describe(), **rec, "peak": float(rec["peak"]),
                              "peak_force": float(np.max(np.abs(force), initial=0.0)),
                              "energy_dissipated": float(rec["dissipated"][-1]) if len(rec["dissipated"]) else 0.0}
    return out

