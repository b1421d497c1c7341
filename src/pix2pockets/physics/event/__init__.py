"""The ``event`` simulator backend (default): analytic event-based pool physics compiled with numba.

Importing this package registers the backend as ``"event"``. The compiled kernels are cached on disk
(next to the modules, or in a user/temp cache directory when the package directory is read-only), so
only the very first process pays the JIT compile.
"""

from pix2pockets.physics.event._cache import ensure_numba_cache_dir

ensure_numba_cache_dir()

from pix2pockets.physics.base import register_simulator  # noqa: E402
from pix2pockets.physics.event.params import PhysicsParams  # noqa: E402
from pix2pockets.physics.event.simulator import BatchOutcome, EventSimulator, pack_table, shots_to_array  # noqa: E402


def _factory(**params: float) -> EventSimulator:
    return EventSimulator(**params)


register_simulator("event", _factory)

__all__ = ["BatchOutcome", "EventSimulator", "PhysicsParams", "pack_table", "shots_to_array"]
