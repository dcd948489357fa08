"""Parameter sweeps: a grid of analyses of one scene, run on Dask, summarised in one table.

The grid is the Cartesian product of

* gaps: the clear distance at rest between the two buildings along a direction
  (:func:`pounding.framework.model.placement.with_gap`; the second building is moved),
* PGA scale factors (applied after the scene's own ``pga``/``scale``),
* records (AT2 files replacing the scene's record, scaled as the scene says), or
  the pairs of a record set (``fema-p695:farfield``: the 22 far-field pairs of
  FEMA P695) replacing the scene's record or pair,
* incidence angles of the ground motion (its first component) [deg],
* coefficients of restitution,
* integrators (by name, default parameters).

Each run is described by plain data: the scene file's TOML text, the run's
parameters and, for a record file, its text. A worker rebuilds the scene from
that (nothing compiled or pickled crosses processes) and returns one row of
plain numbers, so results do not depend on where or in what order runs execute:
a sweep on any number of workers gives the same table as a serial one. A run
that fails gives a row with ``status = "error"`` and the error message; the
others go on.

Each row also says whether the analysis window holds the record's strong
motion (``window_cut``, empty when it does; :mod:`pounding.framework.studies.window`),
and ``sweep.json`` what the records were scaled to (the scene's ``pga``,
``scale`` or ``intensity``/``target``, with the period of a spectral target)
before the sweep's factors.

The CSV table is written as runs complete (a row appended and flushed for each,
so an interrupted sweep keeps what finished), then rewritten in run order when
all are done, with a Parquet copy if pyarrow is installed and the plots of
impacts and peak drift against the gap (matplotlib, imported only there).

Scheduling: serial in this process, a local ``dask.distributed`` cluster of
worker processes (one per core by default: the runs are CPU-bound Python and
numba code that would hold the GIL in threads), or an existing cluster by
scheduler address. On a remote cluster, ``keep`` writes each run's result folder
on the worker's file system.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import os
import tempfile
import time
import tomllib
import warnings
from collections import Counter
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from pounding.errors import InputError

PARAMETERS = ["run", "gap", "pga_scale", "record", "angle", "restitution", "integrator"]
#: The record against the analysis window (:func:`pounding.framework.studies.window.window_columns`; units in the names).
WINDOW = ["window_cut", "window_s", "arias95_s", "peak_time_s", "arias_m_s"]
#: Columns that hold text.
TEXT_COLUMNS = ("record", "integrator", "status", "error", "warnings", "window_cut")
TABLE_CSV = "sweep.csv"
TABLE_PARQUET = "sweep.parquet"
#: What the sweep scaled the records to and every record against the window.
SWEEP_JSON = "sweep.json"

__all__ = ["Case", "SweepResult", "build_cases", "columns", "parse_values", "plot_sweep", "prepare", "read_table", "run_case", "run_sweep"]


# =============================================================================
# The grid
# =============================================================================


@dataclass(frozen=True)
class Case:
    """One run of a sweep. ``None`` means "as in the scene"."""

    run: int
    gap: float | None = None
    pga_scale: float = 1.0
    record: str | None = None
    restitution: float | None = None
    integrator: str | None = None
    angle: float | None = None


def parse_values(text: str, field: str, *, minimum: float | None = None, maximum: float | None = None) -> list[float]:
    """Numbers from ``"0,0.01,0.05"``, a range ``"a:b:n"`` (n values from a to b inclusive) or both, comma-separated."""
    out: list[float] = []
    for item in str(text).split(","):
        item = item.strip()
        if not item:
            continue
        try:
            if ":" in item:
                parts = item.split(":")
                if len(parts) != 3:
                    raise ValueError
                a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
                if n < 1:
                    raise ValueError
                values = [a] if n == 1 else np.linspace(a, b, n).tolist()
            else:
                values = [float(item)]
        except ValueError:
            raise InputError(f"expected numbers separated by commas or a range a:b:n (n >= 1 values), got {item!r}", field=field) from None
        for v in values:
            v = float(f"{v:.12g}")  # 0.30000000000000004 -> 0.3
            if not math.isfinite(v) or (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
                bounds = f"in [{minimum:g}, {maximum:g}]" if minimum is not None and maximum is not None else (f">= {minimum:g}" if minimum is not None else "finite")
                raise InputError(f"expected values {bounds}, got {v:g}", field=field)
            out.append(v)
    if not out:
        raise InputError("expected at least one value", field=field)
    return out


def build_cases(gaps=None, pga_scales=None, records=None, restitutions=None, integrators=None, angles=None) -> list[Case]:
    """The Cartesian product of the parameter lists (gap varies fastest, then the angle), numbered from 0."""
    grid = itertools.product(
        list(records) if records else [None],
        list(integrators) if integrators else [None],
        list(restitutions) if restitutions else [None],
        list(pga_scales) if pga_scales else [1.0],
        list(angles) if angles else [None],
        list(gaps) if gaps else [None],
    )
    return [Case(i, g, float(p), rec, k, integ, None if a is None else float(a))
            for i, (rec, integ, k, p, a, g) in enumerate(grid)]


def columns(storeys: list[int], names: list[str]) -> list[str]:
    """Table columns for impact storeys ``storeys`` (1-based) and buildings ``names``."""
    cols = PARAMETERS + WINDOW + ["status", "error", "warnings", "n_impacts", "min_gap"] + [f"impacts_storey_{s}" for s in storeys]
    for n in names:
        cols += [f"{n}_peak_u", f"{n}_peak_v", f"{n}_peak_phi", f"{n}_peak_drift_ratio_cm"]
    return cols + ["max_impulse", "energy_loss", "runtime_s"]


# =============================================================================
# One run (executes on a worker)
# =============================================================================


def _scene_for(spec: dict, case: dict, record_text: str | None):
    """Rebuild the scene of one case from the TOML text and the overrides."""
    from pounding.io.scene import parse_scene

    data = tomllib.loads(spec["scene_text"])
    an = data.setdefault("analysis", {})
    an.update(spec.get("overrides") or {})
    if case["integrator"] is not None:
        an["integrator"] = case["integrator"]
    if case["restitution"] is not None:
        contact = an.get("contact")
        if isinstance(contact, dict) and "restitution" in contact:
            contact["restitution"] = case["restitution"]  # a value inside the contact table wins over analysis.restitution
        else:
            an["restitution"] = case["restitution"]
    gm = data.setdefault("ground_motion", {"record": "elcentro"})
    if case.get("angle") is not None:
        gm["angle"] = case["angle"]
    from pounding.io.records import P695_PREFIX

    if case["record"] is not None and case["record"].startswith(P695_PREFIX):
        # a pair of a record set replaces the scene's record or pair; the scene's scaling applies to it
        gm.pop("record", None)
        for key in ("format", "dt", "units"):
            gm.pop(key, None)
        gm["components"] = case["record"]
    with tempfile.TemporaryDirectory(prefix="pounding-sweep-") as tmp:
        if isinstance(record_text, (tuple, list)):  # a pair of --records FOLDER (two-component scene)
            written = []
            for name, text in zip(spec["records"][case["record"]], record_text):
                written.append(Path(tmp) / name)
                written[-1].write_text(text, encoding="latin-1")
            for key in ("format", "dt", "units", "record"):
                gm.pop(key, None)
            gm["components"] = [str(p) for p in written]
            origins = dict(zip(map(str, written), spec["record_paths"][case["record"]]))
            try:
                scene = parse_scene(data, source=Path(spec["scene_path"]))
            except InputError as exc:
                if exc.file in origins:  # name the record as the user knows it
                    raise InputError(exc.message, file=origins[exc.file], field=exc.field) from None
                raise
        elif record_text is not None:
            if case["record"] is not None:  # a record of --records: an AT2 file that states its units and dt
                filename = spec["records"][case["record"]]
                for key in ("format", "dt", "units", "components"):
                    gm.pop(key, None)
            else:  # the scene's own record file
                filename = spec["scene_record"]
            path = Path(tmp) / filename
            path.write_text(record_text, encoding="latin-1")
            gm["record"] = str(path)
        if not isinstance(record_text, (tuple, list)):
            try:
                scene = parse_scene(data, source=Path(spec["scene_path"]))
            except InputError as exc:
                if record_text is not None and exc.file == str(path):  # name the record as the user knows it
                    origin = spec["record_paths"].get(case["record"] if case["record"] is not None else "", filename)
                    raise InputError(exc.message, file=origin, field=exc.field) from None
                raise
    if case["pga_scale"] != 1.0:
        scene = scene.with_ground_motion(scene.ground_motion.scaled(case["pga_scale"]))
    if case["gap"] is not None:
        scene = scene.with_gap(case["gap"], spec.get("direction"))
    return scene


def _measures(result, scene, storeys: list[int]) -> dict:
    row = {"n_impacts": result.n_impacts}
    # every contact episode: an impulse law's impacts and a force law's contacts (Result.episodes)
    episodes = result.episodes()
    per = Counter(result.impact_storey(e) for e in episodes)
    for s in storeys:
        row[f"impacts_storey_{s}"] = per.get(s, 0)
    from pounding.framework.engine import peaks as true_peaks

    seg = true_peaks.segments(result)
    for b in scene.buildings:
        pk = result.peaks(b.name)  # over the continuous trajectory (pounding.framework.engine.peaks)
        system = result.systems[result.names.index(b.name)]
        # the drift ratio at each storey's centre of mass, summary.json's peak_drift_ratio_cm
        # (pounding.framework.post.response.drift_ratios): over the continuous trajectory, or the output steps when thinned
        if seg is not None:
            centres = np.array([sl.centre for sl in system.slabs])
            rows = true_peaks.drift_rows(system, centres[:, None, :])[:, 0]
            drift = float(np.max(true_peaks.norm_peaks(true_peaks.building_segments(seg, result, b.name), rows), initial=0.0))
        else:
            from pounding.framework.post.response import drift_ratios

            drift = float(np.max(drift_ratios(system, result.cm(b.name))[0], initial=0.0))
        row[f"{b.name}_peak_u"] = float(pk[:, 0].max())
        row[f"{b.name}_peak_v"] = float(pk[:, 1].max())
        row[f"{b.name}_peak_phi"] = float(pk[:, 2].max())
        row[f"{b.name}_peak_drift_ratio_cm"] = float(drift)
    row["max_impulse"] = float(max((e.impulse for e in episodes), default=0.0))
    row["energy_loss"] = float(sum(e.energy_dissipated for e in episodes))
    return row


def _record_label(spec: dict, scene) -> str:
    """The name of the scene's own record in the table: its file's stem, or the built-in record's name."""
    return scene.ground_motion.name if spec.get("scene_record") is None else Path(spec["scene_record"]).stem


