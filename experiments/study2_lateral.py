#!/usr/bin/env python3
"""Study 2 (paper §V-A, lateral stability): no lateral stability control / ESC only / CS only /
ESC + CS with the point-mass MPC (motion.controller=pmpc), 3 laps per run, GG 1.0:0.05:1.8; a
series ends at its first abort (|β| > 20° or lateral error > 3 m, the defaults; the wheel-lock
abort is off: abort.lock_slip_pct=100). Slip control (ABS/TC) runs in all four, as in the car's
setup; the car's shipped stability parameters throughout.

The rear lateral grip is reduced in the simulated car only (plan_with_nominal_grip=true): the
planner and the MPC keep the unchanged, scaled limits, as in the paper. Robustness: rear μy
0.78 / 0.80 / 0.82 in one sweep. Then the first lap at GG 1.4 (rear μy 0.80) for all four,
traced (the paper's time-series figure), and the first lap at the GG where `none` first
aborts.

Sensitivity (unscored, rear μy 0.80): a 40 ms brake response (brakes.delay 0.006), and the
workspace's old defaults (pure pursuit, the reduced grip known to the planner).

Writes experiments/results/study2_lateral/: sweep*.csv, study2_lateral.png,
study2_timeseries_gg<GG>.png, study2_<sensitivity>.png, traces/, summary.json, scw*.log.

    python3 experiments/study2_lateral.py [--gg 1.0:0.05:1.8] [--refine 1] [--results DIR] [--laps 3] [--trace-gg 1.4]

A third sensitivity (unscored): the longitudinal controller holds its force while ESC acts
(motion.longitudinal.hold_during_esc=true), a declared interplay option, not the car
(closed-loop fidelity spec §8 item 14). The first aborts of rear μy 0.80 are re-run with traces
(diagnosis/), and the traced runs at `none`'s first abort give the knife-edge account
(scwexp.knife_edge: time from rear saturation to |β| = 20°, when ESC and CS act and what they
deliver against the yaw moment a bound says is needed).

Time: ~3 min on 2 cores (3 laps, the default axis).
"""

import argparse
import glob
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import knife_edge, plots, trace_plot  # noqa: E402
from scwexp.studies import (  # noqa: E402
    STUDY2 as STUDY, STUDY2_CONTROLLER as CONTROLLER, STUDY2_BASE_SETS as BASE_SETS,
    STUDY2_PERT as PERT, STUDY2_MAIN_PERT as MAIN_PERT, STUDY2_CONFIGS as CONFIGS,
    STUDY2_TOP as TOP)


def against_none(name):
    """Claim (b)'s P5 asks what each configuration did at `none`'s first-abort GG: each is run
    there (scwexp.refine_first_aborts, probe)."""
    return "none" if name != "none" else None


def figure(per_pert, path, title):
    panels = [(f"rear μy {v}", per_pert[v]) for v in per_pert]
    lines = [(n, label, color, "-") for n, _, label, color in CONFIGS]
    return plots.plot_grid(panels, lines, TOP, "max |β| [deg]", path, title, hline=20.0)


def time_series(scw, args, out, trace_dir, configs, pert, main_pert, mpc, gg, laps=1):
    """The traced run of all four configurations at one GG (rear μy of the main perturbation)
    and its figure: (command, {config: run fields}, figure, {config: trace file})."""
    sub = os.path.join(trace_dir, f"gg{gg:g}")
    os.makedirs(sub, exist_ok=True)
    trace_csv = os.path.join(out, f"timeseries_gg{gg:g}.csv")
    tsets = [f"laps={laps}", f"motion.controller={args.controller}", f"{pert[0]}={main_pert}"] + \
        BASE_SETS + args.set
    tcmd = scwexp.sweep_cmd(scw, args, tsets, [f"gg_scale={gg:g}"], configs, trace_csv,
                            extra=["--trace-dir", sub])
    tcmd.remove("--stop-at-first-abort")
    if mpc:
        i = tcmd.index("--threads")
        tcmd[i:i + 2] = ["--processes", str(max(1, args.processes))]
    scwexp.run(tcmd, log=os.path.join(out, f"scw_traces_gg{gg:g}.log"))
    trace_rows = scwexp.read_csv(trace_csv)
    traces, labels, runs, by_name = [], [], {}, {}
    for name, _, label, _ in CONFIGS:
        found = glob.glob(os.path.join(sub, f"{name}__*.csv"))
        r = next((x for x in trace_rows if x["config"] == name), None)
        if found and r:
            traces.append(found[0])
            by_name[name] = found[0]
            labels.append(f"{label} ({r['status']})")
        if r:
            runs[name] = {k: r.get(k) for k in scwexp.RUN_FIELDS}
    ts_png = os.path.join(out, f"study2_timeseries_gg{gg:g}.png")
    trace_plot.plot(traces, ts_png, labels, "distance", None,
                    f"Study 2: {'first lap' if laps == 1 else f'{laps} laps'} at GG "
                    f"{gg:g}, {args.controller}, "
                    f"rear μy {main_pert} in the car only")
    return tcmd, runs, ts_png, by_name


