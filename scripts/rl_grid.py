"""The paper's RL grid (Tables 2 and 3): train, evaluate and tabulate, resumable run by run.

Every run lives in ``ROOT/<name>`` (default ``runs/rl``); training goes through ``pix2pockets rl train
--resume`` so re-running the driver continues unfinished runs and skips finished ones. Evaluation results go
to ``ROOT/<name>/eval.json`` (re-done when the model has more steps than the evaluation saw).

Usage:
    PYTHONPATH=src python scripts/rl_grid.py list
    PYTHONPATH=src python scripts/rl_grid.py train --steps 500000 [--only one-ppo two-td3 ...] [--env one]
        [--ray [ADDRESS]] [--workers N]   # one run per Ray worker (local instance, or a cluster's address)
    PYTHONPATH=src python scripts/rl_grid.py evaluate --episodes 1000
    PYTHONPATH=src python scripts/rl_grid.py table            # markdown for docs/results.md
    PYTHONPATH=src python scripts/rl_grid.py plot --out docs/rl_learning_curves.png
    PYTHONPATH=src python scripts/rl_grid.py speeds           # training steps/s per run
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ENVS = ("one", "two", "all")
TABLE2_ALGOS = ("ppo", "td3", "a2c", "ddpg", "sac")
ENV_ROWS = {"one": "1-ball", "two": "2-ball", "all": "all-ball"}

# The paper's numbers [%] (Tables 2 and 3).
PAPER_T2 = {
    "one": {"random": 23.6, "ppo": 84.6, "td3": 97.4, "a2c": 35.0, "ddpg": 99.8, "sac": 88.6},
    "two": {"random": 0.90, "ppo": 1.10, "td3": 6.30, "a2c": 0.00, "ddpg": 5.50, "sac": 9.90},
    "all": {"random": 4.30, "ppo": 12.8, "td3": 7.60, "a2c": 10.6, "ddpg": 6.40, "sac": 5.90},
}
# (direct, mirror) for PPO_mask and PPO_mask(max power).
PAPER_T3 = {
    "one": {"mask": (100, 100), "mask-maxp": (100, 100)},
    "two": {"mask": (63.2, 68.5), "mask-maxp": (66.4, 67.5)},
    "all": {"mask": (49.7, 60.7), "mask-maxp": (53.4, 57.1)},
    "turn": {"mask": (0.0, 0.0), "mask-maxp": (0.0, 0.0)},
}


@dataclass(frozen=True)
class Run:
    env: str
    algo: str
    mask: str | None = None
    max_power: bool = False

    @property
    def name(self) -> str:
        parts = [self.env, self.algo]
        if self.mask:
            parts.append(self.mask)
        if self.max_power:
            parts.append("maxp")
        return "-".join(parts)

    def train_args(self) -> list[str]:
        args = ["--algo", self.algo, "--env", self.env]
        if self.mask:
            args += ["--mask", self.mask]
        if self.max_power:
            args.append("--max-power")
        return args


GRID: list[Run] = [Run(env, algo) for env in ENVS for algo in TABLE2_ALGOS] + [
    Run(env, "maskable-ppo", mask, maxp) for env in ENVS for maxp in (False, True) for mask in ("direct", "mirror")
]


def cli(*args: str) -> None:
    cmd = [sys.executable, "-m", "pix2pockets", *args]
    print("+ pix2pockets " + " ".join(args), flush=True)
    subprocess.run(cmd, check=True)


def select(args: argparse.Namespace) -> list[Run]:
    runs = [r for r in GRID if (not args.env or r.env in args.env) and (not args.only or r.name in args.only)]
    if args.only and len(runs) < len(args.only):
        known = {r.name for r in GRID}
        raise SystemExit(f"unknown run names: {sorted(set(args.only) - known)}; see `rl_grid.py list`")
    return runs


def model_steps(path: Path) -> int:
    from pix2pockets.rl.bundle import read_meta

    return read_meta(path).steps


def agent_file(run_dir: Path) -> Path | None:
    """The run's agent with the most steps: ``model.zip``, or ``checkpoint.zip`` of a run cut short."""
    files = [run_dir / name for name in ("model.zip", "checkpoint.zip") if (run_dir / name).exists()]
    return max(files, key=model_steps) if files else None


