import json

import numpy as np
import pytest

from pix2pockets.geometry import TableSpec
from pix2pockets.state import (
    Ball,
    BallClass,
    TableLayout,
    eight_ball_rack,
    layout_from_dict,
    layout_to_dict,
    load_layout,
    random_layout,
    save_layout,
)

R = TableSpec().ball_radius


def test_ball_classes():
    assert Ball.numbered(0).ball_class is BallClass.CUE
    assert Ball.numbered(8).ball_class is BallClass.BLACK
    assert Ball.numbered(3).ball_class is BallClass.SOLID
    assert Ball.numbered(12).ball_class is BallClass.STRIPE
    assert Ball("stripe").ball_class is BallClass.STRIPE


@pytest.mark.parametrize(
    ("balls", "positions", "match"),
    [
        ([Ball.numbered(0), Ball.numbered(1)], [[1.0, 0.5], [1.0 + R, 0.5]], "overlap"),
        ([Ball.numbered(0)], [[R / 2, 0.5]], "off the playing surface"),
        ([Ball.numbered(0)], [[1.0, 2.0]], "off the playing surface"),
        ([Ball(BallClass.CUE), Ball(BallClass.CUE)], [[1.0, 0.5], [2.0, 0.5]], "at most 1"),
        ([Ball.numbered(3), Ball.numbered(3)], [[1.0, 0.5], [2.0, 0.5]], "more than once"),
        ([Ball.numbered(0)], [[np.nan, 0.5]], "finite"),
        ([Ball.numbered(0)], [[1.0, 0.5], [2.0, 0.5]], "positions"),
    ],
)
def test_bad_layouts(balls, positions, match):
    with pytest.raises(ValueError, match=match):
        TableLayout(tuple(balls), positions)


def test_bad_ball():
    with pytest.raises(ValueError, match="unknown ball class"):
        Ball("spotted")
    with pytest.raises(ValueError, match="not a solid"):
        Ball(BallClass.SOLID, 12)


def test_touching_balls_allowed():
    lay = TableLayout((Ball.numbered(0), Ball.numbered(1)), [[1.0, 0.5], [1.0 + 2 * R, 0.5]])
    assert np.linalg.norm(lay.positions[1] - lay.positions[0]) == pytest.approx(2 * R)


def test_positions_read_only():
    lay = TableLayout((Ball.numbered(0),), [[1.0, 0.5]])
    with pytest.raises(ValueError):
        lay.positions[0, 0] = 2.0


def test_rack_is_legal():
    lay = eight_ball_rack(rng=np.random.default_rng(1))
    assert len(lay) == 16
    assert lay.cue_index == 0
    black = lay.black_index
    assert lay.positions[black, 0] > lay.spec.foot_spot[0]
    back_row = [lay.balls[i].ball_class for i in (11, 15)]
    assert sorted(back_row) == sorted([BallClass.SOLID, BallClass.STRIPE])


def test_random_layout_seeded():
    a = random_layout(np.random.default_rng(3), list(range(16)))
    b = random_layout(np.random.default_rng(3), list(range(16)))
    assert a == b
    spec = a.spec
    for p in spec.pockets:
        assert np.all(np.linalg.norm(a.positions - p.centre, axis=1) > p.capture_radius + R)


def test_json_round_trip(tmp_path):
    lay = random_layout(np.random.default_rng(0), [0, 8, 1, 9])
    path = tmp_path / "lay.json"
    save_layout(lay, path)
    assert load_layout(path) == TableLayout(lay.balls, np.round(lay.positions, 6), lay.spec)
    with pytest.raises(ValueError, match="exists"):
        save_layout(lay, path)
    save_layout(lay, path, overwrite=True)


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ([], "JSON object"),
        ({"balls": "x"}, "'balls' list"),
        ({"balls": [{"class": "cue", "x": 1.0}]}, "missing 'y'"),
        ({"balls": [{"class": "ghost", "x": 1.0, "y": 0.5}]}, "unknown ball class"),
        ({"balls": [{"class": "cue", "x": "a", "y": 0.5}]}, "balls\\[0\\]"),
        ({"balls": [{"class": "cue", "number": 3, "x": 1.0, "y": 0.5}]}, "not a cue"),
        ({"format": "other", "balls": []}, "not a layout"),
        ({"table": "12ft", "balls": []}, "unknown table preset"),
    ],
)
def test_bad_layout_dicts(data, match):
    with pytest.raises(ValueError, match=match):
        layout_from_dict(data)


def test_load_errors(tmp_path):
    with pytest.raises(ValueError, match="not found"):
        load_layout(tmp_path / "nope.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ValueError, match="cannot read"):
        load_layout(bad)


def test_dict_is_json():
    lay = random_layout(np.random.default_rng(0), [0, 8])
    doc = json.loads(json.dumps(layout_to_dict(lay)))
    assert doc == layout_to_dict(lay)
