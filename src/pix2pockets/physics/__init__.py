"""Shot simulation: the simulator protocol and its backends (registered by name)."""

from pix2pockets.physics.base import (
    Simulator,
    StopAfter,
    available_simulators,
    make_simulator,
    register_simulator,
)

__all__ = ["Simulator", "StopAfter", "available_simulators", "make_simulator", "register_simulator"]
