#!/usr/bin/env python3
"""Study 3 (paper §V-A, motion controllers): every motion controller the scw binary offers
(scw sweep --list-controllers: pure_pursuit, and pmpc/nmpc once they exist) without and with
lateral stability control (ESC + CS), rear lateral grip −20 %, over increasing GG; a series ends
at its first abort (|β| > 20° or lateral error > 3 m; wheel-lock abort off). The ESC targets
come from the lateral acceleration the motion controller requests (κ = a_y,req / v², paper
Eq. "esc_target_acc"; every motion controller passes its a_y request to the ESC).

A controller the binary rejects is skipped with a note (the study completes with the rest).
The MPC controllers run far slower than pure pursuit, so by default they get one lap per run and
a GG step of 0.1 (--mpc-laps, --mpc-gg), and run on one thread (--mpc-threads: parallel runs of
the Ipopt-based MPCs crashed in MUMPS); expect about 30 s per MPC run.

Writes experiments/results/study3_motion/: sweep_<controller>.csv, study3_motion.png (solid:
without SC, dashed: with ESC + CS), summary.json, scw_<controller>.log.

    python3 experiments/study3_motion.py [--gg 1.0:0.05:1.8] [--laps 3] [--controllers a,b]
"""

import argparse
import os
import sys

import scwexp
import study2_lateral

STUDY = "study3_motion"
BASE_SETS = ["grip.rear_mu_y=0.8", "abort.lock_slip_pct=100"]
VARIANTS = [("off", "subsystems.esc=false,subsystems.cs=false", "without SC", "-"),
            ("sc", "subsystems.esc=true,subsystems.cs=true", "with ESC + CS", "--")]
COLORS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, gg="1.0:0.05:1.8", laps=3)
    p.add_argument("--mpc-gg", default="1.0:0.1:1.6",
                   help="GG values for the MPC controllers (slower than real time x100; "
                        "default 1.0:0.1:1.6)")
    p.add_argument("--mpc-laps", type=int, default=1,
                   help="laps per run for the MPC controllers (default 1)")
    p.add_argument("--mpc-threads", type=int, default=1,
                   help="worker threads for the MPC controllers (default 1: parallel Ipopt/MUMPS "
                        "solves crashed in our runs)")
    p.add_argument("--controllers",
                   help="comma-separated motion controllers (default: all scw offers)")
    args = p.parse_args(argv)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    controllers = (args.controllers.split(",") if args.controllers
                   else scwexp.list_controllers(scw))
    rows, skipped, commands, walls = [], {}, [], {}
    for ctrl in controllers:
        csv_path = os.path.join(out, f"sweep_{ctrl}.csv")
        log = os.path.join(out, f"scw_{ctrl}.log")
        if os.path.exists(csv_path):
            os.remove(csv_path)  # never read a previous run's table
        configs = [f"{ctrl}_{v}:motion.controller={ctrl},{o}" for v, o, _, _ in VARIANTS]
        fast = ctrl == "pure_pursuit"
        laps, gg = (args.laps, args.gg) if fast else (args.mpc_laps, args.mpc_gg)
        run_args = argparse.Namespace(**vars(args))
        if not fast:
            run_args.threads = args.mpc_threads
        cmd = scwexp.sweep_cmd(scw, run_args, [f"laps={laps}"] + BASE_SETS + args.set,
                               [f"gg_scale={gg}"], configs, csv_path)
        t = scwexp.Timer()
        proc = scwexp.run(cmd, log=log, check=False)
        walls[ctrl] = t.seconds()
        commands.append(" ".join(cmd))
        if proc.returncode != 0 or not os.path.exists(csv_path):
            with open(log) as f:
                reason = f.read().strip().splitlines()
            reason = [x for x in reason if not x.startswith("iter") and x.strip()]
            skipped[ctrl] = (f"exit code {proc.returncode}, no results: " +
                             " ".join(reason[-3:]))[:400]
            print(f"skipping {ctrl}: {skipped[ctrl]}")
            continue
        rows += scwexp.read_csv(csv_path)

    plot_configs = []
    for k, ctrl in enumerate(c for c in controllers if c not in skipped):
        for v, _, label, ls in VARIANTS:
            plot_configs.append((f"{ctrl}_{v}", None, f"{ctrl} {label}",
                                 COLORS[k % len(COLORS)], ls))
    png = os.path.join(out, f"{STUDY}.png")
    study2_lateral.plot_sweep(rows, plot_configs, png,
                              "Study 3: motion controllers without (solid) / with (dashed) "
                              "ESC + CS, rear μy −20 %")
    summary = {"study": STUDY, "commands": commands, "wall_time_s": timer.seconds(),
               "wall_time_per_controller_s": walls, "controllers": controllers,
               "skipped": skipped, "figures": [os.path.relpath(png, scwexp.RESULTS)],
               "series": {}}
    for name, _, label, _, _ in plot_configs:
        s = scwexp.series(rows, name)
        a = scwexp.analyse_series(s)
        a["label"] = label
        a["max_abs_sideslip_deg"] = [r["max_abs_sideslip_deg"] for r in s]
        a["mean_lap_time_s"] = [r["mean_lap_time_s"] for r in s]
        a["status"] = [r["status"] for r in s]
        for k in ("esc_count", "cs_count", "abs_count", "tc_count"):
            a[k] = [r[k] for r in s]
        summary["series"][name] = a
        print(f"{name}: max stable GG {a['max_stable']}, first abort {a['first_abort']} "
              f"({a['first_abort_status']}), min lap {scwexp.fmt(a['min_lap_time_s'], 3)} s at "
              f"GG {a['min_lap_value']}")
    scwexp.write_summary(STUDY, summary)
    print(f"{STUDY}: {timer.seconds():.0f} s wall; outputs in {out}")
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
