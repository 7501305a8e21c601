#!/usr/bin/env python3
"""Compares N stability params files (e.g. the car's set and tuned sets from scw tune) on the
training and held-out scenarios of a scenario set (scw evaluate) and on extra tracks (Monza from
../shared/data when present, plus any track files given with --track): a table (Markdown + CSV)
and plots of the mean lap time and max |β| per scenario and set.

    python3 experiments/compare.py [PARAMS.yaml ...] [--scenarios SET.yaml] [--track T.csv ...]
        [--no-default-tracks] [--out DIR] [--threads 0]

Without PARAMS the car's set params/stability/default.yaml is evaluated alone. Writes to
experiments/results/compare/ (or --out): comparison.md, comparison.csv, compare_lap_time.png,
compare_sideslip.png, extra_tracks_set.yaml, summary.json.
"""

import argparse
import csv
import io
import math
import os
import sys

import scwexp  # first: picks Debian's numpy/matplotlib, Agg backend
import report  # noqa: E402  (regenerates report.md after the study)

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MONZA = os.path.join(scwexp.ROOT, "..", "shared", "data", "tracks", "racetrack-database",
                     "tracks", "Monza.csv")
# Scenarios driven on each extra track: nominal and the oversteer case of the default set.
TRACK_SCENARIOS = [
    ("nominal_gg1.1", ["gg_scale=1.1", "laps=2"]),
    ("rear_grip-20_gg1.2", ["grip.rear_mu_y=0.8", "gg_scale=1.2", "laps=2",
                            "abort.lock_slip_pct=100"]),
]


