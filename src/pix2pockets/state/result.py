"""What happened in a shot: events and the final layout."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pix2pockets.state.layout import TableLayout


class EventType(StrEnum):
    """Kinds of events a simulator reports."""

    CUE_STRIKE = "cue_strike"
    BALL_BALL = "ball_ball"
    BALL_CUSHION = "ball_cushion"
    BALL_JAW = "ball_jaw"
    POCKET = "pocket"
    SLIDING_TO_ROLLING = "sliding_to_rolling"
    ROLLING_TO_SPINNING = "rolling_to_spinning"
    SPINNING_TO_STATIONARY = "spinning_to_stationary"
    ROLLING_TO_STATIONARY = "rolling_to_stationary"


@dataclass(frozen=True, slots=True)
class Event:
    """One event.

    Attributes:
        time: time since the cue strike [s].
        kind: event type.
        ball: index (into the starting layout) of the first ball involved.
        other: second ball index for ball-ball events, cushion index for cushion events, jaw segment index
            for jaw events, pocket index for pocket events; -1 otherwise.
    """

    time: float
    kind: EventType
    ball: int
    other: int = -1


@dataclass(frozen=True, slots=True, eq=False)
class ShotResult:
    """The outcome of simulating one shot.

    Attributes:
        initial: the layout before the shot.
        events: all events in time order.
        final: the layout after the shot, pocketed balls removed.
        final_ids: for each ball of ``final``, its index in ``initial``.
        pocketed: indices (into ``initial``) of pocketed balls, in the order they dropped.
        pocketed_into: the pocket index (``TableSpec.pockets`` order) for each entry of ``pocketed``.
        first_contact: index of the first ball the cue ball touched, or ``None``.
        rail_after_contact: whether any ball touched a cushion after the cue ball's first contact.
        duration: time until everything stopped [s].
    """

    initial: TableLayout
    events: tuple[Event, ...]
    final: TableLayout
    final_ids: tuple[int, ...]
    pocketed: tuple[int, ...]
    pocketed_into: tuple[int, ...]
    first_contact: int | None
    rail_after_contact: bool
    duration: float

    @property
    def cue_pocketed(self) -> bool:
        """Whether the cue ball dropped (a scratch)."""
        cue = self.initial.cue_index
        return cue is not None and cue in self.pocketed

    @property
    def rails_touched(self) -> tuple[int, ...]:
        """Indices of balls that touched a cushion (at any time), in first-touch order."""
        seen: list[int] = []
        for e in self.events:
            if e.kind in (EventType.BALL_CUSHION, EventType.BALL_JAW) and e.ball not in seen:
                seen.append(e.ball)
        return tuple(seen)

    @classmethod
    def from_events(
        cls, initial: TableLayout, events: list[Event], final_positions, *, validate: bool = True
    ) -> ShotResult:
        """Build a result from an event list and the final positions of *all* initial balls.

        Positions of pocketed balls in ``final_positions`` are ignored. Derives ``pocketed``,
        ``first_contact`` and ``rail_after_contact`` from the events. ``validate=False`` skips
        re-validating the final layout (``TableLayout.unchecked``): for simulators whose output
        invariants are tested (no overlap, every ball on the table); it is the bulk of the cost.
        """
        events = sorted(events, key=lambda e: e.time)
        cue = initial.cue_index
        pocketed: list[int] = []
        into: list[int] = []
        first_contact: int | None = None
        contact_time = None
        rail_after = False
        for e in events:
            if e.kind is EventType.POCKET and e.ball not in pocketed:
                pocketed.append(e.ball)
                into.append(e.other)
            elif e.kind is EventType.BALL_BALL and first_contact is None and cue is not None:
                if e.ball == cue:
                    first_contact, contact_time = e.other, e.time
                elif e.other == cue:
                    first_contact, contact_time = e.ball, e.time
            elif (
                e.kind in (EventType.BALL_CUSHION, EventType.BALL_JAW)
                and contact_time is not None
                and e.time >= contact_time
            ):
                rail_after = True
        keep = [i for i in range(len(initial)) if i not in pocketed]
        make = TableLayout if validate else TableLayout.unchecked
        final = make(tuple(initial.balls[i] for i in keep), np.asarray(final_positions)[keep], initial.spec)
        duration = events[-1].time if events else 0.0
        return cls(
            initial,
            tuple(events),
            final,
            tuple(keep),
            tuple(pocketed),
            tuple(into),
            first_contact,
            rail_after,
            duration,
        )