def train_args(run: Run, root: str, steps: int, seed: int, checkpoint_every: int) -> list[str]:
    """The ``pix2pockets rl train`` arguments of one run (resumable: ``--resume`` continues a checkpoint)."""
    out = Path(root) / run.name
    return [
        "rl", "train", *run.train_args(), "--steps", str(steps), "--seed", str(seed), "--out", str(out),
        "--resume", "--checkpoint-every", str(checkpoint_every), "--no-progress",
    ]  # fmt: skip


def train_on_worker(argv: list[str]) -> str:
    """One run on a Ray worker: ``pix2pockets rl train`` in a subprocess of that worker's machine."""
    done = subprocess.run([sys.executable, "-m", "pix2pockets", *argv], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"pix2pockets {' '.join(argv)} failed: {done.stderr.strip().splitlines()[-1:]}")
    return argv[argv.index("--out") + 1]


def do_train(args: argparse.Namespace) -> None:
    todo = []
    for run in select(args):
        model = Path(args.root) / run.name / "model.zip"
        if model.exists() and model_steps(model) >= args.steps:
            print(f"= {run.name}: done ({model_steps(model)} steps)")
            continue
        todo.append(train_args(run, args.root, args.steps, args.seed, args.checkpoint_every))
    if args.ray is None:
        for argv in todo:
            cli(*argv)
        return
    # one run per Ray worker; the runs' folders (--root) must be on storage every worker sees
    from pix2pockets.scale.ray_pool import RayPool

    with RayPool(args.ray, args.workers) as pool:
        for out in pool.map(train_on_worker, todo):
            print(f"+ {out}: trained", flush=True)


def _rl_evaluate(out: Path, args: argparse.Namespace, *how: str, force: bool = False) -> None:
    """``pix2pockets rl evaluate`` with the grid's episodes and seed, writing ``out``."""
    extra = ["--force"] if force else []  # a stale evaluation is replaced on purpose
    cli("rl", "evaluate", *how, "--episodes", str(args.episodes), "--seed", str(args.eval_seed),
        "--json", str(out), *extra)  # fmt: skip


def do_evaluate(args: argparse.Namespace) -> None:
    root = Path(args.root)
    envs = ENVS if not args.env else args.env
    for env in envs:
        out = root / f"{env}-random" / "eval.json"
        if not out.exists():
            out.parent.mkdir(parents=True, exist_ok=True)
            _rl_evaluate(out, args, "--policy", "random", "--env", env)
    for env in envs:
        for mask in ("direct", "mirror") if args.masked_random else ():
            for maxp in (False, True):
                out = root / (f"{env}-random-{mask}" + ("-maxp" if maxp else "")) / "eval.json"
                if out.exists():
                    continue
                out.parent.mkdir(parents=True, exist_ok=True)
                extra = ["--max-power"] if maxp else []
                _rl_evaluate(out, args, "--policy", "random", "--env", env, "--mask", mask, *extra)
    for run in select(args):
        model = agent_file(root / run.name)
        out = root / run.name / "eval.json"
        if model is None:
            continue
        if out.exists() and json.loads(out.read_text())["trained_steps"] >= model_steps(model):
            continue
        _rl_evaluate(out, args, "--model", str(model), force=True)


def _ours(root: Path, name: str, key: str = "shot_success") -> str:
    path = root / name / "eval.json"
    if not path.exists():
        return "-"
    data = json.loads(path.read_text())
    rate = data[key]
    text = f"{100 * rate['rate']:.1f}"
    steps = data.get("trained_steps")
    if steps is not None and steps < 500_000:
        text += f" ({steps // 1000}k)"
    return text


def do_table(args: argparse.Namespace) -> None:
    root = Path(args.root)
    print("Table 2: success rate per shot [%], ours | paper (ours: steps trained in brackets when < 500k)\n")
    cols = ("random", *TABLE2_ALGOS)
    print("| Env | " + " | ".join(c.upper() if c != "random" else "Random" for c in cols) + " |")
    print("|---" * (len(cols) + 1) + "|")
    for env in ENVS:
        cells = [f"{_ours(root, f'{env}-{c}')} \\| {PAPER_T2[env][c]:g}" for c in cols]
        print(f"| {ENV_ROWS[env]} | " + " | ".join(cells) + " |")
    print("\nTable 3: MaskablePPO success rate per shot [%], direct \\| mirror; ours / paper\n")
    print(
        "| Env | PPO_mask ours | PPO_mask paper | PPO_mask(max power) ours | PPO_mask(max power) paper "
        "| uniform over mask (ours) | uniform over mask, max power (ours) |"
    )
    print("|---|---|---|---|---|---|---|")
    for env, key in (*((e, "shot_success") for e in ENVS), ("all", "full_turn")):
        row = "Full turn (all-ball)" if key == "full_turn" else ENV_ROWS[env]
        paper_key = "turn" if key == "full_turn" else env
        cells = []
        for suffix, pk in (("", "mask"), ("-maxp", "mask-maxp")):
            ours = " \\| ".join(_ours(root, f"{env}-maskable-ppo-{m}{suffix}", key) for m in ("direct", "mirror"))
            d, m = PAPER_T3[paper_key][pk]
            cells += [ours, f"{d:g} \\| {m:g}"]
        for suffix in ("", "-maxp"):
            cells.append(" \\| ".join(_ours(root, f"{env}-random-{m}{suffix}", key) for m in ("direct", "mirror")))
        print(f"| {row} | " + " | ".join(cells) + " |")


