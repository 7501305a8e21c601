#!/usr/bin/env bash
# Golden outputs: behaviour-preserving restructurings (issue 17) must reproduce these bit for bit.
#   golden.sh check  CASE SCW WORKDIR   compare a fresh run with the committed files (ctest)
#   golden.sh record CASE SCW WORKDIR   rewrite the committed files (never in CI; state why in
#                                       the commit message)
# CASE: simulate (the default scenario, 3 laps: the trace's SHA-256 and the summary), tune (a
# short fixed-seed tune on a small set with crs2+sbplx and the weighted-sum objective, which it
# was recorded with:
# evaluations.csv and the tuned file below its provenance header), sweep (a GG sweep with two configurations: the CSV), scenarios (the expansion of the
# shipped Monte-Carlo set params/scenarios/robust_set.yaml, `scw tune --print-scenarios`: its
# SHA-256).
# To regenerate all of them from the source root after a stated behaviour change:
#   for c in simulate tune sweep scenarios; do
#     test/golden/golden.sh record $c "$PWD/build/ci/tuning/scw" /tmp/scw-golden; done
set -u
mode=$1 test_case=$2 scw=$3 work=$4
here=$(cd "$(dirname "$0")" && pwd)

fail() {
  echo "FAIL: $*"
  echo "If the change of behaviour is intended, re-record with test/golden/golden.sh record" \
    "$test_case <scw> <dir> and say why in the commit message."
  exit 1
}
case $mode in check | record) ;; *) fail "unknown mode '$mode' (check or record)" ;; esac

mkdir -p "$work"
cd "$work" || fail "cannot enter $work"
rm -rf "$test_case" && mkdir "$test_case" && cd "$test_case" || exit 1
# The plots are not compared: without a Python the tune notes it and goes on.
export SCW_PYTHON=/nonexistent-python

# Puts a produced file next to the golden one (record) or compares the two (check).
settle() {
  local produced=$1 golden=$here/$2
  if [ "$mode" = record ]; then
    cp "$produced" "$golden"
    echo "recorded $golden"
  else
    [ -f "$golden" ] || fail "no golden file $golden"
    cmp -s "$produced" "$golden" ||
      fail "$(basename "$golden") differs: $(diff "$golden" "$produced" | head -20)"
  fi
}

case $test_case in
  simulate)
    "$scw" simulate --trace trace.csv --summary summary.yaml --progress never >out.txt 2>&1 ||
      fail "scw simulate failed: $(cat out.txt)"
    sha256sum <trace.csv | cut -d' ' -f1 >trace.sha256
    settle summary.yaml simulate_summary.yaml
    settle trace.sha256 simulate_trace.sha256
    ;;
  tune)
    "$scw" tune --scenarios "$here/golden_set.yaml" --algorithm crs2+sbplx --max-evals 12 --seed 1 \
      --objective sum --threads 2 --no-sensitivity --no-neighbourhood --progress never \
      --out-dir out >out.txt 2>&1 ||
      fail "scw tune failed: $(cat out.txt)"
    grep -v '^#' out/stability_tuned.yaml >tuned_body.yaml
    settle out/evaluations.csv tune_evaluations.csv
    settle out/comparison.csv tune_comparison.csv
    settle tuned_body.yaml tune_stability_tuned_body.yaml
    ;;
  sweep)
    "$scw" sweep --set laps=1 --vary gg_scale=1.0:0.1:1.4 \
      --config none:subsystems.esc=false,subsystems.cs=false,subsystems.abs=false,subsystems.tc=false \
      --config all --threads 2 --progress never -o sweep.csv >out.txt 2>&1 ||
      fail "scw sweep failed: $(cat out.txt)"
    settle sweep.csv sweep.csv
    ;;
  scenarios)
    "$scw" tune --scenarios "$here/../../params/scenarios/robust_set.yaml" --print-scenarios \
      >robust.yaml 2>out.txt || fail "scw tune --print-scenarios failed: $(cat out.txt)"
    sha256sum <robust.yaml | cut -d' ' -f1 >robust.sha256
    settle robust.sha256 robust_set_expanded.sha256
    ;;
  *) fail "unknown case '$test_case'" ;;
esac
echo "golden $test_case: ${mode}ed"
