import threading
import time

import anyio
import pytest

from pix2pockets.web.jobs import BusyError, JobBoard, JobState


def fill(board: JobBoard, n: int, keep: bool = False) -> list:
    jobs = []
    for i in range(n):
        with board.admit() as submit:
            jobs.append(submit(b"x", f"p{i}.png", "auto", keep))
    return jobs


def test_admits_up_to_workers_plus_queue_then_refuses_with_retry_after():
    board = JobBoard(workers=2, queue=3)
    jobs = fill(board, 5)
    assert [board.ahead(j) for j in jobs] == [0, 1, 2, 3, 4]
    with pytest.raises(BusyError) as busy, board.admit():
        pass
    assert "busy" in busy.value.message and busy.value.retry_after >= 1
    assert board.stats()["refused"] == 1


def test_a_place_left_unused_is_given_back():
    board = JobBoard(workers=1, queue=0)
    with pytest.raises(ValueError), board.admit():
        raise ValueError("bad upload")
    with board.admit() as submit:  # the place is free again
        submit(b"x", "a.png", "auto")
    with pytest.raises(BusyError), board.admit():
        pass


def test_places_being_read_count_against_the_limit():
    board = JobBoard(workers=1, queue=1)
    with board.admit(), board.admit(), pytest.raises(BusyError), board.admit():
        pass


def test_jobs_run_in_order_and_report_stages():
    board = JobBoard(workers=1, queue=4)
    first, second = fill(board, 2, keep=True)
    job = board.take()
    assert job is first and job.state == JobState.RUNNING and board.ahead(second) == 0
    board.stage(job, "load")
    board.stage(job, "detect")
    view = board.view(job)
    assert view["state"] == "running" and view["stage"] == "detect" and set(view["stages"]) == {"load"}
    board.finish(job, 200, {"text": "ok"})
    view = board.view(first)
    assert view["state"] == "done" and view["result"] == {"text": "ok"} and set(view["stages"]) == {"load", "detect"}
    assert board.get(first.id) is first and first.data is None  # kept for the page, upload freed
    assert board.take() is second


def test_failed_jobs_carry_status_and_one_line():
    board = JobBoard(workers=1, queue=1)
    (job,) = fill(board, 1, keep=True)
    board.finish(board.take(), 422, {"error": "no cue ball found on the table"})
    assert board.view(job) | {"version": 0} == {
        "job": job.id, "state": "failed", "version": 0, "stages": {}, "status": 422,
        "error": "no cue ball found on the table",
    }  # fmt: skip


def test_answered_requests_are_not_kept_and_kept_jobs_expire():
    board = JobBoard(workers=1, queue=2, keep_s=0.05)
    sync, page = fill(board, 1)[0], fill(board, 1, keep=True)[0]
    board.finish(board.take(), 200, {})
    board.finish(board.take(), 200, {})
    assert board.get(sync.id) is None and board.get(page.id) is page
    time.sleep(0.1)
    assert board.get(page.id) is None


def test_kept_jobs_are_bounded():
    board = JobBoard(workers=1, queue=1, keep_max=3)
    ids = []
    for _ in range(6):
        (job,) = fill(board, 1, keep=True)
        board.finish(board.take(), 200, {})
        ids.append(job.id)
    assert [board.get(i) is not None for i in ids] == [False, False, False, True, True, True]


def test_close_answers_queued_jobs_503_and_stops_the_workers():
    board = JobBoard(workers=1, queue=3)
    running, *queued = fill(board, 3, keep=True)
    assert board.take() is running
    taken = []
    thread = threading.Thread(target=lambda: taken.append(board.take()))
    board.close()
    thread.start()
    thread.join(2)
    assert taken == [None]
    assert all(j.state == JobState.FAILED and j.status == 503 and "shutting down" in j.doc["error"] for j in queued)
    assert running.state == JobState.RUNNING  # finishes on its own
    board.finish(running, 200, {})
    with pytest.raises(BusyError, match="shutting down"), board.admit():
        pass


def test_take_waits_for_a_job_and_gives_up_after_timeout():
    board = JobBoard(workers=1, queue=1)
    assert board.take(timeout=0.05) is None
    threading.Timer(0.05, lambda: fill(board, 1)).start()
    assert board.take(timeout=2) is not None


def test_async_waiters_wake_on_change_and_on_finish():
    board = JobBoard(workers=1, queue=1)
    (job,) = fill(board, 1, keep=True)
    seen = []

    def worker():
        time.sleep(0.05)
        taken = board.take()
        time.sleep(0.05)
        board.stage(taken, "load")
        time.sleep(0.05)
        board.finish(taken, 200, {})

    async def main():
        threading.Thread(target=worker).start()
        await board.wait_async(job, job.version, timeout=5)  # the next change: taken
        seen.append(job.state)
        await board.wait_async(job)  # until it is over
        seen.append(job.state)
        await board.wait_async(job, job.version, timeout=0.05)  # nothing more: times out quietly

    anyio.run(main)
    assert seen == [JobState.RUNNING, JobState.DONE]


@pytest.mark.parametrize(("workers", "queue"), [(0, 1), (1, -1)])
def test_bad_sizes(workers, queue):
    with pytest.raises(ValueError, match="workers >= 1 and queue >= 0"):
        JobBoard(workers, queue)


def test_max_wait_admits_fewer_when_jobs_are_slow():
    board = JobBoard(workers=2, queue=8, max_wait=5.0)
    for seconds in (4.0,) * 30:  # a slow machine: each job takes 4 s
        fill(board, 1)
        taken = board.take()
        taken.started -= seconds
        board.finish(taken, 200, {})
    assert board.stats()["mean_job_s"] == pytest.approx(4.0, abs=0.01)
    jobs = fill(board, 2)  # one round of the two workers fits in 5 s; a second would not
    with pytest.raises(BusyError) as busy, board.admit():
        pass
    assert busy.value.retry_after == 2  # one job's time spread over two workers
    assert board.stats()["admitting"] == 2 and len(jobs) == 2


def test_max_wait_never_refuses_an_idle_worker_and_caps_at_the_queue():
    slow = JobBoard(workers=1, queue=3, max_wait=1.0)
    slow._job_s = 30.0
    fill(slow, 1)  # the worker is free: always admitted
    fast = JobBoard(workers=1, queue=3, max_wait=100.0)
    fast._job_s = 0.1
    assert fast.stats()["admitting"] == 4  # workers + queue


def test_bad_max_wait():
    with pytest.raises(ValueError, match="max_wait"):
        JobBoard(1, 1, max_wait=0)
