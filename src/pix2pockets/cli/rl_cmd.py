"""``pix2pockets rl``: train and evaluate the paper's RL baselines (needs the ``rl`` extra)."""

from __future__ import annotations

import argparse
import sys

from pix2pockets.files import check_output, write_json

ALGO_NAMES = ("ppo", "td3", "a2c", "ddpg", "sac", "maskable-ppo")
ENV_HELP = "one, two, all (the paper's 1-ball, 2-ball, all-ball) or a registered Gymnasium id"
PHYSICS = ("event", "paper")
PHYSICS_HELP = "environment dynamics: event (default) or paper (the paper's own environment, table and powers)"


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("rl", help="train / evaluate RL baselines (PPO, TD3, A2C, DDPG, SAC, MaskablePPO)")
    rl_sub = parser.add_subparsers(dest="rl_command", metavar="ACTION", required=True)

    tr = rl_sub.add_parser("train", help="train one agent (resumable, checkpointed)")
    tr.add_argument("--algo", required=True, choices=ALGO_NAMES)
    tr.add_argument("--env", required=True, help=ENV_HELP)
    tr.add_argument("--steps", type=int, required=True, help="total environment steps (shots); paper: 500000")
    tr.add_argument("--seed", type=int, default=0)
    tr.add_argument("--out", required=True, help="run directory (config, monitor.csv, checkpoint.zip, model.zip)")
    tr.add_argument("--mask", choices=("direct", "mirror"), help="maskable-ppo hitpoint mask (default direct)")
    tr.add_argument("--max-power", action="store_true", help="maskable-ppo: always the strongest power level")
    tr.add_argument("--resume", action="store_true", help="continue the run in --out from its checkpoint")
    tr.add_argument("--checkpoint-every", type=int, default=10_000, help="steps between checkpoints")
    tr.add_argument("--no-progress", action="store_true", help="no progress bar (e.g. for log files)")
    tr.add_argument("--tensorboard", metavar="DIR", help="also log to TensorBoard in DIR (off by default)")
    tr.add_argument("--physics", choices=PHYSICS, default="event", help=PHYSICS_HELP)
    tr.add_argument("--n-envs", type=int, default=1, help="environments side by side, each in a subprocess if > 1")
    tr.add_argument("--device", default="auto", help="torch device: auto (a GPU when there is one), cpu, cuda")
    tr.add_argument("--threads", type=int, help="torch threads (default: 1 on <= 2 cores, else half the free cores)")
    tr.add_argument(
        "--rollout-steps",
        type=int,
        help="ppo / a2c / maskable-ppo: steps per rollout over all --n-envs (default: a resumed run keeps its rollout)",
    )
    tr.set_defaults(func=run_train)

    ev = rl_sub.add_parser("evaluate", help="success rate (95%% interval) and full-turn rate of an agent")
    ev.add_argument("--model", help="agent file (model.zip / checkpoint.zip from `rl train`)")
    ev.add_argument("--policy", choices=("model", "random"), default="model", help="random: uniform baseline")
    ev.add_argument("--env", help=f"with --policy random: {ENV_HELP}")
    ev.add_argument("--mask", choices=("direct", "mirror"), help="with --policy random: uniform among masked actions")
    ev.add_argument("--max-power", action="store_true", help="with --policy random --mask: strongest power only")
    ev.add_argument("--physics", choices=PHYSICS, default=None, help=f"with --policy random: {PHYSICS_HELP}")
    ev.add_argument("--episodes", type=int, default=1000)
    ev.add_argument("--seed", type=int, default=12345, help="seed of the evaluation layouts (not a training seed)")
    ev.add_argument("--json", metavar="OUT.json", help="write the numbers as JSON")
    ev.add_argument("--force", action="store_true", help="overwrite an existing output file")
    ev.set_defaults(func=run_evaluate)

    ex = rl_sub.add_parser("export", help="slim copy of an agent (float16 weights, no optimizer state) to ship")
    ex.add_argument("--model", required=True, help="agent file from `rl train`")
    ex.add_argument("--out", required=True, help="output .zip")
    ex.add_argument("--full-precision", action="store_true", help="keep float32 weights")
    ex.add_argument("--force", action="store_true", help="overwrite an existing output file")
    ex.set_defaults(func=run_export)

    pl = rl_sub.add_parser("plot", help="learning curves (per-shot success) of run directories as a PNG")
    pl.add_argument("runs", nargs="+", help="run directories (each with monitor.csv and config.json)")
    pl.add_argument("--out", required=True, help="PNG path")
    pl.add_argument("--window", type=int, default=2000, help="moving-average window [shots]")
    pl.add_argument("--force", action="store_true", help="overwrite an existing output file")
    pl.set_defaults(func=run_plot)


def _require_rl() -> None:
    from pix2pockets.rl import require_rl

    try:
        require_rl()
    except ImportError as err:
        raise ValueError(str(err)) from None


def run_train(args: argparse.Namespace) -> int:
    _require_rl()
    from pix2pockets.rl.train import TrainConfig, train

    config = TrainConfig(
        algo=args.algo,
        env=args.env,
        steps=args.steps,
        seed=args.seed,
        out=args.out,
        mask=args.mask,
        max_power=args.max_power,
        checkpoint_every=args.checkpoint_every,
        progress=not args.no_progress,
        tensorboard=args.tensorboard,
        physics=args.physics,
        n_envs=args.n_envs,
        device=args.device,
        threads=args.threads,
        rollout_steps=args.rollout_steps,
    )
    path = train(config, resume=args.resume, log=_notice)
    print(f"saved {path}")
    return 0


def _notice(message: str) -> None:
    print(f"pix2pockets rl train: {message}", file=sys.stderr)


def run_evaluate(args: argparse.Namespace) -> int:
    _require_rl()
    from pix2pockets.rl.envs import EnvChoice
    from pix2pockets.rl.evaluate import evaluate_model, evaluate_random

    if args.episodes <= 0:
        raise ValueError(f"--episodes must be > 0, got {args.episodes}")
    check_output(args.json, args.force)
    if args.policy == "random":
        if not args.env:
            raise ValueError("--policy random needs --env")
        choice = EnvChoice(env=args.env, mask=args.mask, max_power=args.max_power, physics=args.physics or "event")
        result = evaluate_random(choice, args.episodes, args.seed)
    else:
        if args.mask or args.max_power or args.physics:
            raise ValueError(
                "--mask / --max-power / --physics apply to --policy random; an agent file knows its mask and physics"
            )
        if not args.model:
            raise ValueError("give --model PATH (or --policy random --env ENV)")
        result = evaluate_model(args.model, args.episodes, args.seed)
    print(result.summary())
    if args.json:
        write_json(args.json, result.to_dict())
    return 0


def run_export(args: argparse.Namespace) -> int:
    _require_rl()
    from pix2pockets.rl.export import slim_agent

    check_output(args.out, args.force, (".zip",))
    path = slim_agent(args.model, args.out, half=not args.full_precision)
    print(f"wrote {path} ({path.stat().st_size / 1e6:.2f} MB)")
    return 0


def run_plot(args: argparse.Namespace) -> int:
    from pix2pockets.rl.curves import plot_learning_curves

    check_output(args.out, args.force, (".png", ".pdf", ".svg"))
    plot_learning_curves(args.runs, args.out, window=args.window)
    print(f"wrote {args.out}")
    return 0
