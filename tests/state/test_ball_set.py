"""Ball sets: the names of classes and groups in an American and a blackball set."""

from __future__ import annotations

import pytest

from pix2pockets.state.ball import BallClass, Group
from pix2pockets.state.ball_set import (
    BallSet,
    class_name,
    group_choices,
    group_name,
    parse_ball_set,
    parse_group,
)


def test_a_blackball_set_names_its_groups_reds_and_yellows():
    assert class_name(BallClass.SOLID, BallSet.BLACKBALL) == "red"
    assert class_name(BallClass.STRIPE, BallSet.BLACKBALL) == "yellow"
    assert class_name(BallClass.BLACK, BallSet.BLACKBALL) == "black"
    assert group_name(Group.SOLIDS, BallSet.BLACKBALL) == "reds"
    assert group_name("stripes", BallSet.BLACKBALL) == "yellows"
    assert class_name("solid") == "solid" and group_name(Group.STRIPES) == "stripes"


def test_groups_are_read_in_their_set():
    assert parse_group("Reds", BallSet.BLACKBALL) is Group.SOLIDS
    assert parse_group("yellows", BallSet.BLACKBALL) is Group.STRIPES
    assert parse_group("stripes") is Group.STRIPES
    assert parse_group("auto", BallSet.BLACKBALL) == "auto"
    with pytest.raises(ValueError, match="reds, yellows"):
        parse_group("solids", BallSet.BLACKBALL)
    with pytest.raises(ValueError, match="unknown group 'reds' for the american set"):
        parse_group("reds")


def test_set_names_and_choices():
    assert parse_ball_set("BLACKBALL") is BallSet.BLACKBALL
    with pytest.raises(ValueError, match="american, blackball"):
        parse_ball_set("snooker")
    assert group_choices() == ("auto", "solids", "stripes", "reds", "yellows")
    assert group_choices(BallSet.BLACKBALL) == ("auto", "reds", "yellows")
