"""One-component runs bit for bit against another commit (e.g. the one before two components).

    python benchmarks/check_identity.py BASE_COMMIT [--quick] [--paper-settings]

Extracts BASE_COMMIT with ``git archive`` into a temporary folder, runs the same set of
one-component scenes (paper pair at 0.03 and 0.5 m, the L-shape scene; five integrators; impulse
and penalty contact; compiled and Python paths) with that code and with this worktree's code,
each in its own process, and compares SHA-256 digests of the recorded modal displacements and
velocities, the energy account and every impact (time, impulse, energy loss). Prints the
configurations that differ; exit code 1 if any does. Nothing is written outside the temporary
folder.

``--paper-settings`` names the impulse law's paper settings (``locate`` halving, and root on the
paper pair at 0.03 m, ``after_impact = "keep"``, tolerance 1e-4 m) and the step (the scene's, else the
record's): the defaults of commits before issue 13, which changed them. A scene that names them must
give what it gave before, bit for bit.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

DUMP = r'''
import hashlib, sys, warnings
import numpy as np
warnings.simplefilter("ignore")
from pounding import load_scene
from pounding.framework.engine.driver import Driver
root, quick, paper = sys.argv[1], sys.argv[2] == "1", sys.argv[3] == "1"
# --paper-settings: the impulse law's settings named as the paper's (before issue 13 they were the
# defaults), and the step given, so that a base commit with other defaults runs the same problem
PAPER = {"locate": "halving", "after_impact": "keep", "tolerance": 1e-4}
scenes = ["examples/paper/pair_gap_0.03.toml", "examples/paper/pair_gap_0.5.toml", "benchmarks/scenes/l_shape_8_rect_4.toml"]
integrators = ["newmark", "hht", "exact"] if quick else ["newmark", "hht", "exact", "central_difference", "generalized_alpha"]
for sc in scenes[:2] if quick else scenes:
    for integ in integrators:
        for contact in ("impulse", "penalty"):
            kw = dict(integrator=integ, integrator_params={}, contact=contact,
                      contact_params={"restitution": 0.5} if contact == "impulse" else {})
            if integ == "central_difference":
                kw["dt"] = 0.002
            if sc.startswith("benchmarks"):
                kw["duration"] = 6.0
            s = load_scene(root + "/" + sc).with_analysis(**kw)
            variants = [("", s)]
            if paper:
                gm = s.ground_motion
                s = s.with_analysis(dt=s.analysis.dt or gm.dt)
                variants = [("", s)]
                if contact == "impulse":
                    variants = [(f"|{loc}", s.with_analysis(contact_params={"restitution": 0.5, **PAPER, "locate": loc}))
                                for loc in (("halving", "root") if sc.endswith("0.03.toml") else ("halving",))]
            for tag, s in variants:
              for use_kernel in (True, False):
                if not use_kernel and not sc.endswith("0.03.toml"):
                    continue
                d = Driver(s, use_kernel=use_kernel)
                d.run()
                h = hashlib.sha256()
                imp = np.array([[i.time, i.impulse, i.energy_loss] for i in d.impacts]).ravel()
                for a in (d.Q, d.V, d.E, imp):
                    h.update(np.ascontiguousarray(a).tobytes())
                print(f"{sc}|{integ}|{contact}{tag}|kernel={use_kernel}", h.hexdigest()[:16], len(d.impacts))
'''


def _dump(code_root: Path, quick: bool, paper: bool = False) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(code_root))
    # cwd: ``python -c`` puts the working directory first on sys.path, before PYTHONPATH; run from this
    # worktree it would import this worktree's code for the base commit too (and report it identical)
    out = subprocess.run([sys.executable, "-c", DUMP, str(ROOT), "1" if quick else "0", "1" if paper else "0"], env=env,
                         cwd=str(code_root), capture_output=True, text=True, check=True).stdout
    return {line.split()[0]: " ".join(line.split()[1:]) for line in out.splitlines() if line.strip()}


def main(argv: list[str]) -> int:
    if not argv or argv[0].startswith("-"):
        print(__doc__)
        return 2
    base, quick, paper = argv[0], "--quick" in argv, "--paper-settings" in argv
    with tempfile.TemporaryDirectory(prefix="pounding-identity-") as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", base], capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        old = _dump(Path(tmp), quick, paper)
    new = _dump(ROOT, quick, paper)
    differ = [k for k in old if new.get(k) != old[k]]
    for k in old:
        print(f"{'SAME   ' if k not in differ else 'DIFFERS'} {k}: {old[k]} -> {new.get(k)}")
    print(f"{len(old) - len(differ)} of {len(old)} configurations identical bit for bit")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
