"""The FastAPI app behind ``pix2pockets serve``: one page, a small JSON API, a pool of workers behind a queue.

Routes:
    ``GET /``: the page (one self-contained HTML file: inline CSS and JS, nothing fetched from elsewhere).
    ``POST /api/jobs``: multipart ``file`` (the photo), ``group`` (``auto``, ``solids``, ``stripes``, ``reds`` or
    ``yellows``) and optionally ``skill`` (``pro``, the default, ``club`` or ``beginner``: the shot and its chance
    are for it), ``table`` (``auto`` or a size), ``set`` (``auto``, ``american`` or ``blackball``) and ``in_hand``
    (``none``, the default: the cue ball where it lies; ``table`` or ``baulk``: ball in hand, placed by the planner);
    answers 202 at once with the job's id; ``GET /api/jobs/{id}`` follows it (queued with the number of photos
    ahead, then each stage, then the answer). ``?since=VERSION`` waits up to 15 s for the next change.
    ``POST /api/suggest``: the same upload, answered when done: the JSON of ``pix2pockets suggest --json`` plus
    ``picture_png_base64`` (the result picture) and ``picture_parts``.
    ``GET /api/example``: the bundled example photo. ``GET /api/health``: ``{"status": "ok", ...}`` with the
    pool's counts. ``GET /favicon.ico``: the icon.

Every error is JSON ``{"error": "<one line>"}``: 400 bad upload, group, skill, table, set or ball in hand, 404 unknown
route or job, 413 upload too large, 422 a readable photo where the table, the cue ball or the group's balls are not
found, 503 busy (with ``Retry-After``), shutting down, or no detector or planner in this build. The photo goes through
the same functions as the CLI (see :mod:`pix2pockets.web.worker`).

Example:
    >>> from pix2pockets.web.app import create_app
    >>> app = create_app(workers=2)  # doctest: +SKIP
    >>> import uvicorn; uvicorn.run(app)  # doctest: +SKIP
"""

from __future__ import annotations

import functools
import io
import logging
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, Response
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import UploadFile
from starlette.exceptions import HTTPException as StarletteHTTPException

from pix2pockets import __version__
from pix2pockets.rules import InHand
from pix2pockets.state.ball_set import BALL_SET_CHOICES, group_choices
from pix2pockets.vision.image_io import MAX_PIXELS
from pix2pockets.web.jobs import BusyError, Job, JobBoard
from pix2pockets.web.pool import MAX_WAIT_S, WorkerPool
from pix2pockets.web.worker import MAX_PICTURE_SIDE, SKILLS, TABLES, EngineSpec, JobOptions, WebError, one_line

if TYPE_CHECKING:  # the app's process stays light: the models and the pipeline live in the workers
    from pix2pockets.pipeline.planning import ShotPlanner
    from pix2pockets.vision.detect.base import Detector

MAX_UPLOAD_BYTES = 20_000_000
"""Largest request body accepted [bytes]; larger uploads get a 413 before they are read in full."""
GROUPS = group_choices()
BALL_SETS = BALL_SET_CHOICES
"""``auto`` and the values of :class:`pix2pockets.state.Group`."""
IN_HAND = tuple(a.value for a in InHand)
"""Where the cue ball is played from: where it lies (``none``) or ball in hand on the table or behind the baulk
line."""
LONG_POLL_S = 15.0
"""Longest a ``GET /api/jobs/{id}?since=N`` waits for the job to change [s]."""
PAGE_CSP = (
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
    "img-src 'self' data: blob:; connect-src 'self'; form-action 'self'; base-uri 'none'"
)

__all__ = ["GROUPS", "MAX_PICTURE_SIDE", "MAX_UPLOAD_BYTES", "WebError", "create_app"]

log = logging.getLogger("pix2pockets.web")


