"""Issue 13's time target against the code of the day it was filed: the defaults then and now.

    python benchmarks/bench_issue_baseline.py [BASE_COMMIT] [--rounds N]

Issue 13 asks for accurate defaults "at no more than 2x today's default solver time". Its "today"
is BASE_COMMIT (default b2a1551, the last commit before the issue's work, the base of
``check_identity.py --paper-settings``). bench_accuracy_targets.py's ``before`` row runs the old
settings with *this* code, whose event handling has since become faster for every setting; this
script measures the old code itself, on the same machine, in the same session:

* ``base default``: BASE_COMMIT's code with its defaults on the paper pair and the L-shape scene
  (El Centro, 0.32 g, k = 0.5): HHT (its default alpha) at the record's step, ``halving``, ``keep``,
  tolerance 1e-4 m. That code does not take ``integrator = None``, so its default integrator is
  named; its dt, locator, rule and tolerance are left unset, as a new user left them;
* ``head before``: this code with those settings named (bench_accuracy_targets.py's ``before``);
* ``head default``: this code with nothing given (today's defaults).

``git archive`` extracts BASE_COMMIT into a temporary folder; each configuration runs in its own
process (3 warm-up runs, then the median solver time, summary.json's ``runtime_s``, of 15), and
the rounds alternate base and head so that both see the same machine. The base's first round
compiles its own numba cache (~1 min). Writes results/issue_baseline.json.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from common import log, write_json

ROOT = Path(__file__).resolve().parents[1]
BASE = "b2a1551"
SCENES = {"paper": "examples/paper/pair_gap_0.03.toml", "lshape": "benchmarks/scenes/l_shape_8_rect_4.toml"}
SETTINGS = {
    # BASE's Analysis defaults, with its default integrator named (it has no integrator = None)
    "base default": dict(integrator="hht", integrator_params={}, dt=None, contact_params={"restitution": 0.5}),
    "head before": dict(integrator="hht", integrator_params={}, dt=0.02,
                        contact_params={"restitution": 0.5, "locate": "halving", "after_impact": "keep", "tolerance": 1e-4}),
    "head default": dict(integrator=None, integrator_params={}, dt=None, contact_params={"restitution": 0.5}),
}

TIME = r'''
import json, statistics, sys, warnings
warnings.simplefilter("ignore")
from pounding import load_scene, run
path, settings = sys.argv[1], json.loads(sys.argv[2])
s = load_scene(path).with_analysis(**settings)
for _ in range(3):
    r = run(s)
t = [run(s).runtime_s for _ in range(15)]
print(json.dumps({"median_s": statistics.median(t), "min_s": min(t), "impacts": r.n_impacts, "dt": r.dt}))
'''


def _time(code_root: Path, scene: str, settings: dict) -> dict:
    env = dict(os.environ, PYTHONPATH=str(code_root))
    # cwd: ``python -c`` puts the working directory first on sys.path (check_identity.py)
    out = subprocess.run([sys.executable, "-c", TIME, str(ROOT / scene), json.dumps(settings)], env=env,
                         cwd=str(code_root), capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv: list[str]) -> int:
    import argparse

    ap = argparse.ArgumentParser(description="issue 13's time target against the code of the day it was filed")
    ap.add_argument("base", nargs="?", default=BASE)
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    base, rounds = args.base, args.rounds
    runs: dict = {name: {lab: [] for lab in SETTINGS} for name in SCENES}
    with tempfile.TemporaryDirectory(prefix="pounding-baseline-") as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", base], capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        for k in range(rounds):
            for name, scene in SCENES.items():
                for lab, settings in SETTINGS.items():
                    r = _time(Path(tmp) if lab.startswith("base") else ROOT, scene, settings)
                    runs[name][lab].append(r)
                    log(f"  round {k + 1} {name:7s} {lab:13s} {r['median_s'] * 1e3:7.1f} ms  dt={r['dt']:g}  impacts {r['impacts']}")
    out = {"base_commit": base, "rounds": rounds, "scenes": {}}
    for name in SCENES:
        row = {lab: {"median_ms": 1e3 * statistics.median(x["median_s"] for x in rs),
                     "spread_ms": [1e3 * min(x["median_s"] for x in rs), 1e3 * max(x["median_s"] for x in rs)],
                     "impacts": rs[0]["impacts"], "dt": rs[0]["dt"]} for lab, rs in runs[name].items()}
        row["default_vs_base_default"] = row["head default"]["median_ms"] / row["base default"]["median_ms"]
        row["default_vs_head_before"] = row["head default"]["median_ms"] / row["head before"]["median_ms"]
        out["scenes"][name] = row
        log(f"{name}: defaults {row['head default']['median_ms']:.1f} ms = {row['default_vs_base_default']:.2f}x the defaults of "
            f"{base} ({row['base default']['median_ms']:.1f} ms), {row['default_vs_head_before']:.2f}x the old settings run by "
            f"this code ({row['head before']['median_ms']:.1f} ms)")
    write_json("issue_baseline.json", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