def run_case(spec: dict, case: dict, record_text: str | None = None) -> dict:
    """Run one case and return its table row (a plain dict). Never raises: a failure is a row with its error.

    ``spec`` and ``case`` are plain data (see :func:`prepare`), so this runs the
    same in this process, in a local worker process or on a remote worker.
    """
    from pounding.framework.post.run import run
    from pounding.framework.studies.window import check_window, window_columns

    t0 = time.perf_counter()
    row = {k: case.get(k) for k in PARAMETERS}
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            scene = _scene_for(spec, case, record_text)
            row.update(window_columns(check_window(case["record"] or _record_label(spec, scene), scene)))
            result = run(scene)
        if caught:
            row["warnings"] = "; ".join(dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught))
        if case["gap"] is None:
            try:
                from pounding.framework.model.placement import rest_gap

                row["gap"] = rest_gap(scene, spec.get("direction"))[0]
            except InputError:
                row["gap"] = None
        row["restitution"] = result.contact.get("restitution", case["restitution"])
        row["integrator"] = result.integrator.get("name", case["integrator"])
        if row["record"] is None:
            row["record"] = _record_label(spec, scene)
        row.update(status="ok", error=None)
        row.update(_measures(result, scene, spec["storeys"]))
        if spec.get("min_gap"):
            from pounding.framework.studies.gap import minimum_gap

            row["min_gap"] = minimum_gap(scene, spec.get("direction")).min_gap
        if spec.get("keep"):
            from pounding.io.results import write_results

            params = {k: row[k] for k in PARAMETERS}

            def extra(folder: Path) -> None:
                (folder / "case.json").write_text(json.dumps(params, indent=1) + "\n")

            write_results(result, Path(spec["keep"]) / f"run_{case['run']:04d}", spec["scene_text"], extra=extra)
    except Exception as exc:  # noqa: BLE001 - a failed run is reported in its row
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    row["runtime_s"] = time.perf_counter() - t0
    return {k: row.get(k) for k in columns(spec["storeys"], spec["names"])}


