"""The ``paper`` simulator backend: the seed paper's own environment dynamics, fast and without its hangs.

The paper simulates 8-ball in a pymunk world (pixels, zoom 2): frictionless discs whose velocities decay
10% per second, 1/300 s steps, ball-ball hits made ideal elastic and cushion hits made mirror reflections
by its collision callbacks, centre-ball strokes that set the cue ball's velocity, a ball pocketed as soon
as it overlaps a pocket circle, and a shot that ends when every ball sleeps. This backend reproduces that
model in SI units on :func:`~pix2pockets.geometry.raster.paper_table` (its exact layout), solving every
contact in closed form on pymunk's step grid (see :mod:`pix2pockets.physics.paper._kernel`), about 150
times faster than stepping pymunk (0.2 ms of CPU per shot).

Differences from the paper's code, on purpose (the defects it had):
    * resting contacts: its callbacks re-applied a pair's velocities from the start of a contact at every
      step the balls kept touching, so clusters could be re-energised forever (its loop gave up after
      1000 s); here a contact is resolved once, and a shot past ``max_time`` fails with a clear error;
    * a ball that comes to rest in a pocket mouth beyond the cushion-nose line drops into that pocket (its
      world kept it there, outside the surface a layout may hold);
    * its cushion callback kept one incoming velocity for all balls, so two balls touching cushions in the
      same step could swap directions; here each ball keeps its own.

Importing this package registers the backend as ``"paper"``.

References:
    Schiøtt et al., pix2pockets, sec. 5.2 and 6.2; its public environment code (read for the facts listed
    in ``docs/physics.md``, not copied); pymunk / Chipmunk2D 7 documentation (``Space.damping``,
    ``idle_speed_threshold``, collision callbacks).
"""

from pix2pockets.physics.event._cache import ensure_numba_cache_dir

ensure_numba_cache_dir()

from pix2pockets.physics.base import register_simulator  # noqa: E402
from pix2pockets.physics.paper.params import PAPER_PX, PaperParams  # noqa: E402
from pix2pockets.physics.paper.simulator import (  # noqa: E402
    PAPER_MAX_SPEED,
    PAPER_POWER_LEVELS,
    PaperSimulator,
    paper_continuous_speed,
    paper_level_speed,
    paper_power_level,
)


def _factory(**params: float) -> PaperSimulator:
    return PaperSimulator(**params)


register_simulator("paper", _factory)

__all__ = [
    "PAPER_MAX_SPEED",
    "PAPER_POWER_LEVELS",
    "PAPER_PX",
    "PaperParams",
    "PaperSimulator",
    "paper_continuous_speed",
    "paper_level_speed",
    "paper_power_level",
]
