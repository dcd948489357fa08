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

    Folders of earlier versions stay behind (a few MB each, and the extension modules' ``aot-*``
    beside them); delete ``pounding/__pycache__/numba-*`` and ``aot-*``
    to reclaim them."""
    try:
        key = cache_key()
    except OSError:  # pragma: no cover - a frozen or zipped install
        return None
    for base in (PACKAGE_ROOT / "__pycache__", Path.home() / ".cache" / "pounding"):
        folder = base / ("numba-" + key)
        try:
            folder.mkdir(parents=True, exist_ok=True)
            if os.access(folder, os.W_OK):
                return str(folder)
        except OSError:
            continue
    return None