# =============================================================================
# The sweep (client side)
# =============================================================================


def _record_files(folder) -> dict[str, Path]:
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{str(folder)!r} is not a folder", field="--records")
    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() == ".at2")
    if not files:
        raise InputError(f"no .AT2 files in {str(folder)!r}", field="--records")
    out: dict[str, Path] = {}
    for p in files:
        if p.stem in out:
            raise InputError(f"two records named {p.stem!r} ({out[p.stem].name}, {p.name})", field="--records")
        out[p.stem] = p
    return out


def prepare(scene_path, *, gaps=None, pga_scales=None, records=None, restitutions=None, integrators=None, direction=None,
            overrides=None, keep=None, angles=None, min_gap=False) -> tuple[dict, list[Case], dict[str, str]]:
    """Check the inputs and describe the sweep as plain data: (spec, cases, record texts by key).

    Raises InputError for anything wrong before any run starts (the scene, the
    direction, parameter ranges, integrator names, the records folder); a bad
    record *file* fails only its own runs.
    """
    from pounding.framework.model.placement import direction_vector, rest_gap
    from pounding.io.ground_motion import BUILTIN_RECORDS
    from pounding.framework.model.levels import common_levels
    from pounding.io.scene import load_scene

    scene_path = Path(scene_path)
    scene = load_scene(scene_path)
    text = scene_path.read_text()
    d = direction_vector(direction)
    if gaps:
        if any(not (math.isfinite(g) and g >= 0) for g in gaps):
            raise InputError(f"expected gaps >= 0 m, got {list(gaps)}", field="--gaps")
        _, d = rest_gap(scene, d)  # fails here when the buildings do not face each other
    if pga_scales and any(not (math.isfinite(p) and p > 0) for p in pga_scales):
        raise InputError(f"expected PGA scale factors > 0, got {list(pga_scales)}", field="--pga-scale")
    if restitutions and any(not (0.0 <= k <= 1.0) for k in restitutions):
        raise InputError(f"expected coefficients of restitution in [0, 1], got {list(restitutions)}", field="--restitution")
    if integrators:
        from pounding.framework.model.registry import INTEGRATORS

        for name in integrators:
            INTEGRATORS.get(name, field="--integrator")
    overrides = dict(overrides or {})
    for key, val in overrides.items():
        if not (isinstance(val, (int, float)) and val > 0):
            raise InputError(f"expected a positive number, got {val!r}", field=f"--{key}")

    record_texts: dict[str, str] = {}
    record_names: dict[str, str] = {}
    record_paths: dict[str, str] = {}
    from pounding.io.records import P695_PREFIX, record_set

    set_members = None
    if records is not None and str(records).startswith(P695_PREFIX):
        set_members = [ref for ref, _ in record_set(str(records))]  # fails here if the package is missing
    elif records and len(scene.ground_motion.components) == 2:
        from pounding.io.records import folder_pairs

        # a two-component scene takes the folder's records as pairs (NGA-West2 RSN numbers)
        for name, (pa, pb) in folder_pairs(records).items():
            record_texts[name] = (pa.read_text(encoding="latin-1"), pb.read_text(encoding="latin-1"))
            record_names[name] = (pa.name, pb.name)
            record_paths[name] = (str(pa), str(pb))
    elif records:
        for name, path in _record_files(records).items():
            record_texts[name] = path.read_text(encoding="latin-1")
            record_names[name] = path.name
            record_paths[name] = str(path)
    scene_record = None
    gm_table = tomllib.loads(text).get("ground_motion", {"record": "elcentro"})
    rec = str(gm_table.get("record", "elcentro"))
    if rec.removeprefix("builtin:") not in BUILTIN_RECORDS:
        p = Path(rec).expanduser()
        p = p if p.is_absolute() else scene_path.parent / p
        record_texts[""] = p.read_text(encoding="latin-1")
        record_paths[""] = str(p)
        scene_record = p.name

    from pounding.framework.studies.fragility_inputs import scene_measure

    storeys = sorted({fa + 1 for i, a in enumerate(scene.buildings) for b in scene.buildings[i + 1:]
                      for fa, _ in common_levels(a, b)})
    spec = {
        "scene_text": text,
        "scene_path": str(scene_path.resolve()),
        "scene_record": scene_record,
        "records": record_names,
        "record_paths": record_paths,
        "direction": None if d is None else [float(d[0]), float(d[1])],
        "overrides": overrides,
        "storeys": storeys,
        "names": [b.name for b in scene.buildings],
        "keep": None if not keep else str(Path(keep).resolve()),
        "intensity": scene_measure(gm_table, scene),
    }
    if angles and any(not math.isfinite(a) for a in angles):
        raise InputError(f"expected finite angles in degrees, got {list(angles)}", field="--angles")
    spec["min_gap"] = bool(min_gap)
    members = set_members if set_members is not None else (list(record_names) if records else None)
    cases = build_cases(gaps, pga_scales, members, restitutions, integrators, angles)
    return spec, cases, record_texts


