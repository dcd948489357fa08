"""Output folders: written whole from a temporary folder, and nothing lost that pounding did not write.

Every folder a command writes into holds a manifest, ``.pounding-manifest.json``:
for each command (``run``, ``plot``, ``render``...), the files it wrote there,
relative to the folder. With it

* a command refuses (exit 2) a folder that holds files pounding did not write,
  unless ``--overwrite`` (:func:`check_target`); files of other commands, in
  the folder or in sub-folders with their own manifest (``RUN/plots``), are
  pounding's and do not count;
* a command's files are written into a temporary folder beside the target and
  moved in when complete (:func:`publish`); the files the same command wrote
  there before and did not write again (the ``vtk/`` of an earlier ``run
  --vtk``) are removed; nothing else is touched: the plots in ``RUN/plots``
  survive a new ``run`` into ``RUN``, and a file pounding did not write is
  never deleted (with ``--overwrite`` only a file of the same name as one being
  written is replaced).

A target that does not exist yet is created by one rename of the temporary
folder, so an interrupted command leaves either the previous files or none.
"""

from __future__ import annotations

import contextlib
import json
import os
import secrets
import shutil
from pathlib import Path

from pounding.errors import InputError

MANIFEST = ".pounding-manifest.json"


def read_manifest(folder: Path) -> dict[str, list[str]]:
    """``{command: [relative paths]}`` of a folder (empty without a manifest or with an unreadable one)."""
    try:
        data = json.loads((Path(folder) / MANIFEST).read_text())
    except (OSError, ValueError):
        return {}
    return {str(k): [str(p) for p in v] for k, v in data.get("files", {}).items()} if isinstance(data, dict) else {}


def _write_manifest(folder: Path, files: dict[str, list[str]]) -> None:
    tmp = folder / f"{MANIFEST}.tmp-{os.getpid()}"
    tmp.write_text(json.dumps({"written_by": "pounding", "files": {k: sorted(v) for k, v in sorted(files.items()) if v}}, indent=1) + "\n")
    os.replace(tmp, folder / MANIFEST)


def owned(folder: Path) -> set[Path]:
    """Files (relative to ``folder``) that a manifest in ``folder`` or below lists."""
    folder = Path(folder)
    out: set[Path] = set()
    for manifest in folder.rglob(MANIFEST):
        base = manifest.parent.relative_to(folder)
        for paths in read_manifest(manifest.parent).values():
            out.update(base / p for p in paths)
    return out


