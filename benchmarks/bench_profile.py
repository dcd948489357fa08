"""cProfile of the paper example with pounding (and, in the full run, two 60-storey buildings).

Writes results/profile_paper_pounding.txt (top functions by own time and by
cumulative time over 5 warm runs) and a short split of the solver time between
the compiled kernel and the Python event handling.
"""

from __future__ import annotations

import cProfile
import io
import pstats

from common import RESULTS, log, quiet_run
from scenes import load, uniform_pair

GROUPS = {
    "compiled stretch, free steps, grazes and end-of-step impulses (free_stretch.py:advance)": ("free_stretch.py", "advance"),
    "compiled held steps (held.py:held_stretch)": ("held.py", "held_stretch"),
    "Python steps with an impact inside (driver.py:python_step)": ("driver.py", "python_step"),
    "impulses in Python (driver.py:contact_at)": ("driver.py", "contact_at"),
    "impact location (driver.py:locate)": ("driver.py", "locate"),
    "transitions for new step sizes (solvers/base.py:transition)": ("base.py", "transition"),
    "model: assembly + eigenproblem (stacked_model.py:Model.__init__)": ("stacked_model.py", "__init__"),
}


def profile(scene, runs: int, name: str, top: int = 30) -> dict:
    quiet_run(scene)  # warm
    pr = cProfile.Profile()
    pr.enable()
    for _ in range(runs):
        quiet_run(scene)
    pr.disable()
    buf = io.StringIO()
    st = pstats.Stats(pr, stream=buf)
    total = st.total_tt
    buf.write(f"# {name}: {runs} runs, profiled total {total:.3f} s ({total / runs * 1e3:.1f} ms per run under the profiler)\n\n")
    split = {}
    for label, (fname, func) in GROUPS.items():
        cum = sum(v[3] for k, v in st.stats.items() if k[0].endswith(fname) and k[2] == func)
        split[label] = cum / total
    buf.write("## share of the profiled time (cumulative, overlapping)\n")
    for label, frac in split.items():
        buf.write(f"  {frac * 100:5.1f} %  {label}\n")
    buf.write("\n## by own time\n")
    st.sort_stats("tottime").print_stats(top)
    buf.write("\n## by cumulative time\n")
    st.sort_stats("cumulative").print_stats(top)
    text = buf.getvalue().replace(str(RESULTS.parent.parent) + "/", "")
    path = RESULTS / f"profile_{name}.txt"
    RESULTS.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    log(f"  wrote {path.name}; " + ", ".join(f"{lab.split(' (')[0]} {f * 100:.0f}%" for lab, f in split.items()))
    return {"split": split, "total_s": total, "runs": runs}


def run(quick: bool = False) -> dict:
    out = {"paper_pounding": profile(load("paper"), 5 if not quick else 3, "paper_pounding" + ("_quick" if quick else ""))}
    if not quick:
        out["uniform_60_pounding"] = profile(uniform_pair(60), 1, "uniform_60_pounding")
    return out
