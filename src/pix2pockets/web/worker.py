"""What one worker does: hold the loaded models, warm them up, and turn an upload into the answer's JSON.

The same :class:`Engine` runs inside a worker process (:func:`serve_forever`, started by
:class:`~pix2pockets.web.pool.WorkerPool`) or in a thread of the app's own process (``workers=0``, tests). A job
goes through the same functions as ``pix2pockets suggest`` (:func:`~pix2pockets.pipeline.photo.load_image`,
:func:`~pix2pockets.pipeline.photo.suggest`, :func:`~pix2pockets.pipeline.draw.render_result`) and reports each
stage (:data:`~pix2pockets.web.jobs.STAGES`) as it starts.
"""

from __future__ import annotations

import base64
import logging
import os
import signal
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pix2pockets.geometry.table import TABLE_PRESETS, table_preset

MAX_PICTURE_SIDE = 2400
"""Longest side of the result picture sent back [px] (bigger pictures are scaled down)."""

log = logging.getLogger("pix2pockets.web")

Report = Callable[[str], None]


class WebError(Exception):
    """An error answered as ``{"error": message}`` with an HTTP status."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


def one_line(message: object, limit: int = 500) -> str:
    """``message`` on one line of at most ``limit`` characters."""
    line = " ".join(str(message).split()) or "error"
    return line if len(line) <= limit else line[: limit - 3] + "..."


@dataclass(frozen=True)
class EngineSpec:
    """What a worker loads: a detector and a planner (None: the defaults), or factories that make them.

    Everything here crosses into worker processes, so it must pickle: the stand-ins of :mod:`pix2pockets.testing`
    do, as do module-level functions and ``functools.partial`` of them.
    """

    detector: Any = None
    planner: Any = None
    detector_factory: Callable[[], Any] | None = None
    max_pixels: int = 64_000_000
    warm: bool = True


class _Reporting:
    """A detector or planner that reports a stage around one of its methods; everything else passes through."""

    def __init__(
        self, inner: Any, method: str, before: Callable[[], None] | None = None, after: Callable[[], None] | None = None
    ) -> None:
        self._inner, self._method, self._before, self._after = inner, method, before, after

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self._inner, name)
        if name != self._method:
            return attr

        def called(*args: Any, **kwargs: Any) -> Any:
            if self._before is not None:
                self._before()
            out = attr(*args, **kwargs)
            if self._after is not None:
                self._after()
            return out

        return called


class _Once:
    """Report ``stage`` the first time it is called."""

    def __init__(self, report: Report, stage: str) -> None:
        self.report, self.stage, self.done = report, stage, False

    def __call__(self) -> None:
        if not self.done:
            self.done = True
            self.report(self.stage)


def picture_parts(photo_shape: tuple[int, ...], picture_shape: tuple[int, ...], scale: float) -> dict | None:
    """Where the photo, the diagram and the caption lie in the result picture, ``[x, y, w, h]`` [px] each.

    The picture of :func:`~pix2pockets.pipeline.draw.render_result` is the photo (``photo_shape``, as shown there) with
    the diagram beside it (as tall as the photo) and a caption band below both; the page cuts it into these parts to
    stack them on a narrow screen. None when the picture is not laid out so.
    """
    ph, pw = photo_shape[:2]
    H, W = picture_shape[:2]
    if not (0 < pw < W and 0 < ph <= H):
        return None

    def box(x: int, y: int, w: int, h: int) -> list[int]:
        return [round(x * scale), round(y * scale), max(1, round(w * scale)), max(1, round(h * scale))]

    return {"photo": box(0, 0, pw, ph), "diagram": box(pw, 0, W - pw, ph), "caption": box(0, ph, W, H - ph)}


SKILLS = ("pro", "club", "beginner")
"""Skill levels the page offers (:data:`pix2pockets.planner.noise.SKILLS`); ``pro`` is the default."""


TABLES = ("auto", *TABLE_PRESETS)
"""Table sizes the page offers; ``auto`` measures the size from the balls when the table has no diamonds."""


@dataclass(frozen=True, slots=True)
class JobOptions:
    """What the player asked for with a photo: their group, their skill level, the table's size, the ball set and
    whether the cue ball is in hand (``none``, ``table`` or ``baulk``)."""

    group: str = "auto"
    skill: str = "pro"
    table: str = "auto"
    ball_set: str = "auto"
    ball_in_hand: str = "none"

    @classmethod
    def of(cls, options: JobOptions | str) -> JobOptions:
        """The options themselves, or the options of a bare group name."""
        return options if isinstance(options, JobOptions) else cls(group=options)


class Engine:
    """One worker's models and its way from an upload to the answer."""

    def __init__(self, spec: EngineSpec) -> None:
        self.spec = spec
        self.detector = spec.detector
        self.planner = spec.planner
        self.skill_planners: dict[str, Any] = {}

    def planner_for(self, skill: str) -> Any:
        """The planner for a skill level: the given planner for every level, else the default one per level."""
        if skill == "pro" or self.spec.planner is not None:
            return self.planner
        if skill not in self.skill_planners:
            from pix2pockets.pipeline.planning import default_planner

            self.skill_planners[skill] = default_planner(skill=skill)
        return self.skill_planners[skill]

    def load(self) -> None:
        """Load the detector and the planner (once).

        Raises:
            WebError: 503 when this build has no detector model or no planner.
        """
        from pix2pockets.pipeline import photo
        from pix2pockets.pipeline.planning import default_planner

        try:
            if self.detector is None and self.spec.detector_factory is not None:
                self.detector = self.spec.detector_factory()
            if self.detector is None:
                self.detector = photo.default_detector()
        except (ValueError, OSError, ImportError) as err:
            raise WebError(503, f"no detector available: {err}") from None
        try:
            if self.planner is None:
                self.planner = default_planner()
        except (ValueError, ImportError) as err:
            raise WebError(503, f"no planner available: {err}") from None

    def warm_up(self) -> float:
        """Compile (or load) the physics kernels and run the bundled example once, so the first upload is quick.

        Returns:
            The seconds it took.
        """
        from pix2pockets.data.examples import example_photo_path
        from pix2pockets.physics.event.warm import compile_kernels

        t = time.perf_counter()
        compile_kernels()
        example = Path(example_photo_path())
        if example.is_file():
            try:
                self.run(example.read_bytes(), example.name, "auto", lambda stage: None)
            except Exception as err:  # a detector that does not know the example; the upload will tell
                log.info("warm-up on the example photo: %s", one_line(err))
        return time.perf_counter() - t

    def run(self, data: bytes, name: str, options: JobOptions | str, report: Report) -> tuple[int, dict]:
        """The answer to one upload: ``(200, the suggest JSON + picture)`` or ``(4xx/503, {"error": ...})``.

        Raises:
            Exception: only for bugs (the caller answers 500).
        """
        try:
            return 200, self._run(data, name, JobOptions.of(options), report)
        except WebError as err:
            return err.status, {"error": one_line(err.message)}

    def _run(self, data: bytes, name: str, options: JobOptions, report: Report) -> dict:
        from pix2pockets.pipeline import photo
        from pix2pockets.pipeline.draw import encode_picture, render_result, shown_photo_size
        from pix2pockets.vision.image_io import decode_image_rgb

        report("load")
        try:
            rgb = photo.load_image(decode_image_rgb(data, name, self.spec.max_pixels))
        except ValueError as err:
            raise WebError(400, str(err)) from None
        self.load()
        report("detect")
        detector = _Reporting(self.detector, "detect", after=_Once(report, "fit"))
        planner = _Reporting(self.planner_for(options.skill), "suggest", before=_Once(report, "plan"))
        spec = None if options.table == "auto" else table_preset(options.table)
        try:
            result = photo.suggest(
                rgb,
                group=options.group,
                detector=detector,
                planner=planner,
                spec=spec,
                ball_set=options.ball_set,
                ball_in_hand=options.ball_in_hand,
            )
        except ValueError as err:
            raise WebError(422, str(err)) from None
        report("draw")
        picture = render_result(rgb, result)
        scale = min(1.0, MAX_PICTURE_SIDE / max(picture.shape[:2]))
        shown = shown_photo_size(rgb.shape[1], rgb.shape[0])
        parts = picture_parts((shown[1], shown[0]), picture.shape, scale)
        if scale < 1.0:
            import cv2

            size = (round(picture.shape[1] * scale), round(picture.shape[0] * scale))
            picture = cv2.resize(picture, size, interpolation=cv2.INTER_AREA)
        png = encode_picture(picture, ".png", fast=True)
        doc = result.to_dict()
        doc["image"]["filename"] = name
        doc["timings_s"] = {k: round(float(v), 4) for k, v in result.timings.items()}
        doc["picture_png_base64"] = base64.b64encode(png).decode("ascii")
        doc["picture_parts"] = parts
        return doc


