"""Observations: the position and class of all 16 balls in a fixed slot order.

Shape ``(48,)``, float32: 16 slots of ``(x, y, c)`` flattened slot by slot (``obs.reshape(16, 3)``
gives one row per slot; the paper's 48-vector):

=======  =====================================================================
slot     ball
=======  =====================================================================
0        cue ball
1 - 7    the shooter's own group ("target"/"blue" balls of the paper)
8        the 8-ball
9 - 15   the opponent's group
=======  =====================================================================

Within a group, a numbered ball keeps its number's slot (solids 1-7 -> 1-7 when own, 9-15 when the
opponent's; stripes 9-15 -> 1-7 when own); balls without a number fill the free slots in order of
``(x, y)`` at the start of the episode. A ball keeps its slot for the whole episode.

Units (``ObsUnits``):
    * ``normalized``: ``x / length`` and ``y / width`` in ``[0, 1]`` (table frame, origin at the head-bottom
      cushion-nose corner);
    * ``paper_pixels``: the paper's environment pixels (its nominal 735 x 410 window: the playing surface
      spans u 40.5-694.5, v 40.5-369.5 inside a 29.5 px border and 11 px cushions; ``u`` right, ``v`` down),
      see :func:`pix2pockets.geometry.raster.table_to_env_pixels`.

Class code ``c``: 0 absent, 0.25 cue, 0.5 own, 0.75 opponent, 1.0 the 8-ball (the paper's class / 4).
An absent slot (ball pocketed or not in this variant) is ``(-1, -1, 0)``.
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np
from gymnasium import spaces

from pix2pockets.geometry.raster import PAPER_ENV_WINDOW_PX, table_to_env_pixels
from pix2pockets.state import BallClass, Group, TableLayout

N_SLOTS = 16
CUE_SLOT = 0
BLACK_SLOT = 8
OWN_SLOTS = tuple(range(1, 8))
OPPONENT_SLOTS = tuple(range(9, 16))
ABSENT = -1.0

CLASS_CODE = {"absent": 0.0, "cue": 0.25, "own": 0.5, "opponent": 0.75, "black": 1.0}
"""Class code of each slot role."""


class ObsUnits(StrEnum):
    """Units of the observation's positions."""

    NORMALIZED = "normalized"
    PAPER_PIXELS = "paper_pixels"


def observation_space(units: ObsUnits = ObsUnits.NORMALIZED) -> spaces.Box:
    """The Box of observations in ``units``."""
    high_xy = 1.0 if ObsUnits(units) is ObsUnits.NORMALIZED else float(max(PAPER_ENV_WINDOW_PX))
    low = np.full((N_SLOTS, 3), ABSENT, dtype=np.float32)
    low[:, 2] = 0.0
    high = np.full((N_SLOTS, 3), high_xy, dtype=np.float32)
    high[:, 2] = 1.0
    return spaces.Box(low=low.ravel(), high=high.ravel(), dtype=np.float32)


def assign_slots(layout: TableLayout, group: Group | None) -> list[int]:
    """The observation slot of each ball of ``layout`` (same order), for a shooter of ``group``.

    ``group=None`` treats solids as own balls (the table is open or holds no group balls).

    Raises:
        ValueError: two balls would share a slot (cannot happen for a valid layout).
    """
    own_class = (group or Group.SOLIDS).ball_class
    slots: list[int | None] = [None] * len(layout)
    free = {"own": list(OWN_SLOTS), "opponent": list(OPPONENT_SLOTS)}
    pending: dict[str, list[int]] = {"own": [], "opponent": []}
    for i, ball in enumerate(layout.balls):
        if ball.ball_class is BallClass.CUE:
            slots[i] = CUE_SLOT
        elif ball.ball_class is BallClass.BLACK:
            slots[i] = BLACK_SLOT
        else:
            role = "own" if ball.ball_class is own_class else "opponent"
            if ball.number is None:
                pending[role].append(i)
                continue
            k = (ball.number - 1) % 8  # 1-7 -> 0-6, 9-15 -> 0-6
            slot = (OWN_SLOTS if role == "own" else OPPONENT_SLOTS)[k]
            slots[i] = slot
            free[role].remove(slot)
    for role, idx in pending.items():
        idx.sort(key=lambda i: (layout.positions[i, 0], layout.positions[i, 1]))
        for i, slot in zip(idx, free[role], strict=False):
            slots[i] = slot
    if any(s is None for s in slots) or len(set(slots)) != len(slots):
        raise ValueError("could not give every ball its own observation slot")
    return [int(s) for s in slots]  # type: ignore[arg-type]


def encode(layout: TableLayout, slots: list[int], units: ObsUnits = ObsUnits.NORMALIZED) -> np.ndarray:
    """The flat observation of ``layout`` whose balls sit in ``slots`` (see :func:`assign_slots`)."""
    obs = np.zeros((N_SLOTS, 3), dtype=np.float32)
    obs[:, :2] = ABSENT
    if len(layout) == 0:
        return obs.ravel()
    spec = layout.spec
    if ObsUnits(units) is ObsUnits.NORMALIZED:
        xy = layout.positions / spec.size
    else:
        xy = table_to_env_pixels(layout.positions, spec)
    for i, slot in enumerate(slots):
        obs[slot, :2] = xy[i]
        obs[slot, 2] = _code(slot)
    return obs.ravel()


def _code(slot: int) -> float:
    if slot == CUE_SLOT:
        return CLASS_CODE["cue"]
    if slot == BLACK_SLOT:
        return CLASS_CODE["black"]
    return CLASS_CODE["own"] if slot in OWN_SLOTS else CLASS_CODE["opponent"]
