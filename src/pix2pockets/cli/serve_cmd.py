"""``pix2pockets serve``: the web page (upload a photo, see the best shot) on a local port.

The workers start, load their models and warm up before the port opens, so a build without a model fails at
once with one line and the first upload is as quick as the rest. Ctrl+C (or SIGTERM) stops taking photos,
answers the queued ones 503 and lets the running ones finish.
"""

from __future__ import annotations

import argparse
import functools
import importlib.util
from typing import Any

from pix2pockets.cli.detector_options import add_model_options, chosen_detector

# (import name(s), package on PyPI) of the ``web`` extra
WEB_PACKAGES = (
    (("fastapi",), "fastapi"),
    (("uvicorn",), "uvicorn"),
    (("python_multipart", "multipart"), "python-multipart"),
)


def missing_web_packages() -> list[str]:
    """PyPI names of the ``web`` extra's packages that cannot be imported."""
    return [pkg for mods, pkg in WEB_PACKAGES if not any(importlib.util.find_spec(m) for m in mods)]


def register(sub: argparse._SubParsersAction) -> None:
    from pix2pockets.web.pool import default_workers

    cores = default_workers()
    parser = sub.add_parser(
        "serve",
        help="run the web page: upload a photo, get the best shot",
        description="Serve the pix2pockets web page and its JSON API (POST /api/jobs, POST /api/suggest) with "
        "uvicorn and a pool of worker processes. Needs the 'web' extra: pip install 'pix2pockets[web]'.",
    )
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    parser.add_argument("--port", type=int, default=8000, help="port to listen on (default: 8000)")
    parser.add_argument(
        "--workers",
        type=int,
        default=cores,
        help=f"worker processes, each with its own models (default: one per core, here {cores}; 0: one photo "
        "at a time in the server's own process)",
    )
    parser.add_argument(
        "--queue",
        type=int,
        default=None,
        help="photos that may wait for a worker; more are refused with 503 and Retry-After (default: 4 per worker)",
    )
    parser.add_argument(
        "--max-wait",
        type=float,
        default=5.0,
        help="refuse (503) a photo whose answer is expected later than this [s], from the mean time per photo and "
        "the photos ahead (default 5; 0: only --queue limits)",
    )
    parser.add_argument("--job-timeout", type=float, default=120.0, help="longest one photo may take [s] (default 120)")
    add_model_options(parser)
    parser.add_argument("--max-upload-mb", type=float, default=20.0, help="largest upload [MB] (default: 20)")
    parser.set_defaults(func=run)


def _check(args: argparse.Namespace) -> None:
    if not 0 <= args.port <= 65535:
        raise ValueError(f"--port must be in 0..65535, got {args.port}")
    if not args.max_upload_mb > 0:
        raise ValueError(f"--max-upload-mb must be positive, got {args.max_upload_mb}")
    if args.workers < 0:
        raise ValueError(f"--workers must be 0 or more, got {args.workers}")
    if args.queue is not None and args.queue < 0:
        raise ValueError(f"--queue must be 0 or more, got {args.queue}")
    if args.max_wait < 0:
        raise ValueError(f"--max-wait must be 0 or more, got {args.max_wait}")
    if not args.job_timeout > 0:
        raise ValueError(f"--job-timeout must be positive, got {args.job_timeout}")


def _detector_from(args: argparse.Namespace) -> Any:
    """The detector the model options ask for (None: the default), made inside each worker."""
    return chosen_detector(args)


def run(args: argparse.Namespace) -> int:
    _check(args)
    missing = missing_web_packages()
    if missing:
        raise ValueError(f"the web page needs {', '.join(missing)}: pip install 'pix2pockets[web]'")
    import uvicorn

    from pix2pockets.web.app import create_app
    from pix2pockets.web.pool import WorkerPool
    from pix2pockets.web.worker import EngineSpec, WebError

    options = argparse.Namespace(**{k: v for k, v in vars(args).items() if k != "func"})
    spec = EngineSpec(detector_factory=functools.partial(_detector_from, options), warm=True)
    pool = WorkerPool(spec, args.workers, args.queue, args.job_timeout, args.max_wait or None)
    what = f"{args.workers} worker process{'es' if args.workers != 1 else ''}" if args.workers else "one worker thread"
    print(f"pix2pockets web page: starting {what} (models load, physics warms up)...", flush=True)
    try:
        pool.start()
    except WebError as err:
        raise ValueError(err.message) from None
    app = create_app(pool=pool, max_upload_bytes=int(args.max_upload_mb * 1e6))
    config = uvicorn.Config(app, host=args.host, port=args.port, log_level="info", timeout_graceful_shutdown=30)
    server = _make_server(config, pool)
    print(
        f"pix2pockets web page: http://{args.host}:{args.port}/ ({what} ready in {pool.start_s:.1f} s, "
        f"queue {pool.board.queue_limit}; Ctrl+C to stop)",
        flush=True,
    )
    try:
        server.run()
    except KeyboardInterrupt:  # uvicorn raises Ctrl+C again once it has shut down cleanly
        pass
    finally:
        pool.stop()
    print("pix2pockets web page: stopped", flush=True)
    return 0


def _make_server(config: Any, pool: Any) -> Any:
    """A uvicorn server that, on Ctrl+C or SIGTERM, first answers queued photos 503, then shuts down."""
    import uvicorn

    class Server(uvicorn.Server):
        def handle_exit(self, sig: int, frame: Any) -> None:
            pool.board.close()
            super().handle_exit(sig, frame)

    return Server(config)
