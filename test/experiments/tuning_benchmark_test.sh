#!/bin/sh
# experiments/tuning_benchmark.py end to end on a tiny problem: the golden tune's three one-lap
# training scenarios, a two-dimensional space, 3 evaluations per tune. Checks the summary (one row
# per method and seed, a deterministic method on two seeds only and identical there, the
# reference run), the table and the figure, and that a second call reuses the finished runs.
# Exit 77 (skipped) without a python3 that has numpy and matplotlib.
# Usage: tuning_benchmark_test.sh SCW SOURCE_DIR WORK_DIR
set -u
scw=$1 src=$2 work=$3
py=""
for cand in python3 /usr/bin/python3; do
  if command -v "$cand" >/dev/null 2>&1 && "$cand" -c "import matplotlib, numpy" >/dev/null 2>&1; then
    py=$cand
    break
  fi
done
[ -n "$py" ] || { echo "skipped: no python3 with numpy and matplotlib"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }

rm -rf "$work" && mkdir -p "$work" || exit 1
cat >"$work/space.yaml" <<'YAML'
name: two
parameters:
  - {key: countersteer_system.steering_factor, lo: 0.3, hi: 1.5, scale: linear}
  - {key: SlipControl.TC.rear.slip_threshold_hold_reduce, lo: 3.0, hi: 20.0, scale: linear}
YAML
run() {
  SCW_BIN=$scw "$py" "$src/experiments/tuning_benchmark.py" --out "$work/out" \
    --scenarios "$src/test/golden/golden_set.yaml" --methods sbplx,crs2+sbplx --seeds 1,2,3 \
    --max-evals 3 --reference-evals 5 --reference-method sbplx --jobs 2 \
    --tune-args "--space $work/space.yaml --search-plant-step 0 --no-freeze" >"$work/$1.txt" 2>&1 ||
    fail "tuning_benchmark.py failed: $(cat "$work/$1.txt")"
}
run first
summary=$work/out/summary.csv
[ -f "$summary" ] || fail "no summary.csv"
# sbplx draws no random numbers: seeds 1 and 2 only; crs2+sbplx: all three; one reference run.
[ "$(grep -c '^sbplx,' "$summary")" = 2 ] || fail "sbplx rows: $(cat "$summary")"
[ "$(grep -c '^crs2+sbplx,' "$summary")" = 3 ] || fail "crs2+sbplx rows: $(cat "$summary")"
[ "$(grep -c '^sbplx@5,1,5,' "$summary")" = 1 ] || fail "reference row: $(cat "$summary")"
md=$work/out/tuning-benchmark.md
grep -q "| sbplx | 3 | 2 (deterministic: identical) |" "$md" || fail "table: $(cat "$md")"
grep -q "| crs2+sbplx | 3 | 3 |" "$md" || fail "table: $(cat "$md")"
grep -q "| sbplx@5 | 5 | 1 |" "$md" || fail "table: $(cat "$md")"
[ -s "$work/out/convergence.png" ] || fail "no convergence.png"
# Every run's CPU and wall time are kept beside its folder.
[ -s "$work/out/runs/sbplx/seed1.time" ] || fail "no time file"
# A second call reuses the finished runs: same rows (times included, read back from the files).
cp "$summary" "$work/summary.first"
run second
cmp -s "$summary" "$work/summary.first" || fail "second call differs: $(diff "$work/summary.first" "$summary")"
echo "ok"
