#!/usr/bin/env python3
"""Study 3 (paper §V-A, motion controllers): pure pursuit, the point-mass MPC (pmpc) and the
nonlinear MPC (nmpc), each without and with lateral stability control (ESC + CS), rear lateral
grip reduced in the simulated car only (plan_with_nominal_grip=true), 3 laps per run,
GG 1.0:0.05:1.8 (scwexp.GG_AXIS) with each first abort bisected to 0.025; a series ends at its
first abort (|β| > 20° or lateral error > 3 m; wheel-lock abort off). Slip control runs in both variants; the car's shipped stability parameters. The ESC
targets come from the lateral acceleration each motion controller requests (paper Eq.
"esc_target_acc").

Robustness: rear μy 0.78 / 0.80 / 0.82 (one sweep per controller). The MPC sweeps run in
worker processes (--processes, default 2). A controller the binary rejects is skipped with a
note. Sensitivity (unscored, rear μy 0.80, pure pursuit and pmpc): a 40 ms brake response.

Writes experiments/results/study3_motion/: sweep_<controller>.csv, study3_motion.png,
study3_brake40ms.png, summary.json, scw_<controller>.log.

    python3 experiments/study3_motion.py [--gg 1.0:0.05:1.8] [--refine 1] [--results DIR] [--laps 3] [--controllers a,b]

Time: ~6.5 min on 2 cores with pure pursuit and pmpc; nmpc adds ~5.4 min.
"""

import argparse
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import plots  # noqa: E402
from scwexp.studies import (  # noqa: E402
    STUDY3 as STUDY, STUDY3_BASE_SETS as BASE_SETS, STUDY3_PERT as PERT,
    STUDY3_MAIN_PERT as MAIN_PERT, STUDY3_CONTROLLERS as CONTROLLERS, STUDY3_VARIANTS as VARIANTS,
    STUDY3_COLORS as COLORS, STUDY3_SENSITIVITY_CONTROLLERS as SENSITIVITY_CONTROLLERS)


def run_controllers(scw, args, out, controllers, pert, extra_sets, tag):
    """One sweep per controller; returns (rows, commands, walls, skipped)."""
    rows, commands, walls, skipped = [], [], {}, {}
    for ctrl in controllers:
        csv_path = os.path.join(out, f"sweep_{ctrl}{tag}.csv")
        log = os.path.join(out, f"scw_{ctrl}{tag}.log")
        configs = [f"{ctrl}_{v}:{o}" for v, o, _, _ in VARIANTS]
        sets = [f"laps={args.laps}", f"motion.controller={ctrl}"] + BASE_SETS + extra_sets
        t = scwexp.Timer()
        mpc = ctrl != "pure_pursuit"
        vary = [f"gg_scale={args.gg}", f"{pert[0]}=" + ",".join(pert[1])]
        if os.path.exists(csv_path):
            os.remove(csv_path)
        cmd = (scwexp.mpc_sweep_cmd(scw, args, sets, vary, configs, csv_path,
                                    processes=args.processes) if mpc else
               scwexp.sweep_cmd(scw, args, sets, vary, configs, csv_path))
        proc = scwexp.run(cmd, log=log, check=False)
        walls[ctrl] = t.seconds()
        commands.append(" ".join(cmd))
        if proc.returncode != 0 or not os.path.exists(csv_path):
            with open(log) as f:
                reason = [x for x in f.read().strip().splitlines()
                          if x.strip() and not x.startswith("iter")]
            skipped[ctrl] = (f"exit code {proc.returncode}, no results: " +
                             " ".join(reason[-3:]))[:400]
            print(f"skipping {ctrl}: {skipped[ctrl]}")
            continue
        crow = scwexp.read_csv(csv_path)
        if scwexp.REFINE_LEVELS > 0:
            # claim (e)'s P5: the SC run at the unprotected series' first-abort GG
            crow, rcmds = scwexp.refine_first_aborts(
                scw, args, sets, configs, crow, pert, csv_path, log, mpc=mpc,
                probe=lambda n, c=ctrl: f"{c}_off" if n == f"{c}_sc" else None)
            commands += rcmds
        walls[ctrl] = t.seconds()
        rows += crow
    return rows, commands, walls, skipped


