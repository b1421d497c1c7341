#!/usr/bin/env bash
# The paper's RL baseline grid (Tables 2 and 3), resumable: re-run to continue where it stopped.
#   STEPS=500000 EPISODES=1000 scripts/run_rl_baselines.sh            # the whole grid, one run at a time
#   STEPS=20000 scripts/run_rl_baselines.sh --env one two             # a subset (args go to rl_grid.py)
# Each run checkpoints every 10k steps into runs/rl/<env>-<algo>[-mask][-maxp]/; a killed job resumes from
# its last checkpoint. Long: at ~100-200 steps/s one 500k-step run takes ~1-1.5 h on this 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
export PYTHONPATH=src OMP_NUM_THREADS=1 MKL_NUM_THREADS=1
PY="${PYTHON:-python}"
STEPS="${STEPS:-500000}"
EPISODES="${EPISODES:-1000}"
"$PY" scripts/rl_grid.py train --steps "$STEPS" "$@"
"$PY" scripts/rl_grid.py evaluate --episodes "$EPISODES" "$@"
"$PY" scripts/rl_grid.py plot --out docs/rl_learning_curves.png "$@"
"$PY" scripts/rl_grid.py table "$@"
