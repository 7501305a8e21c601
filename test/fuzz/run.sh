#!/usr/bin/env bash
# Runs fuzz targets for a measured time or a number of executions:
#   test/fuzz/run.sh SECONDS [TARGET...]        each target for SECONDS
#   test/fuzz/run.sh --runs N [TARGET...]       each target until N executions
# (default: all targets). Needs the fuzz build (README.md). The committed seed corpus
# test/fuzz/corpus/<target> is read, never written: new inputs go to build/fuzz/work/<target>,
# findings (crash-*, leak-*, timeout-*, oom-*) to build/fuzz/artifacts/<target>/, the log to
# build/fuzz/logs/<target>.log. Prints per target: exit status, executions, wall time,
# executions per second, findings.
set -euo pipefail
cd "$(dirname "$0")/../.."
usage="usage: test/fuzz/run.sh SECONDS|--runs N [TARGET...]"
if [ "${1:-}" = "--runs" ]; then
  runs=${2:?$usage}
  budget=(-runs="$runs")
  shift 2
else
  seconds=${1:?$usage}
  budget=(-max_total_time="$seconds")
  shift
fi
targets=("$@")
((${#targets[@]})) || targets=(stability_params plain_yaml scenario_set space track_csv replay_log)
# Allocation stack traces are kept short: they are only needed to report a finding, and
# recording deep ones costs the YAML targets a tenth of their speed.
export ASAN_OPTIONS="${ASAN_OPTIONS:-malloc_context_size=5}"
for t in "${targets[@]}"; do
  bin=build/fuzz/test/fuzz/fuzz_$t
  [ -x "$bin" ] || { echo "missing $bin: build the fuzz targets first (README.md)" >&2; exit 2; }
  mkdir -p "build/fuzz/work/$t" "build/fuzz/artifacts/$t" build/fuzz/logs
  status=0
  start=$(date +%s)
  "$bin" "${budget[@]}" -timeout=20 -rss_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 -artifact_prefix="build/fuzz/artifacts/$t/" \
    "build/fuzz/work/$t" "test/fuzz/corpus/$t" >"build/fuzz/logs/$t.log" 2>&1 || status=$?
  elapsed=$(($(date +%s) - start))
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build/fuzz/logs/$t.log" | grep -o '[0-9]*$' || true)
  rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "build/fuzz/logs/$t.log" | grep -o '[0-9]*$' || true)
  echo "$t: exit $status, ${execs:-?} executions in ${elapsed} s (${rate:-?}/s), findings: $(ls "build/fuzz/artifacts/$t" | wc -l)"
done
