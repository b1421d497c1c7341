"""The job board: a bounded first-in-first-out queue of photos, their progress and their answers.

The web app admits an upload only while there is room (:meth:`JobBoard.admit`), before it reads the body, so the
memory held by uploads is bounded by ``(workers + queue) x max upload``. Room means fewer than ``workers + queue``
jobs held and, with ``max_wait``, an expected answer within ``max_wait`` seconds (from the running mean of job
times): on a slow or busy machine the board refuses sooner instead of letting waits grow. Worker threads take jobs
in order (:meth:`JobBoard.take`), report each pipeline stage as it starts and finish the job with an HTTP status and
a JSON document. Pages follow a job by id (:meth:`JobBoard.get`, :meth:`JobBoard.wait_async`); a finished job the
page asked for is kept a few minutes, a request that waited for its answer drops it at once. All methods are
thread-safe: the app's event loop and the worker threads share one lock.
"""

from __future__ import annotations

import asyncio
import math
import secrets
import threading
import time
from collections import OrderedDict, deque
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

STAGES = ("load", "detect", "fit", "plan", "draw")
"""Pipeline stages a running job reports, in order: read the photo, find balls and diamonds, fit the table and
locate the balls, plan the shot, draw the result."""
FIRST_GUESS_S = 2.0
"""Seconds per job assumed until one has been timed (for ``Retry-After``)."""


class JobState(StrEnum):
    QUEUED = "queued"
    RUNNING = "running"
    DONE = "done"
    FAILED = "failed"


class BusyError(Exception):
    """No room for another job: answered 503 with ``Retry-After``."""

    def __init__(self, message: str, retry_after: int) -> None:
        super().__init__(message)
        self.message = message
        self.retry_after = retry_after


@dataclass(eq=False)
class Job:
    """One photo on its way through the pipeline."""

    id: str
    data: bytes | None
    name: str
    options: Any
    keep: bool
    state: JobState = JobState.QUEUED
    stage: str | None = None
    stage_t0: float = 0.0
    stages: dict[str, float] = field(default_factory=dict)
    status: int | None = None
    doc: dict | None = None
    created: float = field(default_factory=time.monotonic)
    started: float | None = None
    finished: float | None = None
    version: int = 0
    listeners: list[Callable[[], None]] = field(default_factory=list)

    @property
    def over(self) -> bool:
        return self.state in (JobState.DONE, JobState.FAILED)


