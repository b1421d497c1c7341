"""Whole games: visits, the penalty visits after a foul, ball in hand, a winner."""

from __future__ import annotations

import numpy as np
import pytest

from pix2pockets.physics import make_simulator
from pix2pockets.planner.ball_in_hand import best_placement
from pix2pockets.planner.base import Suggestion
from pix2pockets.planner.evaluation import ours_protocol
from pix2pockets.planner.game import GameRecord, play_game
from pix2pockets.planner.noise import noise_model
from pix2pockets.planner.registry import make_planner
from pix2pockets.rules import Foul, InHand, Outcome, TurnResult
from pix2pockets.state import Shot

SIM = make_simulator("event")
NOISE = noise_model("pro")


class Nudge:
    """A planner that always plays the same very soft stroke."""

    name = "nudge"

    def suggest(self, layout, state, rng=None):
        return [Suggestion(Shot(angle=0.3, speed=0.05), success_probability=0.5)]


def scripted(*outcomes: Outcome):
    """A judge that hands out ``outcomes`` in order (a foul with blackball's two penalty visits)."""
    queue = list(outcomes)

    def judge(result, state):
        outcome = queue.pop(0)
        foul = outcome is Outcome.FOUL
        return TurnResult(outcome, state.group, (Foul.NO_CONTACT,) if foul else (), (), 2 if foul else 0)

    return judge


def small_layout(seed: int = 0):
    return ours_protocol().layout(16, seed, 0)


@pytest.mark.parametrize("penalty", [1, 2])
def test_a_foul_gives_the_opponent_its_penalty_visits(penalty):
    """Foul by player 0, then misses, then a win: who wins shows whose visit it was. With two penalty visits player
    1 shoots the second and third shots, player 0 the fourth and player 1 the fifth; with one, they alternate."""
    outcomes = [Outcome.FOUL, Outcome.END_TURN, Outcome.END_TURN, Outcome.END_TURN, Outcome.WIN]
    judge = scripted(*outcomes)

    def with_penalty(result, state):
        judged = judge(result, state)
        return TurnResult(judged.outcome, judged.group, judged.fouls, (), penalty if judged.fouls else 0)

    record = play_game(small_layout(), (Nudge(), Nudge()), SIM, "blackball", NOISE, np.random.default_rng(0),
                       judge=with_penalty)  # fmt: skip
    assert isinstance(record, GameRecord)
    assert record.shots == 5 and record.fouls == (1, 0) and record.visits == 5
    assert record.winner == (1 if penalty == 2 else 0)


def test_a_loss_hands_the_game_to_the_opponent():
    record = play_game(small_layout(), (Nudge(), Nudge()), SIM, "american", NOISE, np.random.default_rng(0),
                       judge=scripted(Outcome.END_TURN, Outcome.LOSS))  # fmt: skip
    assert record.winner == 0 and record.shots == 2


def test_ball_in_hand_goes_to_a_free_spot_the_planner_likes():
    layout = small_layout()
    without = layout.without([layout.cue_index])
    placed, _ = best_placement(without, make_planner("oracle"), ours_protocol().state, np.random.default_rng(0))
    assert placed.cue_index is not None and len(placed) == len(layout)  # a valid layout (validated on creation)
    with pytest.raises(ValueError, match="already has a cue ball"):
        best_placement(layout, make_planner("oracle"), ours_protocol().state, np.random.default_rng(0))


def test_ball_in_hand_in_baulk_stays_behind_the_baulk_line():
    layout = small_layout()
    without = layout.without([layout.cue_index])
    placed, _ = best_placement(
        without, make_planner("oracle"), ours_protocol().state, np.random.default_rng(0), InHand.BAULK
    )
    assert placed.positions[placed.cue_index, 0] <= layout.spec.baulk_line_x
    anywhere, _ = best_placement(without, make_planner("oracle"), ours_protocol().state, np.random.default_rng(0))
    assert anywhere.cue_index is not None
    with pytest.raises(ValueError, match="needs an area"):
        best_placement(without, make_planner("oracle"), ours_protocol().state, np.random.default_rng(0), InHand.NONE)


class Recorder(Nudge):
    """The nudging planner, keeping every layout it is asked about."""

    def __init__(self, seen):
        self.seen = seen

    def suggest(self, layout, state, rng=None):
        self.seen.append(layout)
        return super().suggest(layout, state, rng)


@pytest.mark.parametrize(("in_hand", "placed"), [(InHand.NONE, False), (InHand.BAULK, True), (InHand.TABLE, True)])
def test_after_a_foul_the_cue_ball_lies_or_is_placed_as_the_rules_say(in_hand, placed):
    """A foul leaving the cue ball where it lies (blackball) gives the opponent that layout; in hand, they place
    it (in baulk: behind the baulk line)."""
    queue = [Outcome.FOUL, Outcome.WIN]

    def judge(result, state):
        outcome = queue.pop(0)
        foul = outcome is Outcome.FOUL
        fouls = (Foul.NO_CONTACT,) if foul else ()
        return TurnResult(outcome, state.group, fouls, (), 2 if foul else 0, in_hand if foul else InHand.NONE)

    seen = []
    players = (Recorder(seen), Recorder(seen))
    layout = small_layout()
    play_game(layout, players, SIM, "blackball", NOISE, np.random.default_rng(0), judge=judge)
    first_final = SIM.simulate(layout, NOISE.perturb(Nudge().suggest(layout, None)[0].shot, np.random.default_rng(0)))
    cue_after = seen[1].positions[seen[1].cue_index]
    lies = np.allclose(cue_after, first_final.final.positions[first_final.final.cue_index])
    assert lies != placed
    if in_hand is InHand.BAULK:
        assert cue_after[0] <= layout.spec.baulk_line_x


def test_a_real_game_is_deterministic_and_ends():
    players = (make_planner("oracle"), make_planner("oracle"))
    runs = [play_game(small_layout(3), players, SIM, "blackball", NOISE, np.random.default_rng(7)) for _ in range(2)]
    a, b = runs
    assert (a.winner, a.shots, a.visits, a.fouls, a.pots) == (b.winner, b.shots, b.visits, b.fouls, b.pots)
    assert np.array_equal(a.final.positions, b.final.positions)
    assert a.winner in (0, 1, None) and a.shots >= 1


def test_two_players_are_needed():
    with pytest.raises(ValueError, match="two players"):
        play_game(small_layout(), (Nudge(),), SIM, "american", NOISE, np.random.default_rng(0))
