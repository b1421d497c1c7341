"""Compiling the event kernels ahead of the first shot: once per install, split over two cores.

numba compiles the kernels at their first call and caches them on disk (:mod:`._cache`), so only the first process
after an install pays the compile (about 10 s on two cores, 20 s on one). :func:`compile_kernels` does it on
purpose: the ball-motion kernels in this process while a helper process compiles the event-time kernels
(``_refresh`` and what it calls), then the event loop itself, which then loads both halves from the cache.
:func:`kernels_cached` says whether a process would load them instead of compiling (commands use it to tell the
user what the wait is).

Example:
    >>> from pix2pockets.physics.event.warm import compile_kernels, kernels_cached
    >>> seconds = compile_kernels()  # doctest: +SKIP
    >>> kernels_cached()  # doctest: +SKIP
    True
"""

from __future__ import annotations

import argparse
import contextlib
import os
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

_PACKAGE_ROOT = Path(__file__).resolve().parents[3]  # the folder that holds the ``pix2pockets`` package
_HELPER_TIMEOUT = 300.0  # [s]


def _has_entry(dispatcher) -> bool:
    """Whether numba's disk cache holds a current entry of ``dispatcher`` for this machine."""
    try:
        cache = dispatcher._cache  # numba's per-function Cache (None without cache=True)
        magic = dispatcher.targetctx.codegen().magic_tuple()
        index = cache._cache_file._load_index()  # {} when missing or stale (source changed)
        return any(key[1] == magic for key in index)
    except Exception:  # numba internals moved: report "not cached" (a message too many, nothing worse)
        return False


def kernels_cached() -> bool:
    """Whether the event loop's compiled code is in numba's disk cache, so the first shot loads it (~0.3 s)."""
    from pix2pockets.physics.event._engine import run_shots

    return _has_entry(run_shots)


def _sample(n: int = 3) -> dict:
    """Arguments of the kernels' own types (a short row of balls on a 9-foot table)."""
    from pix2pockets.geometry.table import TableSpec
    from pix2pockets.physics.event.params import PhysicsParams
    from pix2pockets.physics.event.simulator import pack_table

    spec = TableSpec()
    pos = np.column_stack([np.linspace(0.5, 1.5, n), np.full(n, spec.width / 2)])
    return {
        "n": n,
        "pos": pos,
        "prm": PhysicsParams().packed(spec.ball_radius, spec.cushion_height),
        "geo": pack_table(spec),
        "vel": np.zeros((n, 2)),
        "w": np.zeros((n, 3)),
        "acc": np.zeros((n, 2)),
        "wacc": np.zeros((n, 2)),
        "st": np.zeros(n, dtype=np.int64),
        "tend": np.zeros(n),
        "member": np.zeros(n, dtype=np.bool_),
        "length": spec.length,
        "width": spec.width,
    }


def _compile_event_times() -> None:
    """Compile ``_refresh`` (next-event times: roots, cushions, pockets, ball pairs) with the engine's types."""
    from pix2pockets.physics.event._engine import _refresh

    s = _sample()
    n = s["n"]
    i = np.int64(0)
    _refresh(
        i, n, 0.0, s["pos"], s["vel"], s["acc"], s["st"], s["tend"], s["prm"], s["geo"],
        np.zeros((n, n)), np.zeros(n), np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64),
    )  # fmt: skip


def _compile_motion() -> None:
    """Compile the ball-motion kernels (strike, motion, collisions, transitions) with the engine's types."""
    from pix2pockets.physics.event import _motion as m

    s = _sample()
    n, pos, vel, w, st, prm = s["n"], s["pos"], s["vel"], s["w"], s["st"], s["prm"]
    acc, wacc, tend = s["acc"], s["wacc"], s["tend"]
    i, j = np.int64(0), np.int64(1)
    m.strike(i, 0.0, 1.0, 0.0, 0.0, 0.0, vel, w, prm)
    m.set_motion(i, 0.0, vel, w, st, acc, wacc, tend, prm)
    m.kinetic_energy(n, vel, w, st, prm)
    m.advance(n, 0.0, pos, vel, w, st, acc, wacc, prm)
    m.collide_balls(i, j, pos, vel, w, prm)
    m.nudge_apart(i, j, n, pos, st, prm, s["length"], s["width"])
    m.lock_cluster(i, j, n, pos, vel, w, st, prm, s["member"])
    m.collide_cushion(i, 1.0, 0.0, vel, w, prm)
    m.transition(i, 0.0, vel, w, st, acc, wacc, tend, prm)


