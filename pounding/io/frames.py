"""A run's results as data for notebooks: pandas DataFrames and an xarray Dataset, units in the names.

The names are summary.json's and response.npz's, with the unit in brackets in a column name
(``peak_drift_ratio_cm [-]``, ``time [s]``) and in the ``units`` attribute of an xarray variable:

* :func:`storey_peaks` - one row per (building, storey): summary.json's per-storey peaks
  (``peak_u``, ``peak_drift_ratio_cm``, ``peak_storey_shear``, ``peak_floor_acceleration``...);
* :func:`impact_table` - one row per impact: impacts.csv's columns;
* :func:`histories` - time x building x storey (x dof or axis): response.npz's histories
  (``displacement``, ``velocity``, ``drift_ratio_cm``, ``storey_shear``, ``floor_acceleration``...),
  storeys a building does not have are NaN.

Storey shears and overturning moments are the elements' elastic forces: viscous damping forces
(a modal matrix tied to no element) and P-Delta shears are not in them (said in the attributes).
pandas and xarray (the ``data`` extra) are imported only here, when one of these is called.
"""

from __future__ import annotations

import numpy as np

#: unit of each per-storey peak of summary.json (a test checks every per-storey key has one)
PEAK_UNITS = {
    "peak_u": "m", "peak_v": "m", "peak_phi": "rad",
    "peak_drift_ratio_cm": "-", "peak_drift_ratio_corner": "-",
    "peak_storey_shear": "N", "peak_storey_shear_x": "N", "peak_storey_shear_y": "N",
    "peak_overturning_moment": "N m",
    "peak_floor_acceleration": "m/s2", "peak_floor_velocity_jump": "m/s", "peak_floor_acceleration_impact": "m/s2",
}

#: what the storey forces hold, stated next to every storey shear and moment (summary.json: the flag
#: ``storey_shear_includes_damping_forces``, false)
STOREY_FORCES_NOTE = ("storey shears and overturning moments are the elements' elastic forces: viscous damping forces "
                      "and P-Delta shears of gravity loads are not included")

#: response.npz histories (per building) in the Dataset: name -> (extra dimension or None, its labels, units, description)
HISTORIES = {
    "drift_ratio_cm": (None, None, "-", "inter-storey drift ratio magnitude at the storey's centre of mass"),
    "drift_ratio_corner": (None, None, "-", "largest inter-storey drift ratio magnitude over the storey's slab corners"),
    "storey_shear": ("axis", ("x", "y"), "N", "storey shear along x and y; " + STOREY_FORCES_NOTE),
    "overturning_moment": ("axis", ("x", "y"), "N m", "overturning moment at the foot of the storey; " + STOREY_FORCES_NOTE),
    "floor_acceleration": ("dof", ("u", "v", "phi"), "m/s2 (u, v), rad/s2 (phi)",
                           "absolute floor acceleration of the centre of mass (impact spikes apart: impact_table)"),
}


def unit_name(name: str, unit: str) -> str:
    """``name [unit]``, the column naming of every table pounding writes."""
    return f"{name} [{unit}]"


def storey_peaks(result, summary: dict | None = None):
    """Per-storey peaks of every building as a DataFrame.

    Parameters
    ----------
    result : Result
    summary : dict, optional
        :func:`pounding.io.results.summary` of ``result`` (computed when None).

    Returns
    -------
    pandas.DataFrame
        Index (``building``, ``storey``) with storeys 1-based, bottom first; one column per
        :data:`PEAK_UNITS` entry, named ``peak_... [unit]``. ``attrs["notes"]`` says what the
        storey forces hold.
    """
    import pandas as pd

    from pounding.io.results import summary as make_summary

    summary = make_summary(result) if summary is None else summary
    rows = []
    for name, b in summary["buildings"].items():
        for f in range(len(b["peak_u"])):
            rows.append({"building": name, "storey": f + 1,
                         **{unit_name(k, u): b[k][f] for k, u in PEAK_UNITS.items() if k in b}})
    frame = pd.DataFrame(rows).set_index(["building", "storey"])
    frame.attrs["notes"] = STOREY_FORCES_NOTE
    return frame


def impact_table(result):
    """Every impact as a row of a DataFrame: impacts.csv's columns (:data:`pounding.io.results.IMPACT_COLUMNS`),
    ``time [s]`` first; empty (with the columns) for a run without impacts."""
    import pandas as pd

    from pounding.io.results import IMPACT_COLUMNS, impact_rows

    return pd.DataFrame(impact_rows(result), columns=IMPACT_COLUMNS)


def contact_table(result):
    """Every contact as a row of a DataFrame: contacts.csv's columns (:data:`pounding.io.results.CONTACT_COLUMNS`):
    a force law's contact episodes and an impulse law's impacts on one table, the buildings and storeys by
    name, each with its peak force (an impact's equivalent force) and the 1-based ``episode`` it belongs to
    (a pair's chatter merged); empty (with the columns) for a run without contact."""
    import pandas as pd

    from pounding.io.results import CONTACT_COLUMNS, contact_rows

    return pd.DataFrame(contact_rows(result), columns=CONTACT_COLUMNS)


def histories(result):
    """The run's histories as an xarray Dataset.

    Dimensions: ``time`` (nt) [s], ``building`` (names, scene order), ``storey`` (1..the most storeys),
    ``dof`` (``u`` [m], ``v`` [m], ``phi`` [rad]: the slab's centre of mass relative to the ground) and
    ``axis`` (``x``, ``y``). Variables: ``displacement`` and ``velocity`` (time, building, storey, dof)
    and :data:`HISTORIES` (time, building, storey[, axis or dof]); each has ``units`` and
    ``description`` attributes. Storeys above a building's roof are NaN.
    """
    import xarray as xr

    from pounding.io.results import response_histories

    names, nt = list(result.names), len(result.t)
    n = max(s.n_storeys for s in result.systems)
    hist = response_histories(result)

    def stack(per_building, tail: tuple[int, ...]) -> np.ndarray:
        out = np.full((nt, len(names), n, *tail), np.nan)
        for i, name in enumerate(names):
            a = per_building(name)
            out[:, i, : a.shape[1]] = a
        return out

    dof_units = "m (u, v), rad (phi)"
    data = {
        "displacement": (("time", "building", "storey", "dof"), stack(result.cm, (3,)),
                         {"units": dof_units, "description": "displacement of the slab's centre of mass relative to the ground"}),
        "velocity": (("time", "building", "storey", "dof"), stack(lambda b: result.cm(b, velocity=True), (3,)),
                     {"units": "m/s (u, v), rad/s (phi)", "description": "velocity of the slab's centre of mass relative to the ground"}),
    }
    for key, (extra, labels, units, text) in HISTORIES.items():
        dims = ("time", "building", "storey") + ((extra,) if extra else ())
        tail = (len(labels),) if extra else ()
        data[key] = (dims, stack(lambda b: hist[b][key], tail), {"units": units, "description": text})
    coords = {"time": ("time", np.asarray(result.t, dtype=float), {"units": "s"}), "building": names,
              "storey": np.arange(1, n + 1), "dof": ["u", "v", "phi"], "axis": ["x", "y"]}
    return xr.Dataset(data, coords=coords, attrs={"integrator": str(result.integrator.get("name")), "dt [s]": float(result.dt)})
