"""RL baselines: train and evaluate stable-baselines3 agents on the pix2pockets environments.

This package needs the ``rl`` extra (torch, stable-baselines3, sb3-contrib); the rest of pix2pockets never
imports it. Public entry points:

- :func:`pix2pockets.rl.train.train` with a :class:`pix2pockets.rl.train.TrainConfig`
  (CLI: ``pix2pockets rl train``),
- :func:`pix2pockets.rl.evaluate.evaluate_model` / :func:`pix2pockets.rl.evaluate.evaluate_random`
  (CLI: ``pix2pockets rl evaluate``),
- :func:`pix2pockets.rl.agent.load_agent`: a trained agent as a ``TableLayout -> Shot`` function.

Example:
    >>> from pix2pockets.rl import require_rl
    >>> require_rl()  # raises ImportError with an install hint when the extra is missing
"""

from __future__ import annotations

import importlib.util

RL_MODULES = ("torch", "stable_baselines3", "sb3_contrib")
INSTALL_HINT = "install the rl extra: pip install torch==2.13.0 && pip install 'pix2pockets[rl]'"


def missing_rl_modules() -> list[str]:
    """Names of the ``rl`` extra's modules that cannot be imported here."""
    return [name for name in RL_MODULES if importlib.util.find_spec(name) is None]


def require_rl() -> None:
    """Raise ``ImportError`` with an install hint when torch / SB3 / sb3-contrib are missing."""
    missing = missing_rl_modules()
    if missing:
        raise ImportError(f"the RL baselines need {', '.join(missing)}; {INSTALL_HINT}")
