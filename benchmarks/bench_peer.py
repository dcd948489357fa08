"""2. Peer: the same scenes in OpenSeesPy, without pounding, same dt and method, same process.

OpenSees: :func:`pounding.peer.opensees.run_transient` - the full 3-D model (ndm 3,
ndf 6; every frame a planar structure of elasticBeamColumn members, shear walls as
ElasticTimoshenkoBeam chains, rigid diaphragms with the mass at a master node,
UniformExcitation, Transformation constraints, UmfPack, Linear -factorOnce,
Newmark average acceleration, Rayleigh damping from the building's own
coefficients) and recording the master-node displacements every step, as an
OpenSees user would write it. Its time is the whole call (model build, analysis,
recording: the build is < 1 % of it).

pounding: ``newmark`` (beta 1/4, gamma 1/2) at the same dt, contact off; solver time
(``Result.runtime_s``, median of >= 5 warm runs) and wall time of ``run()`` (which
also assembles the model and solves the eigenproblem). Also ``exact`` at the same dt,
which is the same cost with no time-discretisation error.

Errors: as in the work-precision benchmark, against the exact (no-pounding)
reference, over the whole record.

With pounding (:func:`run_pounding`): the symmetric 3 + 3-storey pair of
tests/test_opensees_pounding.py, 10 s of El Centro at dt = 0.002 s, Newmark average
acceleration, a stiff penalty law (k_p = 1e10 N/m per contact point, restitution 1)
against OpenSees zero-length ``ElasticPPGap`` springs
(:func:`pounding.peer.opensees.run_gap_pounding`, Newton). Errors of both against
pounding's own run at dt / 8 (the same discrete law, converged in time), over the
whole 10 s: peak x displacement of every floor and the L2 history error, relative.
"""

from __future__ import annotations

import time

import numpy as np

from common import corner_history, errors, log, med, result_corners, subsample, timed_runs, write_csv
from reference import reference
from scenes import SCENE_TITLES, load, no_pounding, with_method


def settings(quick: bool) -> dict:
    if quick:
        return dict(scenes=["paper"], dts=[0.02], reps=5, os_reps={0.02: 1})
    return dict(scenes=["paper", "lshape"], dts=[0.02, 0.01, 0.005], reps=7, os_reps={0.02: 2, 0.01: 1, 0.005: 1})


def run(quick: bool = False) -> dict:
    from pounding.peer.opensees import load_opensees, run_transient

    cfg = settings(quick)
    ops = load_opensees()
    rows = []
    for name in cfg["scenes"]:
        base = no_pounding(load(name))
        ref = reference(name, False, 0.0025 if quick else 0.0003125)
        for dt in cfg["dts"]:
            n_steps = int(round(base.ground_motion.duration / dt))
            # ours, Newmark average acceleration
            s = with_method(base, "newmark", dt)
            r, solver, wall = timed_runs(s, cfg["reps"])
            D = result_corners(r, s)
            R = subsample(ref.corners, ref.dt, dt, len(r.t))
            e_ours = errors(D, R, r.t, None)
            # ours, exact integrator (same cost class, no discretisation error)
            sx = with_method(base, "exact", dt)
            rx, solver_x, wall_x = timed_runs(sx, cfg["reps"])
            e_x = errors(result_corners(rx, sx), R, rx.t, None)
            # OpenSees, Newmark average acceleration, same dt
            os_times, out = [], None
            for _ in range(cfg["os_reps"][dt]):
                t0 = time.perf_counter()
                out = run_transient(ops, base, base.ground_motion, dt, n_steps, integrator=("Newmark", 0.5, 0.25))
                os_times.append(time.perf_counter() - t0)
            Dos = corner_history(out, base)
            e_os = errors(Dos, R[: len(Dos)], r.t[: len(Dos)], None)
            agree = float(np.max(np.abs(Dos - D)) / np.max(np.abs(R)))
            t_os = med(os_times)
            row = dict(
                scene=name, dt=dt, steps=n_steps,
                ours_newmark_solver_s=med(solver), ours_newmark_solver_min_s=min(solver), ours_newmark_wall_s=med(wall), ours_reps=len(solver),
                ours_newmark_err_l2=e_ours["l2_full"], ours_newmark_err_peak=e_ours["peak"],
                ours_exact_solver_s=med(solver_x), ours_exact_err_l2=e_x["l2_full"], ours_exact_err_peak=e_x["peak"],
                opensees_s=t_os, opensees_reps=len(os_times), opensees_per_step_ms=1e3 * t_os / n_steps,
                opensees_err_l2=e_os["l2_full"], opensees_err_peak=e_os["peak"],
                ours_vs_opensees_max_diff_rel=agree,
                ratio_solver=t_os / med(solver), ratio_wall=t_os / med(wall),
            )
            rows.append(row)
            log(f"  {name:6s} dt={dt:<6g} ours {row['ours_newmark_solver_s'] * 1e3:7.2f} ms (wall {row['ours_newmark_wall_s'] * 1e3:6.1f} ms)"
                f"  OpenSees {t_os:6.2f} s  ratio {row['ratio_solver']:7.0f}x solver / {row['ratio_wall']:6.0f}x wall"
                f"  err ours {e_ours['l2_full']:.2e} OS {e_os['l2_full']:.2e}  diff {agree:.1e}")
    tag = "_quick" if quick else ""
    write_csv(f"peer{tag}.csv", rows)
    plot(rows, tag)
    pounding_rows = run_pounding(ops, cfg["reps"])
    write_csv(f"peer_pounding{tag}.csv", pounding_rows)
    return {"rows": rows, "pounding": pounding_rows}


