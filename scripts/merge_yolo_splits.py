"""Make one YOLO dataset view (symlinks) of the same split of several datasets, e.g. synthetic chunks.

Usage:
    python scripts/merge_yolo_splits.py [--force] OUT SPLIT DATASET [DATASET ...]

OUT must not exist yet; ``--force`` replaces it.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path


def main() -> None:
    args = sys.argv[1:]
    force = "--force" in args
    args = [a for a in args if a != "--force"]
    if len(args) < 3:
        sys.exit(__doc__)
    out, split, sources = Path(args[0]), args[1], [Path(p) for p in args[2:]]
    if out.exists():
        if not force:
            sys.exit(f"error: {out} exists; pass --force to replace it")
        shutil.rmtree(out)
    for sub in ("images", "labels", "meta"):
        (out / split / sub).mkdir(parents=True)
    n = 0
    for src in sources:
        if (src / "data.yaml").exists() and not (out / "data.yaml").exists():
            shutil.copy(src / "data.yaml", out / "data.yaml")
        for sub in ("images", "labels", "meta"):
            folder = src / split / sub
            if not folder.is_dir():
                continue
            for f in folder.iterdir():
                (out / split / sub / f.name).symlink_to(f.resolve())
                n += sub == "images"
    print(f"{out}: {n} images in {split} from {len(sources)} datasets")


if __name__ == "__main__":
    main()
