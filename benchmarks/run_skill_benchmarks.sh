#!/usr/bin/env bash
# Clear rates per skill level (docs/benchmarks-planner.md, "Skill levels"): the search planner planning for
# the player's own noise, and the Oracle under the same noise, one after another on one core.
# Usage: bash benchmarks/run_skill_benchmarks.sh OUT_DIR N_LAYOUTS [SEED]
set -u
OUT=${1:-benchmarks/results}
N=${2:-1000}
SEED=${3:-0}
source "$(dirname "$0")/evaluate_runs.sh"
for skill in pro club beginner; do
  ev "skill-$skill-search-n$N-s$SEED" --planner search --balls 16 --layouts "$N" --seed "$SEED" --skill "$skill"
  ev "skill-$skill-oracle-n$N-s$SEED" --planner oracle --balls 16 --layouts "$N" --seed "$SEED" --skill "$skill"
done