def _run_one_shot() -> None:
    """One shot through the public simulator: compiles (or loads) the event loop itself."""
    from pix2pockets.physics.event.simulator import EventSimulator
    from pix2pockets.state import Shot
    from pix2pockets.state.racks import eight_ball_rack

    EventSimulator().simulate(eight_ball_rack(), Shot(angle=0.0, speed=2.0))


def _run_position_value() -> None:
    """One look-ahead value: compiles (or loads) the planner's position kernel."""
    import numpy as np

    from pix2pockets.geometry.table import TableSpec
    from pix2pockets.planner.position import direct_pot_probabilities

    direct_pot_probabilities(np.array([[0.5, 0.5], [1.0, 0.6]]), 0, [1], TableSpec(), 0.01)


def _start_helper() -> subprocess.Popen | None:
    """A helper process that compiles the event-time kernels (None when one cannot start)."""
    import numba

    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(_PACKAGE_ROOT), env.get("PYTHONPATH", "")) if p)
    if numba.config.CACHE_DIR:  # a cache folder chosen in this process: the helper writes to the same one
        env["NUMBA_CACHE_DIR"] = str(numba.config.CACHE_DIR)
    try:
        return subprocess.Popen(
            [sys.executable, "-m", "pix2pockets.physics.event.warm", "--part", "event-times"],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    except OSError:
        return None


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


@contextlib.contextmanager
def _compile_lock(dispatcher) -> Iterator[None]:
    """An exclusive lock file beside numba's cache, so that processes starting together compile only once."""
    try:
        import fcntl

        handle = open(Path(dispatcher._cache.cache_path) / "pix2pockets-compile.lock", "a")  # noqa: SIM115
    except (ImportError, AttributeError, OSError):  # no locks here: each process compiles what it needs
        yield
        return
    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def compile_kernels(parallel: bool | None = None) -> float:
    """Compile the event kernels into numba's disk cache, or load them when they are there.

    Args:
        parallel: split the compile over two processes (default: when this process may use two or more cores).

    Returns:
        The seconds it took.
    """
    t = time.perf_counter()
    from pix2pockets.physics.event import _engine, _motion

    if not kernels_cached():
        with _compile_lock(_engine.run_shots):  # one process compiles; others wait, then load
            if not kernels_cached():
                helper = None
                if not _has_entry(_engine._refresh) and (parallel if parallel is not None else _cores() >= 2):
                    helper = _start_helper()
                if not _has_entry(_motion.lock_cluster):
                    _compile_motion()
                if helper is not None:
                    try:
                        helper.wait(_HELPER_TIMEOUT)
                    except subprocess.TimeoutExpired:  # this process compiles what is missing
                        helper.kill()
                        helper.wait()
                _run_one_shot()
    _run_one_shot()
    _run_position_value()
    return time.perf_counter() - t


def main(argv: list[str] | None = None) -> int:
    """The helper process: compile one part of the kernels."""
    parser = argparse.ArgumentParser(description="compile a part of the event kernels into numba's cache")
    parser.add_argument("--part", choices=["event-times", "motion", "all"], default="all")
    args = parser.parse_args(argv)
    if args.part == "event-times":
        _compile_event_times()
    elif args.part == "motion":
        _compile_motion()
    else:
        compile_kernels()
    return 0


if __name__ == "__main__":
    sys.exit(main())
