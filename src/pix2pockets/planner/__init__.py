"""Shot planning: hitpoints, mirror table, the paper's Oracle and a physics-checked search planner."""

from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.mirror import PenaltyScheme, cushion_multiplier

__all__ = ["Hitpoint", "PenaltyScheme", "ShotKind", "cushion_multiplier", "find_hitpoints"]
