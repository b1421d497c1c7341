"""What the planner benchmarks that play racks of our protocol share: their options, and the default search planner
(no time budget) with the skill's noise, the event simulator and the protocol."""

from __future__ import annotations

import argparse

from pix2pockets.physics import make_simulator
from pix2pockets.planner.evaluation import Protocol, ours_protocol
from pix2pockets.planner.noise import GaussianNoise, noise_model
from pix2pockets.planner.search import SearchConfig, SearchPlanner


def rack_parser(doc: str, racks: int) -> argparse.ArgumentParser:
    """A parser with ``--racks`` (default ``racks``), ``--seed``, ``--skill`` and ``--json``."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--racks", type=int, default=racks)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--skill", default="pro")
    ap.add_argument("--json", default=None)
    return ap


def rack_setup(skill: str) -> tuple[SearchPlanner, GaussianNoise, object, Protocol]:
    """The default search planner without a time budget planning for ``skill``, that skill's noise, the event
    simulator and our protocol."""
    planner = SearchPlanner(SearchConfig(time_budget=None, noise=skill))
    return planner, noise_model(skill), make_simulator("event"), ours_protocol()
