"""A Ray connection for one command: start a local instance or join a cluster, map a function over pieces."""

from __future__ import annotations

import argparse
import itertools
import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

T = TypeVar("T")
R = TypeVar("R")

LOCAL = "local"
"""``--ray`` without an address: start a Ray instance on this machine for the command."""


def add_ray_arguments(parser: argparse.ArgumentParser, what: str) -> None:
    """Add ``--ray [ADDRESS]`` and ``--workers N`` to a command's parser; ``what`` says how the command uses the
    workers (the start of the help text)."""
    parser.add_argument(
        "--ray",
        nargs="?",
        const=LOCAL,
        default=None,
        metavar="ADDRESS",
        help=f"{what} (the ray extra): alone, a Ray instance on this machine; with an address (auto, "
        "ray://HOST:10001), that cluster",
    )
    parser.add_argument("--workers", type=int, default=None, help="CPUs of the local Ray instance (default: all)")


def require_ray() -> Any:
    """Import ray, or raise ``ValueError`` saying how to install it."""
    try:
        import ray
    except ImportError:
        raise ValueError('--ray needs the ray extra: pip install ".[ray]"') from None
    return ray


def split_range(start: int, count: int, pieces: int) -> list[range]:
    """``range(start, start + count)`` cut into at most ``pieces`` contiguous, near-equal, non-empty ranges."""
    if count < 0 or pieces < 1:
        raise ValueError(f"need count >= 0 and pieces >= 1, got {count} and {pieces}")
    pieces = min(pieces, count) or 1
    bounds = [start + count * k // pieces for k in range(pieces + 1)]
    return [range(a, b) for a, b in itertools.pairwise(bounds) if b > a]


class RayPool:
    """Ray for one command: ``with RayPool(address) as pool: pool.map(fn, pieces)``.

    Args:
        address: ``local`` (or ``None``) starts a Ray instance here and stops it on exit; anything else
            (``auto``, ``ray://host:10001``, ``host:6379``) joins that running cluster and leaves it running.
        workers: CPUs of a local instance (default: all of this machine's); ignored for a cluster.
    """

    def __init__(self, address: str | None = LOCAL, workers: int | None = None) -> None:
        if workers is not None and workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        self.address = address or LOCAL
        self.workers = workers
        self._started = False

    def __enter__(self) -> RayPool:
        ray = require_ray()
        if ray.is_initialized():
            return self
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")  # no usage reporting from a command-line tool
        if self.address == LOCAL:
            ray.init(num_cpus=self.workers or os.cpu_count(), include_dashboard=False, log_to_driver=False)
        else:
            ray.init(address=self.address, log_to_driver=False)
        self._started = True
        return self

    def __exit__(self, *exc: object) -> None:
        if self._started:
            require_ray().shutdown()
            self._started = False

    @property
    def cpus(self) -> int:
        """CPUs the Ray instance offers (the useful number of pieces in flight)."""
        return max(1, int(require_ray().cluster_resources().get("CPU", 1)))

    def map(self, fn: Callable[..., R], pieces: Sequence[T], *args: Any) -> Iterator[R]:
        """``fn(piece, *args)`` for every piece on the Ray workers; results in the order of ``pieces``."""
        ray = require_ray()
        remote = ray.remote(num_cpus=1)(fn)
        shared = [ray.put(a) for a in args]
        refs = [remote.remote(p, *shared) for p in pieces]
        for ref in refs:
            yield ray.get(ref)
