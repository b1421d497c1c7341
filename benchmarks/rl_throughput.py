"""Whole-loop training throughput of ``rl train`` (steps/s) for a set of ``--n-envs`` / thread settings.

Each setting trains a fresh run with :func:`pix2pockets.rl.train.train` (the CLI's path: VecEnv, monitor,
checkpoints) and reads its steps/s from the run's ``stints.jsonl``. ``n_envs`` 1 with one torch thread is
the single-process default of earlier releases.

Usage:
    PYTHONPATH=src python benchmarks/rl_throughput.py --algo ppo --env one --steps 4096 --n-envs 1 2 \
        --json rl_throughput.json
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

from pix2pockets.rl.algos import ALGOS, torch_threads
from pix2pockets.rl.train import STINTS, TrainConfig, train


def measure(algo: str, env: str, steps: int, n_envs: int, threads: int | None, device: str, seed: int = 0) -> dict:
    """Train one fresh run and return its setting with steps/s."""
    with tempfile.TemporaryDirectory() as tmp:
        config = TrainConfig(
            algo, env, steps=steps, seed=seed, out=str(Path(tmp) / "run"), progress=False, checkpoint_every=10**9,
            n_envs=n_envs, threads=threads, device=device,
        )  # fmt: skip
        train(config)
        stint = json.loads((Path(tmp) / "run" / STINTS).read_text().splitlines()[-1])
    return {
        "algo": algo,
        "env": env,
        "n_envs": n_envs,
        "threads": threads or torch_threads(n_envs),
        "device": device,
        "steps": stint["steps"],
        "wall_s": stint["wall_s"],
        "steps_per_s": stint["steps_per_s"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--algo", default="ppo", choices=sorted(ALGOS))
    parser.add_argument("--env", default="one")
    parser.add_argument("--steps", type=int, default=4096)
    parser.add_argument("--n-envs", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--threads", type=int, help="torch threads (default: the CLI's choice per setting)")
    parser.add_argument("--device", default="auto")
    parser.add_argument("--json", metavar="OUT.json")
    args = parser.parse_args()
    rows = []
    for n in args.n_envs:
        row = measure(args.algo, args.env, args.steps, n, args.threads, args.device)
        print(json.dumps(row), flush=True)
        rows.append(row)
    if args.json:
        info = {"cpus": os.cpu_count(), "load_avg": os.getloadavg()}
        Path(args.json).write_text(json.dumps({"machine": info, "rows": rows}, indent=2) + "\n")


if __name__ == "__main__":
    main()
