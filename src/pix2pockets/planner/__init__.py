"""Shot planning: hitpoints, mirror table, the paper's Oracle and a physics-checked search planner."""

from pix2pockets.planner.base import Planner, Suggestion, legal_targets
from pix2pockets.planner.chance import Chance, format_chance, measure_chance
from pix2pockets.planner.hitpoints import Hitpoint, ShotKind, find_hitpoints
from pix2pockets.planner.mirror import PenaltyScheme, cushion_multiplier
from pix2pockets.planner.noise import (
    FASTFIZ,
    NO_NOISE,
    SKILLS,
    GaussianNoise,
    NoiseModel,
    load_noise_file,
    noise_model,
)
from pix2pockets.planner.oracle import OracleConfig, OracleMode, OraclePlanner, oracle_score
from pix2pockets.planner.registry import PLANNER_NAMES, make_planner
from pix2pockets.planner.search import SearchConfig, SearchPlanner

__all__ = [
    "FASTFIZ",
    "NO_NOISE",
    "PLANNER_NAMES",
    "SKILLS",
    "Chance",
    "GaussianNoise",
    "Hitpoint",
    "NoiseModel",
    "OracleConfig",
    "OracleMode",
    "OraclePlanner",
    "PenaltyScheme",
    "Planner",
    "SearchConfig",
    "SearchPlanner",
    "ShotKind",
    "Suggestion",
    "cushion_multiplier",
    "find_hitpoints",
    "format_chance",
    "legal_targets",
    "load_noise_file",
    "make_planner",
    "measure_chance",
    "noise_model",
    "oracle_score",
]
