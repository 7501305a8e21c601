#!/usr/bin/env bash
# Runs every experiment for every parameter set and both actuator models: the paper's three
# simulation studies as the paper ran them (studies 1 and 2 with the point-mass MPC, study 3 with
# pure pursuit and pmpc; 3 laps, GG 1.0:0.05:1.8 with each first abort bisected to 0.025, three
# perturbations each), once with the vehicle file's actuators ("real car") and once with
# plant.actuators=paper_sim ("paper's simulator"), for the car's shipped stability set and each
# params file given; then the comparison of the sets and the report. Outputs go to
# experiments/results/ (not committed): one directory per column,
# experiments/results/columns/<set>__<actuators>/<study>/; the report is
# experiments/results/report.md.
#
#   experiments/run_all.sh [PARAMS.yaml ...]        (SCW_BIN=/path/to/scw to choose the binary)
#   experiments/run_all.sh --quick                  the shipped set, both actuator models, the
#                                                   one-page answer (no seeded runs, no maps)
#
# Environment: ACTUATORS (default "vehicle paper_sim"), STUDY3_CONTROLLERS (default
# pure_pursuit,pmpc; add nmpc for the nonlinear MPC, ~5 min per column), SENSITIVITY=1 (also the
# unscored sensitivity runs, shipped set and vehicle actuators only), PROCESSES (default 2),
# CLAIMS_MAP=1 (also experiments/claims_map.py, the map of what decides each claim: ~30 min on
# an idle 2-vCPU machine for the shipped set with every family, claim (d)'s candidates included,
# and for each given set its actuator families, brake x steering dead time, no brake dynamics
# and the paper's simulator's actuators (also with its steering dead time at 0 and 30 ms, and
# as its IV-2024 code had them), the grip reduction on the whole tyre curve and the PMPC's
# commanded and steering-based ESC targets, and the PMPC's yaw-rate and lateral-acceleration
# feedbacks with both actuator models, the body's roll/pitch modes and the paper's setup as a whole
# (paper_setup), about 25-30 min each),
# STUDY_ARGS (extra options of every study, e.g. "--gg 1.0,1.05 --laps 1" for a quick check),
# PLANTS (default "scw"; "scw ocd" adds each column on Open-Car-Dynamics, the paper's simulator,
# as <set>__<actuators>__ocd: needs a build with OCD, docs/ocd-plant.md),
# SEEDED (default 1, 0 with --quick: studies 2 and 3 over 10 sensor-noise seeds per column,
# experiments/seeded_limit.py, about 20 min a column; SEEDED_PLANTS, default "scw", the plants
# whose columns get them: on OCD they would take hours a column). The wall and CPU time of the
# whole run go to results/run_all.json, which the report's header names.
# RESUME=1 keeps experiments/results and skips every piece (a column, a claims map, the ESC margin
# scan, the comparison) that an earlier run of the same scw binary, experiments scripts, sets and
# study settings finished, so a run cut short (a session's end, a reboot) continues where it
# stopped, and more ACTUATORS, PLANTS or CLAIMS_MAP add their pieces; a piece cut short is run
# again from its start. Results made otherwise are refused.
# Each finished piece's wall and CPU time go to results/.pieces, and run_all.json sums them: a
# resumed run reports every piece's time once.
# Time on the 2-vCPU machine (nearly idle): the full reference (both tuned sets of
# reference-results, CLAIMS_MAP=1 SEEDED=1 SENSITIVITY=1, scw's plant) 77.4 min wall, 145.5
# CPU-min: six columns 3.2-6.2 min each, claims maps 19.4 / 13.3 / 15.0 min, esc_margin 3.1 min;
# then RESUME=1 PLANTS=ocd ACTUATORS=paper_sim adds the three OCD columns in 11.4 min (2026-12-07,
# scripts and binary 46dc788, release build); --quick 4.9 min wall, 7.7 CPU-min (scripts 1cb030a).
# To refresh the committed reference copy afterwards:
#   python3 experiments/report.py --publish experiments/reference-results
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# Debian's python3 has numpy and matplotlib; another python3 first on PATH may not.
py=python3
if ! python3 -c "import matplotlib, numpy" >/dev/null 2>&1 && [ -x /usr/bin/python3 ]; then
  py=/usr/bin/python3
