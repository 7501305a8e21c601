#!/usr/bin/env python3
"""Study 2 (paper §V-A, lateral stability): no lateral stability control / ESC only / CS only /
ESC + CS with the rear lateral grip reduced by 20 % (grip.rear_mu_y=0.8) over increasing GG;
a series ends at its first abort (|β| > 20° or lateral error > 3 m; the wheel-lock abort is off:
abort.lock_slip_pct=100). Slip control (ABS/TC) runs in all four, as in the car's setup.
Then the first lap at GG 1.4 for all four configurations, traced (the paper's time-series
figure; each configuration runs there whether or not its series stopped earlier).

Writes experiments/results/study2_lateral/: sweep.csv, study2_lateral.png (max |β| and mean lap
time per GG), traces/ + study2_timeseries_gg1.4.png, summary.json, scw*.log.

    python3 experiments/study2_lateral.py [--gg 1.0:0.05:1.8] [--laps 3] [--trace-gg 1.4]
"""

import argparse
import glob
import os
import sys

import scwexp  # first: picks Debian's numpy/matplotlib, Agg backend

import matplotlib.pyplot as plt  # noqa: E402
import plot_trace  # noqa: E402

STUDY = "study2_lateral"
BASE_SETS = ["grip.rear_mu_y=0.8", "abort.lock_slip_pct=100"]
CONFIGS = [
    ("none", "subsystems.esc=false,subsystems.cs=false", "no lateral SC", "tab:gray"),
    ("esc", "subsystems.esc=true,subsystems.cs=false", "ESC only", "tab:red"),
    ("cs", "subsystems.esc=false,subsystems.cs=true", "CS only", "tab:blue"),
    ("esc+cs", "subsystems.esc=true,subsystems.cs=true", "ESC + CS", "tab:purple"),
]


def plot_sweep(rows, configs, path, title):
    fig, (ax_b, ax_lap) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for name, _, label, color, *style in configs:
        ls = style[0] if style else "-"
        s = scwexp.series(rows, name)
        if not s:
            continue
        ax_b.plot([r["gg_scale"] for r in s], [r["max_abs_sideslip_deg"] for r in s], ls,
                  marker="o", color=color, ms=3, label=label)
        scwexp.mark_aborts(ax_b, s, "gg_scale", "max_abs_sideslip_deg", color)
        done = [r for r in s if r["status"] == "completed"]
        ax_lap.plot([r["gg_scale"] for r in done], [r["mean_lap_time_s"] for r in done], ls,
                    marker="o", color=color, ms=3, label=label)
        if done:
            best = min(done, key=lambda r: r["mean_lap_time_s"])
            ax_lap.plot([best["gg_scale"]], [best["mean_lap_time_s"]], marker="*", ms=12,
                        color=color, ls="none")
    ax_b.axhline(20.0, color="k", ls=":", lw=1)
    ax_b.set_ylabel("max |β| [deg]")
    ax_b.grid(True, alpha=0.3)
    ax_b.legend(fontsize=8)
    ax_b.set_title(title)
    ax_lap.set_ylabel("mean lap time [s]")
    ax_lap.set_xlabel("acceleration scaling GG [-]")
    ax_lap.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, gg="1.0:0.05:1.8", laps=3)
    p.add_argument("--trace-gg", default="1.4", help="GG of the time-series figure (default 1.4)")
    args = p.parse_args(argv)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    csv_path = os.path.join(out, "sweep.csv")
    configs = [f"{n}:{o}" for n, o, _, _ in CONFIGS]
    cmd = scwexp.sweep_cmd(scw, args, [f"laps={args.laps}"] + BASE_SETS + args.set,
                           [f"gg_scale={args.gg}"], configs, csv_path)
    scwexp.run(cmd, log=os.path.join(out, "scw.log"))
    rows = scwexp.read_csv(csv_path)
    png = os.path.join(out, f"{STUDY}.png")
    plot_sweep(rows, CONFIGS, png, "Study 2: lateral SC configurations, rear μy −20 % "
               "(x: aborted run, ★: minimum lap time)")

    # Time series: the first lap at GG 1.4, every configuration (no stopping: one value).
    trace_dir = os.path.join(out, "traces")
    for old in glob.glob(os.path.join(trace_dir, "*.csv")):
        os.remove(old)
    trace_csv = os.path.join(out, f"timeseries_gg{args.trace_gg}.csv")
    tcmd = [scw, "sweep", "-o", trace_csv, "--trace-dir", trace_dir, "--set", "laps=1"]
    tcmd += BASE_SETS + args.set + scwexp.threads_arg(args) + ["--vary",
                                                               f"gg_scale={args.trace_gg}"]
    for c in configs:
        tcmd += ["--config", c]
    if args.stability:
        tcmd += ["--stability", args.stability]
    scwexp.run(tcmd, log=os.path.join(out, "scw_traces.log"))
    trace_rows = scwexp.read_csv(trace_csv)
    traces, labels = [], []
    for name, _, label, _ in CONFIGS:
        path = os.path.join(trace_dir, f"{name}__gg_scale-{args.trace_gg}.csv")
        if os.path.exists(path):
            r = next(x for x in trace_rows if x["config"] == name)
            traces.append(path)
            labels.append(f"{label} ({r['status']})")
    ts_png = os.path.join(out, f"study2_timeseries_gg{args.trace_gg}.png")
    plot_trace.plot(traces, ts_png, labels, "distance", None,
                    f"Study 2: first lap at GG {args.trace_gg}, rear μy −20 %")

    summary = {"study": STUDY, "command": " ".join(cmd), "trace_command": " ".join(tcmd),
               "wall_time_s": timer.seconds(),
               "figures": [os.path.relpath(x, scwexp.RESULTS) for x in (png, ts_png)],
               "series": {}, "trace_gg": float(args.trace_gg), "trace_runs": {}}
    for name, _, label, _ in CONFIGS:
        s = scwexp.series(rows, name)
        a = scwexp.analyse_series(s)
        a["label"] = label
        a["max_abs_sideslip_deg"] = [r["max_abs_sideslip_deg"] for r in s]
        a["mean_lap_time_s"] = [r["mean_lap_time_s"] for r in s]
        a["status"] = [r["status"] for r in s]
        for k in ("esc_count", "cs_count", "abs_count", "tc_count"):
            a[k] = [r[k] for r in s]
        summary["series"][name] = a
        r = next((x for x in trace_rows if x["config"] == name), None)
        if r:
            summary["trace_runs"][name] = {
                k: r[k] for k in ("status", "progress", "max_abs_sideslip_deg",
                                  "max_abs_lateral_error_m", "max_abs_heading_error_deg",
                                  "max_speed_mps", "end_s_m", "esc_count", "cs_count")}
    # Claim (d) of the paper: lap-time cost versus "none" at GG 1.3.
    at = {}
    for name, *_ in CONFIGS:
        r = scwexp.row_at(rows, name, 1.3)
        at[name] = ({k: r[k] for k in ("status", "mean_lap_time_s", "esc_count", "cs_count")}
                    if r else None)
    summary["gg1.3"] = at
    summary["wall_time_s"] = timer.seconds()
    scwexp.write_summary(STUDY, summary)
    for name, a in summary["series"].items():
        print(f"{name}: max stable GG {a['max_stable']}, first abort {a['first_abort']} "
              f"({a['first_abort_status']}), min lap {scwexp.fmt(a['min_lap_time_s'], 3)} s at "
              f"GG {a['min_lap_value']}")
    print(f"{STUDY}: {timer.seconds():.0f} s wall; outputs in {out}")
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
