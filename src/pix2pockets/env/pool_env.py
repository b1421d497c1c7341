"""The pool environment: one Gymnasium class for the 1-ball, 2-ball and all-ball variants."""

from __future__ import annotations

from enum import StrEnum
from typing import Any, ClassVar

import gymnasium as gym
import numpy as np

from pix2pockets.env.actions import ActionMap, ActionType, paper_action_map
from pix2pockets.env.masks import (
    HitpointFinder,
    MaskKind,
    cue_pocket_angles,
    direction_mask,
    full_mask,
    hitpoint_angles,
)
from pix2pockets.env.observation import ObsUnits, assign_slots, encode, observation_space
from pix2pockets.env.render import HumanWindow, draw_table
from pix2pockets.env.reward import BallSetup, PaperReward, RewardFn, ShotContext, contact_departure
from pix2pockets.geometry.raster import TableRaster, paper_table
from pix2pockets.geometry.table import TableSpec, table_preset
from pix2pockets.physics import Simulator, make_simulator
from pix2pockets.rules import GameState, Outcome, judge_for, own_balls
from pix2pockets.state import BallClass, Group, Shot, TableLayout, random_layout
from pix2pockets.state.ball_set import BallSet, group_name, parse_ball_set, parse_group

DEFAULT_PHYSICS = "event"
"""Simulator backend used when ``physics`` is not given."""

_BALL_NUMBERS = {BallSetup.ONE: [0], BallSetup.TWO: [0, 8], BallSetup.ALL: list(range(16))}


class EpisodeMode(StrEnum):
    """Episode structure (``mode=`` argument).

    ``"turn"``: the paper's environment. A legal pot of a target ball earns another shot from the
    resulting layout; the episode terminates at the first shot that does not (a miss, a foul), or at a
    win or a loss. ``info["is_success"]`` at the end: the game was won - the paper's "Full Turn" in the
    all-ball variant.

    ``"shot"``: every episode is one shot from a fresh layout; ``info["is_success"]``: the shot succeeded
    (a legal pot or a win) - the paper's per-shot success rates.
    """

    TURN = "turn"
    SHOT = "shot"