def figure(per_pert, controllers, path, title):
    panels = [(f"rear μy {v}", per_pert[v]) for v in per_pert]
    lines = [(f"{c}_{v}", f"{c} {label}", COLORS.get(c, "k"), ls)
             for c in controllers for v, _, label, ls in VARIANTS]
    return plots.plot_grid(panels, lines, [("max_abs_sideslip_deg", None, "")],
                               "max |β| [deg]", path, title, hline=20.0)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--controllers", default=",".join(CONTROLLERS),
                   help="comma-separated motion controllers (default pure_pursuit,pmpc,nmpc)")
    p.add_argument("--rear-mu-y", default=",".join(PERT[1]),
                   help="rear lateral grip factors (default 0.78,0.8,0.82)")
    args = p.parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    known = scwexp.list_controllers(scw)
    controllers = args.controllers.split(",")
    pert = (PERT[0], args.rear_mu_y.split(","))
    main_pert = MAIN_PERT if MAIN_PERT in pert[1] else pert[1][len(pert[1]) // 2]
    skipped = {c: "not offered by this scw (scw sweep --list-controllers)"
               for c in controllers if c not in known}
    run_list = [c for c in controllers if c not in skipped]
    rows, commands, walls, sk = run_controllers(scw, args, out, run_list, pert, args.set, "")
    skipped.update(sk)
    done = [c for c in controllers if c not in skipped]
    names = [f"{c}_{v}" for c in done for v, *_ in VARIANTS]
    per_pert = scwexp.perturbed_series(rows, names, *pert)
    png = figure(per_pert, done, os.path.join(out, f"{STUDY}.png"),
                 "Study 3: motion controllers without (solid) / with (dashed) ESC + CS, rear μy "
                 "reduced in the car only")
    summary = {"study": STUDY, "commands": commands, "wall_time_per_controller_s": walls,
               "controllers": controllers, "skipped": skipped,
               "perturbation": {"key": pert[0], "label": "rear μy",
                                "values": [str(v) for v in pert[1]], "main": main_pert},
               "configs": {f"{c}_{v}": f"{c} {label}" for c in done
                           for v, _, label, _ in VARIANTS},
               "runs": per_pert, "figures": [os.path.relpath(png, scwexp.RESULTS)],
               "sensitivity": {}}
    summary["wall_time_main_s"] = timer.seconds()

    if not args.no_sensitivity:
        t = scwexp.Timer()
        veh = scwexp.brake_40ms_vehicle(scw, os.path.join(out, "vehicle_brake40ms.yaml"))
        sens = [c for c in SENSITIVITY_CONTROLLERS if c in done]
        one = (pert[0], [main_pert])
        srows, scmds, _, _ = run_controllers(scw, args, out, sens, one,
                                             args.set + [f"vehicle={veh}"], "_brake40ms")
        snames = [f"{c}_{v}" for c in sens for v, *_ in VARIANTS]
        sp = scwexp.perturbed_series(srows, snames, *one)
        spng = figure(sp, sens, os.path.join(out, "study3_brake40ms.png"),
                      f"Study 3, sensitivity (unscored): 40 ms brake, rear μy {main_pert}")
        summary["sensitivity"]["brake40ms"] = {
            "label": f"40 ms brake response (brakes.delay 0.006 s), rear μy {main_pert}, "
                     + ", ".join(sens), "command": " | ".join(scmds), "wall_time_s": t.seconds(),
            "controllers": sens, "runs": sp, "figures": [os.path.relpath(spng, scwexp.RESULTS)]}
    scwexp.finish_study(STUDY, scw, args, args.set, summary, timer, per_pert, "rear μy", out)
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
