#!/bin/sh
# Smoke test of experiments/plot_trace.py: a one-lap trace from scw simulate turned into a PNG.
# Usage: plot_trace_smoke.sh SCW PLOT_TRACE_PY WORK_DIR. Exit 77 (skipped) without python3 or
# matplotlib.
set -u
scw=$1 script=$2 dir=$3
# The first python3 with numpy and matplotlib (Debian's /usr/bin/python3 if another comes first).
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
rm -f "$dir/trace.csv" "$dir/trace.png"
# Exit 1 (the run aborted) still leaves a trace; only the trace matters here.
"$scw" simulate --set laps=1 --trace "$dir/trace.csv" >/dev/null
rc=$?
if [ "$rc" -gt 1 ] || [ ! -s "$dir/trace.csv" ]; then echo "scw simulate failed ($rc)"; exit 1; fi
"$py" "$script" "$dir/trace.csv" -o "$dir/trace.png" --title "smoke test" || exit 1
test -s "$dir/trace.png" || { echo "no PNG written"; exit 1; }
echo "ok: $dir/trace.png"
