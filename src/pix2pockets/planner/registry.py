"""Planners by name, for the CLI, the pipeline and the environments."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from pix2pockets.planner.base import Planner
from pix2pockets.planner.hitpoints import ShotKind
from pix2pockets.planner.oracle import OracleConfig, OracleMode, OraclePlanner
from pix2pockets.planner.paper_oracle import PaperOracleConfig, PaperOraclePlanner
from pix2pockets.planner.paper_protocol import paper_search_config
from pix2pockets.planner.search import SearchConfig, SearchPlanner

_ORACLES: dict[str, OracleConfig] = {
    "oracle": OracleConfig(OracleMode.BEST_MAX, mirror=False),
    "oracle-mirror": OracleConfig(OracleMode.BEST_MAX, mirror=True),
    "oracle-rand-max": OracleConfig(OracleMode.RANDOM_MAX, mirror=False),
    "oracle-rand-max-mirror": OracleConfig(OracleMode.RANDOM_MAX, mirror=True),
    "oracle-rand-rand": OracleConfig(OracleMode.RANDOM_RANDOM, mirror=False),
    "oracle-rand-rand-mirror": OracleConfig(OracleMode.RANDOM_RANDOM, mirror=True),
}
_SEARCHES: dict[str, dict[str, Any]] = {
    "search": {},
    "search-direct": {"kinds": (ShotKind.DIRECT,)},
    "search-greedy": {"lookahead": 0.0},
    # ablation: the one-step search without the endgame, rescue, two-ply and winning-shot passes, half the replays
    "search-basic": {
        "endgame": 0,
        "rescue_below": 0.0,
        "two_ply": 0,
        "final_scale": 1,
        "samples": 8,
        "refine_samples": 16,
    },
}
PLANNER_NAMES: tuple[str, ...] = (*_ORACLES, *_SEARCHES)
"""Names accepted by :func:`make_planner`: the paper's Oracle variants and our search planner."""


def make_planner(
    name: str,
    physics: str = "event",
    noise: str = "fastfiz",
    time_budget: float | None = 0.5,
    oracle_speed: float | None = None,
    **search_overrides: Any,
) -> Planner:
    """Build a planner by name.

    With ``physics="paper"`` the Oracle variants are the paper's Oracle as its code computes it
    (:class:`~pix2pockets.planner.paper_oracle.PaperOraclePlanner`, always at the paper's power levels) and the
    search planner plays the paper's 30 power levels without spin, by the paper's judgement
    (:func:`~pix2pockets.planner.paper_protocol.paper_search_config`).

    Args:
        name: one of :data:`PLANNER_NAMES`.
        physics: simulator backend the search planner verifies with.
        noise: planning noise model of the search planner.
        time_budget: search decision time limit [s] (``None``: unlimited, reproducible).
        oracle_speed: the Oracle's "max power" stroke speed [m/s] (default ``OracleConfig.max_speed``).
        search_overrides: further :class:`SearchConfig` fields.
    """
    if name in _ORACLES and physics == "paper":
        if oracle_speed is not None:
            raise ValueError("the paper's Oracle plays the paper's top power level; --oracle-speed does not apply")
        base = _ORACLES[name]
        paper = PaperOraclePlanner(PaperOracleConfig(mode=base.mode, mirror=base.mirror))
        paper.name = name
        return paper
    if name in _ORACLES:
        cfg = _ORACLES[name]
        if oracle_speed is not None:
            if not (math.isfinite(oracle_speed) and oracle_speed > 0):
                raise ValueError(f"oracle speed must be positive, got {oracle_speed}")
            cfg = replace(cfg, max_speed=oracle_speed)
        planner = OraclePlanner(cfg)
        planner.name = name
        return planner
    if name in _SEARCHES:
        kw = {**_SEARCHES[name], **search_overrides}
        if physics == "paper":
            kw = {**paper_search_config(), **kw}
        planner = SearchPlanner(SearchConfig(physics=physics, noise=noise, time_budget=time_budget, **kw))
        planner.name = name
        return planner
    raise ValueError(f"unknown planner {name!r}; choose one of {list(PLANNER_NAMES)}")
