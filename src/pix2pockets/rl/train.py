"""Training one baseline: resumable, checkpointed, with a learning-curve CSV.

A run directory holds:

- ``config.json``: the :class:`TrainConfig` (a resumed run must match it),
- ``monitor.csv``: SB3 monitor rows, one per episode of any of the run's environments (reward ``r``, length
  ``l``, wall time ``t``, and ``ep_shots`` / ``ep_successes`` / ``ep_won``), appended to across resumes,
- ``checkpoint.zip``: the latest model every ``checkpoint_every`` steps (no replay buffer: off-policy runs
  resume with an empty buffer, which refills within ``learning_starts`` + a few thousand steps),
- ``model.zip``: the final agent (an agent file, see :mod:`pix2pockets.rl.bundle`),
- ``stints.jsonl``: one line per finished call of :func:`train` on the run (the first and each resume) with its
  steps, wall time (steps/s), environments and, for on-policy learners, the steps per rollout.
"""

from __future__ import annotations

import json
import math
import time
import zipfile
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from pix2pockets.rl.algos import (
    algo_spec,
    build_model,
    configure_torch,
    load_model,
    progress_bar_missing,
)
from pix2pockets.rl.bundle import AgentMeta, write_meta
from pix2pockets.rl.envs import EPISODE_KEYS, EnvChoice, make_env
from pix2pockets.torch_device import resolve_device

CHECKPOINT = "checkpoint.zip"
FINAL = "model.zip"
CONFIG = "config.json"
MONITOR = "monitor.csv"
STINTS = "stints.jsonl"
# Only these config fields must match when resuming (steps may grow, progress / checkpointing may change).
_RESUME_KEYS = ("algo", "env", "mask", "max_power", "seed", "overrides", "physics")


@dataclass(frozen=True, slots=True)
class TrainConfig:
    """One training run.

    Attributes:
        algo: algorithm name (``ppo``, ``td3``, ``a2c``, ``ddpg``, ``sac``, ``maskable-ppo``).
        env: ``one``, ``two``, ``all`` or a registered Gymnasium id.
        steps: total environment steps (shots) to train [steps].
        seed: seed for the policy, the noise and the environment's layouts.
        out: run directory.
        mask: hitpoint mask for MaskablePPO (``direct`` or ``mirror``); default ``direct`` for it.
        max_power: MaskablePPO with the power fixed to the strongest level.
        checkpoint_every: steps between checkpoints.
        progress: show a progress bar.
        tensorboard: TensorBoard log directory (off by default).
        overrides: extra algorithm constructor arguments (e.g. ``{"n_steps": 64}`` in tests).
        physics: the environment's simulator backend (``event`` or ``paper``).
        n_envs: environments stepped side by side (more than one: each in its own subprocess).
        device: torch device for the policy: ``auto`` (a GPU when there is one), ``cpu``, ``cuda``, ...
        threads: torch threads in the training process; ``None``: :func:`pix2pockets.rl.algos.torch_threads`.
        rollout_steps: on-policy learners: steps per rollout over all environments (each collects
            ``rollout_steps / n_envs``); ``None``: a fresh run takes the learner's own ``n_steps`` per environment,
            a resumed run keeps the rollout it had (so a run resumed with more or fewer environments keeps its
            update schedule) where the new environments divide it.
    """

    algo: str
    env: str
    steps: int
    seed: int
    out: str
    mask: str | None = None
    max_power: bool = False
    checkpoint_every: int = 10_000
    progress: bool = True
    tensorboard: str | None = None
    overrides: dict[str, Any] = field(default_factory=dict)
    physics: str = "event"
    n_envs: int = 1
    device: str = "auto"
    threads: int | None = None
    rollout_steps: int | None = None

    def __post_init__(self) -> None:
        spec = algo_spec(self.algo)
        if spec.maskable and self.mask is None:
            object.__setattr__(self, "mask", "direct")
        if self.mask is not None and not spec.maskable:
            raise ValueError(f"--mask is for maskable-ppo only, not {self.algo}")
        if self.max_power and not spec.maskable:
            raise ValueError(f"--max-power is for maskable-ppo only, not {self.algo}")
        if self.steps <= 0:
            raise ValueError(f"steps must be > 0, got {self.steps}")
        if self.checkpoint_every <= 0:
            raise ValueError(f"checkpoint_every must be > 0, got {self.checkpoint_every}")
        if self.n_envs < 1:
            raise ValueError(f"n_envs must be >= 1, got {self.n_envs}")
        if self.threads is not None and self.threads < 1:
            raise ValueError(f"threads must be >= 1, got {self.threads}")
        if self.rollout_steps is not None:
            if not spec.on_policy:
                raise ValueError(f"--rollout-steps is for on-policy learners (ppo, a2c, maskable-ppo), not {self.algo}")
            if self.rollout_steps <= 0 or self.rollout_steps % self.n_envs:
                raise ValueError(
                    f"rollout_steps must be a positive multiple of n_envs ({self.n_envs}), got {self.rollout_steps}"
                )
            if "n_steps" in self.overrides:
                raise ValueError("give the rollout either as rollout_steps or as an n_steps override, not both")
        _ = self.choice  # validates the env variant

    @property
    def n_steps(self) -> int | None:
        """Steps per environment and rollout that :attr:`rollout_steps` asks for (``None``: the learner's own)."""
        return None if self.rollout_steps is None else self.rollout_steps // self.n_envs

    @property
    def choice(self) -> EnvChoice:
        return EnvChoice(
            env=self.env,
            continuous=algo_spec(self.algo).continuous,
            mask=self.mask,
            max_power=self.max_power,
            physics=self.physics,
        )


