"""A trained agent as a shot-suggestion function: ``TableLayout (+ group) -> Shot``.

:func:`load_agent` gives an :class:`RLAgent`; call it with a layout (and the shooter's group) for a
:class:`~pix2pockets.state.Shot`, or use :meth:`RLAgent.as_planner` where the photo pipeline expects a
shot planner (``suggest(layout, state, rng) -> [candidate]``, as ``pix2pockets suggest --agent PATH``).

Example:
    >>> from pix2pockets.rl.agent import load_agent                     # doctest: +SKIP
    >>> agent = load_agent("src/pix2pockets/data/agents/all-ball.zip")  # doctest: +SKIP
    >>> shot = agent(layout, Group.SOLIDS)                               # doctest: +SKIP
"""

from __future__ import annotations

from dataclasses import dataclass
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

    def as_planner(self) -> AgentPlanner:
        """This agent in the pipeline's planner slot."""
        return AgentPlanner(self)

    def close(self) -> None:
        self._env.close()


@dataclass(frozen=True, slots=True)
class AgentSuggestion:
    """The agent's shot with what the environment's physics predicts for it (the planner candidate shape).

    Attributes:
        shot: the stroke.
        target: index of the first ball hit when it drops (the predicted pot), else ``None``.
        pocket: index (``TableSpec.pockets``) of that ball's pocket, else ``None``.
        kind: ``"direct"`` for a predicted pot, else ``None``.
        safety: no pot predicted.
        success_probability: ``None``: an RL policy gives no calibrated probability.
        value: 1.0 for a predicted pot, 0.0 otherwise.
        hitpoint: ``None`` (not from the hitpoint geometry).
    """

    shot: Shot
    target: int | None
    pocket: int | None
    kind: str | None
    safety: bool
    success_probability: float | None = None
    value: float = 0.0
    hitpoint: Any = None


class AgentPlanner:
    """Adapter: an :class:`RLAgent` as a planner, ``suggest(layout, state, rng) -> [AgentSuggestion]``."""

    def __init__(self, agent: RLAgent) -> None:
        self.agent = agent

    def suggest(self, layout: TableLayout, state: Any = None, rng: np.random.Generator | None = None) -> list:
        """One candidate: the agent's shot, its predicted pot filled in by simulating it once."""
        group = getattr(state, "group", None)
        shot = self.agent.suggest(layout, group)
        result = self.agent._env.unwrapped.simulator.simulate(layout, shot)
        first = result.first_contact
        if first is not None and first in result.pocketed:
            pocket = int(result.pocketed_into[list(result.pocketed).index(first)])
            return [AgentSuggestion(shot, int(first), pocket, "direct", safety=False, value=1.0)]
        return [AgentSuggestion(shot, None, None, None, safety=True)]


def load_agent(path: str | Path) -> RLAgent:
    """Load an agent file written by ``pix2pockets rl train`` (needs the ``rl`` extra).

    Raises:
        ValueError: the file is missing or not a pix2pockets agent.
        ImportError: torch / stable-baselines3 are not installed.
    """
    from pix2pockets.rl import require_rl

    require_rl()
    from pix2pockets.rl.algos import configure_torch, load_model

    configure_torch(1)
    meta = read_meta(path)
    return RLAgent(load_model(meta.algo, str(path)), meta)
