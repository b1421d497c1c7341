"""Training throughput of the RL baselines: environment steps (shots) per second, per algorithm.

Measures, on one environment, (a) the bare env with random actions and (b) each algorithm's ``learn``
(simulation + policy + updates, SB3 defaults with the paper's three-layer MLPs, torch on one thread).
On-policy algorithms update after each rollout (PPO every 2048 steps), so PPO / MaskablePPO need at least
one full rollout plus its update to be representative: use ``--steps 2500`` or more.

Usage:
    PYTHONPATH=src python benchmarks/rl_speed.py --env one --steps 2500 --json rl_speed.json
"""

from __future__ import annotations

import argparse
import json
import time

from pix2pockets.rl.algos import ALGOS, algo_spec, build_model
from pix2pockets.rl.envs import EnvChoice, make_env


def env_steps_per_s(choice: EnvChoice, steps: int, seed: int = 0) -> float:
    env = make_env(choice)
    env.action_space.seed(seed)
    env.reset(seed=seed)
    start = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
    wall = time.perf_counter() - start
    env.close()
    return steps / wall


def learn_steps_per_s(algo: str, env_name: str, steps: int, seed: int = 0) -> float:
    from stable_baselines3.common.vec_env import DummyVecEnv

    spec = algo_spec(algo)
    choice = EnvChoice(env_name, continuous=spec.continuous, mask="direct" if spec.maskable else None)
    vec = DummyVecEnv([lambda: make_env(choice)])
    model = build_model(algo, vec, seed)
    start = time.perf_counter()
    model.learn(total_timesteps=steps)
    wall = time.perf_counter() - start
    vec.close()
    return int(model.num_timesteps) / wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="one")
    parser.add_argument("--steps", type=int, default=2500)
    parser.add_argument("--algos", nargs="+", default=sorted(ALGOS), choices=sorted(ALGOS))
    parser.add_argument("--json", metavar="OUT.json")
    args = parser.parse_args()

    import torch

    torch.set_num_threads(1)
    rows = [("random actions (env only)", env_steps_per_s(EnvChoice(args.env), args.steps))]
    print(f"{rows[0][0]:28s} {rows[0][1]:9.1f} steps/s", flush=True)
    for algo in args.algos:
        rate = learn_steps_per_s(algo, args.env, args.steps)
        rows.append((algo, rate))
        print(f"{algo:28s} {rate:9.1f} steps/s   (500k steps: {500_000 / rate / 3600:.1f} h)", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"env": args.env, "steps": args.steps, "steps_per_s": dict(rows)}, fh, indent=2)


if __name__ == "__main__":
    main()
