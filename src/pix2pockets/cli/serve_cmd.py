"""``pix2pockets serve``: the web page (upload a photo, see the best shot) on a local port."""

from __future__ import annotations

import argparse
import importlib.util

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
    parser = sub.add_parser(
        "serve",
        help="run the web page: upload a photo, get the best shot",
        description="Serve the pix2pockets web page and its JSON API (POST /api/suggest) with uvicorn. "
        "Needs the 'web' extra: pip install 'pix2pockets[web]'.",
    )
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    parser.add_argument("--port", type=int, default=8000, help="port to listen on (default: 8000)")
    add_model_options(parser)
    parser.add_argument("--max-upload-mb", type=float, default=20.0, help="largest upload [MB] (default: 20)")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if not 0 <= args.port <= 65535:
        raise ValueError(f"--port must be in 0..65535, got {args.port}")
    if not args.max_upload_mb > 0:
        raise ValueError(f"--max-upload-mb must be positive, got {args.max_upload_mb}")
    missing = missing_web_packages()
    if missing:
        raise ValueError(f"the web page needs {', '.join(missing)}: pip install 'pix2pockets[web]'")
    import uvicorn

    from pix2pockets.pipeline.photo import default_detector
    from pix2pockets.pipeline.planning import default_planner
    from pix2pockets.web.app import create_app

    # load the model and the planner now: a broken build fails here with one line, not on the first upload
    detector = chosen_detector(args) or default_detector()
    app = create_app(detector, default_planner(), max_upload_bytes=int(args.max_upload_mb * 1e6))
    print(f"pix2pockets web page: http://{args.host}:{args.port}/ (Ctrl+C to stop)", flush=True)
    uvicorn.run(app, host=args.host, port=args.port, log_level="info")
    return 0