def _record_key(spec: dict, case: Case) -> str | None:
    from pounding.io.records import P695_PREFIX

    if case.record is not None and case.record.startswith(P695_PREFIX):
        return None  # a member of a record set: the worker reads it from the package
    if case.record is not None:
        return case.record
    return "" if spec["scene_record"] is not None else None


def format_cell(v) -> str:
    """A table cell: empty for None, floats with every digit (repr), anything else as str."""
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    return str(v)


def column_units(col: str) -> str | None:
    """Units of a table column ("-" for a ratio; None for text, counts and ``runtime_s``)."""
    if col in ("gap", "min_gap") or col.endswith(("_peak_u", "_peak_v")):
        return "m"
    if col.endswith("_peak_phi"):
        return "rad"
    if col.endswith("_peak_drift_ratio_cm") or col in ("pga_scale", "restitution"):
        return "-"
    return {"angle": "deg", "max_impulse": "N s", "energy_loss": "J"}.get(col)


def header(cols: list[str]) -> list[str]:
    """The CSV header: ``name [unit]`` where the column has units (:func:`column_units`)."""
    return [c if column_units(c) is None else f"{c} [{column_units(c)}]" for c in cols]


class _Table:
    """The CSV table, appended and flushed row by row."""

    def __init__(self, path: Path, cols: list[str]):
        self.path = path
        self.cols = cols
        self.fh = open(path, "w", newline="")
        self.writer = csv.writer(self.fh)
        self.writer.writerow(header(cols))
        self.fh.flush()

    def append(self, row: dict) -> None:
        self.writer.writerow([format_cell(row.get(c)) for c in self.cols])
        self.fh.flush()

    def close(self) -> None:
        self.fh.close()


