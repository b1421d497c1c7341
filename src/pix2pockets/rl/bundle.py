"""Agent files: an SB3 model zip with a small ``pix2pockets.json`` entry saying how to rebuild its env.

SB3 reads only its own entries of the zip, so the extra entry does not disturb ``Algo.load``; with it,
``rl evaluate`` and :func:`pix2pockets.rl.agent.load_agent` need nothing but the file.
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pix2pockets.rl.algos import algo_spec
from pix2pockets.rl.envs import EnvChoice

META_ENTRY = "pix2pockets.json"
FORMAT_VERSION = 1


@dataclass(frozen=True, slots=True)
class AgentMeta:
    """What an agent file holds.

    Attributes:
        algo: algorithm name.
        choice: the environment variant it was trained on.
        steps: environment steps (= shots) trained.
        seed: training seed.
    """

    algo: str
    choice: EnvChoice
    steps: int
    seed: int

    def __post_init__(self) -> None:
        algo_spec(self.algo)
        if self.steps < 0:
            raise ValueError(f"steps must be >= 0, got {self.steps}")

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": FORMAT_VERSION,
            "algo": self.algo,
            **self.choice.to_dict(),
            "steps": self.steps,
            "seed": self.seed,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> AgentMeta:
        return cls(
            algo=str(data["algo"]),
            choice=EnvChoice.from_dict(data),
            steps=int(data["steps"]),
            seed=int(data["seed"]),
        )


def write_meta(path: str | Path, meta: AgentMeta) -> None:
    """Add (or replace) the metadata entry of an SB3 model zip."""
    path = Path(path)
    with zipfile.ZipFile(path) as zf:
        entries = {name: zf.read(name) for name in zf.namelist() if name != META_ENTRY}
    tmp = path.with_name(path.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, data in entries.items():
            zf.writestr(name, data)
        zf.writestr(META_ENTRY, json.dumps(meta.to_dict(), indent=2))
    tmp.replace(path)


def read_meta(path: str | Path) -> AgentMeta:
    """The metadata of an agent file, with a clear error for files that are not pix2pockets agents."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"agent file {str(path)!r} does not exist")
    try:
        with zipfile.ZipFile(path) as zf:
            data = json.loads(zf.read(META_ENTRY))
    except zipfile.BadZipFile:
        raise ValueError(f"{str(path)!r} is not an SB3 model zip") from None
    except KeyError:
        raise ValueError(f"{str(path)!r} has no {META_ENTRY} entry: not saved by `pix2pockets rl train`") from None
    try:
        return AgentMeta.from_dict(data)
    except (KeyError, TypeError) as err:
        raise ValueError(f"{str(path)!r}: bad {META_ENTRY}: {err}") from None
