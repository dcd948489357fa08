"""The engine's solver time against the code it was redesigned from, side by side.

    python benchmarks/bench_engine_baseline.py [BASE_COMMIT] [--rounds N] [--reps N] [--cases a,b]

The links-and-laws engine must cost no more than 1.1x the solver time of the engine it replaced
(BASE, default 87d36f4) on these scenes, each with the settings its file gives (the same in both
codes, so that the same work is timed):

* ``paper``: the paper pair at 0.03 m (HHT, dt 0.005 s, impulse contact, 15 s of El Centro at 0.32 g);
* ``paper_defaults``: the same pair with every default (no integrator and no dt given: ``exact`` at
  dt 0.01 s, the crossing locator, equilibrium after an impact), the run a new user makes;
* ``lshape``: benchmarks/scenes/l_shape_8_rect_4.toml (8 + 4 storeys, an L against a rectangle);
* ``tall60``: two 60-storey buildings 0.05 m apart (benchmarks/scenes.py ``uniform_pair(60)``);
* ``yielding``: the paper pair with bilinear storey springs at 0.03 m (examples/inelastic_pair);
* ``yielding_free``: the same without contact (the contact-free yielding run);
* ``penalty``: the paper pair with the linear penalty law (``penalty``, k = 1e9 N/m) at the
  scene's dt 0.005 s (the default step now resolves the contact: that is a different run);
* ``yielding_penalty``: the yielding pair of ``yielding`` with that penalty law at its scene's dt
  (the links and the contact forces solved together in each step while slabs press);
* ``fragility``: a fragility study's cost per run: the paper pair under 4 of the synthetic records
  of examples/fragility (El Centro's spectrum, 31.2 s) at 3 PGA levels, serially in one process,
  12 contact-free runs and 12 runs with contact at 0.03 m; the figure is the mean of the runs'
  own solver times (``runtime_s`` in runs.csv and consequences.csv), "impacts" the runs counted.

``git archive`` extracts BASE into a temporary folder; every configuration runs in its own process
on its own code (``PYTHONPATH``), 2 warm-up runs then the median of ``--reps`` solver times
(``Result.runtime_s``: the solve, without loading or compiling), and the rounds alternate base and
head so that both see the same machine. The base's first round compiles its numba cache (about a
minute). Writes results/engine_baseline.json and prints the table.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from common import log, write_json

ROOT = Path(__file__).resolve().parents[1]
BASE = "87d36f4"
CASES = ("paper", "paper_defaults", "lshape", "tall60", "yielding", "yielding_free", "penalty", "yielding_penalty", "fragility")

TIME = r'''
import json, statistics, sys, warnings
warnings.simplefilter("ignore")
sys.path.insert(0, "benchmarks")
from pounding import load_scene, run

case, reps = sys.argv[1], int(sys.argv[2])
if case == "fragility":  # the study's cost per run (its runs' own solver times), not a single run's
    import csv, importlib, tempfile
    try:
        study = importlib.import_module("pounding.framework.studies.fragility")
    except ImportError:  # the base's layout
        study = importlib.import_module("pounding.framework.fragility")
    costs = []
    for i in range(1 + reps):  # the first study compiles
        with tempfile.TemporaryDirectory() as out:
            study.run_fragility("examples/paper/pair_gap_0.03.toml", out + "/study", records=sys.argv[3],
                                levels=[0.1, 0.2, 0.3], consequence_gaps=[0.03], serial=True, plots=False)
            runs = []
            for name in ("runs.csv", "consequences.csv"):
                with open(out + "/study/" + name) as fh:
                    runs += [float(row["runtime_s"]) for row in csv.DictReader(fh) if row.get("runtime_s")]
        if i >= 1:
            costs.append(sum(runs) / len(runs))
    print(json.dumps({"median_s": statistics.median(costs), "min_s": min(costs), "steps": 0, "impacts": len(runs)}))
    sys.exit(0)
if case == "paper":
    scene = load_scene("examples/paper/pair_gap_0.03.toml")
elif case == "paper_defaults":
    scene = load_scene("examples/paper/pair_gap_0.03.toml").with_analysis(integrator=None, integrator_params={}, dt=None)
elif case == "lshape":
    scene = load_scene("benchmarks/scenes/l_shape_8_rect_4.toml")
elif case == "tall60":
    from scenes import uniform_pair
    scene = uniform_pair(60)
elif case == "yielding":
    scene = load_scene("examples/inelastic_pair/pair_yielding_gap_0.03.toml")
elif case == "yielding_free":
    scene = load_scene("examples/inelastic_pair/pair_yielding_no_contact.toml")
elif case == "penalty":
    scene = load_scene("examples/paper/pair_gap_0.03.toml").with_analysis(contact="penalty", contact_params={"stiffness": 1e9, "restitution": 0.5})
elif case == "yielding_penalty":
    scene = load_scene("examples/inelastic_pair/pair_yielding_gap_0.03.toml").with_analysis(
        contact="penalty", contact_params={"stiffness": 1e9, "restitution": 0.5})
times = []
for i in range(2 + reps):
    r = run(scene)
    if i >= 2:
        times.append(r.runtime_s)
print(json.dumps({"median_s": statistics.median(times), "min_s": min(times), "steps": r.steps, "impacts": r.n_impacts}))
'''


def _extract(commit: str, where: Path) -> Path:
    out = where / "base"
    out.mkdir()
    archive = subprocess.run(["git", "archive", commit], cwd=ROOT, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(out)], input=archive, check=True)
    return out


def _records(where: Path) -> Path:
    """4 of the synthetic records of examples/fragility, written once for both codes."""
    sys.path.insert(0, str(ROOT / "examples" / "fragility"))
    from synthetic_records import synthetic_records

    return synthetic_records(where / "records", n=4)


def _time(tree: Path, case: str, reps: int, records: Path) -> dict:
    env = {**__import__("os").environ, "PYTHONPATH": str(tree), "POUNDING_AOT": "0"}
    p = subprocess.run([sys.executable, "-c", TIME, case, str(reps), str(records)], cwd=tree, capture_output=True, text=True, env=env, timeout=3600)
    if p.returncode != 0:
        raise RuntimeError(f"{case} in {tree}: {p.stderr[-1500:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def main(argv: list[str]) -> None:
    base = argv[0] if argv and not argv[0].startswith("--") else BASE
    rounds = int(argv[argv.index("--rounds") + 1]) if "--rounds" in argv else 2
    reps = int(argv[argv.index("--reps") + 1]) if "--reps" in argv else 5
    cases = argv[argv.index("--cases") + 1].split(",") if "--cases" in argv else CASES
    rows: dict[str, dict] = {c: {"base": [], "head": []} for c in cases}
    with tempfile.TemporaryDirectory(prefix="pounding-base-") as tmp:
        trees = {"base": _extract(base, Path(tmp)), "head": ROOT}
        records = _records(Path(tmp))
        for k in range(rounds):
            for case in cases:
                for side in ("base", "head") if k % 2 == 0 else ("head", "base"):
                    out = _time(trees[side], case, reps, records)
                    rows[case][side].append(out)
                    log(f"round {k + 1} {case:14s} {side}: {out['median_s'] * 1e3:9.1f} ms ({out['steps']} steps, {out['impacts']} impacts)")
    table = {}
    for case, r in rows.items():
        b = statistics.median(x["median_s"] for x in r["base"])
        h = statistics.median(x["median_s"] for x in r["head"])
        table[case] = {"base_s": b, "head_s": h, "ratio": h / b, "steps": r["head"][-1]["steps"],
                       "impacts_base": r["base"][-1]["impacts"], "impacts_head": r["head"][-1]["impacts"]}
    write_json("engine_baseline.json", {"base": base, "rounds": rounds, "reps": reps, "cases": table})
    print(f"| scene | base [ms] | head [ms] | head / base | impacts base / head |")
    print("|---|---|---|---|---|")
    for case, t in table.items():
        print(f"| {case} | {t['base_s'] * 1e3:.1f} | {t['head_s'] * 1e3:.1f} | {t['ratio']:.2f} | {t['impacts_base']} / {t['impacts_head']} |")


if __name__ == "__main__":
    main(sys.argv[1:])
