"""Slim agent files for shipping: half-precision policy weights, no optimizer state.

An SB3 PPO zip on the paper's ``MultiDiscrete([36000, 30])`` action space is ~25 MB: a 64 x 36,030 action
head (9 MB in float32) plus Adam's two moment buffers of the same size. For inference only the weights
matter; :func:`slim_agent` stores them as float16 (loading converts back to float32) and empties the
optimizer state, giving ~4.5 MB. ``rl evaluate`` and :func:`pix2pockets.rl.agent.load_agent` read slim files
like any other agent file; they can even resume training (with a fresh Adam state).
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

from pix2pockets.rl.bundle import META_ENTRY, read_meta

POLICY_ENTRY = "policy.pth"
OPTIMIZER_ENTRY = "policy.optimizer.pth"


def slim_agent(src: str | Path, dst: str | Path, half: bool = True) -> Path:
    """Write a slim copy of agent file ``src`` to ``dst`` (returns ``dst``).

    Args:
        src: an agent file from ``pix2pockets rl train``.
        dst: output path (``.zip``); must differ from ``src``.
        half: store floating-point weights as float16.
    """
    import torch

    src, dst = Path(src), Path(dst)
    if src.resolve() == dst.resolve():
        raise ValueError("slim_agent writes a new file: dst must differ from src")
    read_meta(src)  # a clear error for files that are not agents
    with zipfile.ZipFile(src) as zf:
        entries = {name: zf.read(name) for name in zf.namelist()}
    policy = torch.load(io.BytesIO(entries[POLICY_ENTRY]), map_location="cpu", weights_only=True)
    if half:
        policy = {k: v.half() if v.is_floating_point() else v for k, v in policy.items()}
    buf = io.BytesIO()
    torch.save(policy, buf)
    entries[POLICY_ENTRY] = buf.getvalue()
    if OPTIMIZER_ENTRY in entries:
        opt = torch.load(io.BytesIO(entries[OPTIMIZER_ENTRY]), map_location="cpu", weights_only=True)
        buf = io.BytesIO()
        torch.save({"state": {}, "param_groups": opt["param_groups"]}, buf)
        entries[OPTIMIZER_ENTRY] = buf.getvalue()
    dst.parent.mkdir(parents=True, exist_ok=True)
    tmp = dst.with_name(dst.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=9) as zf:
        for name, data in entries.items():
            if name != META_ENTRY:
                zf.writestr(name, data)
        zf.writestr(META_ENTRY, entries[META_ENTRY])
    tmp.replace(dst)
    return dst
