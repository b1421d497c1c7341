"""Copy a synthetic dataset with labels made by the current rules (the images are rendered again and checked).

Usage:
    python scripts/relabel_synth.py [--force] SRC OUT

SRC is a dataset written by ``pix2pockets synth`` (or merged with ``merge_yolo_splits.py``); it is not
modified. OUT must be absent or empty; ``--force`` replaces it.
"""

from __future__ import annotations

import sys

from pix2pockets.synth.relabel import relabel_dataset


def main() -> None:
    args = sys.argv[1:]
    force = "--force" in args
    args = [a for a in args if a != "--force"]
    if len(args) != 2:
        sys.exit(__doc__)
    try:
        counts = relabel_dataset(args[0], args[1], force=force, progress=True)
    except (ValueError, OSError) as err:
        sys.exit(f"error: {err}")
    print(f"{args[1]}: " + ", ".join(f"{n} {split}" for split, n in counts.items() if n))


if __name__ == "__main__":
    main()
