#!/usr/bin/env python3
"""Study 1 (paper §V-A, longitudinal stability): slip control (ABS + TC) on vs off with the
point-mass MPC (motion.controller=pmpc, the paper's controller for studies 1 and 2), nominal
grip, 3 laps per run, GG 1.0:0.05:1.8 (scwexp.GG_AXIS) with each first abort bisected to 0.025;
a series ends at its first abort.

The paper ends the test when a tyre begins to lock or spin: here slip below -50 % (lock) or
above +30 % (spin) for at least 0.1 s (abort.lock_slip_pct=50, abort.spin_slip_pct=30,
abort.slip_time=0.1). The lateral-error abort is lifted (abort.max_lateral_error=100, the
largest allowed); |β| > 20°, leaving the track and the time-out still end a run and are reported
as safety stops, not slip-control failures. ESC and countersteer run in both configurations, as
in the car's default setup; the car's shipped stability parameters throughout.

Robustness: three sensor-noise seeds (sensor_noise=true, seed 1/2/3) in one sweep. Sensitivity
(unscored): the same with a 40 ms brake response (vehicle file with brakes.delay 0.006).

Writes experiments/results/study1_longitudinal/: sweep.csv, sweep_brake40ms.csv,
study1_longitudinal.png, study1_brake40ms.png, summary.json, scw*.log.

    python3 experiments/study1_longitudinal.py [--gg 1.0:0.05:1.8] [--refine 1] [--results DIR] [--laps 3] [--processes 2]

Diagnostic (unscored): the same with ESC and CS off in both configurations. The first abort of
each configuration is re-run with `scw simulate --trace` and described (diagnosis/).

Time: ~6 min on 2 cores (3 laps, the default axis).
"""

import argparse
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import plots  # noqa: E402
from scwexp.studies import (  # noqa: E402
    STUDY1 as STUDY, STUDY1_CONTROLLER as CONTROLLER, STUDY1_BASE_SETS as BASE_SETS,
    STUDY1_PERT as PERT, STUDY1_CONFIGS as CONFIGS, STUDY1_TOP as TOP)


def figure(per_pert, path, title):
    panels = [(f"sensor-noise seed {v}", per_pert[v]) for v in per_pert]
    lines = [(n, label, color, "-") for n, _, label, color in CONFIGS]
    return plots.plot_grid(panels, lines, TOP, "max |slip| [%] (front solid, rear dashed)",
                               path, title)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--seeds", default="1,2,3", help="sensor-noise seeds (default 1,2,3)")
    p.add_argument("--controller", default=CONTROLLER, help="motion controller (default pmpc)")
    args = p.parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    pert = (PERT[0], [int(x) for x in args.seeds.split(",")])
    mpc = args.controller != "pure_pursuit"
    sets = [f"laps={args.laps}", f"motion.controller={args.controller}"] + BASE_SETS + args.set
    configs = [f"{n}:{o}" for n, o, _, _ in CONFIGS]
    names = [n for n, *_ in CONFIGS]
    cmd, rows = scwexp.study_sweep(scw, args, sets, configs, os.path.join(out, "sweep.csv"),
                                   os.path.join(out, "scw.log"), pert=pert, mpc=mpc)
    main_wall = timer.seconds()
    per_pert = scwexp.perturbed_series(rows, names, *pert)
    png = figure(per_pert, os.path.join(out, f"{STUDY}.png"),
                 f"Study 1: slip control on/off, {args.controller}, nominal grip "
                 "(x: aborted run, ★: minimum lap time)")
    summary = {"study": STUDY, "command": " ".join(cmd), "controller": args.controller,
               "wall_time_main_s": main_wall, "perturbation": {"key": pert[0],
                                                               "label": "sensor-noise seed",
                                                               "values": [str(v) for v in pert[1]]},
               "configs": {n: label for n, _, label, _ in CONFIGS},
               "runs": per_pert, "figures": [os.path.relpath(png, scwexp.RESULTS)],
               "sensitivity": {}}

    if not args.no_sensitivity:
        t = scwexp.Timer()
        veh = scwexp.brake_40ms_vehicle(scw, os.path.join(out, "vehicle_brake40ms.yaml"))
        scmd, srows = scwexp.study_sweep(scw, args, sets + [f"vehicle={veh}"], configs,
                                         os.path.join(out, "sweep_brake40ms.csv"),
                                         os.path.join(out, "scw_brake40ms.log"), pert=pert,
                                         mpc=mpc)
        sp = scwexp.perturbed_series(srows, names, *pert)
        spng = figure(sp, os.path.join(out, "study1_brake40ms.png"),
                      "Study 1, sensitivity: 40 ms brake response (unscored)")
        summary["sensitivity"]["brake40ms"] = {
            "label": "40 ms brake response (brakes.delay 0.006 s)", "command": " ".join(scmd),
            "wall_time_s": t.seconds(), "runs": sp,
            "figures": [os.path.relpath(spng, scwexp.RESULTS)]}
        # Diagnostic (unscored): ESC and CS off in both configurations; the paper does not say
        # whether they ran in its study 1, and their brake pulses can lock a wheel themselves.
        t = scwexp.Timer()
        nconfigs = [f"{c},subsystems.esc=false,subsystems.cs=false" for c in configs]
        scmd, srows = scwexp.study_sweep(scw, args, sets, nconfigs,
                                         os.path.join(out, "sweep_no_esc_cs.csv"),
                                         os.path.join(out, "scw_no_esc_cs.log"), pert=pert,
                                         mpc=mpc)
        sp = scwexp.perturbed_series(srows, names, *pert)
        spng = figure(sp, os.path.join(out, "study1_no_esc_cs.png"),
                      "Study 1, diagnostic (unscored): ESC and CS off in both configurations")
        summary["sensitivity"]["no_esc_cs"] = {
            "label": "ESC and CS off in both configurations (slip control alone)",
            "command": " ".join(scmd), "wall_time_s": t.seconds(), "runs": sp,
            "figures": [os.path.relpath(spng, scwexp.RESULTS)]}
    # Where and how each configuration's first abort happened (seed of the first column).
    first = str(pert[1][0])
    summary["diagnosis"] = scwexp.diagnose_series(
        scw, args, sets, [(n, o) for n, o, _, _ in CONFIGS], per_pert[first], pert[0], first,
        out)
    summary["diagnosis_perturbation"] = first
    scwexp.finish_study(STUDY, scw, args, sets, summary, timer, per_pert, "seed", out, main_wall)
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
