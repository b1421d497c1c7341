# Sourced by the run_*_benchmarks.sh scripts (OUT set first): `ev NAME ARGS...` runs
# `pix2pockets evaluate planner ARGS` on one core into "$OUT/NAME.json" and prints its wall time.
export OMP_NUM_THREADS=1 PYTHONPATH=src
PY=${PY:-python}
mkdir -p "$OUT"
ev() { # name args...
  local name=$1; shift
  local start=$SECONDS
  echo "=== $name: $*"
  $PY -m pix2pockets evaluate planner "$@" --no-progress --force --json "$OUT/$name.json" || echo "FAILED $name"
  echo "$((SECONDS - start)) s wall"
}