def do_details(args: argparse.Namespace) -> None:
    """Every evaluated run with its intervals (ours only)."""
    root = Path(args.root)
    print("| run | trained steps | episodes | success per shot [95% CI] | first shot | full turn |")
    print("|---|---|---|---|---|---|")

    def fmt(r: dict) -> str:
        lo, hi = r["ci95"]
        return f"{100 * r['rate']:.1f} [{100 * lo:.1f}, {100 * hi:.1f}]"

    names = [f"{env}-random" for env in ENVS] + [r.name for r in select(args)]
    names += [f"{e}-random-{m}{x}" for e in ENVS for x in ("", "-maxp") for m in ("direct", "mirror")]
    for name in names:
        path = root / name / "eval.json"
        if not path.exists():
            continue
        d = json.loads(path.read_text())
        steps = "-" if d["trained_steps"] is None else str(d["trained_steps"])
        print(
            f"| {name} | {steps} | {d['episodes']} | {fmt(d['shot_success'])} ({d['shot_success']['trials']} shots)"
            f" | {fmt(d['first_shot_success'])} | {fmt(d['full_turn'])} |"
        )


def do_plot(args: argparse.Namespace) -> None:
    runs = [str(Path(args.root) / r.name) for r in select(args) if (Path(args.root) / r.name / "monitor.csv").exists()]
    cli("rl", "plot", *runs, "--out", args.out, "--window", str(args.window), "--force")


def do_speeds(args: argparse.Namespace) -> None:
    """Training throughput of each run, from its training log (every resumed part of a run together)."""
    print("| run | steps | wall [s] | steps/s |")
    print("|---|---|---|---|")
    for run in select(args):
        path = Path(args.root) / run.name / "stints.jsonl"
        if not path.exists():
            continue
        rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
        steps = sum(r["steps"] for r in rows)
        wall = sum(r["wall_s"] for r in rows)
        if steps:
            print(f"| {run.name} | {steps} | {wall:.0f} | {steps / wall:.1f} |")


def do_list(args: argparse.Namespace) -> None:
    for run in select(args):
        model = agent_file(Path(args.root) / run.name)
        state = f"{model_steps(model)} steps ({model.name})" if model else "not started"
        print(f"{run.name:32s} {state}")


def main() -> None:
    from pix2pockets.scale.ray_pool import add_ray_arguments

    parser = argparse.ArgumentParser(description="The paper's RL grid: train / evaluate / table / plot.")
    parser.add_argument("action", choices=("list", "train", "evaluate", "table", "plot", "speeds", "details"))
    parser.add_argument("--root", default="runs/rl")
    parser.add_argument("--env", nargs="+", choices=ENVS)
    parser.add_argument("--only", nargs="+", help="run names (see list)")
    parser.add_argument("--steps", type=int, default=500_000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--checkpoint-every", type=int, default=10_000)
    parser.add_argument("--episodes", type=int, default=1000)
    parser.add_argument("--eval-seed", type=int, default=12345)
    parser.add_argument(
        "--masked-random",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="also evaluate uniform-random play over each hitpoint mask (Table 3's untrained reference)",
    )
    add_ray_arguments(parser, "train: one run per Ray worker (--root on storage every worker sees)")
    parser.add_argument("--out", default="docs/rl_learning_curves.png")
    parser.add_argument("--window", type=int, default=2000)
    args = parser.parse_args()
    actions = {"list": do_list, "train": do_train, "evaluate": do_evaluate, "table": do_table, "plot": do_plot}
    actions["speeds"] = do_speeds
    actions["details"] = do_details
    actions[args.action](args)


if __name__ == "__main__":
    main()
