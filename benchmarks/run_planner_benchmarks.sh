#!/usr/bin/env bash
# Runs the planner numbers of docs/benchmarks-planner.md one after another (one core, background-friendly).
# Usage: bash benchmarks/run_planner_benchmarks.sh OUT_DIR N_ORACLE N_SEARCH N_OTHER
set -u
OUT=${1:-benchmarks/results}
NO=${2:-1000}
NS=${3:-1000}
NR=${4:-1000}
source "$(dirname "$0")/evaluate_runs.sh"
ev "event-none-search" --planner search --balls 16 --layouts $NS --seed 0 --noise none --physics event
ev "event-fastfiz-search" --planner search --balls 16 --layouts $NS --seed 0 --noise fastfiz --physics event
ev "event-fastfiz-search-seed1" --planner search --balls 16 --layouts $NS --seed 1 --noise fastfiz --physics event
for p in oracle search; do  # the paper's 1-ball: pot the lone cue ball
  ev "event-none-$p-1ball" --planner $p --balls 1 --layouts $NO --seed 0 --noise none --physics event
  ev "event-fastfiz-$p-1ball" --planner $p --balls 1 --layouts $NO --seed 0 --noise fastfiz --physics event
done
for p in oracle oracle-mirror; do
  ev "event-none-$p" --planner $p --balls 16 --layouts $NO --seed 0 --noise none --physics event
  ev "event-fastfiz-$p" --planner $p --balls 16 --layouts $NO --seed 0 --noise fastfiz --physics event
done
for p in oracle-rand-max oracle-rand-max-mirror oracle-rand-rand oracle-rand-rand-mirror; do
  ev "event-none-$p" --planner $p --balls 16 --layouts $NR --seed 0 --noise none --physics event
done
for p in oracle oracle-mirror; do
  ev "pymunk-none-$p" --planner $p --balls 16 --layouts $NR --seed 0 --noise none --physics pymunk
done
echo "=== aim-precision"
$PY -m pix2pockets experiment aim-precision --planners oracle oracle-mirror --layouts 400 --force --json "$OUT/aim-precision-oracle.json"
echo "=== ball-shift"
$PY -m pix2pockets experiment ball-shift --planners oracle oracle-mirror search --layouts 400 --force --json "$OUT/ball-shift.json"
echo "=== decision time"
$PY benchmarks/planner_decision_time.py --layouts 50 --json "$OUT/decision-time.json"
echo "=== aim-precision search"
$PY -m pix2pockets experiment aim-precision --planners search --layouts 100 --force --json "$OUT/aim-precision-search.json"
echo "=== done"