def extra_tracks_set(tracks, path):
    """A scenario-set file with the track scenarios as its training group."""
    lines = ["name: extra_tracks", "training:"]
    for t in tracks:
        stem = os.path.splitext(os.path.basename(t))[0].lower()
        for name, sets in TRACK_SCENARIOS:
            items = ", ".join(f'"{s}"' for s in [f"track={os.path.abspath(t)}"] + sets)
            lines.append(f"  - {{name: {stem}_{name}, weight: 1.0, set: [{items}]}}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def read_rows(path, group_rename=None):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if group_rename:
        for r in rows:
            r["group"] = group_rename
    return rows


def markdown(rows, labels):
    scenarios = []
    for r in rows:
        key = (r["group"], r["scenario"])
        if key not in scenarios:
            scenarios.append(key)
    head = "| group | scenario | " + " | ".join(labels) + " |"
    out = [head, "|" + "---|" * (2 + len(labels))]
    for g, sc in scenarios:
        cells = []
        for lab in labels:
            r = next((x for x in rows if x["group"] == g and x["scenario"] == sc and
                      x["set"] == lab), None)
            if r is None:
                cells.append("–")
            elif r["status"] == "completed":
                cells.append(f"{float(r['mean_lap_time_s']):.3f} s, |β| "
                             f"{float(r['max_abs_sideslip_deg']):.1f}°, ESC "
                             f"{r['esc_count']}, CS {r['cs_count']}")
            else:
                cells.append(f"**{r['status']}** at {100 * float(r['progress']):.0f} %")
        out.append(f"| {g} | {sc} | " + " | ".join(cells) + " |")
    out.append("")
    out.append("Cells: mean lap time, max |β|, ESC and CS activations; an aborted run shows its "
               "status and the fraction of the planned distance driven.")
    return "\n".join(out)


def bar_plot(rows, labels, field, ylabel, path, title):
    scenarios = []
    for r in rows:
        key = f"{r['group']}/{r['scenario']}"
        if key not in scenarios:
            scenarios.append(key)
    x = np.arange(len(scenarios))
    w = 0.8 / max(1, len(labels))
    fig, ax = plt.subplots(figsize=(max(7, 0.9 * len(scenarios) + 2), 4.5))
    for k, lab in enumerate(labels):
        vals, aborted = [], []
        for sc in scenarios:
            r = next((y for y in rows if f"{y['group']}/{y['scenario']}" == sc and
                      y["set"] == lab), None)
            v = scwexp.to_float(r[field]) if r else math.nan
            vals.append(v)
            aborted.append(r is not None and r["status"] != "completed")
        bars = ax.bar(x + (k - (len(labels) - 1) / 2) * w, np.nan_to_num(vals), w, label=lab)
        for b, ab in zip(bars, aborted):
            if ab:
                b.set_hatch("//")
                ax.annotate("abort", (b.get_x() + b.get_width() / 2, b.get_height()),
                            ha="center", va="bottom", fontsize=7, rotation=90)
    ax.set_xticks(x)
    ax.set_xticklabels(scenarios, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    if field == "mean_lap_time_s":
        finite = [scwexp.to_float(r[field]) for r in rows
                  if not math.isnan(scwexp.to_float(r[field]))]
        if finite:
            ax.set_ylim(0.95 * min(finite), 1.02 * max(finite))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("params", nargs="*", help="stability params files (car's ROS 2 layout)")
    p.add_argument("--scenarios", help="scenario set file (default: scw's built-in set)")
    p.add_argument("--track", action="append", default=[],
                   help="extra track file (.csv centre line or .yaml), repeatable")
    p.add_argument("--no-default-tracks", action="store_true",
                   help="do not add Monza from ../shared/data even when present")
    p.add_argument("--out", default=None, help="output folder (default results/compare)")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--no-report", action="store_true")
    args = p.parse_args(argv)
    scw = scwexp.find_scw()
    is_default_out = args.out is None
    out = scwexp.results_dir("compare") if is_default_out else args.out
    os.makedirs(out, exist_ok=True)
    timer = scwexp.Timer()
    params = args.params or [os.path.join(scwexp.ROOT, "params", "stability", "default.yaml")]
    for f in params + args.track:
        if not os.path.isfile(f):
            sys.exit(f"error: no such file: {f}")
    labels = [os.path.basename(f) for f in params]
    if len(set(labels)) != len(labels):
        sys.exit("error: the params files need distinct file names (they label the columns)")

    base_csv = os.path.join(out, "evaluate_sets.csv")
    cmd = [scw, "evaluate"] + [os.path.abspath(f) for f in params] + ["--csv", base_csv,
                                                                      "--threads",
                                                                      str(args.threads)]
    if args.scenarios:
        cmd += ["--scenarios", os.path.abspath(args.scenarios)]
    scwexp.run(cmd, log=os.path.join(out, "scw_evaluate.log"))
    rows = read_rows(base_csv)

    tracks = list(args.track)
    if not args.no_default_tracks and os.path.isfile(MONZA):
        tracks.append(os.path.normpath(MONZA))
    elif not args.no_default_tracks:
        print(f"note: {os.path.normpath(MONZA)} not present; no Monza scenarios")
    commands = [" ".join(cmd)]
    if tracks:
        set_path = os.path.join(out, "extra_tracks_set.yaml")
        extra_tracks_set(tracks, set_path)
        track_csv = os.path.join(out, "evaluate_tracks.csv")
        tcmd = [scw, "evaluate"] + [os.path.abspath(f) for f in params] + [
            "--scenarios", set_path, "--csv", track_csv, "--threads", str(args.threads)]
        scwexp.run(tcmd, log=os.path.join(out, "scw_evaluate_tracks.log"))
        rows += read_rows(track_csv, group_rename="extra_tracks")
        commands.append(" ".join(tcmd))

    fields = list(rows[0].keys())
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    csv_path = os.path.join(out, "comparison.csv")
    with open(csv_path + ".tmp", "w") as f:
        f.write(buf.getvalue())
    os.replace(csv_path + ".tmp", csv_path)
    md_path = os.path.join(out, "comparison.md")
    with open(md_path, "w") as f:
        f.write("# Comparison of stability parameter sets\n\n" + markdown(rows, labels) + "\n")
    lap_png = os.path.join(out, "compare_lap_time.png")
    beta_png = os.path.join(out, "compare_sideslip.png")
    bar_plot(rows, labels, "mean_lap_time_s", "mean lap time [s]", lap_png,
             "Mean lap time per scenario (hatched: aborted)")
    bar_plot(rows, labels, "max_abs_sideslip_deg", "max |β| [deg]", beta_png,
             "Max sideslip per scenario (hatched: aborted)")
    totals = {}
    for lab in labels:
        mine = [r for r in rows if r["set"] == lab]
        totals[lab] = {"completed": sum(r["status"] == "completed" for r in mine),
                       "runs": len(mine)}
    if is_default_out:
        scwexp.write_summary("compare", {
            "labels": labels, "commands": commands, "tracks": tracks,
            "wall_time_s": timer.seconds(), "totals": totals,
            "markdown": os.path.relpath(md_path, scwexp.RESULTS),
            "figures": [os.path.relpath(x, scwexp.RESULTS) for x in (lap_png, beta_png)]})
    print(markdown(rows, labels))
    print(f"compare: {timer.seconds():.0f} s wall; outputs in {out}")
    if is_default_out:
        report.update(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
