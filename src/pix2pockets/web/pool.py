"""The worker pool: a fixed set of workers, each with its models loaded, fed in order from one job board.

Each worker is a process of its own (``workers >= 1``, the server's default: one per core) or, with
``workers=0``, a thread of the app's process (one photo at a time; tests and debugging). A thread per worker
takes the next job from the :class:`~pix2pockets.web.jobs.JobBoard`, hands it to its worker over a pipe,
passes the stages on to the board as they arrive and finishes the job with the worker's answer. A worker that
dies is started again (its job answered 500); one that runs past ``job_timeout`` is stopped and started again
(its job answered 503). Memory is bounded: a fixed number of workers, a bounded queue.

Example:
    >>> from pix2pockets.web.pool import WorkerPool
    >>> from pix2pockets.web.worker import EngineSpec
    >>> pool = WorkerPool(EngineSpec(), workers=2, queue=8)  # doctest: +SKIP
    >>> pool.start()  # loads and warms up both workers  # doctest: +SKIP
"""

from __future__ import annotations

import contextlib
import functools
import logging
import multiprocessing
import os
import threading
import time
import weakref
from collections.abc import Iterator
from typing import Any

from pix2pockets.web.jobs import JobBoard
from pix2pockets.web.worker import Engine, EngineSpec, Report, WebError, one_line, serve_forever

log = logging.getLogger("pix2pockets.web")

MAX_WAIT_S = 5.0
"""Default longest expected wait for an answer [s]: past it a photo is refused (503) rather than queued."""
START_TIMEOUT_S = 600.0
"""Longest a worker may take to load its models and warm up [s] (a first compile included)."""
_ONE_THREAD = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1"}
_env_lock = threading.Lock()


def default_workers() -> int:
    """One worker per core this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


@contextlib.contextmanager
def _one_thread_env() -> Iterator[None]:
    """Environment for a new worker process: numeric libraries on one thread (the pool spreads the cores)."""
    with _env_lock:
        saved = {k: os.environ.get(k) for k in _ONE_THREAD}
        os.environ.update(_ONE_THREAD)
        try:
            yield
        finally:
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v


class ThreadWorker:
    """A worker in the app's own process (``workers=0``): models loaded at the first job, no warm-up."""

    def __init__(self, spec: EngineSpec) -> None:
        self.engine = Engine(spec)

    def start(self) -> None:
        """Load and warm up now when the spec says so; otherwise the models load with the first job (whose answer
        then says if they are missing)."""
        if self.engine.spec.warm:
            self.engine.load()
            self.engine.warm_up()

    def run(self, data: bytes, name: str, options: Any, report: Report) -> tuple[int, dict]:
        return self.engine.run(data, name, options, report)

    def stop(self, timeout: float) -> None:
        """Nothing to stop."""


class ProcessWorker:
    """A worker that runs jobs in a spawned process of its own: its own models, threads and ONNX Runtime inference
    state, none shared with the server."""

    def __init__(self, spec: EngineSpec, index: int, job_timeout: float) -> None:
        self.spec = spec
        self.index = index
        self.job_timeout = job_timeout
        self.process: Any = None
        self.conn: Any = None
        self.pid: int | None = None
        self.warm_s = 0.0

    def launch(self) -> None:
        """Start the process (returns at once; :meth:`wait_ready` waits for its models)."""
        ctx = multiprocessing.get_context("spawn")
        parent, child = ctx.Pipe()
        process = ctx.Process(
            target=serve_forever, args=(child, self.spec), name=f"pix2pockets-worker-{self.index}", daemon=True
        )
        with _one_thread_env():
            process.start()
        child.close()
        self.process, self.conn = process, parent

    def wait_ready(self, timeout: float = START_TIMEOUT_S) -> None:
        """Wait until the worker has loaded its models and warmed up.

        Raises:
            WebError: the worker's own reason (e.g. 503 no detector model), or 500 when it died or hung.
        """
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                if self.conn.poll(0.2):
                    message = self.conn.recv()
                    if message[0] == "ready":
                        self.pid, self.warm_s = message[1], message[2]
                        return
                    self._kill()
                    raise WebError(message[1], message[2])
            except (EOFError, OSError):
                pass
            if not self.process.is_alive():
                code = self.process.exitcode
                self._kill()
                raise WebError(500, f"worker {self.index} exited with code {code} while starting")
        self._kill()
        raise WebError(500, f"worker {self.index} did not start within {timeout:.0f} s")

    def start(self) -> None:
        self.launch()
        self.wait_ready()

    def _restart(self) -> None:
        self._kill()
        try:
            self.start()
        except WebError as err:  # tried again at the next job
            log.error("worker %d could not be restarted: %s", self.index, err.message)

    def run(self, data: bytes, name: str, options: Any, report: Report) -> tuple[int, dict]:
        if self.process is None or not self.process.is_alive():
            self._restart()
            if self.process is None or not self.process.is_alive():
                return 503, {"error": "no worker is available; try again later"}
        try:
            self.conn.send(("job", data, name, options))
        except (OSError, ValueError):
            self._restart()
            return 500, {"error": "internal error: the worker could not take the photo"}
        end = time.monotonic() + self.job_timeout
        while True:
            try:
                if self.conn.poll(0.25):
                    message = self.conn.recv()
                    if message[0] == "stage":
                        report(message[1])
                        continue
                    return message[1], message[2]
            except (EOFError, OSError):
                pass
            if not self.process.is_alive():
                code = self.process.exitcode
                log.error("worker %d stopped (exit code %s) on %s; starting a new one", self.index, code, name)
                self._restart()
                return 500, {"error": f"internal error: the worker stopped while reading this photo (exit code {code})"}
            if time.monotonic() > end:
                log.error("worker %d took over %.0f s on %s; starting a new one", self.index, self.job_timeout, name)
                self._restart()
                return 503, {"error": f"the photo took longer than {self.job_timeout:.0f} s; try a smaller one"}

    def _kill(self) -> None:
        if self.process is not None and self.process.is_alive():
            self.process.kill()
            self.process.join(5)
        if self.conn is not None:
            self.conn.close()
        self.process = self.conn = None

    def stop(self, timeout: float) -> None:
        """Ask the worker to exit (after its job), then make sure it has."""
        if self.process is None:
            return
        with contextlib.suppress(OSError, ValueError):
            self.conn.send(("stop",))
        self.process.join(timeout)
        self._kill()