def run_pounding(ops, reps: int) -> list[dict]:
    """The penalty pair against OpenSees gap elements: time and error side by side."""
    import sys

    from common import ROOT
    from pounding.peer.opensees import run_gap_pounding

    sys.path.insert(0, str(ROOT / "tests"))
    sys.path.insert(0, str(ROOT))
    from tests.test_opensees_pounding import DT, DURATION, STIFFNESS, _penalty, _scene

    scene = _scene(_penalty())
    r, solver, wall = timed_runs(scene, reps)
    fine = _scene(_penalty(), dt=DT / 8)
    rf, _, _ = timed_runs(fine, 1)
    t0 = time.perf_counter()
    ux, _, iterations, _ = run_gap_pounding(ops, scene, STIFFNESS, DT, r.steps)
    t_os = time.perf_counter() - t0
    out = []
    for name in r.names:
        ours = r.cm(name)[:, :, 0]
        ref = rf.cm(name)[::8, :, 0][: len(ours)]
        peer = ux[name]
        scale = np.abs(ref).max()
        row = dict(
            case="penalty pair 3+3, dt 0.002, 10 s", building=name, steps=r.steps,
            ours_solver_s=med(solver), ours_wall_s=med(wall), opensees_s=t_os, opensees_newton_iterations=iterations,
            ratio_solver=t_os / med(solver), ratio_wall=t_os / med(wall),
            ours_err_peak=float(np.max(np.abs(np.abs(ours).max(axis=0) - np.abs(ref).max(axis=0))) / scale),
            opensees_err_peak=float(np.max(np.abs(np.abs(peer).max(axis=0) - np.abs(ref).max(axis=0))) / scale),
            ours_err_l2=float(np.linalg.norm(ours - ref) / np.linalg.norm(ref)),
            opensees_err_l2=float(np.linalg.norm(peer - ref) / np.linalg.norm(ref)),
            ours_vs_opensees_max_diff_rel=float(np.abs(ours - peer).max() / scale),
            duration_s=DURATION,
        )
        out.append(row)
        log(f"  pounding {name:5s} ours {row['ours_solver_s'] * 1e3:7.1f} ms (wall {row['ours_wall_s'] * 1e3:6.1f} ms)  OpenSees {t_os:6.2f} s"
            f"  ratio {row['ratio_solver']:6.0f}x solver / {row['ratio_wall']:5.0f}x wall  err (peak, L2) ours {row['ours_err_peak']:.1e}, {row['ours_err_l2']:.1e}"
            f"  OS {row['opensees_err_peak']:.1e}, {row['opensees_err_l2']:.1e}  diff {row['ours_vs_opensees_max_diff_rel']:.1e}")
    return out


def plot(rows, tag=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from common import RESULTS

    scenes = sorted({r["scene"] for r in rows}, key=["paper", "lshape"].index)
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.5 * len(scenes), 5), squeeze=False)
    for ax, name in zip(axes[0], scenes):
        pts = [r for r in rows if r["scene"] == name]
        for key_t, key_e, label, style in (
            ("opensees_s", "opensees_err_l2", "OpenSeesPy 3-D model, Newmark", "s-"),
            ("ours_newmark_wall_s", "ours_newmark_err_l2", "pounding newmark, run() wall", "^-"),
            ("ours_newmark_solver_s", "ours_newmark_err_l2", "pounding newmark, solver", "o-"),
        ):
            ax.loglog([max(p[key_e], 1e-16) for p in pts], [p[key_t] for p in pts], style, label=label)
            for p in pts:
                ax.annotate(f"dt={p['dt']:g}", (max(p[key_e], 1e-16), p[key_t]), fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_xlabel("relative L2 error of corner histories (whole record, no pounding)")
        ax.set_ylabel("time [s]")
        ax.set_title(SCENE_TITLES[name], fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("pounding vs OpenSeesPy, same scene, method and dt (El Centro, whole record)")
    fig.tight_layout()
    path = RESULTS / f"peer{tag}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    log(f"  wrote {path.name}")
