"""Web round trip: POST /api/suggest on the bundled example photo, in-process (FastAPI TestClient).

The app runs with ``workers=0`` (its job board and one worker thread in this process), so the numbers are the
pipeline plus the web layer, without worker processes; ``benchmarks/web_load.py`` measures the server under load.

Reports the request's wall time, the pipeline's own time (``timings_s.total``, as in ``benchmarks/pipeline.py``)
and the rest (multipart parsing, decoding, the result picture, PNG and base64 encoding, JSON): the cost of
the web layer. Uses the bundled detector and the default planner when this build has them, otherwise the
stand-ins of ``pix2pockets.testing`` (exact labels of the example photo / a nearest-pocket planner), and says so.

Usage:
    PYTHONPATH=src:. python benchmarks/web.py --json OUT.json [--runs 5]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--group", default="auto")
    parser.add_argument("--json", help="write results here")
    args = parser.parse_args(argv)

    from fastapi.testclient import TestClient

    from pix2pockets.data.examples import example_photo_path
    from pix2pockets.pipeline import photo, planning
    from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
    from pix2pockets.web.app import create_app

    path = Path(example_photo_path())
    data = path.read_bytes()
    notes = []
    try:
        detector, det_name = photo.default_detector(), "onnx"
    except ValueError as err:
        labels = json.loads(path.with_name(path.stem + ".labels.json").read_text())
        detector, det_name = LabelsDetector(labels), "labels stand-in"
        notes.append(f"detector missing ({err}); exact labels used")
    try:
        planner = planning.default_planner()
        plan_name = type(planner).__name__
    except (ValueError, ImportError) as err:
        planner, plan_name = NearestPocketPlanner(), "nearest-pocket stand-in"
        notes.append(f"planner missing ({err}); stand-in used")

    client = TestClient(create_app(detector, planner))
    files = {"file": (path.name, data, "image/jpeg")}
    wall, pipe, sizes = [], [], []
    for _ in range(args.runs + 1):  # the first run warms up (numba, onnxruntime)
        t = time.perf_counter()
        r = client.post("/api/suggest", files=files, data={"group": args.group})
        dt = time.perf_counter() - t
        if r.status_code != 200:
            print(f"error {r.status_code}: {r.json()['error']}", file=sys.stderr)
            return 1
        doc = r.json()
        wall.append(dt)
        pipe.append(doc["timings_s"]["total"])
        sizes.append(len(r.content))
    wall, pipe = wall[1:], pipe[1:]
    out = {
        "image": f"{path.name} ({doc['image']['width']}x{doc['image']['height']}, {len(data)} bytes)",
        "detector": det_name,
        "planner": plan_name,
        "runs": args.runs,
        "median_request_s": statistics.median(wall),
        "median_pipeline_s": statistics.median(pipe),
        "median_web_overhead_s": statistics.median(w - p for w, p in zip(wall, pipe, strict=True)),
        "response_bytes": sizes[-1],
        "notes": notes,
    }
    print(f"POST /api/suggest, {out['image']}; detector {det_name}, planner {plan_name}; {args.runs} runs")
    print(f"{'part':<28} {'median s':>9}")
    print(f"{'request (wall)':<28} {out['median_request_s']:9.3f}")
    print(f"{'pipeline (timings_s.total)':<28} {out['median_pipeline_s']:9.3f}")
    print(f"{'web layer (the rest)':<28} {out['median_web_overhead_s']:9.3f}")
    print(f"response: {out['response_bytes'] / 1e6:.2f} MB (JSON with the base64 PNG picture)")
    for n in notes:
        print("note:", n)
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