def foreign(folder: Path) -> list[Path]:
    """Files in ``folder`` (recursively, relative) that pounding did not write, sorted."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    mine = owned(folder)
    out = []
    for p in folder.rglob("*"):
        rel = p.relative_to(folder)
        if p.is_dir() or p.name == MANIFEST or rel in mine:
            continue
        if any(part.startswith(".") and (".tmp-" in part or ".old-" in part) for part in rel.parts):
            continue  # pounding's own temporary folders of a command still running or killed
        out.append(rel)
    return sorted(out)


def record(folder: str | Path, command: str, paths) -> None:
    """Add ``paths`` (in ``folder``) to what ``command`` wrote there, for a command that writes its
    files in place as it goes (a sweep's table row by row): recorded before the first row, the
    files of an interrupted command are still pounding's, so its rerun is not refused."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    files = read_manifest(folder)
    files[command] = sorted(set(files.get(command, ())) | _relative(folder, paths))
    _write_manifest(folder, files)


def _relative(folder: Path, paths) -> set[str]:
    """The ``paths`` as the manifest keeps them: relative to the (resolved) ``folder``; a relative path as given."""
    return {str(Path(p).resolve().relative_to(folder)) if Path(p).is_absolute() else str(p) for p in paths}


def settle(folder: str | Path, command: str, paths) -> None:
    """Record ``paths`` (in ``folder``) as everything ``command`` wrote there, at the end of a command that
    writes in place (:func:`record` as it went): its files of an earlier run that it did not write this
    time (the plots of a rerun with ``--no-plots``) are removed, as :func:`publish` removes them."""
    folder = Path(folder).resolve()
    files = read_manifest(folder)
    new = _relative(folder, paths)
    for rel in sorted(set(files.get(command, ())) - new):
        _remove_own(folder, rel)
    files[command] = sorted(new)
    _write_manifest(folder, files)


def check_target(folder: Path, *, overwrite: bool, option: str = "--out") -> None:
    """Refuse a folder that holds files pounding did not write (unless ``overwrite``) or is a file.

    Raises
    ------
    InputError
        Naming the folder, how many such files and one of them, and the way out.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder} is a file, not a folder", field=option)
    if overwrite:
        return
    others = foreign(folder)
    if others:
        n = len(others)
        raise InputError(
            f"{folder} holds {n} file{'' if n == 1 else 's'} pounding did not write (e.g. {others[0]}); choose an empty "
            "or new folder, or pass --overwrite to write beside them (they are kept)",
            field=option,
        )


@contextlib.contextmanager
def staging(target: str | Path):
    """Yield a temporary folder beside ``target`` (created); removed afterwards, whatever happens (Ctrl-C included)."""
    target = Path(target).resolve()
    target.parent.mkdir(parents=True, exist_ok=True)
    # the name is chosen first and the folder made inside the try: a Ctrl-C that lands just after
    # the folder exists is cleaned up too (mkdtemp before the try left it behind)
    while True:
        tmp = target.parent / f".{target.name}.tmp-{secrets.token_hex(4)}"
        if not tmp.exists():
            break
    try:
        tmp.mkdir(mode=0o700)
        yield tmp
    finally:
        shutil.rmtree(tmp, ignore_errors=True)  # gone already when published


def publish(tmp: Path, target: str | Path, command: str) -> list[Path]:
    """Move every file of ``tmp`` into ``target`` and record them under ``command`` in its manifest.

    The files ``command`` wrote into ``target`` before and did not write this
    time are removed (they are its own, now stale); every other file stays.
    Returns the paths written (in ``target``).
    """
    tmp, target = Path(tmp), Path(target).resolve()
    new = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*") if p.is_file() and p.name != MANIFEST)
    if not target.exists():
        _write_manifest(tmp, {command: new})
        # the staging folder is private while it fills; published, it gets the mode any new folder of the
        # user gets (0o777 less the umask), so that colleagues read the results as they read the user's other files
        os.chmod(tmp, (tmp.stat().st_mode & 0o7000) | (0o777 & ~_umask()))  # (a setgid bit inherited from the parent stays)
        os.replace(tmp, target)  # one rename: the folder appears complete or not at all
        return [target / p for p in new]
    files = read_manifest(target)
    stale = set(files.get(command, ())) - set(new)
    for rel in new:
        dest = target / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        if dest.is_dir() and not dest.is_symlink():
            raise InputError(f"cannot write {rel}: {dest} is a folder", field=command)
        os.replace(tmp / rel, dest)
    for rel in sorted(stale):
        _remove_own(target, rel)
    for other in files:
        if other != command:
            files[other] = [p for p in files[other] if p not in new]  # now this command's
    files[command] = new
    _write_manifest(target, files)
    shutil.rmtree(tmp, ignore_errors=True)
    return [target / p for p in new]


def _umask() -> int:
    """The process's file-mode creation mask: Linux reports it in /proc/self/status; elsewhere it is
    read by setting it and setting it back (a moment in which another thread's new files would get 022)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _remove_own(target: Path, rel: str) -> None:
    """Remove a file pounding wrote, and the folders it leaves empty (up to ``target``)."""
    path = target / rel
    with contextlib.suppress(FileNotFoundError):
        if path.is_file() or path.is_symlink():
            path.unlink()
    parent = path.parent
    while parent != target and parent.is_dir() and not any(parent.iterdir()):
        parent.rmdir()
        parent = parent.parent


def write_folder(target: str | Path, command: str, write) -> list[Path]:
    """Run ``write(tmp)`` into a staging folder, then :func:`publish` it into ``target``.

    Returns the paths ``write`` returned, moved to ``target`` and in its order (a plotter's figures),
    or else every path written, sorted.
    """
    with staging(target) as tmp:
        made = write(tmp)
        published = publish(tmp, target, command)
    if isinstance(made, (list, tuple)) and made and all(isinstance(p, Path) for p in made):
        return [Path(target).resolve() / Path(p).resolve().relative_to(tmp.resolve()) for p in made]
    return published
