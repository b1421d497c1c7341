"""Ball sets: the American numbered set and the UK blackball set, and the names of their classes and groups.

An ``american`` set has a cue ball, solids 1-7, the 8 and stripes 9-15; a ``blackball`` set (UK 8-ball) has a cue
ball, 7 reds, 7 yellows and the black. The rules and the planner work with two object-ball groups either way: in a
blackball set the reds take the place of the solids (``Group.SOLIDS``, ``BallClass.SOLID``) and the yellows the
place of the stripes, and only the names the user sees change (:func:`class_name`, :func:`group_name`).

Example:
    >>> group_name(Group.SOLIDS, BallSet.BLACKBALL)
    'reds'
    >>> parse_group("yellows", BallSet.BLACKBALL)
    <Group.STRIPES: 'stripes'>
"""

from __future__ import annotations

from enum import StrEnum

from pix2pockets.state.ball import BallClass, Group


class BallSet(StrEnum):
    """The set of balls on the table."""

    AMERICAN = "american"
    BLACKBALL = "blackball"


BALL_SET_CHOICES: tuple[str, ...] = ("auto", *(s.value for s in BallSet))
"""What a user may ask for: a set, or ``auto`` to read it from the photo."""

_CLASS_NAMES: dict[BallSet, dict[BallClass, str]] = {
    BallSet.AMERICAN: {c: c.value for c in BallClass},
    BallSet.BLACKBALL: {
        BallClass.CUE: "cue",
        BallClass.BLACK: "black",
        BallClass.SOLID: "red",
        BallClass.STRIPE: "yellow",
    },
}
_GROUP_NAMES: dict[BallSet, dict[Group, str]] = {
    BallSet.AMERICAN: {g: g.value for g in Group},
    BallSet.BLACKBALL: {Group.SOLIDS: "reds", Group.STRIPES: "yellows"},
}


def parse_ball_set(value: str | BallSet) -> BallSet:
    """A ball set from its name, with a clear error for others."""
    try:
        return BallSet(str(value).lower())
    except ValueError:
        raise ValueError(f"unknown ball set {value!r}; choose {', '.join(s.value for s in BallSet)}") from None


def class_name(ball_class: BallClass | str, ball_set: BallSet = BallSet.AMERICAN) -> str:
    """The name of a ball class in a set: ``solid`` is ``red`` in a blackball set, ``stripe`` is ``yellow``."""
    return _CLASS_NAMES[ball_set][BallClass(ball_class)]


def group_name(group: Group | str, ball_set: BallSet = BallSet.AMERICAN) -> str:
    """The name of a group in a set: ``solids`` is ``reds`` in a blackball set, ``stripes`` is ``yellows``."""
    return _GROUP_NAMES[ball_set][Group(group)]


def group_choices(ball_set: BallSet | None = None) -> tuple[str, ...]:
    """The group names a user may give for a set (every set's when ``None``), ``auto`` first."""
    sets = list(BallSet) if ball_set is None else [ball_set]
    return ("auto", *(name for s in sets for name in _GROUP_NAMES[s].values()))


def set_of_group(name: str) -> BallSet | None:
    """The set whose group is called ``name`` (``reds`` -> blackball), ``None`` for ``auto`` or no group."""
    for ball_set, names in _GROUP_NAMES.items():
        if str(name).lower() in names.values():
            return ball_set
    return None


def parse_group(value: str | Group, ball_set: BallSet = BallSet.AMERICAN) -> Group | str:
    """A group from a user's name for it in ``ball_set`` (``auto`` stays ``"auto"``).

    Raises:
        ValueError: a name that is no group of the set (``reds`` for an American set, say), with the choices.
    """
    text = str(value).lower()
    if text == "auto":
        return "auto"
    for group, name in _GROUP_NAMES[ball_set].items():
        if text == name:
            return group
    raise ValueError(
        f"unknown group {value!r} for the {ball_set.value} set; choose {', '.join(group_choices(ball_set))}"
    )