class JobBoard:
    """Bounded job queue shared by the app (producer) and the worker threads (consumers).

    Args:
        workers: jobs that run at once.
        queue: jobs that may wait beyond those.
        max_wait: refuse a job whose answer is expected later than this [s] (None: only the count limits).
        keep_s: how long a finished job the page follows stays readable [s].
        keep_max: most finished jobs kept (oldest dropped first).
    """

    def __init__(
        self,
        workers: int,
        queue: int,
        max_wait: float | None = None,
        keep_s: float = 300.0,
        keep_max: int | None = None,
    ) -> None:
        if workers < 1 or queue < 0:
            raise ValueError(f"need workers >= 1 and queue >= 0, got {workers} and {queue}")
        if max_wait is not None and not max_wait > 0:
            raise ValueError(f"max_wait must be positive, got {max_wait}")
        self.workers = workers
        self.queue_limit = queue
        self.max_wait = max_wait
        self.keep_s = keep_s
        self.keep_max = keep_max if keep_max is not None else 4 * (workers + queue) + 16
        self._lock = threading.Lock()
        self._ready = threading.Condition(self._lock)
        self._waiting: deque[Job] = deque()
        self._jobs: dict[str, Job] = {}
        self._kept: OrderedDict[str, float] = OrderedDict()  # finished job id -> time finished
        self._reserved = 0
        self._running = 0
        self._closing: str | None = None
        self._job_s = FIRST_GUESS_S  # running mean of job durations [s]
        self.served = 0
        self.refused = 0

    # --- admission (the app) ---------------------------------------------------------------------------------
    @property
    def capacity(self) -> int:
        """Jobs the board holds at most: running + waiting (+ admitted uploads still being read)."""
        return self.workers + self.queue_limit

    def retry_after(self) -> int:
        """Seconds until a place is likely free [s] (the ``Retry-After`` header)."""
        with self._lock:
            return self._retry_after()

    def _limit(self) -> int:
        """Jobs the board holds now: the capacity, fewer when the mean job time would push answers past max_wait."""
        if self.max_wait is None:
            return self.capacity
        rounds = math.floor(self.max_wait / max(self._job_s, 1e-3))  # jobs each worker can finish in max_wait
        return min(self.capacity, max(self.workers, rounds * self.workers))

    def _retry_after(self) -> int:
        held = len(self._waiting) + self._reserved + self._running
        return max(1, math.ceil((held + 1 - self._limit()) * self._job_s / self.workers))

    @contextmanager
    def admit(self) -> Iterator[Callable[..., Job]]:
        """A place on the board for one upload, or :class:`BusyError`.

        Yields ``submit(data, name, options, keep)``, which turns the place into a queued job; leaving the block
        without submitting gives the place back (a bad upload, a client that went away).
        """
        with self._lock:
            if self._closing:
                raise BusyError(self._closing, 5)
            held = len(self._waiting) + self._reserved + self._running
            if held >= self._limit():
                self.refused += 1
                wait = self._retry_after()
                raise BusyError(
                    f"the server is busy ({len(self._waiting)} photos waiting, {self._running} being looked at); "
                    f"try again in {wait} s",
                    wait,
                )
            self._reserved += 1
        placed: list[Job] = []

        def submit(data: bytes, name: str, options: Any, keep: bool = False) -> Job:
            if placed:
                raise RuntimeError("this place already holds a job")
            job = Job(secrets.token_urlsafe(12), data, name, options, keep)
            with self._lock:
                self._reserved -= 1
                placed.append(job)
                if self._closing:
                    self._finish_locked(job, 503, {"error": self._closing})
                    return job
                self._jobs[job.id] = job
                self._waiting.append(job)
                self._ready.notify()
            return job

        try:
            yield submit
        finally:
            if not placed:
                with self._lock:
                    self._reserved -= 1

    # --- the workers -----------------------------------------------------------------------------------------
    def take(self, timeout: float | None = None) -> Job | None:
        """The next queued job, now running; None when the board closes (or after ``timeout`` [s])."""
        with self._lock:
            end = None if timeout is None else time.monotonic() + timeout
            while not self._waiting:
                if self._closing:
                    return None
                left = None if end is None else end - time.monotonic()
                if left is not None and left <= 0:
                    return None
                self._ready.wait(left)
            job = self._waiting.popleft()
            job.state = JobState.RUNNING
            job.started = time.monotonic()
            self._running += 1
            self._changed(job)
            return job

    def stage(self, job: Job, name: str) -> None:
        """Job ``job`` starts pipeline stage ``name``; the previous stage's time is recorded."""
        with self._lock:
            now = time.monotonic()
            if job.stage is not None:
                job.stages[job.stage] = round(now - job.stage_t0, 4)
            job.stage = name
            job.stage_t0 = now
            self._changed(job)

    def finish(self, job: Job, status: int, doc: dict) -> None:
        """A running job's answer: HTTP ``status`` and its JSON document."""
        with self._lock:
            self._running -= 1
            if job.started is not None:
                self._job_s = 0.8 * self._job_s + 0.2 * (time.monotonic() - job.started)
            self._finish_locked(job, status, doc)

    def _finish_locked(self, job: Job, status: int, doc: dict) -> None:
        now = time.monotonic()
        if job.stage is not None and job.stage not in job.stages:
            job.stages[job.stage] = round(now - job.stage_t0, 4)
        job.stage = None
        job.state = JobState.DONE if status == 200 else JobState.FAILED
        job.status, job.doc, job.finished, job.data = status, doc, now, None
        self.served += status == 200
        if job.keep:
            self._kept[job.id] = now
            self._prune(now)
        else:
            self._jobs.pop(job.id, None)
        self._changed(job)

    def _prune(self, now: float) -> None:
        while self._kept:
            oldest, t = next(iter(self._kept.items()))
            if len(self._kept) <= self.keep_max and now - t <= self.keep_s:
                break
            self._kept.popitem(last=False)
            self._jobs.pop(oldest, None)

    def _changed(self, job: Job) -> None:
        job.version += 1
        listeners, job.listeners = job.listeners, []
        for wake in listeners:
            wake()

    # --- reading -------------------------------------------------------------------------------------------
    def get(self, job_id: str) -> Job | None:
        """The job with this id while it is queued, running or kept; None otherwise."""
        with self._lock:
            self._prune(time.monotonic())
            return self._jobs.get(job_id)

    def view(self, job: Job) -> dict:
        """The job as the page reads it (``GET /api/jobs/{id}``)."""
        with self._lock:
            out: dict = {"job": job.id, "state": job.state.value, "version": job.version, "stages": dict(job.stages)}
            if job.state == JobState.QUEUED:
                out["ahead"] = self._ahead(job)
            elif job.state == JobState.RUNNING:
                out["stage"] = job.stage
            else:
                out["status"] = job.status
                if job.state == JobState.DONE:
                    out["result"] = job.doc
                else:
                    out["error"] = (job.doc or {}).get("error", "error")
            return out

    def _ahead(self, job: Job) -> int:
        for i, other in enumerate(self._waiting):
            if other is job:
                return i
        return 0

    def ahead(self, job: Job) -> int:
        """Queued jobs in front of ``job``."""
        with self._lock:
            return self._ahead(job)

    async def wait_async(self, job: Job, version: int = -1, timeout: float | None = None) -> None:
        """Wait (without a thread) until ``job`` changes past ``version`` (-1: until it is over), or ``timeout``."""
        loop = asyncio.get_running_loop()
        while True:
            future = loop.create_future()

            def wake(future: asyncio.Future = future) -> None:
                loop.call_soon_threadsafe(lambda: future.done() or future.set_result(None))

            with self._lock:
                if job.over or (version >= 0 and job.version > version):
                    return
                job.listeners.append(wake)
            try:
                await asyncio.wait_for(future, timeout)
            except TimeoutError:
                with self._lock:
                    if wake in job.listeners:
                        job.listeners.remove(wake)
                return

    def stats(self) -> dict:
        """Counts for ``/api/health``."""
        with self._lock:
            return {
                "workers": self.workers,
                "running": self._running,
                "queued": len(self._waiting),
                "queue": self.queue_limit,
                "max_wait_s": self.max_wait,
                "admitting": self._limit(),
                "served": self.served,
                "refused": self.refused,
                "mean_job_s": round(self._job_s, 3),
            }

    # --- shutting down -------------------------------------------------------------------------------------
    def close(self, reason: str = "the server is shutting down; try again later") -> None:
        """Take no more jobs: queued ones are answered 503 ``reason``; running ones finish."""
        with self._lock:
            if self._closing:
                return
            self._closing = reason
            while self._waiting:
                self._finish_locked(self._waiting.popleft(), 503, {"error": reason})
            self._ready.notify_all()

    @property
    def closing(self) -> bool:
        return self._closing is not None

    def idle(self) -> bool:
        """No job is running or waiting."""
        with self._lock:
            return not self._running and not self._waiting
