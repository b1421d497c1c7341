"""Learning curves from run directories (``monitor.csv`` + ``config.json``); numpy + matplotlib only."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ENV_TITLES = {"one": "1-ball", "two": "2-ball", "all": "all-ball"}


@dataclass(frozen=True, slots=True)
class Curve:
    """Per-shot success over training.

    Attributes:
        label: e.g. ``ppo`` or ``maskable-ppo (mirror, max power)``.
        env: the run's ``env`` value.
        steps: training steps at the end of each window [shots].
        success: per-shot success rate in the window ending there.
    """

    label: str
    env: str
    steps: np.ndarray
    success: np.ndarray


def run_label(config: dict) -> str:
    """A short legend label for a run's config."""
    label = str(config["algo"])
    extras = [config["mask"]] if config.get("mask") else []
    if config.get("max_power"):
        extras.append("max power")
    return f"{label} ({', '.join(extras)})" if extras else label


def read_monitor(path: str | Path) -> dict[str, np.ndarray]:
    """Columns of an SB3 monitor CSV (the first line is a JSON comment)."""
    with open(path, newline="") as fh:
        first = fh.readline()
        if not first.startswith("#"):
            fh.seek(0)
        rows = list(csv.DictReader(fh))
    if not rows:
        return {}
    return {key: np.array([_number(r[key]) for r in rows]) for key in rows[0]}


def _number(text: str) -> float:
    if text in ("True", "False"):
        return float(text == "True")
    try:
        return float(text)
    except ValueError:
        return float("nan")


def learning_curve(run: str | Path, window: int = 2000, points: int = 200) -> Curve:
    """The per-shot success rate of a run over a trailing window of ``window`` shots."""
    run = Path(run)
    config = json.loads((run / "config.json").read_text())
    cols = read_monitor(run / "monitor.csv")
    if not cols or "ep_shots" not in cols:
        return Curve(run_label(config), str(config["env"]), np.zeros(0), np.zeros(0))
    steps = np.cumsum(cols["l"])
    shots = np.cumsum(cols["ep_shots"])
    wins = np.cumsum(cols["ep_successes"])
    ends = np.linspace(min(window, shots[-1]), shots[-1], min(points, len(shots)))
    idx_end = np.searchsorted(shots, ends, side="left").clip(0, len(shots) - 1)
    idx_start = np.searchsorted(shots, shots[idx_end] - window, side="right") - 1
    s_start = np.where(idx_start >= 0, shots[idx_start.clip(0)], 0.0)
    w_start = np.where(idx_start >= 0, wins[idx_start.clip(0)], 0.0)
    rate = (wins[idx_end] - w_start) / np.maximum(shots[idx_end] - s_start, 1)
    return Curve(run_label(config), str(config["env"]), steps[idx_end], rate)


def plot_learning_curves(runs: list[str], out: str | Path, window: int = 2000) -> None:
    """One panel per environment, one line per run; saved as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = [learning_curve(r, window) for r in runs]
    envs = [e for e in ENV_TITLES if any(c.env == e for c in curves)]
    envs += sorted({c.env for c in curves} - set(envs))
    if not envs:
        raise ValueError("no runs to plot")
    fig, axes = plt.subplots(1, len(envs), figsize=(4.5 * len(envs), 3.6), squeeze=False)
    for ax, env in zip(axes[0], envs, strict=True):
        for c in (c for c in curves if c.env == env):
            ax.plot(c.steps, 100 * c.success, label=c.label)
        ax.set_title(ENV_TITLES.get(env, env))
        ax.set_xlabel("training steps (shots)")
        ax.set_ylim(-2, 102)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0][0].set_ylabel(f"success per shot [%] (last {window} shots)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
