#!/usr/bin/env bash
# Runs every experiment: the paper's three simulation studies as the paper ran them (studies 1
# and 2 with the point-mass MPC, study 3 with pure pursuit, pmpc and nmpc; 3 laps, GG step 0.05,
# three perturbations each, sensitivity runs beside), the comparison of parameter sets (the car's
# set plus any files given as arguments) and the report. Outputs go to experiments/results/ (not
# committed); the report is experiments/results/report.md.
#
#   experiments/run_all.sh [PARAMS.yaml ...]        (SCW_BIN=/path/to/scw to choose the binary)
#
# About 15 min on 2 cores (MPC runs in 2 worker processes; each study well under 20 min).
# To refresh the committed reference copy afterwards:
#   python3 experiments/report.py --publish experiments/reference-results
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# Debian's python3 has numpy and matplotlib; another python3 first on PATH may not.
py=python3
if ! python3 -c "import matplotlib, numpy" >/dev/null 2>&1 && [ -x /usr/bin/python3 ]; then
  py=/usr/bin/python3
fi
start=$SECONDS
"$py" "$here/study1_longitudinal.py" --no-report
"$py" "$here/study2_lateral.py" --no-report
"$py" "$here/study3_motion.py" --no-report
"$py" "$here/compare.py" --no-report "$here/../params/stability/default.yaml" "$@"
"$py" "$here/report.py"
echo "run_all: $((SECONDS - start)) s; report: $here/results/report.md"