def knife_edge_of(scw, args, sets, none_abort, main_pert, xfiles, xr):
    """The knife-edge analysis of the traced runs at `none`'s first abort (xfiles: {config:
    trace}, xr: {config: run fields}): its numbers and the report's lines."""
    act = scwexp.column_info(args)["actuators"]
    vc = knife_edge.vehicle_constants(scw)
    t_act = knife_edge.SIM_ACTUATORS.get(act, vc)["brake_s"]
    corners = scwexp.track_corners(scw, sets)
    res = knife_edge.analyse_all(xfiles, vc["iz"], t_act, vc["alpha_peak_rad"],
                                 {n: xr.get(n, {}).get("status") for n in xfiles},
                                 vc["half_track_front"])
    ke = {"gg": none_abort, "mu": main_pert, "t_act": t_act, "iz": vc["iz"],
          "half_track": vc["half_track_front"],
          "results": res,
          "lines": [knife_edge.describe(n, lab, res.get(n), corners,
                                     xr.get(n, {}).get("status"))
                    for n, _, lab, _ in CONFIGS] + [knife_edge.verdict_line(res, act)]}
    return ke


def sensitivity(scw, args, out, configs, names, pert, main_pert, mpc, summary):
    """The unscored sensitivity runs at the main rear μy (40 ms brake, old defaults, the
    throttle held while ESC acts), each into summary["sensitivity"]."""
    one = (pert[0], [main_pert])
    variants = [
        ("brake40ms", "40 ms brake response (brakes.delay 0.006 s), rear μy " + main_pert,
         None, mpc, args.controller),
        ("old_defaults", "old defaults: pure pursuit, reduced grip known to the planner "
         "(plan_with_nominal_grip=false), rear μy " + main_pert, None, False,
         "pure_pursuit"),
        ("esc_hold", "interplay option, not the car: the longitudinal controller holds its "
         "force while ESC acts (motion.longitudinal.hold_during_esc=true), rear μy "
         + main_pert, None, mpc, args.controller),
    ]
    for tag, label, _, vmpc, ctrl in variants:
        t = scwexp.Timer()
        vsets = [f"laps={args.laps}", f"motion.controller={ctrl}"] + BASE_SETS + args.set
        if tag == "brake40ms":
            veh = scwexp.brake_40ms_vehicle(scw, os.path.join(out, "vehicle_brake40ms.yaml"))
            vsets.append(f"vehicle={veh}")
        elif tag == "esc_hold":
            vsets.append("motion.longitudinal.hold_during_esc=true")
        else:
            vsets = [s for s in vsets if not s.startswith("plan_with_nominal_grip")] + \
                ["plan_with_nominal_grip=false"]
        scmd, srows = scwexp.study_sweep(scw, args, vsets, configs,
                                         os.path.join(out, f"sweep_{tag}.csv"),
                                         os.path.join(out, f"scw_{tag}.log"), pert=one,
                                         mpc=vmpc, probe=against_none)
        sp = scwexp.perturbed_series(srows, names, *one)
        spng = figure(sp, os.path.join(out, f"study2_{tag}.png"),
                      f"Study 2, sensitivity (unscored): {label}")
        summary["sensitivity"][tag] = {"label": label, "command": " ".join(scmd),
                                       "wall_time_s": t.seconds(), "runs": sp,
                                       "figures": [os.path.relpath(spng, scwexp.RESULTS)]}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--rear-mu-y", default=",".join(PERT[1]),
                   help="rear lateral grip factors (default 0.78,0.8,0.82)")
    p.add_argument("--trace-gg", default="1.4", help="GG of the time-series figure (default 1.4)")
    p.add_argument("--controller", default=CONTROLLER, help="motion controller (default pmpc)")
    args = p.parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    pert = (PERT[0], args.rear_mu_y.split(","))
    main_pert = MAIN_PERT if MAIN_PERT in pert[1] else pert[1][len(pert[1]) // 2]
    mpc = args.controller != "pure_pursuit"
    sets = [f"laps={args.laps}", f"motion.controller={args.controller}"] + BASE_SETS + args.set
    configs = [f"{n}:{o}" for n, o, _, _ in CONFIGS]
    names = [n for n, *_ in CONFIGS]
    cmd, rows = scwexp.study_sweep(scw, args, sets, configs, os.path.join(out, "sweep.csv"),
                                   os.path.join(out, "scw.log"), pert=pert, mpc=mpc,
                                   probe=against_none)
    main_wall = timer.seconds()
    per_pert = scwexp.perturbed_series(rows, names, *pert)
    png = figure(per_pert, os.path.join(out, f"{STUDY}.png"),
                 f"Study 2: lateral SC configurations, {args.controller}, rear μy reduced in the "
                 "car only (x: aborted run, ★: minimum lap time)")

    # Time series: the first lap at the trace GG (the paper's 1.4) and at the GG where `none`
    # first aborts, rear μy of the main perturbation, all four configurations.
    trace_dir = os.path.join(out, "traces")
    os.makedirs(trace_dir, exist_ok=True)
    for old in glob.glob(os.path.join(trace_dir, "*.csv")) + \
            glob.glob(os.path.join(trace_dir, "*", "*.csv")):
        os.remove(old)

    ts_args = (scw, args, out, trace_dir, configs, pert, main_pert, mpc)
    tcmd, trace_runs, ts_png, trace_files = time_series(*ts_args, float(args.trace_gg))
    extra_ts, ke = None, None
    none_abort = per_pert[main_pert]["none"]["first_abort"]
    if none_abort is not None:
        if abs(none_abort - float(args.trace_gg)) > 1e-9:
            _, xruns, xpng, xfiles = time_series(*ts_args, none_abort, laps=args.laps)
            extra_ts = {"gg": none_abort, "runs": xruns,
                        "figure": os.path.relpath(xpng, scwexp.RESULTS)}
        else:
            xfiles = trace_files
        # The mechanism at the knife edge (issue 25 part 3), from those traces.
        ke = knife_edge_of(scw, args, sets, none_abort, main_pert, xfiles,
                           xruns if extra_ts else trace_runs)

    summary = {"study": STUDY, "command": " ".join(cmd), "trace_command": " ".join(tcmd),
               "controller": args.controller, "wall_time_main_s": main_wall,
               "perturbation": {"key": pert[0], "label": "rear μy",
                                "values": [str(v) for v in pert[1]], "main": main_pert},
               "configs": {n: label for n, _, label, _ in CONFIGS}, "runs": per_pert,
               "figures": [os.path.relpath(x, scwexp.RESULTS) for x in (png, ts_png)],
               "trace_gg": float(args.trace_gg), "trace_runs": trace_runs,
               "trace_at_none_abort": extra_ts, "knife_edge": ke, "sensitivity": {}}

    if not args.no_sensitivity:
        sensitivity(scw, args, out, configs, names, pert, main_pert, mpc, summary)
    # Where and how each configuration's first abort happened (main rear μy), from a trace.
    summary["diagnosis"] = scwexp.diagnose_series(
        scw, args, sets, [(n, o) for n, o, _, _ in CONFIGS], per_pert[main_pert], pert[0],
        main_pert, out)
    summary["diagnosis_perturbation"] = main_pert
    scwexp.finish_study(STUDY, scw, args, sets, summary, timer, per_pert, "rear μy", out, main_wall)
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
