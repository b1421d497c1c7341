"""``pix2pockets evaluate TARGET``: a command group; each target lives in its own module.

To add a target, write ``pix2pockets/cli/evaluate_<name>.py`` with ``register(subparsers)`` (adds a parser
and sets ``func``) and add its module path to :data:`TARGETS`.
"""

from __future__ import annotations

import argparse
import importlib

# Evaluation targets: name -> module with register(subparsers).
TARGETS: dict[str, str] = {
    "detector": "pix2pockets.cli.evaluate_detector",
    "planner": "pix2pockets.cli.evaluate_planner",
}


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("evaluate", help="evaluate a component (detector, ...) and write JSON")
    targets = parser.add_subparsers(dest="target", metavar="TARGET")
    for module in TARGETS.values():
        importlib.import_module(module).register(targets)
    parser.set_defaults(func=lambda args: _no_target(parser))


def _no_target(parser: argparse.ArgumentParser) -> int:
    parser.print_help()
    return 2
