"""Training one baseline: resumable, checkpointed, with a learning-curve CSV.

A run directory holds:

- ``config.json``: the :class:`TrainConfig` (a resumed run must match it),
- ``monitor.csv``: SB3 ``Monitor`` rows, one per episode (reward ``r``, length ``l``, wall time ``t``, and
  ``ep_shots`` / ``ep_successes`` / ``ep_won``), appended to across resumes,
- ``checkpoint.zip``: the latest model every ``checkpoint_every`` steps (no replay buffer: off-policy runs
  resume with an empty buffer, which refills within ``learning_starts`` + a few thousand steps),
- ``model.zip``: the final agent (an agent file, see :mod:`pix2pockets.rl.bundle`),
- ``stints.jsonl``: one line per call of :func:`train` on the run (the first and each resume) with its steps and
  wall time (steps/s).
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from pix2pockets.rl.algos import algo_spec, build_model, configure_torch, load_model
from pix2pockets.rl.bundle import AgentMeta, write_meta
from pix2pockets.rl.envs import EPISODE_KEYS, EnvChoice, make_env

CHECKPOINT = "checkpoint.zip"
FINAL = "model.zip"
CONFIG = "config.json"
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
        _ = self.choice  # validates the env variant

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
    from stable_baselines3.common.monitor import Monitor
    from stable_baselines3.common.vec_env import DummyVecEnv

    def factory() -> Any:
        return Monitor(
            make_env(config.choice), str(Path(config.out)), info_keywords=EPISODE_KEYS, override_existing=not resume
        )

    return DummyVecEnv([factory])


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


def _check_resume(config: TrainConfig, out: Path) -> None:
    saved = {"physics": "event", **json.loads((out / CONFIG).read_text())}  # a config without it: event
    mine = asdict(config)
    diff = [k for k in _RESUME_KEYS if saved.get(k) != mine.get(k)]
    if diff:
        pairs = ", ".join(f"{k}: {saved.get(k)!r} -> {mine.get(k)!r}" for k in diff)
        raise ValueError(f"cannot resume {str(out)!r} with different settings ({pairs})")


def train(config: TrainConfig, resume: bool = False) -> Path:
    """Train (or resume) a run; returns the path of the final agent file ``model.zip``.

    Raises:
        ValueError: the run directory already holds a run and ``resume`` is false, or it holds a run with
            different settings.
    """
    configure_torch()
    out = Path(config.out)
    has_run = (out / CONFIG).exists()
    if has_run and not resume:
        raise ValueError(f"{str(out)!r} already holds a run; pass --resume to continue it or choose another --out")
    if has_run:
        _check_resume(config, out)
    resume = resume and has_run
    out.mkdir(parents=True, exist_ok=True)
    (out / CONFIG).write_text(json.dumps(asdict(config), indent=2))

    env = _make_vec_env(config, resume)
    ckpt = out / CHECKPOINT
    if resume and ckpt.exists():
        model = load_model(config.algo, str(ckpt), env=env)
        if algo_spec(config.algo).action_noise and getattr(model, "action_noise", None) is None:
            model.action_noise = build_model(config.algo, env, config.seed, **config.overrides).action_noise
    else:
        model = build_model(config.algo, env, config.seed, tensorboard_log=config.tensorboard, **config.overrides)
    done = int(model.num_timesteps)
    # Fresh layouts after a resume instead of replaying the first stint's sequence.
    env.seed(config.seed + done)
    remaining = config.steps - done
    start = time.perf_counter()
    if remaining > 0:
        model.learn(
            total_timesteps=remaining,
            callback=_checkpoint_callback(config),
            reset_num_timesteps=False,
            progress_bar=config.progress,
        )
    wall = time.perf_counter() - start
    trained = int(model.num_timesteps) - done
    save_agent(model, config, out / CHECKPOINT)
    save_agent(model, config, out / FINAL)
    env.close()
    stint = {"steps_before": done, "steps": trained, "wall_s": round(wall, 2)}
    stint["steps_per_s"] = round(trained / wall, 2) if wall > 0 and trained else None
    with (out / STINTS).open("a") as fh:
        fh.write(json.dumps(stint) + "\n")
    return out / FINAL
