"""``pix2pockets warmup``: compile the physics engine and load the models now, not at the first photo.

Also the first-run notice the other commands share: :func:`compile_in_background` says on one line what the wait
is and compiles the physics kernels in a thread while the photo is read and its balls found; :class:`AfterCompile`
holds a planner back until the compile is done (so the planner loads the kernels instead of compiling them twice).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import threading
import time
from pathlib import Path
from typing import Any, TextIO

from pix2pockets.cli.detector_options import add_model_options, chosen_detector

FIRST_RUN_NOTICE = (
    "pix2pockets: compiling the physics engine, once after an install (about 10 s; later runs start at once)..."
)


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser(
        "warmup",
        help="compile the physics engine and load the models now (the first run after an install)",
        description="Compile the physics engine's numba kernels into their on-disk cache and run the bundled example "
        "photo through the pipeline, so that the next 'suggest' or 'serve' starts at once. Safe to run again: a "
        "compiled engine is loaded from the cache.",
    )
    add_model_options(parser)
    parser.add_argument("--no-example", action="store_true", help="only compile the physics engine")
    parser.add_argument("--synth", action="store_true", help="also compile the renderer of 'pix2pockets synth'")
    parser.set_defaults(func=run)


def compile_in_background(stream: TextIO | None = None) -> threading.Thread | None:
    """When the physics kernels are not compiled yet: print :data:`FIRST_RUN_NOTICE` and compile them in a thread.

    Returns:
        The compiling thread, or None when the kernels are in the cache (nothing is printed).
    """
    from pix2pockets.physics.event.warm import compile_kernels, kernels_cached

    if kernels_cached():
        return None
    print(FIRST_RUN_NOTICE, file=stream or sys.stderr, flush=True)

    def work() -> None:
        with contextlib.suppress(Exception):  # the planner compiles what is missing at its first shot
            compile_kernels()

    thread = threading.Thread(target=work, name="pix2pockets-compile", daemon=True)
    thread.start()
    return thread


class AfterCompile:
    """A planner that waits for the background compile before its first plan (same answers as ``planner``)."""

    def __init__(self, planner: Any, compiling: threading.Thread) -> None:
        self.planner = planner
        self.compiling = compiling

    def suggest(self, *args: Any, **kwargs: Any) -> list:
        """``planner.suggest`` once the kernels are compiled."""
        self.compiling.join()
        return self.planner.suggest(*args, **kwargs)


def _cache_folder() -> str:
    from pix2pockets.physics.event._engine import run_shots

    try:
        return str(run_shots._cache.cache_path)
    except AttributeError:
        return "numba's cache"


def run(args: argparse.Namespace) -> int:
    from pix2pockets.physics.event.warm import compile_kernels, kernels_cached

    cached = kernels_cached()
    if not cached:
        print("physics engine: compiling (once after an install)...", flush=True)
    seconds = compile_kernels()
    verb = "loaded from the cache" if cached else "compiled"
    print(f"physics engine: {verb} in {seconds:.1f} s ({_cache_folder()})", flush=True)
    if not args.no_example:
        from pix2pockets.data.examples import example_photo_path
        from pix2pockets.pipeline.photo import default_detector, suggest

        t = time.perf_counter()
        detector = chosen_detector(args) or default_detector()
        photo = example_photo_path()
        if Path(photo).is_file():
            result = suggest(photo, detector=detector)
            print(f"models and pipeline: the bundled example in {time.perf_counter() - t:.1f} s ({result.text})")
        else:
            print(f"models: loaded in {time.perf_counter() - t:.1f} s (no bundled example photo in this build)")
    if args.synth:
        from pix2pockets.synth import render_sample

        t = time.perf_counter()
        render_sample(0, size=(160, 90))
        print(f"renderer: ready in {time.perf_counter() - t:.1f} s")
    return 0
