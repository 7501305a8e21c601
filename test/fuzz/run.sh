#!/usr/bin/env bash
# Runs fuzz targets for a measured time: test/fuzz/run.sh SECONDS [TARGET...] (default: all).
# Needs the fuzz build (README.md). The committed seed corpus test/fuzz/corpus/<target> is read,
# never written: new inputs go to build/fuzz/work/<target>, findings (crash-*, leak-*, timeout-*,
# oom-*) to build/fuzz/artifacts/<target>/, the log to build/fuzz/logs/<target>.log.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:?usage: test/fuzz/run.sh SECONDS [TARGET...]}
shift
targets=("$@")
((${#targets[@]})) || targets=(stability_params plain_yaml scenario_set space track_csv replay_log)
for t in "${targets[@]}"; do
  bin=build/fuzz/test/fuzz/fuzz_$t
  [ -x "$bin" ] || { echo "missing $bin: build the fuzz targets first (README.md)" >&2; exit 2; }
  mkdir -p "build/fuzz/work/$t" "build/fuzz/artifacts/$t" build/fuzz/logs
  status=0
  "$bin" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=16384 \
    -print_final_stats=1 -artifact_prefix="build/fuzz/artifacts/$t/" \
    "build/fuzz/work/$t" "test/fuzz/corpus/$t" >"build/fuzz/logs/$t.log" 2>&1 || status=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build/fuzz/logs/$t.log" | grep -o '[0-9]*$' || true)
  echo "$t: exit $status, ${execs:-?} executions in ${seconds} s, findings: $(ls "build/fuzz/artifacts/$t" | wc -l)"
done
