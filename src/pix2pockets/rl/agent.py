"""A trained agent as a shot-suggestion function: ``TableLayout (+ group) -> Shot``.

Example:
    >>> from pix2pockets.rl.agent import load_agent                     # doctest: +SKIP
    >>> agent = load_agent("src/pix2pockets/data/agents/all-ball.zip")  # doctest: +SKIP
    >>> shot = agent(layout, Group.SOLIDS)                               # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from pix2pockets.rl.bundle import AgentMeta, read_meta
from pix2pockets.rl.envs import make_env
from pix2pockets.state import Group, Shot, TableLayout


class RLAgent:
    """A loaded agent and the environment variant it was trained on (used to encode layouts and decode
    actions). Call it, or :meth:`suggest`, with a layout and the shooter's group."""

    def __init__(self, model: Any, meta: AgentMeta) -> None:
        from pix2pockets.rl.algos import algo_spec

        self.model = model
        self.meta = meta
        self._maskable = algo_spec(meta.algo).maskable
        self._env = make_env(meta.choice)

    def action_for(self, layout: TableLayout, group: Group | None = None) -> Any:
        """The agent's (deterministic) action for ``layout``."""
        options: dict[str, Any] = {"layout": layout}
        if group is not None:
            options["group"] = group
        obs, _ = self._env.reset(options=options)
        if self._maskable:
            masks = np.asarray(self._env.get_wrapper_attr("action_masks")(), dtype=bool)
            action, _ = self.model.predict(obs, deterministic=True, action_masks=masks)
        else:
            action, _ = self.model.predict(obs, deterministic=True)
        return action

    def suggest(self, layout: TableLayout, group: Group | None = None) -> Shot:
        """The suggested shot (direction [rad] and speed [m/s]) for ``layout``.

        Args:
            layout: balls on the table (must hold the cue ball).
            group: the shooter's group on all-ball tables (``None``: open table / the env's default).
        """
        if layout.cue_index is None:
            raise ValueError("the layout has no cue ball: nothing to shoot with")
        action = self.action_for(layout, group)
        # The env's action map without execution noise: the intended stroke.
        return self._env.unwrapped.actions.to_shot(np.asarray(action))

    __call__ = suggest

    def close(self) -> None:
        self._env.close()


def load_agent(path: str | Path) -> RLAgent:
    """Load an agent file written by ``pix2pockets rl train`` (needs the ``rl`` extra).

    Raises:
        ValueError: the file is missing or not a pix2pockets agent.
        ImportError: torch / stable-baselines3 are not installed.
    """
    from pix2pockets.rl import require_rl

    require_rl()
    from pix2pockets.rl.algos import configure_torch, load_model

    configure_torch()
    meta = read_meta(path)
    return RLAgent(load_model(meta.algo, str(path)), meta)
