"""Plot of clear rate against skill level from the JSON files of ``run_skill_benchmarks.sh``.

Usage::

    PYTHONPATH=src python benchmarks/plot_skill_clear.py benchmarks/results 1000 0 docs/skill_clear_rate.png
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SKILLS = ("pro", "club", "beginner")
PLANNERS = ("search", "oracle")


def load(folder: Path, n: int, seed: int) -> dict[tuple[str, str], dict]:
    """``(skill, planner) -> evaluate planner JSON`` for the files that exist."""
    out = {}
    for skill in SKILLS:
        for planner in PLANNERS:
            path = folder / f"skill-{skill}-{planner}-n{n}-s{seed}.json"
            if path.is_file():
                out[skill, planner] = json.loads(path.read_text())
    return out


def main() -> None:
    folder, n, seed, png = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    data = load(folder, n, seed)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(8, 3.4))
    for ax, key, title in (
        (axes[0], "full_turn_clear", "full-turn clear"),
        (axes[1], "per_shot_success", "per-shot success"),
    ):
        for planner, marker in zip(PLANNERS, ("o", "s"), strict=True):
            xs, ys, lo, hi = [], [], [], []
            for i, skill in enumerate(SKILLS):
                d = data.get((skill, planner))
                if d is None:
                    continue
                xs.append(i)
                ys.append(100 * d[key])
                lo.append(max(0.0, 100 * (d[key] - d[key + "_ci95"][0])))
                hi.append(max(0.0, 100 * (d[key + "_ci95"][1] - d[key])))
            ax.errorbar(xs, ys, yerr=[lo, hi], marker=marker, capsize=3, label=planner)
            for x, y in zip(xs, ys, strict=True):
                ax.annotate(f"{y:.1f}", (x, y), textcoords="offset points", xytext=(6, 4), fontsize=7)
        ax.set_xticks(range(len(SKILLS)), SKILLS)
        ax.set_ylabel("%")
        ax.set_title(f"{title}, {n} racks, 95% intervals", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"wrote {png} from {len(data)} files")


if __name__ == "__main__":
    main()
