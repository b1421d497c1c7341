"""The FastAPI app behind ``pix2pockets serve``: one page and a small JSON API.

Routes:
    ``GET /``: the page (one self-contained HTML file: inline CSS and JS, nothing fetched from elsewhere).
    ``POST /api/suggest``: multipart ``file`` (the photo) and ``group`` (``auto``, ``solids`` or
    ``stripes``); answers the JSON of ``pix2pockets suggest --json`` plus ``picture_png_base64``
    (the result picture).
    ``GET /api/example``: the bundled example photo.
    ``GET /api/health``: ``{"status": "ok", ...}``.

Every error is JSON ``{"error": "<one line>"}``: 400 bad upload or group, 413 upload too large,
422 a readable photo where the table, the cue ball or the group's balls are not found, 503 no detector or
planner in this build. The photo goes through the same functions as the CLI
(:func:`~pix2pockets.pipeline.photo.load_image`, :func:`~pix2pockets.pipeline.photo.suggest`,
:func:`~pix2pockets.pipeline.draw.render_result`).

Example:
    >>> from pix2pockets.web.app import create_app
    >>> app = create_app()  # doctest: +SKIP
    >>> import uvicorn; uvicorn.run(app)  # doctest: +SKIP
"""

from __future__ import annotations

import base64
import logging
import threading
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import UploadFile
from starlette.exceptions import HTTPException as StarletteHTTPException

from pix2pockets import __version__
from pix2pockets.pipeline.planning import ShotPlanner
from pix2pockets.state import Group
from pix2pockets.vision.detect.base import Detector
from pix2pockets.vision.image_io import MAX_PIXELS

MAX_UPLOAD_BYTES = 20_000_000
"""Largest request body accepted [bytes]; larger uploads get a 413 before they are read in full."""
MAX_PICTURE_SIDE = 2400
"""Longest side of the result picture sent back [px] (bigger pictures are scaled down)."""
GROUPS = ("auto", *(g.value for g in Group))
PAGE_CSP = (
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
    "img-src 'self' data: blob:; connect-src 'self'; form-action 'self'; base-uri 'none'"
)

log = logging.getLogger(__name__)


class WebError(Exception):
    """An error answered as ``{"error": message}`` with an HTTP status."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


def _error(status: int, message: str) -> JSONResponse:
    line = " ".join(str(message).split()) or "error"
    return JSONResponse({"error": line if len(line) <= 500 else line[:497] + "..."}, status_code=status)


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


def _png(rgb: np.ndarray, max_side: int) -> bytes:
    import cv2

    h, w = rgb.shape[:2]
    if max(h, w) > max_side:
        s = max_side / max(h, w)
        rgb = cv2.resize(rgb, (round(w * s), round(h * s)), interpolation=cv2.INTER_AREA)
    from pix2pockets.pipeline.draw import encode_picture

    return encode_picture(rgb, ".png", fast=True)


def _page() -> str:
    return resources.files("pix2pockets.web").joinpath("index.html").read_text(encoding="utf-8")


def create_app(
    detector: Detector | None = None,
    planner: ShotPlanner | None = None,
    *,
    max_upload_bytes: int = MAX_UPLOAD_BYTES,
    max_pixels: int = MAX_PIXELS,
    example_photo: str | Path | None = None,
) -> FastAPI:
    """The web app.

    Args:
        detector: the detector (default: the bundled ONNX model, loaded at the first request).
        planner: the shot planner (default: :func:`pix2pockets.pipeline.planning.default_planner`).
        max_upload_bytes: largest request body [bytes].
        max_pixels: largest decoded image [pixels] (decompression-bomb guard).
        example_photo: the photo behind ``GET /api/example`` (default: the bundled example).

    Raises:
        ValueError: for a non-positive limit.
    """
    if max_upload_bytes < 1 or max_pixels < 1:
        raise ValueError("max_upload_bytes and max_pixels must be positive")
    from pix2pockets.data.examples import example_photo_path

    example = Path(example_photo) if example_photo is not None else Path(example_photo_path())
    page = _page().replace("{{MAX_UPLOAD_BYTES}}", str(max_upload_bytes)).replace("{{VERSION}}", __version__)
    slots: dict[str, Any] = {"detector": detector, "planner": planner}
    busy = threading.Lock()  # one photo at a time: bounds memory (decoded photos) and shares the cores

    def resolve(name: str, factory: Callable[[], Any]) -> Any:
        if slots[name] is None:
            try:
                slots[name] = factory()
            except (ValueError, OSError, ImportError) as err:
                raise WebError(503, f"no {name} available: {err}") from None
        return slots[name]

    def run_pipeline(data: bytes, name: str, group: str) -> dict:
        from pix2pockets.pipeline import photo
        from pix2pockets.pipeline.draw import render_result
        from pix2pockets.pipeline.planning import default_planner
        from pix2pockets.vision.image_io import decode_image_rgb

        with busy:
            try:
                rgb = photo.load_image(decode_image_rgb(data, name, max_pixels))
            except ValueError as err:
                raise WebError(400, str(err)) from None
            det = resolve("detector", photo.default_detector)
            plan = resolve("planner", default_planner)
            try:
                result = photo.suggest(rgb, group=group, detector=det, planner=plan)
            except ValueError as err:
                raise WebError(422, str(err)) from None
            picture = _png(render_result(rgb, result), MAX_PICTURE_SIDE)
        doc = result.to_dict()
        doc["image"]["filename"] = name
        doc["timings_s"] = {k: round(float(v), 4) for k, v in result.timings.items()}
        doc["picture_png_base64"] = base64.b64encode(picture).decode("ascii")
        return doc

    app = FastAPI(title="pix2pockets", version=__version__, docs_url=None, redoc_url=None)

    @app.exception_handler(WebError)
    async def web_error(request: Request, err: WebError) -> JSONResponse:
        return _error(err.status, err.message)

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

    @app.get("/api/health")
    async def health() -> dict:
        return {
            "status": "ok",
            "version": __version__,
            "groups": list(GROUPS),
            "max_upload_bytes": max_upload_bytes,
            "example": example.is_file(),
        }

    @app.get("/api/example")
    async def example_photo() -> FileResponse:
        if not example.is_file():
            raise WebError(404, "the bundled example photo is missing from this build")
        return FileResponse(example, filename=example.name)

    @app.post("/api/suggest")
    async def suggest(request: Request) -> JSONResponse:
        length = request.headers.get("content-length", "")
        if length.isdigit() and int(length) > max_upload_bytes:
            raise WebError(413, f"upload is too large (limit {max_upload_bytes / 1e6:.1f} MB)")
        limited = Request(request.scope, _limited(request.receive, max_upload_bytes))
        async with limited.form(max_files=1, max_fields=8) as form:
            group = form.get("group", "auto")
            if not isinstance(group, str) or group.strip().lower() not in GROUPS:
                raise WebError(400, f"unknown group {str(group)[:40]!r}; choose {', '.join(GROUPS)}")
            upload = form.get("file")
            if not isinstance(upload, UploadFile):
                raise WebError(400, "no photo uploaded (send it as the multipart file field 'file')")
            data = await upload.read()
            name = _upload_name(upload)
        try:
            doc = await run_in_threadpool(run_pipeline, data, name, group.strip().lower())
        except WebError:
            raise
        except Exception as err:  # a bug, not bad input: log it, answer one line
            log.exception("pipeline failed on %s", name)
            raise WebError(500, f"internal error: {type(err).__name__}: {err}") from None
        return JSONResponse(doc)

    return app
