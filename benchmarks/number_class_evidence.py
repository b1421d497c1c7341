"""Score the detector with the ball-number reader as extra class evidence (an experiment; not the shipped path).

The ball classifier's four ball chances (cue, black, solid, stripe) are multiplied by the reader's chances summed
over each class's numbers, raised to ``--power`` (0 leaves them as shipped), and rescaled to the classifier's
total ball chance; then ``pix2pockets evaluate detector`` runs as usual. Eighteenth session:
``docs/benchmarks-detector.md``. Since the nineteenth session the detector also weighs the classes across the
table by number (``vision/stages/number_posterior.py``); add ``-- --numbers none`` to repeat the eighteenth session's
runs.

Usage:
    PYTHONPATH=src python benchmarks/number_class_evidence.py --power 1 --data DATASET --json OUT.json
        [-- extra 'evaluate detector' options, e.g. --post class-aware]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from pix2pockets.cli.main import main as cli_main
from pix2pockets.vision import ball_classifier
from pix2pockets.vision.stages.ball_numbers import NUMBERS_OF_CLASS, BallNumberReader


def class_chances(number_probs: np.ndarray) -> np.ndarray:
    """(n, 4) chances of cue, black, solid and stripe from the reader's (n, 16) number chances."""
    return np.stack([number_probs[:, list(ns)].sum(axis=1) for ns in NUMBERS_OF_CLASS], axis=1)


def with_number_evidence(reader: BallNumberReader, power: float):
    """A replacement for ``BallClassifier.classify`` that folds in the reader's class chances."""
    shipped = ball_classifier.BallClassifier.classify

    def classify(self, image_rgb, boxes, aspect=None):
        probs = np.asarray(shipped(self, image_rgb, boxes, aspect), dtype=float)
        if len(probs) == 0:
            return probs
        ball = probs[:, :4] * class_chances(reader.read(image_rgb, boxes, aspect)) ** power
        ball *= probs[:, :4].sum(axis=1, keepdims=True) / np.maximum(ball.sum(axis=1, keepdims=True), 1e-12)
        return np.concatenate([ball, probs[:, 4:]], axis=1).astype(np.float32)

    return classify


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--power", type=float, default=1.0, help="weight of the reader's evidence (0: as shipped)")
    ap.add_argument("--data", required=True)
    ap.add_argument("--json", required=True)
    args, extra = ap.parse_known_args()
    ball_classifier.BallClassifier.classify = with_number_evidence(BallNumberReader.from_default(), args.power)
    extra = [a for a in extra if a != "--"]
    return cli_main(["evaluate", "detector", "--data", args.data, "--json", args.json, "--force", *extra])


if __name__ == "__main__":
    sys.exit(main())
