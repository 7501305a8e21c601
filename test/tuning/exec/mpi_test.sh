#!/usr/bin/env bash
# The MPI backend end to end (test/tuning/exec/CMakeLists.txt).
#   mpi_test.sh CASE SCW MPIRUN WORKDIR
# CASE: reference (the plain runs the other cases compare with), tune_np1, tune_np2, tune_np4,
# evaluate_np2, sweep_np2, killed_worker. Exit 0 pass, 1 fail, 77 skipped.
set -u
test_case=$1 scw=$2 mpirun=$3 work=$4

skip() {
  echo "SKIP: $*"
  exit 77
}
fail() {
  echo "FAIL: $*"
  exit 1
}

"$scw" --version | grep -q '^MPI: built in' ||
  skip "scw is built without MPI ($("$scw" --version | tail -1))"
[ -n "$mpirun" ] && [ -x "$mpirun" ] || skip "no mpirun (Debian: openmpi-bin)"
# Open MPI refuses root without these (the CI runs as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# The plots take seconds and are not compared: without a Python the run notes it and goes on.
export SCW_PYTHON=/nonexistent-python
mkdir -p "$work"
cd "$work" || fail "cannot enter $work"

set_file=$work/set.yaml
tune_args=(tune --scenarios "$set_file" --max-evals 20 --no-sensitivity --progress never)
evaluate_args=(evaluate --scenarios "$set_file" --progress never
  "$(dirname "$0")/../../../params/stability/default.yaml" ref/stability_tuned.yaml)
front_args=(tune --scenarios "$set_file" --front 3 --max-evals 4 --no-neighbourhood --progress never)
sweep_args=(sweep --set laps=1 --vary gg_scale=1.0:0.1:1.5 --stop-at-first-abort
  --config none:subsystems.esc=false,subsystems.cs=false --config all --progress never)

on_mpi() {
  local n=$1
  shift
  "$mpirun" --oversubscribe -np "$n" "$scw" "$@"
}

# The tuned files start with a provenance header (date, run folder): compare what follows it.
same_run() {
  local a=$1 b=$2
  cmp "$a/evaluations.csv" "$b/evaluations.csv" || fail "$b/evaluations.csv differs from $a's"
  cmp "$a/comparison.csv" "$b/comparison.csv" || fail "$b/comparison.csv differs from $a's"
  for f in stability_tuned.yaml stability_overrides.yaml; do
    [ -s "$b/$f" ] || fail "$b/$f is missing"
    diff <(grep -v '^#' "$a/$f") <(grep -v '^#' "$b/$f") >/dev/null ||
      fail "$b/$f differs from $a's (beyond the header)"
  done
}

case $test_case in
  reference)
    # Four one-lap training scenarios (one clean, three critical) and one held-out scenario, on
    # the centre line: no racing-line optimisation (a shorter preparation in every process), and
    # some runs abort early, so the jobs differ in length.
    cat >"$set_file" <<'EOF'