def quiet_threads() -> None:
    """One thread per numeric library in a worker process: the pool already gives each core its worker."""
    import cv2

    cv2.setNumThreads(1)


def _release_memory() -> Callable[[], None]:
    """A function that hands freed heap memory back to the system (glibc's ``malloc_trim``; elsewhere nothing)."""
    try:
        import ctypes

        trim = ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return lambda: None
    return lambda: trim(0) and None


def serve_forever(conn: Any, spec: EngineSpec) -> None:
    """A worker process: load and warm up, then answer jobs from ``conn`` until told to stop or the pipe closes.

    Messages in: ``("job", data, name, group)``, ``("stop",)``. Out: ``("ready", pid, warm_s)`` or
    ``("failed", status, message)`` once, then per job ``("stage", name)``... and ``("done", status, doc)``.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C reaches the whole group: the server decides, not us
    logging.basicConfig(level=logging.INFO, format="%(levelname)s:     worker %(process)d: %(message)s")
    quiet_threads()
    engine = Engine(spec)
    try:
        engine.load()
        warm = engine.warm_up() if spec.warm else 0.0
    except WebError as err:
        conn.send(("failed", err.status, one_line(err.message)))
        return
    except Exception as err:
        log.exception("worker failed to start")
        conn.send(("failed", 500, one_line(f"worker failed to start: {type(err).__name__}: {err}")))
        return
    release = _release_memory()
    release()
    conn.send(("ready", os.getpid(), warm))
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):  # the server is gone
            return
        if message[0] != "job":
            return
        _, data, name, group = message
        try:
            status, doc = engine.run(data, name, group, lambda stage: conn.send(("stage", stage)))
        except Exception as err:  # a bug: the server log gets the traceback, the client one line
            log.exception("pipeline failed on %s", name)
            status, doc = 500, {"error": one_line(f"internal error: {type(err).__name__}: {err}")}
        del data
        conn.send(("done", status, doc))
        del doc
        release()  # the decoded photo and the pictures are freed: keep the worker's resident memory flat