def _make_vec_env(config: TrainConfig, resume: bool) -> Any:
    """The training VecEnv: ``n_envs`` copies (subprocesses when more than one) under one ``monitor.csv``.

    A resumed run appends to its ``monitor.csv``; a fresh one starts it anew.
    """
    from stable_baselines3.common.monitor import ResultsWriter
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

    choice = config.choice

    def factory() -> Any:
        return make_env(choice)

    factories = [factory] * config.n_envs
    venv = SubprocVecEnv(factories) if config.n_envs > 1 else DummyVecEnv(factories)
    path = str(Path(config.out) / MONITOR)
    env = VecMonitor(venv, None, info_keywords=EPISODE_KEYS)  # its own writer would truncate a resumed file
    append = resume and Path(path).exists()
    header = {"t_start": env.t_start, "env_id": choice.env_id}
    env.results_writer = ResultsWriter(path, header=header, extra_keys=EPISODE_KEYS, override_existing=not append)
    return env


def rollout_steps(model: Any) -> int:
    """Steps one collection round of ``model`` takes across all its environments (``learn`` counts in these)."""
    n_steps = getattr(model, "n_steps", None)  # on-policy: PPO, A2C, MaskablePPO
    if n_steps is not None:
        return int(n_steps) * int(model.n_envs)
    freq = getattr(model, "train_freq", None)
    per_env = int(freq.frequency) if freq is not None and str(freq.unit.value) == "step" else 1
    return per_env * int(model.n_envs)


def planned_steps(done: int, target: int, rollout: int) -> int:
    """The step count a run ends at: SB3 finishes whole rollouts, so ``target`` rounds up past ``done``."""
    if target <= done:
        return done
    return done + math.ceil((target - done) / rollout) * rollout