name: mpi_test
training:
  - {name: clean_gg1.1, set: [motion.raceline=centerline, kind=clean, gg_scale=1.1, laps=1]}
  - {name: power_on_c1, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.throttle.corner=[1]", "events.throttle.s=[20]", "events.throttle.lap=[1]", "events.throttle.duration=[1.0]", "events.throttle.value=[1.0]"]}
  - {name: late_braking_c7, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.late_braking.corner=[7]", "events.late_braking.s=[0]", "events.late_braking.distance=[20]"]}
  - {name: rear_grip_loss_c5, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.rear_grip.corner=[5]", "events.rear_grip.s=[0]", "events.rear_grip.lap=[1]", "events.rear_grip.duration=[1.5]", "events.rear_grip.factor=[0.65]"]}
held_out:
  - {name: power_on_c2, set: [motion.raceline=centerline, kind=critical, laps=1, abort.max_lateral_error=10, "events.throttle.corner=[2]", "events.throttle.s=[10]", "events.throttle.lap=[1]", "events.throttle.duration=[0.8]", "events.throttle.value=[0.9]"]}
EOF
    rm -rf ref
    "$scw" "${tune_args[@]}" --out-dir ref >ref.log 2>&1 || fail "plain tune failed: $(cat ref.log)"
    "$scw" "${evaluate_args[@]}" -o ref_evaluate.csv >ref_evaluate.md 2>ref_evaluate.log ||
      fail "plain evaluate failed: $(cat ref_evaluate.log)"
    "$scw" "${sweep_args[@]}" -o ref_sweep.csv >ref_sweep.txt 2>ref_sweep.log ||
      fail "plain sweep failed: $(cat ref_sweep.log)"
    rm -rf ref_front
    "$scw" "${front_args[@]}" --out-dir ref_front >ref_front.log 2>&1 ||
      fail "plain front failed: $(cat ref_front.log)"
    ;;

  front_np2)
    # The front's searches run in lockstep threads; their batches go out on the main thread
    # (MPI_THREAD_FUNNELED): the same front as the plain run.
    rm -rf front_np2
    on_mpi 2 "${front_args[@]}" --out-dir front_np2 >front_np2.log 2>&1 ||
      fail "mpirun -np 2 scw tune --front failed: $(cat front_np2.log)"
    cmp ref_front/front.csv front_np2/front.csv || fail "front.csv differs from the plain run's"
    for k in 0 1 2; do
      same_run "ref_front/point_$k" "front_np2/point_$k"
    done
    ;;

  tune_np*)
    n=${test_case#tune_np}
    rm -rf "np$n"
    on_mpi "$n" "${tune_args[@]}" --out-dir "np$n" >"np$n.log" 2>&1 ||
      fail "mpirun -np $n scw tune failed: $(cat "np$n.log")"
    same_run ref "np$n"
    grep -qx "ranks: $n" "np$n/manifest.yaml" || fail "np$n/manifest.yaml lacks 'ranks: $n'"
    # One thread per rank by default with more than one rank (one rank: all cores, as plain).
    if [ "$n" -gt 1 ]; then
      grep -qx "threads_per_rank: 1" "np$n/manifest.yaml" ||
        fail "np$n/manifest.yaml lacks 'threads_per_rank: 1'"
    fi
    ;;

  evaluate_np2)
    on_mpi 2 "${evaluate_args[@]}" -o np2_evaluate.csv >np2_evaluate.md 2>np2_evaluate.log ||
      fail "mpirun -np 2 scw evaluate failed: $(cat np2_evaluate.log)"
    cmp ref_evaluate.csv np2_evaluate.csv || fail "evaluate: the CSV differs"
    cmp ref_evaluate.md np2_evaluate.md || fail "evaluate: the table differs"
    ;;

  sweep_np2)
    on_mpi 2 "${sweep_args[@]}" -o np2_sweep.csv >np2_sweep.txt 2>np2_sweep.log ||
      fail "mpirun -np 2 scw sweep failed: $(cat np2_sweep.log)"
    cmp ref_sweep.csv np2_sweep.csv || fail "sweep: the CSV differs"
    cmp ref_sweep.txt np2_sweep.txt || fail "sweep: the table differs"
    ;;

  killed_worker)
    # Rank 1 dies by SIGKILL when it receives its 10th job (a test-only fault point,
    # SCW_TEST_FAULT; docs/robustness.md): a defined point of the run, whatever the machine's
    # speed. Rank 0 then waits for that job's result, so the run cannot end first; mpirun sees
    # the dead rank and stops rank 0 with SIGTERM. Without the screen before the search
    # (--no-freeze) the 10th job falls in the optimisation, after evaluations are logged.
    rm -rf killed
    status=0
    SCW_TEST_FAULT=worker-job:10:KILL "$mpirun" --oversubscribe -x SCW_TEST_FAULT -np 2 "$scw" \
      "${tune_args[@]}" --no-freeze --out-dir killed >killed.log 2>&1 || status=$?
    [ "$status" -ne 0 ] || fail "mpirun exited with 0 although rank 1 died at its 10th job: $(cat killed.log)"
    log=killed/evaluations.csv
    [ -f "$log" ] || fail "no evaluation log after the kill: $(cat killed.log)"
    grep -q "stopped by SIGTERM" killed.log || fail "no message from rank 0: $(cat killed.log)"
    grep -q -- "--resume $log" killed.log || fail "the message does not say how to resume"
    # The log is whole: ends with a line break, every row has the header's number of cells.
    [ "$(tail -c 1 "$log" | od -An -c | tr -d ' ')" = '\n' ] || fail "$log ends inside a row"
    awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit bad }' "$log" ||
      fail "$log has a row with a different number of cells than its header"
    rows=$(($(wc -l <"$log") - 1))
    "$scw" "${tune_args[@]}" --no-freeze --out-dir killed --resume "$log" >resumed.log 2>&1 ||
      fail "the plain --resume failed: $(cat resumed.log)"
    grep -q "($rows replayed)" resumed.log || fail "the resume did not replay the $rows logged rows"
    # The same run uninterrupted (without the screen, as above), in one process.
    rm -rf ref_nofreeze
    "$scw" "${tune_args[@]}" --no-freeze --out-dir ref_nofreeze >ref_nofreeze.log 2>&1 ||
      fail "the uninterrupted run failed: $(cat ref_nofreeze.log)"
    same_run ref_nofreeze killed
    ;;

  *)
    fail "unknown case $test_case"
    ;;
esac
echo "ok: $test_case"
