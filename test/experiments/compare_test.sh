#!/bin/sh
# test/experiments/compare_test.py with a python3 that has numpy and matplotlib (Debian's);
# exit 77 (skipped) without one. Usage: compare_test.sh EXPERIMENTS_DIR WORK_DIR
for cand in python3 /usr/bin/python3; do
  if command -v "$cand" >/dev/null 2>&1 && "$cand" -c "import matplotlib, numpy" >/dev/null 2>&1; then
    exec "$cand" "$(dirname "$0")/compare_test.py" "$1" "$2"
  fi
done
echo "skipped: no python3 with numpy and matplotlib (apt-get install python3-matplotlib)"
exit 77