fi
quick=0
if [ "${1:-}" = --quick ]; then
  quick=1; shift
  [ $# -eq 0 ] || { echo "run_all: --quick runs the shipped set only: drop $*" >&2; exit 2; }
fi
for f in "$@"; do
  [ -f "$f" ] || { echo "run_all: no such params file: $f" >&2; exit 2; }
done
seeded=${SEEDED:-$((1 - quick))}
actuators=${ACTUATORS:-vehicle paper_sim}
ctrls=${STUDY3_CONTROLLERS:-pure_pursuit,pmpc}
procs=${PROCESSES:-2}
results="$here/results"
cols="$results/columns"
# What made the results: the scw binary the scripts use (its version names its git revision) and
# the revision of the experiments scripts.
scw_bin=$(cd "$here" && "$py" -c "from scwexp.paths import find_scw; print(find_scw())")
scripts_rev=$(git -C "$here/.." rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ -n "$(git -C "$here/.." status --porcelain -- "$here" 2>/dev/null)" ]; then
  scripts_rev+="+dirty"
fi
# What shapes a piece's content (ACTUATORS, PLANTS and CLAIMS_MAP only add or drop pieces, so a
# resumed run may add columns or maps).
stamp="$("$scw_bin" --version | head -1); scripts $scripts_rev; sets $*; quick $quick"
stamp+="; seeded $seeded on ${SEEDED_PLANTS:-scw}; controllers $ctrls"
stamp+="; sensitivity ${SENSITIVITY:-0}; args ${STUDY_ARGS:-}"
if [ "${RESUME:-0}" = 1 ] && [ -f "$results/.stamp" ]; then
  if [ "$(cat "$results/.stamp")" != "$stamp" ]; then
    echo "run_all: RESUME=1, but the results were made by '$(cat "$results/.stamp")'," \
      "this run is '$stamp': run without RESUME" >&2
    exit 2
  fi
  echo "run_all: resuming ($(wc -l < "$results/.pieces" 2>/dev/null || echo 0) pieces done)"
else
  rm -rf "$cols" "$results/.pieces"
  mkdir -p "$results"
  echo "$stamp" > "$results/.stamp"
fi
start=$SECONDS
# The CPU seconds (user + system) of this shell's finished children so far: `times` runs in this
# shell (in a pipe or $(...) it would report a subshell's children) and writes to a file.
times_cpu() {
  tail -1 "$results/.times" | awk '{ t = 0; for (i = 1; i <= 2; i++) { split($i, a, "m");
    t += a[1] * 60 + substr(a[2], 1, length(a[2]) - 1) } printf "%.2f", t }'
}
# piece NAME COMMAND...: runs COMMAND unless RESUME=1 and NAME is finished in results/.pieces;
# then records NAME, its wall and its CPU seconds there.
piece() {
  local name=$1
  shift
  if [ "${RESUME:-0}" = 1 ] && grep -q "^$name " "$results/.pieces" 2>/dev/null; then
    echo "run_all: $name finished earlier, kept"
    return 0
  fi
  local w0=$SECONDS c0 c1 wall
  times > "$results/.times"
  c0=$(times_cpu)
  "$@"
  wall=$((SECONDS - w0))
  echo "run_all: $name: $wall s"
  times > "$results/.times"
  c1=$(times_cpu)
  rm -f "$results/.times"
  echo "$name $wall $(awk -v a="$c1" -v b="$c0" 'BEGIN { printf "%.2f", a - b }')" >> "$results/.pieces"
}
# One column (the loop below sets dir, common, sens, plant, act, label, pset, stab), from an empty
# directory: a piece cut short starts again.
column() {
  rm -rf "$dir"
  "$py" "$here/study1_longitudinal.py" "${common[@]}" "${sens[@]}"
  "$py" "$here/study2_lateral.py" "${common[@]}" "${sens[@]}"
  "$py" "$here/study3_motion.py" "${common[@]}" "${sens[@]}" --controllers "$ctrls"
  if [ "$seeded" = 1 ] && [[ " ${SEEDED_PLANTS:-scw} " == *" $plant "* ]]; then
    for st in 2 3; do
      "$py" "$here/seeded_limit.py" --study "$st" --controllers "$ctrls" --results "$dir" \
        --label "$label" --processes "$procs" --set "plant.actuators=$act" "${pset[@]}" \
        "${stab[@]}"
    done
  fi
}
sets=("shipped")
for f in "$@"; do sets+=("$(cd "$(dirname "$f")" && pwd)/$(basename "$f")"); done
for set in "${sets[@]}"; do
  if [ "$set" = shipped ]; then
    label=shipped; stab=()
  else
    label=$(basename "$set" .yaml); stab=(--stability "$set")
  fi
  for plant in ${PLANTS:-scw}; do
  for act in $actuators; do
    dir="$cols/${label}__${act}"
    pset=()
    if [ "$plant" != scw ]; then dir="${dir}__${plant}"; pset=(--set "plant.model=$plant"); fi
    # shellcheck disable=SC2206  # STUDY_ARGS is split into words on purpose
    common=(--no-report --results "$dir" --label "$label" --processes "$procs"
            --set "plant.actuators=$act" "${pset[@]}" "${stab[@]}" ${STUDY_ARGS:-})
    sens=(--no-sensitivity)
    if [ "${SENSITIVITY:-0}" = 1 ] && [ "$set" = shipped ] && [ "$act" = vehicle ]; then sens=(); fi
    piece "column:$(basename "$dir")" column
  done
  done
