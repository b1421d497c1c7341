"""Score the detector with variants of the table-wide class scores (``vision/stages/number_posterior.py``).

The shipped scoring spreads each candidate's own class scores over its class's numbers by the ball-number
reader's chances within the class and weighs every number across the table (at most once). The variants:
``--power A`` also multiplies the own scores by the reader's class sums to the power A (total kept);
``--absent`` changes the "number not in view" odds, ``--object-absent`` those of the object balls only;
``--uniform`` replaces the reader's chances by 1/16 (a control: only "one class per ball" is then weighed
across the table); ``--keep-one`` scores the cue and the 8 as without the reader. Then ``pix2pockets evaluate
detector`` runs as usual. Nineteenth session: ``docs/benchmarks-detector.md``.

Usage:
    PYTHONPATH=src python benchmarks/number_posterior_variants.py [--power A] [--absent ODDS]
        [--object-absent ODDS] [--uniform] [--keep-one] --data DATASET --json OUT.json
        [-- extra 'evaluate detector' options, e.g. --split test]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from pix2pockets.cli.main import main as cli_main
from pix2pockets.vision import ball_classifier, number_posterior
from pix2pockets.vision.classes import ONE_PER_TABLE
from pix2pockets.vision.detect.postprocess import at_most_one_posterior
from pix2pockets.vision.stages.ball_numbers import N_NUMBERS, NUMBERS_OF_CLASS


def variant_scores(args: argparse.Namespace):
    """A replacement for ``table_class_scores`` as the options describe."""

    def scores(own: np.ndarray, number_probs: np.ndarray, absent_odds: float) -> np.ndarray:
        probs = np.full_like(number_probs, 1.0 / N_NUMBERS) if args.uniform else number_probs
        weighed = own
        if args.power:
            sums = np.stack([number_probs[:, list(ns)].sum(axis=1) for ns in NUMBERS_OF_CLASS], axis=1)
            weighed = own * np.maximum(sums, 1e-9) ** args.power
            weighed *= own.sum(axis=1, keepdims=True) / np.maximum(weighed.sum(axis=1, keepdims=True), 1e-12)
        absent = np.full(N_NUMBERS, args.absent)
        if args.object_absent is not None:
            absent[[n for n in range(N_NUMBERS) if n not in (0, 8)]] = args.object_absent
        out = number_posterior.table_class_scores(weighed, probs, absent)
        if args.keep_one:
            for kind in ONE_PER_TABLE:
                out[:, kind] = at_most_one_posterior(own[:, kind], ball_classifier.IN_VIEW_ABSENT_ODDS)
        return out

    return scores


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--power", type=float, default=0.0, help="weight of the reader's class sums (0: as shipped)")
    ap.add_argument("--absent", type=float, default=ball_classifier.IN_VIEW_ABSENT_ODDS, help="'not in view' odds")
    ap.add_argument("--object-absent", type=float, default=None, help="'not in view' odds of numbers 1-7, 9-15")
    ap.add_argument("--uniform", action="store_true", help="control: the reader's chances replaced by 1/16")
    ap.add_argument("--keep-one", action="store_true", help="cue and 8 scored as without the reader")
    ap.add_argument("--data", required=True)
    ap.add_argument("--json", required=True)
    args, extra = ap.parse_known_args()
    ball_classifier.table_class_scores = variant_scores(args)
    extra = [a for a in extra if a != "--"]
    return cli_main(["evaluate", "detector", "--data", args.data, "--json", args.json, "--force", *extra])


if __name__ == "__main__":
    sys.exit(main())