def write_csv(rows: list[dict], cols: list[str], path: Path) -> Path:
    """Write the table atomically (a temporary file beside ``path``, then renamed)."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header(cols))
        for r in rows:
            w.writerow([format_cell(r.get(c)) for c in cols])
    os.replace(tmp, path)
    return path


def write_parquet(rows: list[dict], cols: list[str], path: Path) -> Path | None:
    """The table as Parquet, or None without pyarrow."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return None
    data = {c: [r.get(c) for r in rows] for c in cols}
    types = {}
    for c, vals in data.items():
        present = [v for v in vals if v is not None]
        if c in TEXT_COLUMNS:
            types[c] = pa.string()
        elif present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
            types[c] = pa.int64()
        else:
            types[c] = pa.float64()
    fields = [pa.field(c, types[c], metadata=None if column_units(c) is None else {"units": column_units(c)}) for c in cols]
    table = pa.table({c: pa.array(data[c], type=types[c]) for c in cols}, schema=pa.schema(fields))
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    pq.write_table(table, tmp)
    os.replace(tmp, path)
    return path


def read_table(path) -> list[dict]:
    """Rows of a sweep CSV with numbers parsed back (empty cells -> None), keyed by column name (units dropped)."""
    out = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            row = {}
            for k, v in r.items():
                k = k.split(" [", 1)[0]
                if v == "":
                    row[k] = None
                elif k in TEXT_COLUMNS:
                    row[k] = v
                else:
                    try:
                        row[k] = int(v)
                    except ValueError:
                        row[k] = float(v)
            out.append(row)
    return out


@dataclass
class SweepResult:
    """What a sweep wrote: rows in run order and the files."""

    rows: list[dict]
    columns: list[str]
    csv: Path
    parquet: Path | None = None
    plots: list[Path] = field(default_factory=list)
    runtime_s: float = 0.0
    workers: int = 0  # 0: serial
    #: what the records were scaled to (:func:`pounding.framework.studies.fragility_inputs.scene_measure`), before ``pga_scale``
    intensity: dict = field(default_factory=dict)
    #: every record against the analysis window (:class:`pounding.framework.studies.window.WindowCheck`)
    window: list = field(default_factory=list)
    #: ``sweep.json``: the two above
    description: Path | None = None

    @property
    def failed(self) -> list[dict]:
        return [r for r in self.rows if r["status"] != "ok"]


