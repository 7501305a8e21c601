"""What every study driver shares: its command-line options (the GG axis, --refine, --results,
--label, --stability, ...), the column it belongs to (parameter set and actuator model), its
common end (summary.json, the printed lines) and the report's regeneration after it."""

import os
import subprocess
import sys

from scwexp import paths, sweeps
from scwexp.paths import ROOT, set_results
from scwexp.results import fmt, write_summary
from scwexp.track import track_corners
from scwexp.sweeps import GG_AXIS


def add_common_args(parser, gg=GG_AXIS, laps=3):
    parser.add_argument("--gg", default=gg,
                        help=f"GG values: start:step:stop or a comma list (default {gg})")
    parser.add_argument("--refine", type=int, default=sweeps.REFINE_LEVELS,
                        help="bisection rounds of each series' first abort (default "
                             f"{sweeps.REFINE_LEVELS}: half a step; 0: none)")
    parser.add_argument("--results", metavar="DIR",
                        help="write the outputs under DIR instead of experiments/results")
    parser.add_argument("--label", help="name of the parameter set in the report")
    parser.add_argument("--laps", type=int, default=laps, help=f"laps per run (default {laps})")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
    parser.add_argument("--stability", help="stability params file (default: the car's)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="extra scenario override for every run (repeatable)")
    parser.add_argument("--processes", type=int, default=2,
                        help="worker processes of the MPC sweeps (default 2)")
    parser.add_argument("--no-sensitivity", action="store_true",
                        help="skip the unscored sensitivity runs (40 ms brake and the others of the study)")
    parser.add_argument("--no-report", action="store_true",
                        help="do not regenerate experiments/results/report.md")


def apply_common_args(args):
    """The effect of --results and --refine (call before writing anything)."""
    sweeps.REFINE_LEVELS = max(0, int(args.refine))
    if args.results:
        set_results(args.results)


def column_info(args):
    """What the report needs to name this run's column: the parameter set and the actuators."""
    act, plant = "vehicle", "scw"
    for x in args.set:
        if x.startswith("plant.actuators="):
            act = x.split("=", 1)[1]
        if x.startswith("plant.model="):
            plant = x.split("=", 1)[1]
    return {"set_label": args.label or (os.path.splitext(os.path.basename(args.stability))[0]
                                        if args.stability else "shipped"),
            "stability": os.path.relpath(os.path.abspath(args.stability), ROOT)
            if args.stability else "params/stability/default.yaml (the car's)",
            "actuators": act, "plant": plant, "gg_axis": args.gg, "refine_levels": sweeps.REFINE_LEVELS}


def finish_study(study, scw, args, sets, summary, timer, per_pert, pert_label, out,
                 main_wall=None):
    """The common end of a study: adds the track's corners, the wall and CPU time and the
    column's settings to `summary` and writes it, then prints one line per perturbation value and
    configuration of `per_pert` ({value: {config: analyse_series(...)}}, the value named by
    `pert_label`, e.g. "seed" or "rear μy") and the total time (and that of the main sweep, when
    given). The study then calls update_report(args) itself."""
    summary["corners"] = track_corners(scw, sets)
    summary["wall_time_s"] = timer.seconds()
    summary["cpu_time_s"] = timer.cpu_seconds()
    summary["column"] = column_info(args)
    write_summary(study, summary)
    for v, ser in per_pert.items():
        for name, a in ser.items():
            print(f"{pert_label} {v} {name}: max stable GG {a['max_stable']}, first abort "
                  f"{a['first_abort']} ({a['first_abort_status']}), min lap "
                  f"{fmt(a['min_lap_time_s'], 3)} s at GG {a['min_lap_value']}")
    main = "" if main_wall is None else f" (main sweep {main_wall:.0f} s)"
    print(f"{study}: {timer.seconds():.0f} s wall{main}; outputs in {out}")


def update_report(args):
    """Regenerates report.md after a study (unless it ran with --no-report) by running the
    report's entry point, experiments/report.py: the drivers never import the report."""
    if getattr(args, "no_report", False):
        return
    sys.stdout.flush()
    subprocess.run([sys.executable, os.path.join(paths.HERE, "report.py")], cwd=paths.ROOT,
                   check=False)
