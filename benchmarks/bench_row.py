"""Rows: a row of five 10-storey buildings against two pairs (issue #17's target: at most 3x).

The row is scenes.uniform_row(5, 10): five uniform-plan buildings alternating the two types
of scenes.uniform_pair, 0.05 m apart, El Centro at 0.32 g and 20 deg, hht, dt = 0.005 s,
impulse contact; every neighbour shares all 10 levels, so 4 adjacent pairs x 10 storeys of
slab pairs (and 6 far pairs, left to the cheap bounds). "Two pairs" is two runs of
scenes.uniform_pair(10) (the row's first two buildings alone). Warm runs (numba cache loaded
first), median wall time of ``run()`` over ``reps`` repetitions; the solver time
(``runtime_s``) beside it. Results: benchmarks/results/row.json.

    python benchmarks/bench_row.py [--quick]
"""

from __future__ import annotations

import sys

from common import log, med, timed_runs, warm_up, write_json


def main(quick: bool = False) -> dict:
    from scenes import uniform_pair, uniform_row

    reps = 1 if quick else 5
    warm_up()
    pair = uniform_pair(10, gap=0.05)
    row = uniform_row(5, 10, gap=0.05)
    r_pair, s_pair, w_pair = timed_runs(pair, reps)
    r_row, s_row, w_row = timed_runs(row, reps)
    out = {
        "reps": reps,
        "pair": {"wall_s": med(w_pair), "solver_s": med(s_pair), "steps": r_pair.steps, "impacts": r_pair.n_impacts},
        "row_of_5": {"wall_s": med(w_row), "solver_s": med(s_row), "steps": r_row.steps, "impacts": r_row.n_impacts},
    }
    out["row_over_two_pairs_wall"] = out["row_of_5"]["wall_s"] / (2 * out["pair"]["wall_s"])
    out["row_over_two_pairs_solver"] = out["row_of_5"]["solver_s"] / (2 * out["pair"]["solver_s"])
    log(f"pair of 10-storey buildings: {out['pair']['wall_s']:.3f} s wall ({out['pair']['solver_s']:.3f} s solver), "
        f"{out['pair']['impacts']} impacts")
    log(f"row of five 10-storey buildings: {out['row_of_5']['wall_s']:.3f} s wall ({out['row_of_5']['solver_s']:.3f} s solver), "
        f"{out['row_of_5']['impacts']} impacts")
    log(f"row / two pairs: {out['row_over_two_pairs_wall']:.2f}x wall, {out['row_over_two_pairs_solver']:.2f}x solver (target <= 3x)")
    write_json("row_quick.json" if quick else "row.json", out)
    return out


if __name__ == "__main__":
    main("--quick" in sys.argv)
