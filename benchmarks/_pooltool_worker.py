"""Run shots in pooltool (its own venv; see compare_pooltool.py). Not imported by the project.

Usage: POOLTOOL_PYTHON benchmarks/_pooltool_worker.py IN.json OUT.json

IN: table size, ball constants and cases (ball centres in the pix2pockets table frame, ball 0 the cue
ball, with its initial velocity and spin after the strike). pooltool's frame has the long axis along +y,
so pix2pockets (x, y) maps to pooltool (W - y, x) (a rotation; vectors and spins rotate the same way).
OUT: per case the final centres (pix2pockets frame), the pocketed ball indices and the CPU seconds.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import pooltool as pt
from pooltool import constants as const
from pooltool.objects.ball.datatypes import BallState
from pooltool.physics.resolve.ball_ball.friction import AlciatoreBallBallFriction
from pooltool.physics.resolve.ball_ball.frictional_inelastic import FrictionalInelastic
from pooltool.physics.resolve.ball_cushion.impulse_frictional_inelastic import (
    ImpulseFrictionalInelasticCircular,
    ImpulseFrictionalInelasticLinear,
)
from pooltool.physics.resolve.resolver import Resolver, default_resolver


def main() -> None:
    src, dst = sys.argv[1], sys.argv[2]
    cfg = json.loads(Path(src).read_text())
    L, W, R = cfg["length"], cfg["width"], cfg["R"]
    p = cfg["params"]
    base = default_resolver()
    resolver = Resolver(
        ball_ball=FrictionalInelastic(
            friction=AlciatoreBallBallFriction() if cfg.get("ball_friction") else AlciatoreBallBallFriction(0, 0, 0)
        ),
        ball_linear_cushion=ImpulseFrictionalInelasticLinear(),
        ball_circular_cushion=ImpulseFrictionalInelasticCircular(),
        ball_pocket=base.ball_pocket,
        stick_ball=base.stick_ball,
        transition=base.transition,
        version=base.version,
    )
    engine = pt.physics.engine.PhysicsEngine(resolver=resolver)
    specs = pt.objects.PocketTableSpecs(
        l=L, w=W, corner_pocket_width=cfg["corner_mouth"], side_pocket_width=cfg["side_mouth"]
    )
    table = pt.Table.from_table_specs(specs)
    ball_kw = dict(
        R=R,
        m=p["m"],
        u_s=p["mu_slide"],
        u_r=p["mu_roll"],
        u_sp_proportionality=p["spin_per_metre"],
        u_b=1e-9,  # pooltool requires > 0; unused by the Alciatore ball-ball friction
        e_b=p["e_ball"],
        e_c=p["e_cushion"],
        f_c=p["mu_cushion"],
        g=p["g"],
    )
    out = []
    for case in cfg["cases"]:
        balls = {}
        for k, (x, y) in enumerate(case["xy"]):
            ball = pt.Ball.create(str(k), xy=(W - y, x), **ball_kw)
            balls[str(k)] = ball
        vx, vy, wx, wy, wz = case["cue"]
        rvw = np.array([[W - case["xy"][0][1], case["xy"][0][0], R], [-vy, vx, 0.0], [-wy, wx, wz]])
        balls["0"].state = BallState(rvw=rvw, s=const.sliding, t=0.0)
        system = pt.System(table=table, balls=balls, cue=pt.Cue(cue_ball_id="0", V0=0.0))
        c0 = time.process_time()
        try:
            pt.simulate(system, engine=engine, inplace=True, max_events=20000)
            err = None
        except Exception as e:
            err = f"{type(e).__name__}: {e}"
        cpu = time.process_time() - c0
        final, pocketed = [], []
        for k in range(len(case["xy"])):
            st = system.balls[str(k)].state
            px, py = st.rvw[0][0], st.rvw[0][1]
            final.append([float(py), float(W - px)])
            if st.s == const.pocketed:
                pocketed.append(k)
        out.append({"final": final, "pocketed": pocketed, "cpu_s": cpu, "error": err})
    Path(dst).write_text(json.dumps(out))


if __name__ == "__main__":
    main()
