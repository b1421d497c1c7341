"""The paper's Oracle: rank hitpoints by cut angle and pocket window, shoot hard.

score = (window / 60 deg + cos(cut angle)) x m, with m the cushion multiplier (1 for direct shots; see
:func:`~pix2pockets.planner.mirror.cushion_multiplier`). Variants from the paper's Table 3:

* ``O(rand angle, rand power)``: a uniformly random hitpoint, a random one of ``power_levels`` speeds;
* ``O(rand angle, max power)``: a uniformly random hitpoint at ``max_speed``;
* ``O(best angle, max power)``: the best-scoring hitpoint at ``max_speed`` (the paper's Oracle).

Hitpoints are direct only, or direct + mirror (bank and kick). With no hitpoint the Oracle plays straight
at the nearest legal ball. In the paper's 1-ball task (only the cue ball on the table) the hitpoints are the
cue ball's own pocket windows, the widest first.

References:
    Schiøtt et al., pix2pockets, sections "Oracle", "Introduce Mirror table" and Table 3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import StrEnum

import numpy as np

from pix2pockets.planner.base import Suggestion, cue_pot_suggestions, fallback_shot, legal_targets, lone_cue
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.mirror import PAPER_TEXT_PENALTY, PenaltyScheme, cushion_multiplier
from pix2pockets.rules import GameState
from pix2pockets.state import Shot, TableLayout

WINDOW_SCALE = math.radians(60.0)  # the paper divides the pocket window by 60 degrees


class OracleMode(StrEnum):
    """How the Oracle picks angle and power."""

    RANDOM_RANDOM = "rand-rand"  # O(rand angle, rand power)
    RANDOM_MAX = "rand-max"  # O(rand angle, max power)
    BEST_MAX = "best-max"  # O(best angle, max power)


@dataclass(frozen=True, slots=True)
class OracleConfig:
    """Oracle settings.

    Attributes:
        mode: angle / power choice.
        mirror: add bank and kick hitpoints (the paper's "direct, mirror").
        max_speed: the "max power" stroke speed [m/s].
        power_levels: number of equally spaced speeds up to ``max_speed`` for random power (paper: 30).
        max_cut: largest cut angle kept [rad] (paper: 80 deg).
        scheme: cushion penalty scheme (paper text 0.33 per cushion, or its code's 1/2 bank, 3/4 kick).
        penalty: per-cushion multiplier for the paper-text scheme.
    """

    mode: OracleMode = OracleMode.BEST_MAX
    mirror: bool = False
    max_speed: float = 5.0
    power_levels: int = 30
    max_cut: float = math.radians(80.0)
    scheme: PenaltyScheme = PenaltyScheme.PAPER_TEXT
    penalty: float = PAPER_TEXT_PENALTY
    kinds: tuple[ShotKind, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mode", OracleMode(self.mode))
        object.__setattr__(self, "scheme", PenaltyScheme(self.scheme))
        if not self.max_speed > 0:
            raise ValueError(f"OracleConfig.max_speed must be positive, got {self.max_speed}")
        if self.power_levels < 1:
            raise ValueError(f"OracleConfig.power_levels must be >= 1, got {self.power_levels}")
        if not 0.0 < self.penalty <= 1.0:
            raise ValueError(f"OracleConfig.penalty must be in (0, 1], got {self.penalty}")
        kinds = (ShotKind.DIRECT, ShotKind.BANK, ShotKind.KICK) if self.mirror else (ShotKind.DIRECT,)
        object.__setattr__(self, "kinds", kinds)


def oracle_score(
    hp: Hitpoint, scheme: PenaltyScheme = PenaltyScheme.PAPER_TEXT, penalty: float = PAPER_TEXT_PENALTY
) -> float:
    """The paper's Oracle score of one hitpoint: ``(window / 60 deg + cos(cut)) * m``."""
    m = cushion_multiplier(hp.kind, len(hp.cushions), scheme, penalty)
    return (hp.window / WINDOW_SCALE + math.cos(hp.cut_angle)) * m


class OraclePlanner:
    """The paper's Oracle as a :class:`~pix2pockets.planner.base.Planner`.

    Example:
        >>> from pix2pockets.state import Ball, TableLayout
        >>> from pix2pockets.rules import GameState
        >>> lay = TableLayout((Ball.numbered(0), Ball.numbered(1)), [[1.0, 0.3], [1.8, 0.3]])
        >>> best = OraclePlanner().suggest(lay, GameState())[0]
        >>> (best.target, best.pocket, best.kind.value)
        (1, 2, 'direct')
    """

    def __init__(self, config: OracleConfig | None = None) -> None:
        self.config = config or OracleConfig()
        mirror = "-mirror" if self.config.mirror else ""
        self.name = f"oracle-{self.config.mode.value}{mirror}"

    def scored_hitpoints(self, layout: TableLayout, state: GameState) -> list[tuple[float, Hitpoint]]:
        """All hitpoints for the shooter's legal targets with their scores, best first (stable order)."""
        cfg = self.config
        hps = find_hitpoints(layout, legal_targets(layout, state), kinds=cfg.kinds, max_cut=cfg.max_cut)
        scored = [(oracle_score(h, cfg.scheme, cfg.penalty), h) for h in hps]
        order = sorted(range(len(scored)), key=lambda i: -scored[i][0])
        return [scored[i] for i in order]

    def suggest(
        self, layout: TableLayout, state: GameState, rng: np.random.Generator | None = None
    ) -> list[Suggestion]:
        """Ranked suggestions: the chosen hitpoint first, then the rest by score."""
        cfg = self.config
        rng = rng if rng is not None else np.random.default_rng(0)
        if lone_cue(layout):  # the paper's 1-ball task: pot the cue ball, the widest pocket window is best
            suggestions = cue_pot_suggestions(layout, cfg.max_speed)
        else:
            suggestions = [
                Suggestion(Shot(angle=h.cue_angle, speed=cfg.max_speed), h.target, h.pocket, h.kind, None, s, h)
                for s, h in self.scored_hitpoints(layout, state)
            ]
        if not suggestions:
            return [fallback_shot(layout, state, cfg.max_speed)]
        if cfg.mode is not OracleMode.BEST_MAX:
            pick = int(rng.integers(len(suggestions)))
            chosen = suggestions.pop(pick)
            if cfg.mode is OracleMode.RANDOM_RANDOM:
                level = int(rng.integers(1, cfg.power_levels + 1))
                chosen = replace(chosen, shot=replace(chosen.shot, speed=cfg.max_speed * level / cfg.power_levels))
            suggestions.insert(0, chosen)
        return suggestions
