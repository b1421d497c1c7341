"""The worker pool with real worker processes (spawned; stand-in detector and planner, so no model is needed)."""

import io
import threading
import time

import numpy as np
import pytest
from PIL import Image

from pix2pockets.testing import NearestPocketPlanner
from pix2pockets.web.jobs import JobState
from pix2pockets.web.pool import WorkerPool
from pix2pockets.web.worker import EngineSpec, WebError
from tests.web.standins import CrashOnDark, GatedDetector, HangOnDark, SlowDetector, missing_model


def dark_png() -> bytes:
    buf = io.BytesIO()
    Image.fromarray(np.full((120, 160, 3), 10, np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def submit(pool: WorkerPool, data: bytes, name: str = "table.jpg"):
    with pool.board.admit() as place:
        return place(data, name, "auto", True)


def wait(job, timeout: float = 60.0):
    end = time.monotonic() + timeout
    while not job.over:
        assert time.monotonic() < end, f"job still {job.state} after {timeout} s"
        time.sleep(0.02)
    return job


@pytest.fixture
def make_pool():
    pools = []

    def make(detector, workers=1, **kwargs) -> WorkerPool:
        pool = WorkerPool(EngineSpec(detector, NearestPocketPlanner(), warm=False), workers, **kwargs)
        pools.append(pool)
        pool.start()
        return pool

    yield make
    for pool in pools:
        pool.stop(5)


def test_two_workers_take_two_photos_at_once(rendered, make_pool):
    data, labels = rendered
    pool = make_pool(SlowDetector(labels, 1.0), workers=2)
    assert len(set(pool.pids())) == 2
    a, b = submit(pool, data), submit(pool, data)
    wait(a), wait(b)
    assert a.status == b.status == 200, (a.doc, b.doc)
    assert max(a.started, b.started) < min(a.finished, b.finished)  # they overlapped
    assert set(a.stages) == {"load", "detect", "fit", "plan", "draw"} and a.stages["detect"] >= 0.9
    assert a.doc["suggestion"] == b.doc["suggestion"]


def test_a_worker_that_dies_is_replaced(rendered, make_pool):
    data, labels = rendered
    pool = make_pool(CrashOnDark(labels))
    before = pool.pids()
    crashed = wait(submit(pool, dark_png(), "dark.png"))
    assert crashed.status == 500 and "worker stopped" in crashed.doc["error"] and "exit code 3" in crashed.doc["error"]
    fine = wait(submit(pool, data))
    assert fine.status == 200 and pool.pids() != before


def test_a_photo_past_the_time_limit_is_stopped(rendered, make_pool):
    data, labels = rendered
    pool = make_pool(HangOnDark(labels), job_timeout=2.0)
    hung = wait(submit(pool, dark_png(), "dark.png"))
    assert hung.status == 503 and "longer than 2 s" in hung.doc["error"]
    assert wait(submit(pool, data)).status == 200


def test_a_worker_without_its_model_fails_the_start_with_one_line():
    pool = WorkerPool(EngineSpec(detector_factory=missing_model, planner=NearestPocketPlanner(), warm=False), 1)
    with pytest.raises(WebError) as err:
        pool.start()
    assert err.value.status == 503
    assert err.value.message == "no detector available: detector model not found: detector.onnx"
    assert pool.pids() == []


def test_stop_finishes_the_running_photo_and_refuses_the_queued(rendered, make_pool, tmp_path):
    data, labels = rendered
    gate = tmp_path / "go"
    pool = make_pool(GatedDetector(labels, gate), workers=1, queue=2)
    running, queued = submit(pool, data), submit(pool, data)
    while running.state != JobState.RUNNING:
        time.sleep(0.01)
    stopper = threading.Thread(target=pool.stop, args=(30,))
    stopper.start()
    wait(queued, 5)
    assert queued.status == 503 and "shutting down" in queued.doc["error"]
    assert not running.over
    gate.touch()
    stopper.join(30)
    assert running.status == 200 and pool.pids() == []
