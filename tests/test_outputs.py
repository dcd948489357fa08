"""Nothing lost: output folders refuse files pounding did not write, and a rerun replaces only its own files."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from pounding.errors import InputError
from pounding.io import outputs

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "paper" / "pair_gap_0.03.toml"


def pounding(*args, check=True):
    proc = subprocess.run([sys.executable, "-m", "pounding", *map(str, args)], capture_output=True, text=True)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()}


def stage(tmp_path: Path, names: dict[str, str]) -> Path:
    src = Path(tmp_path) / "staged"
    src.mkdir(parents=True)
    for name, text in names.items():
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_text(text)
    return src


def test_publish_replaces_only_the_commands_own_files(tmp_path):
    """A second publish of a command removes the files its first wrote and this one did not; other commands'
    files and files pounding did not write stay; the manifest says who wrote what."""
    target = tmp_path / "run"
    outputs.publish(stage(tmp_path / "a", {"summary.json": "1", "vtk/a.vtu": "v"}), target, "run")
    outputs.publish(stage(tmp_path / "b", {"plan.png": "p"}), target / "plots", "plot")
    (target / "notes.txt").write_text("mine")
    (target / "vtk" / "by_hand.vtu").write_text("mine")
    outputs.publish(stage(tmp_path / "c", {"summary.json": "2"}), target, "run")
    assert files(target) == {".pounding-manifest.json", "summary.json", "notes.txt", "vtk/by_hand.vtu", "plots/plan.png", "plots/.pounding-manifest.json"}
    assert (target / "summary.json").read_text() == "2"
    assert outputs.read_manifest(target) == {"run": ["summary.json"]}
    assert outputs.foreign(target) == [Path("notes.txt"), Path("vtk/by_hand.vtu")]


def test_check_target_refuses_foreign_files_unless_overwrite(tmp_path):
    (tmp_path / "x.csv").write_text("data")
    with pytest.raises(InputError, match=r"1 file pounding did not write \(e\.g\. x\.csv\).*--overwrite"):
        outputs.check_target(tmp_path, overwrite=False)
    outputs.check_target(tmp_path, overwrite=True)
    outputs.check_target(tmp_path / "new", overwrite=False)  # a folder to be created is fine


def test_a_failed_write_leaves_the_folder_as_it_was(tmp_path):
    target = tmp_path / "run"
    outputs.publish(stage(tmp_path / "a", {"summary.json": "1"}), target, "run")

    def boom(folder):
        (folder / "summary.json").write_text("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        outputs.write_folder(target, "run", boom)
    assert (target / "summary.json").read_text() == "1"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "run"]  # no temporary folder left ("a" held the staged files)


def test_run_refuses_a_folder_with_other_files_then_keeps_them_with_overwrite(tmp_path):
    """`run --out DIR` where DIR holds a file pounding did not write: exit 2, one line, nothing written, nothing run;
    with --overwrite the results are written beside it and it is kept."""
    out = tmp_path / "o"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    proc = pounding("run", PAPER, "--out", out, "--duration", "0.5", "--quiet", check=False)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    assert "notes.txt" in proc.stderr and "--overwrite" in proc.stderr
    assert files(out) == {"notes.txt"}
    pounding("run", PAPER, "--out", out, "--duration", "0.5", "--quiet", "--overwrite")
    assert (out / "notes.txt").read_text() == "keep me" and (out / "summary.json").is_file()


def test_plots_and_vtk_of_other_commands_survive_a_rerun_its_own_stale_files_do_not(tmp_path):
    """run --vtk, plot, then run again without --vtk: plots/ stays (the plot command's), vtk/ goes (the earlier
    run's own output, now stale), a file put in by hand stays."""
    out = tmp_path / "o"
    pounding("run", PAPER, "--out", out, "--duration", "0.5", "--quiet", "--vtk")
    pounding("plot", out)
    (out / "plots" / "annotated.png").write_bytes(b"by hand")
    plots = files(out / "plots")
    pounding("run", PAPER, "--out", out, "--duration", "0.5", "--quiet", "--overwrite")
    assert files(out / "plots") == plots
    assert not (out / "vtk").exists()
    assert {"summary.json", "response.npz", "impacts.csv"} <= files(out)


def test_plot_refuses_an_out_folder_with_other_files(tmp_path):
    run = tmp_path / "run"
    pounding("run", PAPER, "--out", run, "--duration", "0.3", "--quiet")
    figs = tmp_path / "figs"
    figs.mkdir()
    (figs / "paper.tex").write_text("x")
    proc = pounding("plot", run, "--out", figs, check=False)
    assert proc.returncode == 2 and "paper.tex" in proc.stderr
    pounding("plot", run, "--out", figs, "--overwrite")
    assert (figs / "paper.tex").read_text() == "x" and (figs / "plan.png").is_file()


def test_sweep_refuses_a_folder_with_other_files_and_reruns_over_its_own(tmp_path):
    """`sweep --out DIR` with a file pounding did not write: exit 2 and nothing run or written; a sweep's own
    table (claimed in the manifest before its first row) does not block a rerun, and a hand-made file survives
    --overwrite."""
    out = tmp_path / "s"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    args = ("sweep", PAPER, "--gaps", "0.5", "--duration", "0.3", "--serial", "--no-plots", "--out", out)
    proc = pounding(*args, check=False)
    assert proc.returncode == 2 and "notes.txt" in proc.stderr and files(out) == {"notes.txt"}
    pounding(*args, "--overwrite")
    assert (out / "notes.txt").read_text() == "keep me" and (out / "sweep.csv").is_file()
    (out / "notes.txt").unlink()
    pounding(*args)  # its own files only: no --overwrite needed
    assert "sweep.csv" in outputs.read_manifest(out)["sweep"]


def test_run_help_names_the_paraview_file_it_writes(tmp_path):
    """`run --help` names the .pvd that `run --vtk` actually writes."""
    from pounding.cli import VTK_SERIES

    assert VTK_SERIES in pounding("run", "--help").stdout.replace("\n", " ").replace("  ", " ")
    pounding("run", PAPER, "--out", tmp_path / "o", "--duration", "0.1", "--quiet", "--vtk")
    assert (tmp_path / "o" / VTK_SERIES).is_file()


def test_a_new_results_folder_gets_the_users_usual_mode(tmp_path):
    """The staging folder is private while it fills; the published folder has the mode of any new folder
    (0o777 less the umask: readable by colleagues under the usual 022), like the files in it."""
    import os
    import stat

    from pounding.io.outputs import write_folder

    old = os.umask(0o022)
    try:
        write_folder(tmp_path / "run", "run", lambda tmp: [(tmp / "a.txt").write_text("x") and tmp / "a.txt"])
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "run").stat().st_mode) == 0o755