def _checkpoint_callback(config: TrainConfig) -> Any:
    """An SB3 callback saving ``checkpoint.zip`` (atomically) every ``config.checkpoint_every`` steps."""
    from stable_baselines3.common.callbacks import BaseCallback

    class Checkpoint(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next_save = 0

        def _on_training_start(self) -> None:
            self.next_save = (self.num_timesteps // config.checkpoint_every + 1) * config.checkpoint_every

        def _on_step(self) -> bool:
            if self.num_timesteps >= self.next_save:
                save_agent(self.model, config, Path(config.out) / CHECKPOINT)
                self.next_save += config.checkpoint_every
            return True

    return Checkpoint()


def save_agent(model: Any, config: TrainConfig, path: Path) -> None:
    """Save ``model`` with its metadata, atomically (a crash never leaves a half-written file)."""
    tmp = path.with_name(path.stem + ".partial.zip")
    model.save(str(tmp), exclude=["replay_buffer"])
    write_meta(tmp, AgentMeta(config.algo, config.choice, int(model.num_timesteps), config.seed))
    tmp.replace(path)


def _resumed_n_steps(config: TrainConfig, agent: Path, say: Callable[[str], None]) -> int | None:
    """Steps per environment a resumed on-policy run collects: the share of ``config.rollout_steps``, else the share
    that keeps the agent file's rollout over ``config.n_envs`` environments; ``None``: as saved (also for off-policy
    learners, and when the environments cannot share the saved rollout evenly, which is said)."""
    if not algo_spec(config.algo).on_policy or config.n_steps is not None:
        return config.n_steps
    with zipfile.ZipFile(agent) as zf:  # SB3's agent file: its "data" entry is JSON
        data = json.loads(zf.read("data"))
    saved_steps, saved_envs = int(data["n_steps"]), int(data["n_envs"])
    if saved_envs == config.n_envs:
        return None
    total = saved_steps * saved_envs
    if total % config.n_envs:
        say(f"{config.n_envs} env(s) cannot share the run's {total}-step rollouts evenly; each collects {saved_steps}")
        return None
    return total // config.n_envs


def _check_resume(config: TrainConfig, out: Path) -> None:
    saved = {"physics": "event", **json.loads((out / CONFIG).read_text())}  # a config without it: event
    mine = asdict(config)
    diff = [k for k in _RESUME_KEYS if saved.get(k) != mine.get(k)]
    if diff:
        pairs = ", ".join(f"{k}: {saved.get(k)!r} -> {mine.get(k)!r}" for k in diff)
        raise ValueError(f"cannot resume {str(out)!r} with different settings ({pairs})")


def _has_run(out: Path) -> bool:
    """A directory holds a run once it has an agent file; a ``config.json`` alone is a start that failed."""
    return (out / CONFIG).exists() and ((out / CHECKPOINT).exists() or (out / FINAL).exists())


def train(config: TrainConfig, resume: bool = False, log: Callable[[str], None] | None = None) -> Path:
    """Train (or resume) a run; returns the path of the final agent file ``model.zip``.

    Args:
        config: the run.
        resume: continue the run in ``config.out`` from its checkpoint.
        log: receives notices (steps rounded up to whole rollouts, progress bar unavailable); ignored if ``None``.

    Raises:
        ValueError: the run directory already holds a run and ``resume`` is false, or it holds a run with
            different settings.
    """
    say = log or (lambda _msg: None)
    out = Path(config.out)
    has_run = _has_run(out)
    if has_run and not resume:
        raise ValueError(f"{str(out)!r} already holds a run; pass --resume to continue it or choose another --out")
    if has_run:
        _check_resume(config, out)
    resume = resume and has_run
    progress = config.progress
    if progress and (missing := progress_bar_missing()):
        say(f"no progress bar: it needs {' and '.join(missing)} (pip install {' '.join(missing)}); training without")
        progress = False
    device = resolve_device(config.device)
    configure_torch(config.threads, config.n_envs)
    out.mkdir(parents=True, exist_ok=True)

    env = _make_vec_env(config, resume)
    try:
        ckpt = out / CHECKPOINT
        if resume and ckpt.exists():
            n_steps = _resumed_n_steps(config, ckpt, say)
            model = load_model(config.algo, str(ckpt), env=env, device=device, n_steps=n_steps)
            if algo_spec(config.algo).action_noise and getattr(model, "action_noise", None) is None:
                model.action_noise = build_model(config.algo, env, config.seed, **config.overrides).action_noise
        else:
            rollout = {} if config.n_steps is None else {"n_steps": config.n_steps}
            model = build_model(
                config.algo,
                env,
                config.seed,
                tensorboard_log=config.tensorboard,
                device=device,
                **config.overrides,
                **rollout,
            )
        (out / CONFIG).write_text(json.dumps(asdict(config), indent=2))
        done = int(model.num_timesteps)
        end = planned_steps(done, config.steps, rollout_steps(model))
        if end > max(done, config.steps):
            say(
                f"{config.algo} collects {rollout_steps(model)}-step rollouts ({config.n_envs} env(s)): "
                f"training to {end} steps, not {config.steps}"
            )
        # Fresh layouts after a resume instead of replaying the first stint's sequence.
        env.seed(config.seed + done)
        remaining = config.steps - done
        start = time.perf_counter()
        if remaining > 0:
            model.learn(
                total_timesteps=remaining,
                callback=_checkpoint_callback(config),
                reset_num_timesteps=False,
                progress_bar=progress,
            )
        wall = time.perf_counter() - start
        trained = int(model.num_timesteps) - done
        save_agent(model, config, out / CHECKPOINT)
        save_agent(model, config, out / FINAL)
    finally:
        env.close()
    stint = {"steps_before": done, "steps": trained, "wall_s": round(wall, 2), "n_envs": config.n_envs}
    if algo_spec(config.algo).on_policy:
        stint["rollout_steps"] = rollout_steps(model)
    stint["steps_per_s"] = round(trained / wall, 2) if wall > 0 and trained else None
    with (out / STINTS).open("a") as fh:
        fh.write(json.dumps(stint) + "\n")
    return out / FINAL
