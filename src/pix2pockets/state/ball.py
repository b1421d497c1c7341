"""Balls: class, number and group."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum


class BallClass(StrEnum):
    """Detector-level ball classes (the paper's four ball classes)."""

    CUE = "cue"
    BLACK = "black"
    SOLID = "solid"
    STRIPE = "stripe"


class Group(StrEnum):
    """A player's object-ball group in 8-ball."""

    SOLIDS = "solids"
    STRIPES = "stripes"

    @property
    def ball_class(self) -> BallClass:
        return BallClass.SOLID if self is Group.SOLIDS else BallClass.STRIPE

    @property
    def other(self) -> Group:
        return Group.STRIPES if self is Group.SOLIDS else Group.SOLIDS


CLASS_CAPS: dict[BallClass, int] = {
    BallClass.CUE: 1,
    BallClass.BLACK: 1,
    BallClass.SOLID: 7,
    BallClass.STRIPE: 7,
}
"""How many balls of each class a table can hold."""


def class_of_number(number: int) -> BallClass:
    """The class of ball ``number`` (0 cue, 1-7 solid, 8 black, 9-15 stripe)."""
    if not 0 <= number <= 15:
        raise ValueError(f"ball number must be 0-15, got {number}")
    if number == 0:
        return BallClass.CUE
    if number == 8:
        return BallClass.BLACK
    return BallClass.SOLID if number < 8 else BallClass.STRIPE


def parse_ball_class(value: str) -> BallClass:
    """Parse a class name (case-insensitive) with a clear error for unknown names."""
    try:
        return BallClass(str(value).lower())
    except ValueError:
        raise ValueError(f"unknown ball class {value!r}; expected one of {[c.value for c in BallClass]}") from None


@dataclass(frozen=True, slots=True)
class Ball:
    """One ball.

    Attributes:
        ball_class: cue, black, solid or stripe.
        number: 0-15 when known (0 is the cue ball), ``None`` when only the class is known (e.g. from a
            photo).
    """

    ball_class: BallClass
    number: int | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.ball_class, BallClass):
            object.__setattr__(self, "ball_class", parse_ball_class(self.ball_class))
        if self.number is not None and class_of_number(self.number) is not self.ball_class:
            raise ValueError(f"ball number {self.number} is not a {self.ball_class.value} ball")

    @classmethod
    def numbered(cls, number: int) -> Ball:
        """The ball with this number."""
        return cls(class_of_number(number), number)

    @property
    def group(self) -> Group | None:
        """The group this ball belongs to (``None`` for cue and black)."""
        if self.ball_class is BallClass.SOLID:
            return Group.SOLIDS
        if self.ball_class is BallClass.STRIPE:
            return Group.STRIPES
        return None

    @property
    def label(self) -> str:
        """Short display label: the number when known, else the class."""
        return str(self.number) if self.number is not None else self.ball_class.value