def test_a_new_results_folder_keeps_the_setgid_bit_of_a_shared_folder(tmp_path):
    """In a group's shared folder (setgid: new files take the folder's group), the published folder keeps
    the bit a plain mkdir there would get, so the group keeps owning what is written inside it later."""
    import os
    import stat

    from pounding.io.outputs import write_folder

    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o2775)
    probe = shared / "probe"
    probe.mkdir()
    write_folder(shared / "run", "run", lambda tmp: [(tmp / "a.txt").write_text("x") and tmp / "a.txt"])
    assert stat.S_IMODE((shared / "run").stat().st_mode) & 0o2000 == stat.S_IMODE(probe.stat().st_mode) & 0o2000


def test_a_sweep_rerun_without_plots_removes_its_earlier_plots(tmp_path):
    """A sweep rerun over its own folder with --no-plots leaves no plot of the earlier grid beside the new table
    (its own files of the earlier run that it did not write again are stale: removed, as a run's are)."""
    out = tmp_path / "s"
    base = ("sweep", PAPER, "--gaps", "0.5,0.4", "--duration", "0.3", "--serial", "--out", out)
    pounding(*base)
    drawn = {f for f in files(out) if f.endswith(".png")}
    assert drawn
    pounding(*base, "--no-plots")
    assert not {f for f in files(out) if f.endswith(".png")} and (out / "sweep.csv").is_file()
    assert not any(f.endswith(".png") for f in outputs.read_manifest(out)["sweep"])