def record_checks(spec: dict, cases: list[Case], texts: dict) -> list:
    """Each record of the sweep against the analysis window, on the scene its first run builds.

    The times checked do not depend on the gap, angle, scale or contact, so one scene per record
    answers for all its runs. A record that does not load is left out: its runs report the error.
    """
    from pounding.framework.studies.window import check_window

    checks: dict = {}
    for case in cases:
        if case.record in checks:
            continue
        key = _record_key(spec, case)
        try:
            scene = _scene_for(spec, asdict(case), None if key is None else texts[key])
        except InputError:
            checks[case.record] = None
            continue
        checks[case.record] = check_window(case.record or _record_label(spec, scene), scene)
    return [c for c in checks.values() if c is not None]


def write_description(spec: dict, cases: list[Case], checks: list, path: Path) -> Path:
    """``sweep.json``: what the records were scaled to, the factors on top, and every record against the window."""
    body = {"intensity": spec["intensity"], "pga_scale": sorted({c.pga_scale for c in cases}),
            "window": [c.as_dict() for c in checks]}
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(json.dumps(body, indent=1) + "\n")
    os.replace(tmp, path)
    return path


def _error_row(spec: dict, case: Case, exc: BaseException) -> dict:
    row = {k: v for k, v in asdict(case).items()}
    row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    return {k: row.get(k) for k in columns(spec["storeys"], spec["names"])}


def run_sweep(scene_path, out, *, gaps=None, pga_scales=None, records=None, restitutions=None, integrators=None, direction=None,
              overrides=None, keep: bool = False, workers: int | None = None, scheduler: str | None = None, serial: bool = False,
              plots: bool = True, progress=None, angles=None, min_gap: bool | None = None) -> SweepResult:
    """Run the grid and write ``out/sweep.csv`` (incrementally), ``out/sweep.parquet``, ``out/sweep.json`` and the plots.

    Before the runs start, every record is checked against the analysis window
    (:mod:`pounding.framework.studies.window`): a :class:`~pounding.framework.studies.window.WindowWarning`
    names the records whose strong motion or peak comes after its end, and their rows say so
    in ``window_cut``. ``sweep.json`` states what the records were scaled to (for a spectral
    target: the period, whose it is, and the damping) and every record's check.

    Parameters
    ----------
    scene_path : path of the scene file (TOML)
    out : output folder (created)
    gaps, pga_scales, restitutions : lists of numbers, optional
    records : folder of .AT2 files, or a record set name (``"fema-p695:farfield"``), optional
    angles : list of incidence angles of the ground motion [deg], optional
    min_gap : also find each run's minimum gap for no contact (one more run without contact);
        default: when ``angles`` are given
    integrators : list of integrator names, optional
    direction : direction of the gap (see :func:`pounding.framework.model.placement.direction_vector`)
    overrides : {"dt": s, "duration": s}, optional
    keep : also write every run's result folder into ``out/runs/run_NNNN``
    workers : worker processes of the local cluster (default: the number of cores)
    scheduler : address of an existing dask.distributed scheduler (``tcp://host:port``)
    serial : run in this process, without Dask
    progress : callable(done, total, row), optional

    Notes
    -----
    The local cluster starts worker processes with ``spawn``: a script that
    calls this must do so under ``if __name__ == "__main__":``.
    """
    out = Path(out)
    if min_gap is None:
        min_gap = bool(angles)
    spec, cases, texts = prepare(scene_path, gaps=gaps, pga_scales=pga_scales, records=records, restitutions=restitutions,
                                 integrators=integrators, direction=direction, overrides=overrides, keep=(out / "runs") if keep else None,
                                 angles=angles, min_gap=min_gap)
    from pounding.framework.studies.window import WindowWarning, window_warning
    from pounding.io.outputs import record

    checks = record_checks(spec, cases, texts)
    message = window_warning(checks, _scaled_by(spec["intensity"]), TABLE_CSV)
    if message:  # said before the runs start: a long sweep can be stopped and rerun with a longer duration
        warnings.warn(message, WindowWarning, stacklevel=2)
    record(out, "sweep", [TABLE_CSV, SWEEP_JSON])  # claimed before the first row: an interrupted sweep's table is pounding's
    description = write_description(spec, cases, checks, out / SWEEP_JSON)
    cols = columns(spec["storeys"], spec["names"])
    table = _Table(out / TABLE_CSV, cols)
    rows: dict[int, dict] = {}
    t0 = time.perf_counter()
    n_workers = 0

    def done(case: Case, row: dict) -> None:
        rows[case.run] = row
        table.append(row)
        if progress is not None:
            progress(len(rows), len(cases), row)

    try:
        if serial:
            for case in cases:
                key = _record_key(spec, case)
                done(case, run_case(spec, asdict(case), None if key is None else texts[key]))
        else:
            n_workers = _run_dask(spec, cases, texts, done, workers=workers, scheduler=scheduler)
    finally:
        table.close()
    ordered = [rows[c.run] for c in cases]
    write_csv(ordered, cols, out / TABLE_CSV)
    parquet = write_parquet(ordered, cols, out / TABLE_PARQUET)
    paths = plot_sweep(ordered, spec["names"], out) if plots else []
    if plots and angles:
        paths += plot_sweep_angles(ordered, out)
    # names relative to out: the manifest keeps a relative path as given, and out may itself be relative; what an
    # earlier sweep wrote here and this one did not (its plots, when this one draws none) is stale and goes
    from pounding.io.outputs import settle

    settle(out, "sweep", [Path(p).relative_to(out) for p in [out / TABLE_CSV, description, parquet, *paths] if p is not None])
    return SweepResult(ordered, cols, out / TABLE_CSV, parquet, paths, time.perf_counter() - t0, n_workers, spec["intensity"],
                       checks, description)


