#!/bin/sh
# experiments/run_all.sh's RESUME=1 with stand-ins for python3 and scw (no study runs): a run that
# stops in its second column keeps its first; RESUME=1 runs only what is missing and sums the
# pieces' times once; a resumed run with other study settings is refused (exit 2); more ACTUATORS
# add their column only.
#   run_all_resume_test.sh EXPERIMENTS_DIR WORK_DIR
set -u
src=$1
work=$2
rm -rf "$work"
mkdir -p "$work/tree/experiments" "$work/bin"
cp "$src/run_all.sh" "$work/tree/experiments/"
log="$work/calls.log"
# python3: the run_all checks (-c ...) succeed, the scw binary is the stand-in; every script call
# is logged, and the one named by FAIL_AT for the column named by FAIL_DIR fails.
cat > "$work/bin/python3" <<'EOF'
#!/bin/sh
if [ "$1" = -c ]; then
  case "$2" in *find_scw*) echo "$FAKE_SCW" ;; esac
  exit 0
fi
script=$(basename "$1")
shift
echo "$script $*" >> "$CALLS"
case "$script $*" in *"$FAIL_AT"*"$FAIL_DIR"*) [ -n "$FAIL_AT" ] && exit 1 ;; esac
exit 0
EOF
cat > "$work/bin/scw" <<'EOF'
#!/bin/sh
echo "scw 0.1.0 (git revision stand-in)"
EOF
chmod +x "$work/bin/python3" "$work/bin/scw"
export PATH="$work/bin:$PATH" FAKE_SCW="$work/bin/scw" CALLS="$log" SEEDED=0
ra="$work/tree/experiments/run_all.sh"
res="$work/tree/experiments/results"
fail() { echo "FAIL: $*"; exit 1; }
count() { grep -c "$1" "$log" || true; }

# 1. Stops in the second column's study 2.
: > "$log"
FAIL_AT=study2_lateral.py FAIL_DIR=shipped__paper_sim bash "$ra" > "$work/run1.log" 2>&1 &&
  fail "the first run should stop"
grep -q "^column:shipped__vehicle " "$res/.pieces" || fail "the finished column is not recorded"
grep -q "paper_sim" "$res/.pieces" && fail "the column cut short is recorded"

# 2. RESUME=1: the first column is kept, the second runs from its start, then the rest.
: > "$log"
RESUME=1 bash "$ra" > "$work/run2.log" 2>&1 || { cat "$work/run2.log"; fail "the resumed run failed"; }
[ "$(count study1_longitudinal.py)" = 1 ] || fail "study 1 should run once (the second column)"
grep -q "shipped__vehicle" "$log" && fail "the finished column ran again"
[ "$(count esc_margin.py)" = 1 ] && [ "$(count compare.py)" = 1 ] && [ "$(count report.py)" = 1 ] ||
  fail "esc_margin, compare and report should run once"
[ "$(wc -l < "$res/.pieces")" = 4 ] || fail "4 pieces expected: $(cat "$res/.pieces")"
grep -q '"resumed": true' "$res/run_all.json" || fail "run_all.json: $(cat "$res/run_all.json")"
grep -q '"pieces": 4' "$res/run_all.json" || fail "run_all.json: $(cat "$res/run_all.json")"

# 3. Other study settings: refused, nothing run.
: > "$log"
RESUME=1 STUDY_ARGS="--laps 1" bash "$ra" > "$work/run3.log" 2>&1
[ $? = 2 ] || fail "a resumed run with other settings should exit 2"
grep -q "run without RESUME" "$work/run3.log" || fail "the refusal should say why"
[ -s "$log" ] && fail "a refused run ran: $(cat "$log")"

# 4. One more actuator model: its column only.
: > "$log"
RESUME=1 ACTUATORS="vehicle paper_sim paper_sim_v1" bash "$ra" > "$work/run4.log" 2>&1 ||
  fail "adding a column failed"
[ "$(count study1_longitudinal.py)" = 1 ] && grep -q "paper_sim_v1" "$log" ||
  fail "only the new column should run: $(cat "$log")"
echo "run_all resume: ok"
