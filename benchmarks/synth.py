"""Synthetic renderer throughput: images per second at a given size on one core.

Usage:
    PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/synth.py --n 40 --size 960x540 --json out.json

Reports wall-clock and process CPU time per image (the machine is shared, so CPU time is the fairer
single-core number), split by stage, after a warm-up render that compiles/loads the numba kernels.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")


from pix2pockets.synth import renderer as rnd
from pix2pockets.synth.labels import build_labels


def run(n: int, size: tuple[int, int], seed: int) -> dict:
    rnd.render(seed + 10_000, size)  # warm-up: numba cache load, texture caches
    stages: dict[str, float] = {}
    wall0, cpu0 = time.perf_counter(), time.process_time()
    for i in range(n):
        t = time.process_time()

        def lap(name: str, t0: float) -> float:
            now = time.process_time()
            stages[name] = stages.get(name, 0.0) + now - t0
            return now

        r_layout, r_scene, r_cam, r_fx = rnd._streams((seed, i), 4)
        spec = rnd._spec(r_layout)
        layout, _ = rnd.sample_layout(r_layout, spec)
        scene = rnd.sample_scene(r_scene, layout)
        cam, kind = rnd.sample_camera(r_cam, spec, size, None, scene.floor_z, scene.rail_width)
        t = lap("scene+camera", t)
        raw, ids, depth, sil = rnd.trace(scene, cam)
        t = lap("ray cast", t)
        exposure = rnd._exposure(scene, raw, ids)
        r_plain = copy.deepcopy(r_fx)
        image, occ, _, _ = rnd._photograph(raw, depth, scene, cam, kind, exposure, r_fx, 1.0)
        t = lap("photo (tone map, occluders, camera pipeline)", t)
        signal = rnd.diamond_signal(image, scene, cam, kind, raw, ids, depth, exposure, r_plain, 1.0)
        t = lap("diamond visibility (photo without diamonds)", t)
        build_labels(scene, cam, ids, occ, sil, diamond_signal=signal)
        lap("labels", t)
    wall = time.perf_counter() - wall0
    cpu = time.process_time() - cpu0
    # the full public path, for the headline number
    w1, c1 = time.perf_counter(), time.process_time()
    for i in range(n):
        rnd.render_sample((seed + 1, i), size)
    full_wall, full_cpu = time.perf_counter() - w1, time.process_time() - c1
    return {
        "n": n,
        "size": list(size),
        "images_per_s_cpu": round(n / full_cpu, 2),
        "images_per_s_wall": round(n / full_wall, 2),
        "ms_per_image_cpu": round(1000 * full_cpu / n, 1),
        "stages_ms_cpu": {k: round(1000 * v / n, 1) for k, v in stages.items()},
        "staged_total_ms_cpu": round(1000 * cpu / n, 1),
        "staged_total_ms_wall": round(1000 * wall / n, 1),
        "load_average": [round(float(v), 2) for v in os.getloadavg()],
        "python": platform.python_version(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=40)
    parser.add_argument("--size", default="960x540")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args()
    size = rnd.parse_size(args.size)
    res = run(args.n, size, args.seed)
    print(f"synth renderer, {args.n} images at {size[0]}x{size[1]}, one core")
    print(f"{'metric':<28} value")
    print(f"{'images/s (CPU time)':<28} {res['images_per_s_cpu']}")
    print(f"{'images/s (wall, shared box)':<28} {res['images_per_s_wall']}")
    print(f"{'ms/image (CPU)':<28} {res['ms_per_image_cpu']}")
    for k, v in res["stages_ms_cpu"].items():
        print(f"  {k:<26} {v} ms")
    print(f"{'load average':<28} {res['load_average']}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(res, f, indent=1)


if __name__ == "__main__":
    main()