def _error(status: int, message: str, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse({"error": one_line(message)}, status_code=status, headers=headers)


def _limited(receive: Callable, limit: int) -> Callable:
    """Wrap an ASGI ``receive`` so that reading more than ``limit`` body bytes raises a 413."""
    seen = 0

    async def receive_limited() -> dict:
        nonlocal seen
        message = await receive()
        if message["type"] == "http.request":
            seen += len(message.get("body", b""))
            if seen > limit:
                raise WebError(413, f"upload is too large (limit {limit / 1e6:.1f} MB)")
        return message

    return receive_limited


def _upload_name(upload: UploadFile) -> str:
    """The uploaded file's base name, printable and short (it is echoed in messages)."""
    name = Path((upload.filename or "").replace("\\", "/")).name
    name = "".join(c for c in name if c.isprintable())[:80]
    return name or "upload"


def _page() -> str:
    return resources.files("pix2pockets.web").joinpath("index.html").read_text(encoding="utf-8")


@functools.lru_cache(maxsize=1)
def favicon() -> bytes:
    """A 32x32 icon: a black 8-ball on the cloth (ICO bytes, drawn here: nothing to ship or fetch)."""
    from PIL import Image, ImageDraw

    size = 128
    im = Image.new("RGBA", (size, size), (0, 0, 0, 0))
    draw = ImageDraw.Draw(im)
    draw.rounded_rectangle((0, 0, size - 1, size - 1), radius=24, fill=(29, 107, 69, 255))
    draw.ellipse((14, 14, size - 15, size - 15), fill=(18, 18, 18, 255))
    draw.ellipse((40, 34, size - 41, size - 47), fill=(250, 250, 250, 255))
    draw.ellipse((54, 44, size - 55, 62), outline=(18, 18, 18, 255), width=4)
    draw.ellipse((52, 58, size - 53, 80), outline=(18, 18, 18, 255), width=4)
    out = io.BytesIO()
    im.resize((32, 32), Image.Resampling.LANCZOS).save(out, format="ICO", sizes=[(32, 32)])
    return out.getvalue()


def create_app(
    detector: Detector | None = None,
    planner: ShotPlanner | None = None,
    *,
    max_upload_bytes: int = MAX_UPLOAD_BYTES,
    max_pixels: int = MAX_PIXELS,
    example_photo: str | Path | None = None,
    workers: int = 0,
    queue: int | None = None,
    job_timeout: float = 120.0,
    max_wait: float | None = MAX_WAIT_S,
    detector_factory: Callable[[], Detector | None] | None = None,
    pool: WorkerPool | None = None,
) -> FastAPI:
    """The web app.

    Args:
        detector: the detector (default: the bundled ONNX model); it must pickle when ``workers`` >= 1.
        planner: the shot planner (default: :func:`pix2pockets.pipeline.planning.default_planner`).
        max_upload_bytes: largest request body [bytes].
        max_pixels: largest decoded image [pixels] (decompression-bomb guard).
        example_photo: the photo behind ``GET /api/example`` (default: the bundled example).
        workers: worker processes, each with its own models (0: one worker thread in this process).
        queue: photos that may wait for a worker (default 4 per worker); more get 503 with ``Retry-After``.
        job_timeout: longest one photo may take [s].
        max_wait: refuse (503) a photo whose answer is expected later than this [s], from the mean job time and
            the photos ahead (None: only ``queue`` limits).
        detector_factory: makes the detector inside each worker (e.g. from ``--model``), instead of ``detector``.
        pool: a pool already started (``pix2pockets serve`` starts it before serving); the arguments above that
            describe workers are then ignored.

    Raises:
        ValueError: for a non-positive limit, or a negative number of workers or queue.
    """
    if max_upload_bytes < 1 or max_pixels < 1:
        raise ValueError("max_upload_bytes and max_pixels must be positive")
    from pix2pockets.data.examples import example_photo_path

    if pool is None:
        spec = EngineSpec(detector, planner, detector_factory, max_pixels, warm=workers > 0)
        pool = WorkerPool(spec, workers, queue, job_timeout, max_wait)
    board: JobBoard = pool.board
    example = Path(example_photo) if example_photo is not None else Path(example_photo_path())
    page = _page().replace("{{MAX_UPLOAD_BYTES}}", str(max_upload_bytes)).replace("{{VERSION}}", __version__)

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        await run_in_threadpool(pool.start)
        yield
        board.close()
        await run_in_threadpool(pool.stop)

    app = FastAPI(title="pix2pockets", version=__version__, docs_url=None, redoc_url=None, lifespan=lifespan)
    app.state.pool = pool

    @app.exception_handler(WebError)
    async def web_error(request: Request, err: WebError) -> JSONResponse:
        return _error(err.status, err.message)

    @app.exception_handler(BusyError)
    async def busy_error(request: Request, err: BusyError) -> JSONResponse:
        return _error(503, err.message, {"Retry-After": str(err.retry_after)})

    @app.exception_handler(StarletteHTTPException)
    async def http_error(request: Request, err: StarletteHTTPException) -> JSONResponse:
        return _error(err.status_code, str(err.detail))

    @app.exception_handler(RequestValidationError)
    async def validation_error(request: Request, err: RequestValidationError) -> JSONResponse:
        first = err.errors()[0] if err.errors() else {}
        where = ".".join(str(p) for p in first.get("loc", ()))
        return _error(422, f"{where}: {first.get('msg', 'invalid request')}")

    @app.exception_handler(Exception)
    async def unexpected_error(request: Request, err: Exception) -> JSONResponse:
        # the server still logs the traceback; the client gets one line
        return _error(500, f"internal error: {type(err).__name__}")

    @app.get("/", response_class=HTMLResponse)
    async def index() -> HTMLResponse:
        return HTMLResponse(page, headers={"Content-Security-Policy": PAGE_CSP})

    @app.get("/favicon.ico")
    async def icon() -> Response:
        return Response(favicon(), media_type="image/x-icon", headers={"Cache-Control": "max-age=86400"})

    @app.get("/api/health")
    async def health() -> dict:
        return {
            "status": "shutting down" if board.closing else "ok",
            "version": __version__,
            "groups": list(GROUPS),
            "skills": list(SKILLS),
            "tables": list(TABLES),
            "ball_sets": list(BALL_SETS),
            "ball_in_hand": list(IN_HAND),
            "max_upload_bytes": max_upload_bytes,
            "example": example.is_file(),
            **board.stats(),
        }

    @app.get("/api/example")
    async def example_route() -> FileResponse:
        if not example.is_file():
            raise WebError(404, "the bundled example photo is missing from this build")
        return FileResponse(example, filename=example.name)

    async def accept(request: Request, keep: bool) -> Job:
        """Admit, read and check one upload; queue it as a job."""
        length = request.headers.get("content-length", "")
        if length.isdigit() and int(length) > max_upload_bytes:
            raise WebError(413, f"upload is too large (limit {max_upload_bytes / 1e6:.1f} MB)")
        if not pool.started:
            await run_in_threadpool(pool.start)
        with board.admit() as submit:  # BusyError (503) before the body is read
            limited = Request(request.scope, _limited(request.receive, max_upload_bytes))
            async with limited.form(max_files=1, max_fields=8) as form:
                group = form.get("group", "auto")
                if not isinstance(group, str) or group.strip().lower() not in GROUPS:
                    raise WebError(400, f"unknown group {str(group)[:40]!r}; choose {', '.join(GROUPS)}")
                skill = form.get("skill", "pro")
                if not isinstance(skill, str) or skill.strip().lower() not in SKILLS:
                    raise WebError(400, f"unknown skill {str(skill)[:40]!r}; choose {', '.join(SKILLS)}")
                table = form.get("table", "auto")
                if not isinstance(table, str) or table.strip().lower() not in TABLES:
                    raise WebError(400, f"unknown table {str(table)[:40]!r}; choose {', '.join(TABLES)}")
                ball_set = form.get("set", "auto")
                if not isinstance(ball_set, str) or ball_set.strip().lower() not in BALL_SETS:
                    raise WebError(400, f"unknown ball set {str(ball_set)[:40]!r}; choose {', '.join(BALL_SETS)}")
                in_hand = form.get("in_hand", "none")
                if not isinstance(in_hand, str) or in_hand.strip().lower() not in IN_HAND:
                    raise WebError(400, f"unknown ball in hand {str(in_hand)[:40]!r}; choose {', '.join(IN_HAND)}")
                upload = form.get("file")
                if not isinstance(upload, UploadFile):
                    raise WebError(400, "no photo uploaded (send it as the multipart file field 'file')")
                data = await upload.read()
                name = _upload_name(upload)
            _check_header(data, name, max_pixels)
            options = JobOptions(
                group.strip().lower(),
                skill.strip().lower(),
                table.strip().lower(),
                ball_set.strip().lower(),
                in_hand.strip().lower(),
            )
            return submit(data, name, options, keep)

    @app.post("/api/suggest")
    async def suggest(request: Request) -> JSONResponse:
        job = await accept(request, keep=False)
        await board.wait_async(job)
        headers = {"Retry-After": str(board.retry_after())} if job.status == 503 else None
        return JSONResponse(job.doc, status_code=job.status or 500, headers=headers)

    @app.post("/api/jobs", status_code=202)
    async def submit_job(request: Request) -> JSONResponse:
        job = await accept(request, keep=True)
        doc = board.view(job)
        doc["url"] = f"api/jobs/{job.id}"
        return JSONResponse(doc, status_code=202)

    @app.get("/api/jobs/{job_id}")
    async def follow_job(job_id: str, since: int = -1) -> JSONResponse:
        job = board.get(job_id)
        if job is None:
            raise WebError(404, "no such job (finished jobs are kept a few minutes)")
        if since >= 0:
            await board.wait_async(job, since, LONG_POLL_S)
        return JSONResponse(board.view(job))

    return app


def _check_header(data: bytes, name: str, max_pixels: int) -> None:
    """Refuse what is plainly not a usable image from its header (the worker decodes the rest)."""
    from pix2pockets.vision.image_io import probe_image

    try:
        probe_image(data, name, max_pixels)
    except ValueError as err:
        raise WebError(400, str(err)) from None
