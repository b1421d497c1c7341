"""Numba's on-disk cache for the compiled kernels: a writable location, never stale code.

numba keys a cached function on its own source file only, not on the modules it calls and inlines, so
after an edit to e.g. ``_motion.py`` a cached ``_engine.run_shot`` would silently keep the old code. We
stamp the cache with a hash of all kernel sources and drop it when they change.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from pathlib import Path

_HERE = Path(__file__).resolve().parent
_KERNEL_MODULES = ("_balls", "_roots", "_motion", "_impact", "_detect", "_engine", "params")
"""Every module of the compiled kernels (``@njit``) and the constants they read: an edit to any of them drops the
cache."""
_STAMP = "pix2pockets-event-kernels.stamp"


def _writable(directory: Path) -> bool:
    try:
        directory.mkdir(parents=True, exist_ok=True)
        probe = directory / f".p2p-write-test-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
        return True
    except OSError:
        return False


def _sources_hash() -> str:
    h = hashlib.sha256()
    for name in _KERNEL_MODULES:
        h.update((_HERE / f"{name}.py").read_bytes())
    return h.hexdigest()


def _drop_stale(directory: Path) -> None:
    """Delete this package's numba cache files in ``directory`` if the kernel sources changed."""
    stamp = directory / _STAMP
    digest = _sources_hash()
    try:
        if stamp.read_text() == digest:
            return
    except OSError:
        pass
    for path in directory.glob("*.nb[ic]"):
        if path.name.split(".", 1)[0] in _KERNEL_MODULES:
            path.unlink(missing_ok=True)
    with contextlib.suppress(OSError):
        stamp.write_text(digest)


def ensure_numba_cache_dir() -> None:
    """Point numba at a writable cache directory if its default locations are read-only.

    numba caches next to the source (``__pycache__``) and falls back to a per-user cache directory;
    when neither is writable (read-only install and home), caching would fail at import. In that case
    (and only if ``NUMBA_CACHE_DIR`` is not set) use a per-user folder in the system temp directory.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    in_tree = _HERE / "__pycache__"
    if _writable(in_tree):
        _drop_stale(in_tree)
        return
    from numba.misc.appdirs import AppDirs

    if _writable(Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)):
        return
    import numba

    uid = os.getuid() if hasattr(os, "getuid") else "user"
    fallback = Path(tempfile.gettempdir()) / f"pix2pockets-numba-{uid}"
    fallback.mkdir(parents=True, exist_ok=True)
    numba.config.CACHE_DIR = str(fallback)
