"""Evaluating agents: per-shot success rate with a 95% interval, first-shot rate, full-turn rate.

Definitions (the paper's Tables 2 and 3):

- *success rate*: the fraction of shots that legally pocket a target ball (or win), over every shot of
  ``episodes`` training-mode episodes (an episode is one turn: it ends at the first failed shot or when the
  game ends). On 1-ball and 2-ball one shot decides the episode, so this is the per-layout rate.
- *first-shot rate*: the same for the first shot of each episode only (fresh random layouts).
- *full-turn rate*: the fraction of episodes won in one turn (all-ball: every own ball, then the 8).

Intervals are Wilson score intervals at 95%.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import gymnasium as gym
import numpy as np

from pix2pockets.rl.envs import EnvChoice, make_env, read_outcome

Z95 = 1.959963984540054
MAX_SHOTS_PER_EPISODE = 200
"""Safety cap on one evaluation episode [shots]; a turn of 8-ball needs at most 8 successful shots."""

Policy = Callable[[Any, gym.Env], Any]
"""Maps (observation, env) to an action."""


def wilson_interval(successes: int, trials: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (``(0, 1)`` when there are no trials)."""
    if trials < 0 or not 0 <= successes <= max(trials, 0):
        raise ValueError(f"need 0 <= successes <= trials, got {successes} of {trials}")
    if trials == 0:
        return 0.0, 1.0
    p = successes / trials
    denom = 1 + z * z / trials
    centre = (p + z * z / (2 * trials)) / denom
    half = z * math.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / denom
    # Exact ends at p = 0 and p = 1 (the formula gives them up to round-off).
    lo = 0.0 if successes == 0 else max(0.0, centre - half)
    hi = 1.0 if successes == trials else min(1.0, centre + half)
    return lo, hi


@dataclass(frozen=True, slots=True)
class Rate:
    """A success proportion with its 95% Wilson interval."""

    successes: int
    trials: int
    rate: float
    ci95: tuple[float, float]

    @classmethod
    def of(cls, successes: int, trials: int) -> Rate:
        return cls(successes, trials, successes / trials if trials else 0.0, wilson_interval(successes, trials))


@dataclass(frozen=True, slots=True)
class EvalResult:
    """An evaluation's numbers.

    Attributes:
        policy: ``random`` or the algorithm name.
        choice: the environment variant.
        episodes: episodes played.
        seed: seed of the first reset (layouts) and of the random policy.
        shot_success: per-shot success rate (the paper's success rate).
        first_shot_success: success rate of each episode's first shot.
        full_turn: episodes won within one turn.
        mean_reward: mean normalised reward per shot.
        mean_shots: mean shots per episode.
        trained_steps: training steps of the agent (``None`` for the random policy).
    """

    policy: str
    choice: EnvChoice
    episodes: int
    seed: int
    shot_success: Rate
    first_shot_success: Rate
    full_turn: Rate
    mean_reward: float
    mean_shots: float
    trained_steps: int | None = None

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["choice"] = self.choice.to_dict()
        return data

    def summary(self) -> str:
        """A few human-readable lines."""

        def fmt(r: Rate) -> str:
            return f"{100 * r.rate:.1f}% [{100 * r.ci95[0]:.1f}, {100 * r.ci95[1]:.1f}] ({r.successes}/{r.trials})"

        steps = "" if self.trained_steps is None else f", trained {self.trained_steps} steps"
        return "\n".join(
            [
                f"{self.policy} on {self.choice.env_id} ({self.choice.physics} physics){steps}: "
                f"{self.episodes} episodes, seed {self.seed}",
                f"  success per shot:  {fmt(self.shot_success)}",
                f"  first shot:        {fmt(self.first_shot_success)}",
                f"  full turn:         {fmt(self.full_turn)}",
                f"  mean reward/shot:  {self.mean_reward:+.3f}, mean shots/episode {self.mean_shots:.2f}",
            ]
        )


def run_episodes(env: gym.Env, policy: Policy, episodes: int, seed: int) -> dict[str, Any]:
    """Play ``episodes`` episodes; the first reset is seeded, later ones continue the env's generator."""
    if episodes <= 0:
        raise ValueError(f"episodes must be > 0, got {episodes}")
    shots = successes = firsts = wins = 0
    reward_sum = 0.0
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed if ep == 0 else None)
        for k in range(MAX_SHOTS_PER_EPISODE):
            obs, reward, terminated, truncated, info = env.step(policy(obs, env))
            success, won = read_outcome(terminated, truncated, info)
            shots += 1
            successes += int(success)
            reward_sum += float(reward)
            if k == 0:
                firsts += int(success)
            if terminated or truncated:
                wins += int(won)
                break
    return {
        "shot_success": Rate.of(successes, shots),
        "first_shot_success": Rate.of(firsts, episodes),
        "full_turn": Rate.of(wins, episodes),
        "mean_reward": reward_sum / shots,
        "mean_shots": shots / episodes,
    }


def masked_sample(mask: np.ndarray, nvec: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A uniform draw per ``MultiDiscrete`` dimension among the entries its part of ``mask`` allows."""
    action, start = [], 0
    for n in (int(k) for k in nvec):
        allowed = np.flatnonzero(mask[start : start + n])
        action.append(int(rng.choice(allowed)) if allowed.size else int(rng.integers(n)))
        start += n
    return np.array(action, dtype=np.int64)


def evaluate_random(choice: EnvChoice, episodes: int, seed: int = 0) -> EvalResult:
    """The random baseline: uniform actions from the env's action space (seeded).

    With a mask in ``choice`` the draw is uniform among the allowed actions (direction bins at the
    hitpoints, and the power levels the mask leaves), i.e. an untrained MaskablePPO's support.
    """
    env = make_env(choice)
    env.action_space.seed(seed)
    rng = np.random.default_rng(seed)

    def act(_obs: Any, e: gym.Env) -> Any:
        if choice.mask is None:
            return e.action_space.sample()
        mask = np.asarray(e.get_wrapper_attr("action_masks")(), dtype=bool)
        return masked_sample(mask, e.action_space.nvec, rng)

    try:
        numbers = run_episodes(env, act, episodes, seed)
    finally:
        env.close()
    return EvalResult("random" if choice.mask is None else "random-masked", choice, episodes, seed, **numbers)


def model_policy(model: Any, maskable: bool) -> Policy:
    """A deterministic policy from an SB3 model (masked when the model is a MaskablePPO)."""

    def act(obs: Any, env: gym.Env) -> Any:
        if maskable:
            masks = np.asarray(env.get_wrapper_attr("action_masks")(), dtype=bool)
            action, _ = model.predict(obs, deterministic=True, action_masks=masks)
        else:
            action, _ = model.predict(obs, deterministic=True)
        return action

    return act


def evaluate_model(path: str, episodes: int, seed: int = 0) -> EvalResult:
    """Evaluate an agent file saved by ``pix2pockets rl train`` on the env it was trained on."""
    from pix2pockets.rl.algos import algo_spec, configure_torch, load_model
    from pix2pockets.rl.bundle import read_meta

    configure_torch(1)
    meta = read_meta(path)
    model = load_model(meta.algo, path)
    env = make_env(meta.choice)
    try:
        numbers = run_episodes(env, model_policy(model, algo_spec(meta.algo).maskable), episodes, seed)
    finally:
        env.close()
    return EvalResult(meta.algo, meta.choice, episodes, seed, trained_steps=meta.steps, **numbers)