done
if [ "${CLAIMS_MAP:-0}" = 1 ] && [ "$quick" = 0 ]; then
  piece "claims_map:shipped" "$py" "$here/claims_map.py" --no-report --processes "$procs"
  fams=brake_steer,no_brake_dyn,paper_sim,paper_sim_steer,paper_sim_v1,grip_curve,esc_target
  fams+=,pmpc_yaw_feedback,pmpc_yaw_paper_sim,pmpc_ay_feedback,pmpc_ay_paper_sim,body_modes
  fams+=,paper_setup
  for f in "$@"; do
    piece "claims_map:$(basename "$f" .yaml)" "$py" "$here/claims_map.py" --no-report \
      --processes "$procs" --stability "$f" --families "$fams"
  done
fi
piece esc_margin "$py" "$here/esc_margin.py" --no-report --processes "$procs"
if [ "$quick" = 0 ]; then
  piece compare "$py" "$here/compare.py" --no-report "$here/../params/stability/default.yaml" "$@"
fi
# The run's wall and CPU time for the report's header: the sums over its pieces (each counted
# once, also when the run was resumed).
read -r wall cpu npieces < <(awk '{ w += $2; c += $3; n++ } END { printf "%d %.1f %d\n", w, c, n }' \
  "$results/.pieces")
printf '{"mode": "%s", "wall_s": %d, "cpu_s": %s, "commit": "%s", "sets": %d, "pieces": %d, "resumed": %s}\n' \
  "$([ "$quick" = 1 ] && echo quick || echo full)" "$wall" "$cpu" "$scripts_rev" \
  "${#sets[@]}" "$npieces" "$([ "${RESUME:-0}" = 1 ] && echo true || echo false)" \
  > "$results/run_all.json"
"$py" "$here/report.py"
echo "run_all: ${wall} s over ${npieces} pieces (this invocation $((SECONDS - start)) s); report: $results/report.md"
