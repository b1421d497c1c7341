"""Make sure numba has a writable place for its on-disk cache of the compiled kernels."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def _writable(directory: Path) -> bool:
    try:
        directory.mkdir(parents=True, exist_ok=True)
        probe = directory / f".p2p-write-test-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
        return True
    except OSError:
        return False


def ensure_numba_cache_dir() -> None:
    """Point numba at a writable cache directory if its default locations are read-only.

    numba caches next to the source (``__pycache__``) and falls back to a per-user cache directory;
    when neither is writable (read-only install and home), caching would fail at import. In that case
    (and only if ``NUMBA_CACHE_DIR`` is not set) use a per-user folder in the system temp directory.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    if _writable(Path(__file__).resolve().parent / "__pycache__"):
        return
    from numba.misc.appdirs import AppDirs

    if _writable(Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)):
        return
    import numba

    uid = os.getuid() if hasattr(os, "getuid") else "user"
    fallback = Path(tempfile.gettempdir()) / f"pix2pockets-numba-{uid}"
    fallback.mkdir(parents=True, exist_ok=True)
    numba.config.CACHE_DIR = str(fallback)