def _dispatch(board: JobBoard, worker: ThreadWorker | ProcessWorker) -> None:
    """Feed one worker from the board until the board closes."""
    while True:
        job = board.take()
        if job is None:
            return
        try:
            report = functools.partial(board.stage, job)
            status, doc = worker.run(job.data or b"", job.name, job.options, report)
        except Exception as err:  # a bug in the pool itself: answer it, keep serving
            log.exception("job %s failed", job.id)
            status, doc = 500, {"error": one_line(f"internal error: {type(err).__name__}: {err}")}
        board.finish(job, status, doc)


class WorkerPool:
    """A fixed set of workers fed from one :class:`~pix2pockets.web.jobs.JobBoard`.

    Args:
        spec: what every worker loads.
        workers: worker processes (0: one worker thread in this process).
        queue: photos that may wait for a worker (default: 4 per worker); more are refused with 503.
        job_timeout: longest one photo may take [s].
        max_wait: refuse a photo whose answer is expected later than this [s] (None: only ``queue`` limits).
    """

    def __init__(
        self,
        spec: EngineSpec,
        workers: int = 0,
        queue: int | None = None,
        job_timeout: float = 120.0,
        max_wait: float | None = MAX_WAIT_S,
    ):
        if workers < 0:
            raise ValueError(f"workers must be >= 0, got {workers}")
        if queue is not None and queue < 0:
            raise ValueError(f"queue must be >= 0, got {queue}")
        if not job_timeout > 0:
            raise ValueError(f"job_timeout must be positive, got {job_timeout}")
        n = max(1, workers)
        self.spec = spec
        self.processes = workers > 0
        self.board = JobBoard(n, 4 * n if queue is None else queue, max_wait)
        self.workers: list[ThreadWorker | ProcessWorker] = (
            [ProcessWorker(spec, i, job_timeout) for i in range(n)] if self.processes else [ThreadWorker(spec)]
        )
        self._threads: list[threading.Thread] = []
        self._lock = threading.Lock()
        self.started = False
        self.start_s = 0.0
        weakref.finalize(self, self.board.close)  # idle worker threads end with the pool

    def start(self) -> None:
        """Start the workers and wait until every one has loaded its models and warmed up (once).

        Raises:
            WebError: a worker could not start (e.g. 503 when the build has no detector model).
        """
        with self._lock:
            if self.started:
                return
            t = time.perf_counter()
            try:
                if self.processes:
                    for w in self.workers:  # all at once: the first compile is shared through a lock file
                        w.launch()
                    for w in self.workers:
                        w.wait_ready()
                else:
                    self.workers[0].start()
            except WebError:
                for w in self.workers:
                    w.stop(1.0)
                raise
            for w in self.workers:
                thread = threading.Thread(
                    target=_dispatch, args=(self.board, w), name="pix2pockets-dispatch", daemon=True
                )
                thread.start()
                self._threads.append(thread)
            self.start_s = time.perf_counter() - t
            self.started = True

    def stop(self, timeout: float = 30.0) -> None:
        """Refuse queued photos (503), let running ones finish (up to ``timeout`` [s]), then end the workers."""
        self.board.close()
        end = time.monotonic() + timeout
        for thread in self._threads:
            thread.join(max(0.0, end - time.monotonic()))
        for w in self.workers:
            w.stop(max(0.5, end - time.monotonic()))

    def pids(self) -> list[int]:
        """Process ids of the live worker processes."""
        return [w.process.pid for w in self.workers if isinstance(w, ProcessWorker) and w.process is not None]
