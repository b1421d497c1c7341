"""Writing output files safely: whole files or nothing, with normal permissions; no silent overwrites."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str | os.PathLike[str], data: bytes | str) -> None:
    """Write ``data`` to ``path`` via a temporary file in the same folder and a rename.

    A failure leaves no partial file; the result gets the usual permissions (``0o666`` minus the umask).
    """
    target = Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_json(path: str | os.PathLike[str], data: Any, indent: int = 2) -> None:
    """Write ``data`` as JSON (UTF-8, trailing newline) with :func:`write_atomic`."""
    write_atomic(path, json.dumps(data, indent=indent) + "\n")


def check_output(path: str | None, force: bool, suffixes: tuple[str, ...] | None = None) -> None:
    """Refuse outputs that would overwrite a file (without ``force``), sit in a missing folder, or have
    an unsupported suffix."""
    if path is None or path == "-":
        return
    p = Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"output {path}: unsupported file type (use one of {', '.join(suffixes)})")
    if p.is_dir():
        raise ValueError(f"output {path} is a directory")
    if not p.parent.exists():
        raise ValueError(f"output folder {p.parent} does not exist")
    if p.exists() and not force:
        raise ValueError(f"output {path} exists; use --force to overwrite it")
