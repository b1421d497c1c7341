#!/usr/bin/env bash
# Runs the `paper` physics numbers of docs/benchmarks-planner.md (one core, background-friendly).
# Usage: bash benchmarks/run_paper_benchmarks.sh OUT_DIR N_ORACLE N_SEARCH
set -u
OUT=${1:-benchmarks/results}
NO=${2:-1000}
NS=${3:-1000}
source "$(dirname "$0")/evaluate_runs.sh"
evp() { local name=$1; shift; ev "$name" --physics paper "$@"; }  # every run here is on the paper physics
# the reference protocol: layout i after np.random.seed(12345 + i), the first 1000 / 300 layouts
evp "paper-oracle" --planner oracle --layouts $NO
evp "paper-oracle-mirror" --planner oracle-mirror --layouts $NO
evp "paper-oracle-mirror-300" --planner oracle-mirror --layouts 300
# the paper's environment with its defects switched back on
evp "paper-oracle-defects" --planner oracle --layouts $NO --paper-defects spawn-in-pocket,early-eight-wins
evp "paper-oracle-mirror-defects" --planner oracle-mirror --layouts $NO --paper-defects spawn-in-pocket,early-eight-wins
evp "paper-search" --planner search --layouts $NS
echo "=== physics check against a pymunk re-creation of the paper's world"
$PY benchmarks/paper_pymunk_check.py --shots 500 --json "$OUT/paper-pymunk-check.json"
echo "=== done"