def _scaled_by(intensity: dict) -> str:
    """How a sweep's records were scaled, for the window warning."""
    if "target_g" in intensity:
        return f"their whole-record {intensity['label']} (to {intensity['target_g']:g} g)"
    return "a factor" if intensity["name"] == "scale" else "nothing (used as read)"


def _run_dask(spec, cases, texts, done, *, workers=None, scheduler=None) -> int:
    """Run the cases on a dask.distributed cluster (:func:`pounding.framework.studies.cluster.run_jobs`); returns the number of workers."""
    from pounding.framework.studies.cluster import Shared, run_jobs

    jobs = []
    for case in cases:
        key = _record_key(spec, case)
        jobs.append((case, (spec, asdict(case), None if key is None else Shared(key))))
    return run_jobs(run_case, jobs, done, lambda case, exc: done(case, _error_row(spec, case, exc)), shared=texts,
                    workers=workers, scheduler=scheduler, name="pounding-sweep-run")


# =============================================================================
# Plots
# =============================================================================


def _legend(ax) -> None:
    """A legend that fits: a record set gives 22 lines or more (outside the axes, small, in columns)."""
    n = len(ax.get_legend_handles_labels()[0])
    if n <= 10:
        ax.legend(fontsize=8)
    else:
        ax.legend(fontsize=5, ncol=1 + n // 24, loc="upper left", bbox_to_anchor=(1.01, 1.0))


def plot_sweep(rows: list[dict], names: list[str], out) -> list[Path]:
    """``impacts_vs_gap.png`` and ``drift_vs_gap.png`` in ``out``: one line per combination of the other parameters.

    Returns the paths written (none without matplotlib or without successful runs).
    """
    ok = [r for r in rows if r["status"] == "ok" and r.get("gap") is not None]
    if not ok:
        return []
    try:
        from matplotlib.figure import Figure
    except ImportError:
        return []
    others = ("pga_scale", "record", "restitution", "integrator")
    groups: dict[tuple, list[dict]] = {}
    for r in ok:
        groups.setdefault(tuple(r[k] for k in others), []).append(r)
    varying = [k for i, k in enumerate(others) if len({g[i] for g in groups}) > 1]

    def label(key) -> str:
        parts = [f"{k} {key[others.index(k)]}" for k in varying]
        return ", ".join(parts)

    out = Path(out)
    paths = []
    fig = Figure(figsize=(7, 4.5), dpi=120, layout="constrained")
    ax = fig.add_subplot()
    for key, rs in groups.items():
        rs = sorted(rs, key=lambda r: r["gap"])
        ax.plot([r["gap"] for r in rs], [r["n_impacts"] for r in rs], marker="o", label=label(key) or None)
    ax.set_xlabel("gap at rest [m]")
    ax.set_ylabel("number of impacts")
    ax.set_title("Impacts against the separation gap")
    ax.grid(True, alpha=0.3)
    if varying:
        _legend(ax)
    paths.append(out / "impacts_vs_gap.png")
    fig.savefig(paths[-1], format="png")

    fig = Figure(figsize=(7, 4.5), dpi=120, layout="constrained")
    ax = fig.add_subplot()
    styles = ["-", "--", ":", "-."]
    for j, (key, rs) in enumerate(groups.items()):
        rs = sorted(rs, key=lambda r: r["gap"])
        for i, name in enumerate(names):
            lab = ", ".join(x for x in (name, label(key)) if x)
            ax.plot([r["gap"] for r in rs], [100.0 * r[f"{name}_peak_drift_ratio_cm"] for r in rs], linestyle=styles[i % len(styles)],
                    marker="o", color=f"C{(j if len(groups) > 1 else i) % 10}", label=lab)
    ax.set_xlabel("gap at rest [m]")
    ax.set_ylabel("peak inter-storey drift [%]")
    ax.set_title("Peak drift (centres of mass) against the separation gap")
    ax.grid(True, alpha=0.3)
    _legend(ax)
    paths.append(out / "drift_vs_gap.png")
    fig.savefig(paths[-1], format="png")
    return paths


def governing_angles(rows: list[dict]) -> dict[tuple, tuple[float, float]]:
    """For each combination of the other parameters: (angle [deg], min_gap [m]) of the angle that needs the largest gap."""
    others = ("gap", "pga_scale", "record", "restitution", "integrator")
    best: dict[tuple, tuple[float, float]] = {}
    for r in rows:
        if r["status"] != "ok" or r.get("min_gap") is None or r.get("angle") is None:
            continue
        key = tuple(r[k] for k in others)
        if key not in best or r["min_gap"] > best[key][1]:
            best[key] = (r["angle"], r["min_gap"])
    return best


def plot_sweep_angles(rows: list[dict], out) -> list[Path]:
    """``gap_vs_angle.png`` (minimum gap for no contact against the incidence angle) and
    ``impacts_vs_angle.png``, one line per combination of the other parameters."""
    ok = [r for r in rows if r["status"] == "ok" and r.get("angle") is not None]
    if not ok:
        return []
    try:
        from matplotlib.figure import Figure
    except ImportError:
        return []
    others = ("gap", "pga_scale", "record", "restitution", "integrator")
    groups: dict[tuple, list[dict]] = {}
    for r in ok:
        groups.setdefault(tuple(r[k] for k in others), []).append(r)
    varying = [k for i, k in enumerate(others) if len({g[i] for g in groups}) > 1]
    paths = []
    for what, ylabel, name in (("min_gap", "minimum gap for no contact [m]", "gap_vs_angle.png"),
                               ("n_impacts", "number of impacts", "impacts_vs_angle.png")):
        if what == "min_gap" and all(r.get("min_gap") is None for r in ok):
            continue
        fig = Figure(figsize=(7, 4.5), dpi=120, layout="constrained")
        ax = fig.add_subplot()
        for key, rs in groups.items():
            rs = sorted(rs, key=lambda r: r["angle"])
            lab = ", ".join(f"{k} {key[others.index(k)]}" for k in varying) or None
            line, = ax.plot([r["angle"] for r in rs], [r[what] for r in rs], marker="o", ms=3, label=lab)
            if what == "min_gap":
                top = max(rs, key=lambda r: r["min_gap"])
                ax.plot([top["angle"]], [top["min_gap"]], "*", color=line.get_color(), ms=11)
        ax.set_xlabel("incidence angle of the (first) component from x [deg]")
        ax.set_ylabel(ylabel)
        ax.set_title(("Required gap" if what == "min_gap" else "Impacts") + " against the angle of incidence (* governing)"
                     if what == "min_gap" else "Impacts against the angle of incidence")
        ax.grid(True, alpha=0.3)
        if varying:
            _legend(ax)
        paths.append(Path(out) / name)
        fig.savefig(paths[-1], format="png")
    return paths