class PoolEnv(gym.Env):
    """8-ball pool on a 9-foot table (or the paper's own table), one cue stroke per step.

    ## Description
    The agent sees every ball's position and class and plays one stroke per step: a direction and a
    power. The stroke sets the cue ball moving (centre hit, no spin) and a physics backend simulates the
    shot to rest. Three variants (``balls=``), as in the pix2pockets paper (sec. 6.2):

    | variant | id                          | balls   | goal                                                     |
    |---------|-----------------------------|---------|----------------------------------------------------------|
    | one     | ``pix2pockets/OneBall-v0``  | cue     | pocket the cue ball                                      |
    | two     | ``pix2pockets/TwoBall-v0``  | cue + 8 | pocket the 8 with the cue ball, cue ball stays on table  |
    | all     | ``pix2pockets/AllBall-v0``  | 16      | pocket your group, then the 8, without a foul            |

    Fouls and wins follow our 8-ball rules (:mod:`pix2pockets.rules`): the first ball hit must be a target,
    after contact a ball must drop or touch a cushion, the cue ball must stay up, and the 8 wins only when
    the group was cleared before the shot (an early 8 loses, even together with the last own ball).

    ## Action Space
    ``action_type="discrete"`` (default, the paper's): ``MultiDiscrete([36000, 30])``

    | index | meaning   | mapping                                                          |
    |-------|-----------|------------------------------------------------------------------|
    | 0     | direction | ``a / 100 - 180`` degrees, counter-clockwise from +x (to foot)  |
    | 1     | power     | linear ``min_speed .. max_speed`` (0.2 .. 8.0 m/s), 30 levels    |

    ``action_type="continuous"``: ``Box(-1, 1, (2,))``: direction ``180 * a[0]`` degrees, speed
    ``min_speed + (a[1] + 1) / 2 * (max_speed - min_speed)``. Optional Gaussian execution noise:
    ``aim_noise_deg`` [deg], ``speed_noise`` [m/s]. See :mod:`pix2pockets.env.actions`.
    ``physics="paper"``: the paper's powers, 0.019-0.971 m/s in 30 levels (10-500 px/s in its world), up to
    0.699 m/s continuous; the direction is the same table-frame angle (the paper's own pixel angle, with
    ``v`` down, is its negative).
    ``action_masks()`` (discrete only) gives MaskablePPO the direction bins of the planner's hitpoints.

    ## Observation Space
    ``Box(shape=(48,), float32)``: ``(x, y, c)`` for each of 16 ball slots, flattened slot by slot
    (``obs.reshape(16, 3)`` gives one row per slot).

    | slot   | ball               |
    |--------|--------------------|
    | 0      | cue ball           |
    | 1-7    | own group (target) |
    | 8      | the 8-ball         |
    | 9-15   | opponent's group   |

    ``x, y`` in ``[0, 1]`` (``x / length``, ``y / width``; table frame, origin at the head-bottom corner),
    or the paper's pixels with ``obs_units="paper_pixels"``. ``c``: 0.25 cue, 0.5 own, 0.75 opponent,
    1.0 the 8. An absent ball (pocketed, or not in this variant) is ``(-1, -1, 0)``.
    See :mod:`pix2pockets.env.observation`.

    ## Rewards
    The paper's reward (:class:`~pix2pockets.env.reward.PaperReward`): +100 win, -100 loss, +10 per target
    ball hit, +50 per target ball pocketed, ``1000 / (v + 10) - 50`` for the best pocket direction ``v``
    [deg] of the first ball hit, ``-50 d / D`` when nothing is hit, -80 for pocketing the cue ball (not in
    the 1-ball variant, where that is the goal); clipped to [-210, 210] and divided by 210. Any
    :class:`~pix2pockets.env.reward.RewardFn` can replace it (``reward_fn=``).

    ## Starting State
    Random legal layouts (no overlap, centres a ball radius inside the cushions and clear of every
    pocket) drawn from ``self.np_random``; in the all-ball variant the shooter's group is drawn too.
    ``reset(options={"layout": TableLayout, "group": "solids" | "stripes" | "reds" | "yellows"})`` starts from a
    given layout (e.g. read from a photo); the 1-ball variant accepts only a lone cue ball, the others need the
    cue ball and the 8.

    ## Episode End
    Terminated: in ``mode="turn"`` (default) at the first shot that does not earn another shot, or at a
    win or a loss; in ``mode="shot"`` after every shot. Truncated only when the physics backend fails on
    a shot (see ``sim_errors``); a turn has at most 8 shots.
    ``info``: ``outcome``, ``fouls``, ``pocketed``, ``shot_success``, ``won``, ``shots``,
    ``reward_terms`` and, at the end, ``is_success``.

    ## Arguments
    ``gymnasium.make("pix2pockets/AllBall-v0", **kwargs)`` or ``PoolEnv(balls="all", **kwargs)``:

    * ``balls``: ``"one"``, ``"two"`` or ``"all"``.
    * ``action_type``: ``"discrete"`` or ``"continuous"``.
    * ``mode``: ``"turn"`` or ``"shot"`` (see Episode End).
    * ``physics``: simulator backend name (``"event"``, the default; ``"paper"``: the paper's own environment
      dynamics on its table; ``"pymunk"``) or a ``Simulator``; ``physics_params``: keyword parameters for
      the backend.
    * ``table``: preset name (``"9ft"``, ``"8ft"``, ``"7ft"``, ``"6ft"``, ``"uk7"``, ``"uk6"``) or a
      ``TableSpec``; default the 9-foot table, the UK 7-foot one for a blackball set, the paper's
      (:func:`~pix2pockets.geometry.raster.paper_table`) with ``physics="paper"``.
    * ``ball_set``: ``"american"`` (solids and stripes) or ``"blackball"`` (reds and yellows, which play as the
      solids and the stripes; the reset info and the ``group`` option use their names). The turn is judged the
      same way: WEPF blackball rules end a turn, foul or not, where these rules do (their foul penalty, two visits
      for the opponent, lies beyond one turn).
    * ``n_angles``, ``n_powers``, ``min_speed``, ``max_speed``: the action mapping (defaults 0.2-8.0 m/s;
      the paper's power levels with ``physics="paper"``).
    * ``aim_noise_deg``, ``speed_noise``: execution noise (0 = none).
    * ``reward_fn``: a ``RewardFn`` (default ``PaperReward()``).
    * ``obs_units``: ``"normalized"`` or ``"paper_pixels"``.
    * ``mask_kind``: ``"direct"`` or ``"mirror"`` hitpoints for ``action_masks()``; ``mask_width``: extra
      bins allowed on each side of a hitpoint's bin; ``hitpoint_finder``: replaces the planner's
      ``find_hitpoints``.
    * ``render_mode``: ``None``, ``"rgb_array"`` or ``"human"``; ``render_width``: image width [px].
    * ``sim_errors``: ``"truncate"`` (default): a shot the backend cannot finish (its bounded event count
      or time cap, a ``RuntimeError``) truncates the episode with reward 0 and ``info["sim_error"]``;
      ``"raise"`` re-raises it.

    ## Version History
    * v0: initial version.
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["human", "rgb_array"], "render_fps": 4}

    def __init__(
        self,
        balls: str = "all",
        action_type: str = "discrete",
        mode: str = EpisodeMode.TURN,
        physics: str | Simulator | None = None,
        physics_params: dict[str, Any] | None = None,
        table: str | TableSpec | None = None,
        n_angles: int = 36_000,
        n_powers: int = 30,
        min_speed: float | None = None,
        max_speed: float | None = None,
        aim_noise_deg: float = 0.0,
        speed_noise: float = 0.0,
        reward_fn: RewardFn | None = None,
        obs_units: str = ObsUnits.NORMALIZED,
        mask_kind: str = MaskKind.DIRECT,
        mask_width: int = 0,
        hitpoint_finder: HitpointFinder | None = None,
        render_mode: str | None = None,
        render_width: int = 800,
        sim_errors: str = "truncate",
        ball_set: str = "american",
    ) -> None:
        self.setup = BallSetup(balls)
        self.mode = EpisodeMode(mode)
        self.ball_set = parse_ball_set(ball_set)
        paper = physics == "paper"
        if table is None:
            table = paper_table() if paper else ("uk7" if self.ball_set is BallSet.BLACKBALL else "9ft")
        self.spec_table = table if isinstance(table, TableSpec) else table_preset(table)
        default_actions = min_speed is None and max_speed is None and (n_angles, n_powers) == (36_000, 30)
        if paper and default_actions:
            self.actions = paper_action_map(action_type, aim_noise_deg, speed_noise)
        else:
            lo = 0.2 if min_speed is None else min_speed
            hi = 8.0 if max_speed is None else max_speed
            self.actions = ActionMap(ActionType(action_type), n_angles, n_powers, lo, hi, aim_noise_deg, speed_noise)
        self.action_space = self.actions.space
        self.obs_units = ObsUnits(obs_units)
        self.observation_space = observation_space(self.obs_units)
        if physics is None or isinstance(physics, str):
            self.simulator = make_simulator(physics or DEFAULT_PHYSICS, **(physics_params or {}))
        else:
            if physics_params:
                raise ValueError("physics_params only apply when physics is a backend name")
            self.simulator = physics
        self.reward_fn: RewardFn = reward_fn if reward_fn is not None else PaperReward()
        self.mask_kind = MaskKind(mask_kind)
        if mask_width < 0:
            raise ValueError(f"mask_width must be >= 0, got {mask_width}")
        self.mask_width = mask_width
        self.hitpoint_finder = hitpoint_finder
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']} or None, got {render_mode!r}")
        self.render_mode = render_mode
        self.render_width = render_width
        if sim_errors not in ("truncate", "raise"):
            raise ValueError(f"sim_errors must be 'truncate' or 'raise', got {sim_errors!r}")
        self.sim_errors = sim_errors
        self._window: HumanWindow | None = None
        self.layout: TableLayout | None = None
        self.group: Group | None = None
        self._slots: list[int] = []
        self._shots = 0
        self._last_shot: Shot | None = None
        self._last_start: np.ndarray | None = None
        self._mask: np.ndarray | None = None

    # ------------------------------------------------------------------ gymnasium API
    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict]:
        super().reset(seed=seed)
        options = dict(options or {})
        layout = options.pop("layout", None)
        group = options.pop("group", None)
        if group is not None:
            group = parse_group(group, self.ball_set)
            if group == "auto":
                raise ValueError("reset option 'group' names a group (solids or stripes; reds or yellows), not auto")
        if options:
            raise ValueError(f"unknown reset options {sorted(options)}; known: layout, group")
        if layout is None:
            layout = random_layout(self.np_random, _BALL_NUMBERS[self.setup], self.spec_table)
            if group is None and self.setup is BallSetup.ALL:
                group = Group.SOLIDS if self.np_random.random() < 0.5 else Group.STRIPES
        else:
            self._check_layout(layout)
        self.group = Group(group) if group is not None else Group.SOLIDS
        self.layout = layout
        self._slots = assign_slots(layout, self.group)
        self._shots = 0
        self._last_shot = None
        self._last_start = None
        self._mask = None
        if self.render_mode == "human":
            self.render()
        return self._obs(), {"group": group_name(self.group, self.ball_set), "ball_set": self.ball_set.value}

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        if self.layout is None:
            raise RuntimeError("call reset() before step()")
        before = self.layout
        cue = before.cue_index
        if cue is None:
            raise RuntimeError("the episode has ended (no cue ball on the table); call reset()")
        shot = self.actions.to_shot(np.asarray(action), self.np_random)
        try:
            result = self.simulator.simulate(before, shot)
        except RuntimeError as err:  # the backend's bounded failure (event cap, time cap)
            if self.sim_errors == "raise":
                raise
            gym.logger.warn(f"shot simulation failed, episode truncated: {err}")
            self._shots += 1
            info = {"outcome": "sim_error", "sim_error": str(err), "shot_success": False, "won": False}
            info["shots"] = self._shots
            return self._obs(), 0.0, False, True, info
        targets = tuple(self.targets(before))
        if self.setup is BallSetup.ONE:
            turn = None
            won = result.cue_pocketed
            lost = False
            succeeded = won
            outcome = Outcome.WIN.value if won else Outcome.END_TURN.value
            fouls: list[str] = []
        else:
            turn = judge_for(self.ball_set)(result, GameState(self.group))
            won = turn.outcome is Outcome.WIN
            lost = turn.outcome is Outcome.LOSS or result.cue_pocketed
            succeeded = turn.outcome in (Outcome.CONTINUE, Outcome.WIN)
            outcome = turn.outcome.value
            fouls = [f.value for f in turn.fouls]
        ctx = ShotContext(
            self.setup, shot, result, targets, turn, won, lost, succeeded, contact_departure(result, shot)
        )
        terms = self.reward_fn.terms(ctx) if isinstance(self.reward_fn, PaperReward) else None
        reward = float(self.reward_fn.total(terms) if terms is not None else self.reward_fn(ctx))
        self._shots += 1
        self._last_shot = shot
        self._last_start = before.positions[cue].copy()
        self.layout = result.final
        self._slots = [self._slots[i] for i in result.final_ids]
        self._mask = None
        continues = self.mode is EpisodeMode.TURN and turn is not None and turn.outcome is Outcome.CONTINUE
        terminated = not continues
        info: dict[str, Any] = {
            "outcome": outcome,
            "fouls": fouls,
            "pocketed": len(result.pocketed),
            "shot_success": succeeded,
            "won": won,
            "shots": self._shots,
        }
        if terms is not None:
            info["reward_terms"] = terms
        if terminated:
            info["is_success"] = won if self.mode is EpisodeMode.TURN else succeeded
        if self.render_mode == "human":
            self.render()
        return self._obs(), reward, terminated, False, info

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn('render() called without a render_mode; pass render_mode="rgb_array" or "human"')
            return None
        if self.layout is None:
            raise RuntimeError("call reset() before render()")
        raster = TableRaster.fit(self.layout.spec, self.render_width)
        frame = draw_table(self.layout, raster, self._last_shot, self._last_start)
        if self.render_mode == "rgb_array":
            return frame
        if self._window is None:
            self._window = HumanWindow()
        self._window.show(frame, self.metadata["render_fps"])
        return None

    def close(self) -> None:
        if self._window is not None:
            self._window.close()
            self._window = None

    # ------------------------------------------------------------------ extras
    def targets(self, layout: TableLayout | None = None) -> list[int]:
        """Indices of the target ("blue") balls: own group while any is left, else the 8."""
        layout = layout if layout is not None else self.layout
        if layout is None or self.setup is BallSetup.ONE:
            return []
        own = own_balls(layout, self.group)
        if own:
            return own
        black = layout.black_index
        return [] if black is None else [black]

    def action_masks(self) -> np.ndarray:
        """Boolean mask for MaskablePPO: the direction bins of the hitpoints, all power levels.

        Raises:
            ValueError: the action space is continuous.
        """
        if self.actions.action_type is not ActionType.DISCRETE:
            raise ValueError("action_masks() needs action_type='discrete'")
        if self.layout is None:
            raise RuntimeError("call reset() before action_masks()")
        if self._mask is None:
            if self.setup is BallSetup.ONE:
                angles = cue_pocket_angles(self.layout, self.mask_kind)
            elif self.layout.cue_index is None:
                angles = np.zeros(0)
            else:
                angles = hitpoint_angles(self.layout, self.targets(), self.mask_kind, self.hitpoint_finder)
            direction = direction_mask(angles, self.actions.n_angles, self.mask_width)
            self._mask = full_mask(direction, self.actions.n_powers)
        return self._mask.copy()

    def _obs(self) -> np.ndarray:
        if self.layout is None:
            raise RuntimeError("call reset() first")
        return encode(self.layout, self._slots, self.obs_units)

    def _check_layout(self, layout: TableLayout) -> None:
        if not isinstance(layout, TableLayout):
            raise ValueError(f"options['layout'] must be a TableLayout, got {type(layout).__name__}")
        if layout.cue_index is None:
            raise ValueError("options['layout'] has no cue ball")
        if self.setup is BallSetup.ONE and len(layout) != 1:
            raise ValueError("the 1-ball variant takes a layout with only the cue ball")
        if self.setup is not BallSetup.ONE and layout.black_index is None:
            raise ValueError(f"the {self.setup.value}-ball variant needs the 8-ball in options['layout']")
        if self.setup is BallSetup.TWO and any(
            b.ball_class not in (BallClass.CUE, BallClass.BLACK) for b in layout.balls
        ):
            raise ValueError("the 2-ball variant takes a layout with only the cue ball and the 8")
