#!/usr/bin/env python3
"""Study 1 (paper §V-A, longitudinal stability): slip control (ABS + TC) on vs off over
increasing acceleration scaling GG; 3 laps per run; a series ends at its first abort (wheel lock:
slip < -95 % for 0.5 s, wheel spin: slip > 50 % for 0.5 s; the other abort conditions stay on).
ESC and countersteer run in both configurations, as in the car's default setup.

Writes experiments/results/study1_longitudinal/: sweep.csv, study1_longitudinal.png (max front
slip solid, rear dashed, and mean lap time per GG), summary.json, scw.log.

    python3 experiments/study1_longitudinal.py [--gg 1.0:0.05:1.8] [--laps 3] [--threads 0]
"""

import argparse
import os
import sys

import scwexp  # first: picks Debian's numpy/matplotlib, Agg backend

import matplotlib.pyplot as plt  # noqa: E402

STUDY = "study1_longitudinal"
CONFIGS = [
    ("sc_on", "subsystems.abs=true,subsystems.tc=true", "slip control on", "tab:blue"),
    ("sc_off", "subsystems.abs=false,subsystems.tc=false", "slip control off", "tab:red"),
]


def plot(rows, path):
    fig, (ax_slip, ax_lap) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for k, (name, _, label, color) in enumerate(CONFIGS):
        s = scwexp.series(rows, name)
        if not s:
            continue
        gg = [r["gg_scale"] for r in s]
        ax_slip.plot(gg, [r["max_slip_front_pct"] for r in s], "-o", color=color, ms=3,
                     label=f"{label}, front")
        ax_slip.plot(gg, [r["max_slip_rear_pct"] for r in s], "--s", color=color, ms=3,
                     label=f"{label}, rear")
        scwexp.mark_aborts(ax_slip, s, "gg_scale", "max_slip_front_pct", color)
        scwexp.mark_aborts(ax_slip, s, "gg_scale", "max_slip_rear_pct", color)
        done = [r for r in s if r["status"] == "completed"]
        ax_lap.plot([r["gg_scale"] for r in done], [r["mean_lap_time_s"] for r in done], "-o",
                    color=color, ms=3, label=label)
        for r in s:
            if r["status"] != "completed":
                ax_lap.axvline(r["gg_scale"], color=color, ls=":", lw=1)
                ax_lap.annotate(f"abort: {r['status']}", (r["gg_scale"], 0.95 - 0.45 * k), color=color,
                                xycoords=("data", "axes fraction"), rotation=90, ha="right",
                                va="top", fontsize=8)
    ax_slip.set_ylabel("max |slip| [%]")
    ax_slip.grid(True, alpha=0.3)
    ax_slip.legend(fontsize=8)
    ax_slip.set_title("Study 1: slip control on/off (x: aborted run)")
    ax_lap.set_ylabel("mean lap time [s]")
    ax_lap.set_xlabel("acceleration scaling GG [-]")
    ax_lap.grid(True, alpha=0.3)
    ax_lap.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, gg="1.0:0.05:1.8", laps=3)
    args = p.parse_args(argv)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    csv_path = os.path.join(out, "sweep.csv")
    sets = [f"laps={args.laps}"] + args.set
    cmd = scwexp.sweep_cmd(scw, args, sets, [f"gg_scale={args.gg}"],
                           [f"{n}:{o}" for n, o, _, _ in CONFIGS], csv_path)
    scwexp.run(cmd, log=os.path.join(out, "scw.log"))
    rows = scwexp.read_csv(csv_path)
    png = os.path.join(out, f"{STUDY}.png")
    plot(rows, png)

    summary = {"study": STUDY, "command": " ".join(cmd), "wall_time_s": timer.seconds(),
               "figures": [os.path.relpath(png, scwexp.RESULTS)], "series": {}}
    for name, _, label, _ in CONFIGS:
        s = scwexp.series(rows, name)
        a = scwexp.analyse_series(s)
        a["label"] = label
        a["max_slip_front_pct"] = [r["max_slip_front_pct"] for r in s]
        a["max_slip_rear_pct"] = [r["max_slip_rear_pct"] for r in s]
        a["mean_lap_time_s"] = [r["mean_lap_time_s"] for r in s]
        a["status"] = [r["status"] for r in s]
        for k in ("abs_count", "tc_count", "esc_count", "cs_count"):
            a[k] = [r[k] for r in s]
        summary["series"][name] = a
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
