"""Shared settings for the environment tests."""

from __future__ import annotations

# The paper's pymunk physics loses only 10% of speed per second (a shot takes ~30-60 s simulated); the
# environment tests check behaviour, not physics, so they let balls stop much sooner.
FAST_PHYSICS = {"physics": "pymunk", "physics_params": {"damping": 0.2, "rest_speed": 0.05}}

DEFAULT_PHYSICS: dict = {}
"""The environment's default backend (the event-based simulator)."""

BACKENDS = {"event": {"physics": "event"}, "pymunk": FAST_PHYSICS}
"""Backends that semantic tests run on."""
