"""The simulator slot: one protocol, backends registered by name.

Example:
    >>> from pix2pockets.physics import make_simulator
    >>> sim = make_simulator("event")          # doctest: +SKIP
    >>> result = sim.simulate(layout, shot)    # doctest: +SKIP
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Protocol, runtime_checkable

import numpy as np

from pix2pockets.state import Shot, ShotResult, TableLayout


class StopAfter(StrEnum):
    """When a simulation may stop early.

    ``REST``: run until every ball is at rest (the full outcome).
    ``FIRST_CONTACT``: stop once the cue ball's first contact (or a no-contact outcome) is known.
    ``FIRST_POCKET``: stop at the first ball pocketed (or at rest if none drops).
    """

    REST = "rest"
    FIRST_CONTACT = "first_contact"
    FIRST_POCKET = "first_pocket"


@runtime_checkable
class Simulator(Protocol):
    """Layout + shot -> shot result with events. Positions are in the table frame [m]."""

    name: str

    def simulate(self, layout: TableLayout, shot: Shot, stop: StopAfter = StopAfter.REST) -> ShotResult:
        """Simulate one shot struck on the layout's cue ball."""
        ...

    def simulate_batch(
        self, layout: TableLayout, shots: Sequence[Shot], stop: StopAfter = StopAfter.REST
    ) -> list[ShotResult]:
        """Simulate many candidate shots from one layout, each from the same start (full results; backends with
        a faster batch give it as ``simulate_arrays``)."""
        return [self.simulate(layout, shot, stop) for shot in shots]


@dataclass(frozen=True, slots=True)
class BatchOutcome:
    """Lean results of many shots from one layout (no per-event objects).

    Attributes:
        first_contact: the cue ball's first contact (layout index) or -1, shape (m,).
        pocket: pocket index each ball dropped into or -1, shape (m, n).
        final_positions: final centres [m] (pocketed balls: where they dropped), shape (m, n, 2).
        status: 0 ok, 1 event budget exceeded, 2 non-finite numbers, shape (m,).
        n_events: events per shot, shape (m,).
        cue: the cue ball's layout index.
    """

    first_contact: np.ndarray
    pocket: np.ndarray
    final_positions: np.ndarray
    status: np.ndarray
    n_events: np.ndarray
    cue: int

    @property
    def pocketed(self) -> np.ndarray:
        """Boolean mask of pocketed balls, shape (m, n)."""
        return self.pocket >= 0

    @property
    def cue_pocketed(self) -> np.ndarray:
        """Whether the cue ball dropped, shape (m,)."""
        return self.pocket[:, self.cue] >= 0

    @property
    def final_cue(self) -> np.ndarray:
        """Final cue-ball centre [m], shape (m, 2)."""
        return self.final_positions[:, self.cue]


SimulatorFactory = Callable[..., Simulator]
_REGISTRY: dict[str, SimulatorFactory] = {}
# Built-in backends, imported on first use; each module calls register_simulator() on import.
_BUILTIN_MODULES: dict[str, str] = {
    "event": "pix2pockets.physics.event",
    "pymunk": "pix2pockets.physics.pymunk_backend",
    "paper": "pix2pockets.physics.paper",
}


def register_simulator(name: str, factory: SimulatorFactory) -> None:
    """Register a backend factory under ``name`` (called with keyword parameters)."""
    _REGISTRY[name] = factory


def _load_builtins() -> None:
    for name, module in _BUILTIN_MODULES.items():
        if name not in _REGISTRY:
            try:
                importlib.import_module(module)
            except ModuleNotFoundError as err:
                if err.name != module:  # a real missing dependency inside the backend
                    raise


def available_simulators() -> list[str]:
    """Names of the registered backends."""
    _load_builtins()
    return sorted(_REGISTRY)


def make_simulator(name: str = "event", **params: Any) -> Simulator:
    """Build the backend called ``name`` with keyword ``params``."""
    _load_builtins()
    try:
        factory = _REGISTRY[name]
    except KeyError:
        raise ValueError(f"unknown simulator {name!r}; available: {available_simulators()}") from None
    return factory(**params)
