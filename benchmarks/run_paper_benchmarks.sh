#!/usr/bin/env bash
# Runs the `paper` physics numbers of docs/benchmarks-planner.md (one core, background-friendly).
# Usage: bash benchmarks/run_paper_benchmarks.sh OUT_DIR N_ORACLE N_SEARCH
set -u
OUT=${1:-benchmarks/results}
NO=${2:-1000}
NS=${3:-1000}
export OMP_NUM_THREADS=1 PYTHONPATH=src
PY=${PY:-python}
mkdir -p "$OUT"
ev() { # name args...
  local name=$1; shift
  echo "=== $name: $*"
  /usr/bin/time -f "%e s wall" $PY -m pix2pockets evaluate planner --physics paper "$@" --no-progress --force \
    --json "$OUT/$name.json" || echo "FAILED $name"
}
# the reference protocol: layout i after np.random.seed(12345 + i), the first 1000 / 300 layouts
ev "paper-oracle" --planner oracle --layouts $NO
ev "paper-oracle-mirror" --planner oracle-mirror --layouts $NO
ev "paper-oracle-mirror-300" --planner oracle-mirror --layouts 300
# the paper's environment with its defects switched back on
ev "paper-oracle-defects" --planner oracle --layouts $NO --paper-defects spawn-in-pocket,early-eight-wins
ev "paper-oracle-mirror-defects" --planner oracle-mirror --layouts $NO --paper-defects spawn-in-pocket,early-eight-wins
ev "paper-search" --planner search --layouts $NS
echo "=== physics check against a pymunk re-creation of the paper's world"
$PY benchmarks/paper_pymunk_check.py --shots 500 --json "$OUT/paper-pymunk-check.json"
echo "=== done"
