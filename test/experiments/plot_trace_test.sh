#!/bin/sh
# experiments/plot_trace.py over the real program: a trace and summary from scw simulate (an
# aborting run) rendered to a PNG, and a CSV that is not a trace refused with a message (exit 2,
# no traceback). Usage: plot_trace_test.sh SCW PLOT_TRACE_PY WORK_DIR. Exit 77 (skipped) without
# a python3 with numpy and matplotlib.
set -u
scw=$1 script=$2 dir=$3
py=""
for cand in python3 /usr/bin/python3; do
  if command -v "$cand" >/dev/null 2>&1 && "$cand" -c "import matplotlib, numpy" >/dev/null 2>&1; then
    py=$cand; break
  fi
done
if [ -z "$py" ]; then
  echo "skipped: no python3 with numpy and matplotlib (apt-get install python3-matplotlib)"; exit 77
fi
mkdir -p "$dir" || exit 1
rm -f "$dir"/*.csv "$dir"/*.yaml "$dir"/*.png "$dir"/*.txt "$dir"/*.keep
fail() { echo "FAIL: $*"; exit 1; }

# Rear traction grip 0.7 on a plan for nominal grip: the car spins within the first lap (exit 1).
"$scw" simulate --set grip.rear_mu_x=0.7 plan_with_nominal_grip=true gg_scale=1.1 laps=1 \
  --trace "$dir/run.csv" --summary "$dir/run.yaml" >/dev/null 2>&1
rc=$?
[ "$rc" -le 1 ] && [ -s "$dir/run.csv" ] && [ -s "$dir/run.yaml" ] || fail "scw simulate ($rc)"
grep -q '^status: completed' "$dir/run.yaml" && echo "note: the run did not abort"

# The summary beside the trace (run.yaml) is found; the parameter set named for the title.
"$py" "$script" "$dir/run.csv" -o "$dir/run.png" --params "shipped set" >"$dir/out.txt" 2>&1 ||
  { cat "$dir/out.txt"; fail "render"; }
[ -s "$dir/run.png" ] || fail "no PNG written"
# Without --summary and --params: the title from the trace's meta file (run.csv.meta.yaml, written
# by scw simulate --trace), and the panels of issue 27 (yaw rate against ESC's reference, yaw
# moment, steering and throttle requested against output).
[ -s "$dir/run.csv.meta.yaml" ] || fail "scw simulate wrote no run.csv.meta.yaml"
mv "$dir/run.yaml" "$dir/run.summary.keep"
"$py" "$script" "$dir/run.csv" -o "$dir/meta.png" >"$dir/out.txt" 2>&1 ||
  { cat "$dir/out.txt"; fail "render from the meta file"; }
mv "$dir/run.summary.keep" "$dir/run.yaml"
# The title names the track and the overrides too (issue 50 finding 18: "scenario default" alone
# did not say that --set track=monza drove Monza).
grep -q '^title: scenario default on Yas Marina North (--set grip.rear_mu_x=0.7 plan_with_nominal_grip=true gg_scale=1.1 laps=1) — parameters: built-in (the car.s shipped set) | abort: ' \
  "$dir/out.txt" || { cat "$dir/out.txt"; fail "the title is not taken from the meta file"; }
grep -q '^panels: speed, lateral, heading, beta, yaw, moment, steer, throttle, slip, brake, int$' \
  "$dir/out.txt" || { cat "$dir/out.txt"; fail "a panel is missing"; }
# Several traces (overlay mode) and a lap of one, over time.
"$py" "$script" "$dir/run.csv" "$dir/run.csv" --labels "a,b" --summary "$dir/run.yaml" \
  --summary "$dir/run.yaml" -o "$dir/two.png" >"$dir/out.txt" 2>&1 || { cat "$dir/out.txt"; fail "overlay"; }
"$py" "$script" "$dir/run.csv" --lap 0 --x time -o "$dir/lap.png" >"$dir/out.txt" 2>&1 ||
  { cat "$dir/out.txt"; fail "--lap 0 --x time"; }

# Not a trace: a clear message and exit 2, never a traceback.
printf 'group,scenario,set,status\ntraining,a,baseline,completed\n' >"$dir/other.csv"
printf 't_s,lap,s_m,vx_mps,lateral_error_m,heading_error_deg,beta_deg\n0,0,0,abc,0,0,0\n' \
  >"$dir/words.csv"
printf '\211PNG\r\n\032\n\000\000' >"$dir/binary.csv"
: >"$dir/empty.csv"
for f in other words binary empty; do
  "$py" "$script" "$dir/$f.csv" -o "$dir/$f.png" >"$dir/out.txt" 2>&1
  rc=$?
  [ "$rc" -eq 2 ] || { cat "$dir/out.txt"; fail "$f.csv: exit $rc, expected 2"; }
  grep -q "Traceback" "$dir/out.txt" && { cat "$dir/out.txt"; fail "$f.csv: a traceback"; }
  grep -q "plot_trace.py: error: .*$f.csv" "$dir/out.txt" || { cat "$dir/out.txt"; fail "$f.csv: message"; }
  [ ! -e "$dir/$f.png" ] || fail "$f.csv: a PNG was written"
done
"$py" "$script" "$dir/other.csv" 2>&1 | grep -q "is not a scw trace (scw simulate --trace): it lacks" ||
  fail "other.csv: the message does not say what is missing"
echo "ok: $dir/run.png $dir/two.png $dir/lap.png"
