"""Where numba caches the package's compiled functions, keyed on their source.

numba keys a cached function on its own source file only: a change in a function
it calls from another module would leave it stale. The cache folder is therefore
keyed on the source of every module that declares compiled functions, found by
scanning the package for ``@njit`` (:func:`compiled_modules`), not by a hand-kept
list. ``NUMBA_CACHE_DIR``, when set, is numba's and is left alone.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import re
from pathlib import Path

#: the package's root folder (``pounding/``)
PACKAGE_ROOT = Path(__file__).resolve().parent.parent


def enabled() -> bool:
    """Whether compiled code is used: numba is installed and ``NUMBA_DISABLE_JIT`` is not set.

    Decided without importing numba."""
    if os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0"):
        return False
    return importlib.util.find_spec("numba") is not None


def compiled_modules() -> list[Path]:
    """Source files of the package that declare compiled functions (a line ``@njit``), sorted.

    Files under ``__pycache__`` are not the package's source: the cache folder lives there, and a
    file in it must never move the key that names it (the next process would compile everything
    again, into a new folder)."""
    pattern = re.compile(rb"^@njit\b", re.MULTILINE)
    out = []
    for path in _sources():  # (not under __pycache__: generated modules live in the cache itself, keying on them would move it)
        try:
            if pattern.search(path.read_bytes()):
                out.append(path)
        except OSError:  # pragma: no cover - unreadable file
            continue
    return out


def cache_key() -> str:
    """Digest of the source of every compiled module (:func:`compiled_modules`). Kept while no source
    file of the package changes (size and modification time): scanning and reading them all costs
    ~20 ms, and a process asks several times (numba's folder, the extension module's)."""
    stamp = _source_stamp()
    hit = _key.get(PACKAGE_ROOT)
    if hit is not None and hit[0] == stamp:
        return hit[1]
    digest = hashlib.sha1()
    for path in compiled_modules():
        digest.update(str(path.relative_to(PACKAGE_ROOT)).encode())
        digest.update(path.read_bytes())
    key = digest.hexdigest()[:12]
    _key[PACKAGE_ROOT] = (stamp, key)
    return key


_key: dict = {}  # package root -> (source stamp, key)


def _sources() -> list[Path]:
    """The package's Python files, sorted, not descending into ``__pycache__`` (numba's cache
    folders hold thousands of files)."""
    out = []
    for folder, dirs, files in os.walk(PACKAGE_ROOT):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        out.extend(Path(folder) / f for f in files if f.endswith(".py"))
    return sorted(out)


def _source_stamp() -> tuple:
    return tuple((str(p), st.st_size, st.st_mtime_ns) for p in _sources() for st in (p.stat(),))


def cache_dir() -> str | None:
    """numba's cache folder for this exact version of the compiled modules (None: numba's default).

    Folders of earlier versions beside the package (about 80 MB each, and the extension modules'
    ``aot-*`` beside them) are removed by the warm-up that fills a new one (:func:`prune_stale`);
    those in the user's cache, shared by every install, are left alone."""
    try:
        key = cache_key()
    except OSError:  # pragma: no cover - a frozen or zipped install
        return None
    for base in cache_bases():
        folder = base / ("numba-" + key)
        try:
            folder.mkdir(parents=True, exist_ok=True)
            if os.access(folder, os.W_OK):
                return str(folder)
        except OSError:
            continue
    return None



def cache_bases() -> tuple[Path, Path]:
    """Where the cache folders may live, in order of preference: beside the package's bytecode,
    else in the user's cache (a read-only install)."""
    return PACKAGE_ROOT / "__pycache__", Path.home() / ".cache" / "pounding"


#: the extension module's name and its manifest's (:mod:`pounding.compiler.prebuilt`, which builds them into ``aot-<key>``)
EXTENSION_MODULE = "pounding_core"
EXTENSION_MANIFEST = "manifest.json"
#: the name of a cache folder this package writes: numba's, or the extension module's
#: (:mod:`pounding.compiler.prebuilt`), each keyed on the source (:func:`cache_key`)
_FOLDER = re.compile(r"^(numba|aot)-([0-9a-f]{12})$")
#: [s] a folder changed more recently than this may be in use by a process that is still running
#: (one started before the source changed): it is left for a later warm-up
PRUNE_AFTER_S = 600.0


def _written_by_us(folder: Path) -> bool:
    """Whether every file under ``folder`` is one a cache of this package writes: numba's index and
    data files (``*.nbi``, ``*.nbc``) and the warm-up's marker, or the extension module and its
    manifest. A folder holding anything else is left alone, whatever its name."""
    for path in folder.rglob("*"):
        if path.is_dir():
            continue
        name = path.name
        if not (name.endswith((".nbi", ".nbc")) or ".nbi.tmp." in name or ".nbc.tmp." in name  # (numba's, half written)
                or name in ("warmed.json", EXTENSION_MANIFEST) or name.startswith(EXTENSION_MODULE + ".")):
            return False
    return True


def _newest_change(folder: Path) -> float:
    """The latest modification time [s since the epoch] of the folder or anything in it."""
    return max([folder.stat().st_mtime] + [p.stat().st_mtime for p in folder.rglob("*")])


def stale_folders(base: Path, key: str, *, now: float | None = None) -> list[Path]:
    """The cache folders in ``base`` of other versions of the compiled modules than ``key``: named as
    this package names them (``numba-<key>``, ``aot-<key>``), holding only what it writes, and
    unchanged for :data:`PRUNE_AFTER_S`. Sorted."""
    import time

    now = time.time() if now is None else now
    out = []
    try:
        entries = sorted(base.iterdir())
    except OSError:
        return out
    for folder in entries:
        m = _FOLDER.match(folder.name)
        if m is None or m.group(2) == key or not folder.is_dir() or folder.is_symlink():
            continue
        try:
            if now - _newest_change(folder) >= PRUNE_AFTER_S and _written_by_us(folder):
                out.append(folder)
        except OSError:  # vanished or unreadable meanwhile: not ours to judge
            continue
    return out


def prune_stale() -> tuple[int, int]:
    """Remove the cache folders of earlier versions (:func:`stale_folders`) beside this install's
    package (``pounding/__pycache__``: the versions of this very install, whose source changed), and
    only there: the user's cache (``~/.cache/pounding``, where a read-only install keeps its cache)
    is shared by every install of the user, whose folders are other versions still in use.
    Returns (folders removed, bytes freed); a folder that cannot be measured or removed is skipped."""
    import shutil

    try:
        key = cache_key()
    except OSError:  # pragma: no cover - a frozen or zipped install
        return 0, 0
    count = freed = 0
    own = cache_bases()[0]
    for folder in stale_folders(own, key):
        try:
            size = sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())
            shutil.rmtree(folder)
        except OSError:  # vanished meanwhile (another warm-up pruning), or not ours to remove
            continue
        count, freed = count + 1, freed + size
    return count, freed
