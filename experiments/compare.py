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

Time: ~20 s per params file on 2 cores.
"""

import argparse
import csv
import io
import math
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402

from scwexp import plots  # noqa: E402,F401  (the Agg backend, before pyplot)
import matplotlib.pyplot as plt  # noqa: E402

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


def scenario_keys(rows):
    """`group/scenario` of every row, in first-seen order (one chart row each)."""
    keys = []
    for r in rows:
        key = f"{r['group']}/{r['scenario']}"
        if key not in keys:
            keys.append(key)
    return keys


def find_row(rows, key, lab):
    return next((r for r in rows if f"{r['group']}/{r['scenario']}" == key and r["set"] == lab),
                None)


def aborted_text(r):
    """'aborted: sideslip at 43 %' for a run that did not complete ('not run' when missing)."""
    if r is None:
        return "not run"
    progress = scwexp.to_float(r.get("progress"))
    at = "" if math.isnan(progress) else f" at {100 * progress:.0f} %"
    return f"aborted: {r['status']}{at}"


# Inches per bar and around the bars of one scenario; the width is fixed, so the figure grows
# downwards with the number of scenarios instead of sideways.
BAR_IN, GAP_IN, FIG_W_IN, DPI = 0.22, 0.18, 9.0, 110


def horizontal_figure(n_rows, bars_per_row):
    height = 1.5 + n_rows * (bars_per_row * BAR_IN + GAP_IN)
    return plt.subplots(figsize=(FIG_W_IN, height), constrained_layout=True)


def finish(fig, ax, path, info, n_rows):
    ax.set_ylim(n_rows - 0.5, -0.5)  # the first scenario on top, as in comparison.md
    ax.grid(True, axis="x", alpha=0.3)
    fig.savefig(path, dpi=DPI, metadata={"Software": None})
    w, h = fig.get_size_inches()
    info["size_px"] = (round(w * DPI), round(h * DPI))
    info["xlim"] = tuple(ax.get_xlim())
    plt.close(fig)
    return info


def lap_time_plot(rows, labels, path):
    """The mean lap time per scenario. With several sets: each set's difference to the first one
    (labels[0]) in seconds, so that differences of a tenth of a second are visible whatever the
    lap time; the first set's own lap time is written beside the scenario's name. With one set:
    the lap times themselves from 0 s, so that a short track's bar is as visible as a long one's.
    A run that did not complete has no lap time: it is marked × at 0 with its status and the
    fraction of the distance driven. Returns what was drawn (for the tests): size_px, xlim,
    values {(scenario, set): x}, aborted [(scenario, set)], title."""
    keys = scenario_keys(rows)
    base, others = labels[0], labels[1:]
    shown = others if others else [base]
    fig, ax = horizontal_figure(len(keys), len(shown))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    w = 0.8 / len(shown)
    info = {"values": {}, "aborted": []}
    ticks, legend = [], set()
    extent = [0.0]
    marks = []  # (x, y, text, colour) of aborted runs, placed once the axis range is known
    for i, key in enumerate(keys):
        b = find_row(rows, key, base)
        b_val = scwexp.to_float(b["mean_lap_time_s"]) if b and b["status"] == "completed" \
            else math.nan
        if others:
            ticks.append(f"{key}  [{base}: " +
                         (f"{b_val:.2f} s]" if not math.isnan(b_val) else aborted_text(b) + "]"))
        else:
            ticks.append(key)
        for k, lab in enumerate(shown):
            y = i + (k - (len(shown) - 1) / 2) * w
            color = colors[(k + (1 if others else 0)) % len(colors)]
            r = b if not others else find_row(rows, key, lab)
            v = scwexp.to_float(r["mean_lap_time_s"]) if r and r["status"] == "completed" \
                else math.nan
            if math.isnan(v):
                info["aborted"].append((key, lab))
                marks.append((y, aborted_text(r), color))
                continue
            if others and math.isnan(b_val):
                # No difference without the first set's lap time: the lap time itself, as text.
                info["aborted"].append((key, base))
                marks.append((y, f"{v:.2f} s ({base} did not complete)", color))
                continue
            x = v - b_val if others else v
            info["values"][(key, lab)] = x
            extent.append(x)
            ax.barh(y, x, w, color=color, label=None if lab in legend else lab)
            legend.add(lab)
            ax.annotate(f"{x:+.2f} s" if others else f"{x:.2f} s", (x, y),
                        xytext=(3 if x >= 0 else -3, 0), textcoords="offset points",
                        ha="left" if x >= 0 else "right", va="center", fontsize=7)
    lo, hi = min(extent), max(extent)
    span = max(hi - lo, 0.2 if others else 1.0)
    # Room for the value labels on both sides, and for the aborted runs' text right of 0.
    ax.set_xlim(lo - (0.3 * span if lo < 0 else 0.0),
                hi + 0.35 * span + (0.45 * span if marks else 0.0))
    for y, text, color in marks:
        ax.plot([0.0], [y], marker="x", color=color, ms=7, mew=2, ls="none")
        ax.annotate(text, (0.0, y), xytext=(6, 0), textcoords="offset points", va="center",
                    fontsize=7, color=color)
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_yticks(range(len(keys)))
    ax.set_yticklabels(ticks, fontsize=7)
    if others:
        ax.set_xlabel(f"mean lap time minus {base}'s [s] (negative: faster)")
        title = (f"Mean lap time per scenario: {', '.join(others)} against {base}\n"
                 "× = the run did not complete (status, distance driven)")
    else:
        ax.set_xlabel("mean lap time [s]")
        title = f"Mean lap time per scenario: {base}\n× = the run did not complete"
    fig.suptitle(title, fontsize=9)  # centred on the figure: the row labels make the axes narrow
    if ax.get_legend_handles_labels()[1]:
        ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3,
                  frameon=False)
    info["title"] = title
    return finish(fig, ax, path, info, len(keys))


def sideslip_plot(rows, labels, path):
    """Max |β| per scenario and set (horizontal bars from 0); a run that did not complete is
    hatched (its value is the largest |β| until it ended). Returns what was drawn, as
    lap_time_plot."""
    keys = scenario_keys(rows)
    fig, ax = horizontal_figure(len(keys), len(labels))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    w = 0.8 / len(labels)
    info = {"values": {}, "aborted": []}
    legend = set()
    for k, lab in enumerate(labels):
        for i, key in enumerate(keys):
            r = find_row(rows, key, lab)
            v = scwexp.to_float(r["max_abs_sideslip_deg"]) if r else math.nan
            y = i + (k - (len(labels) - 1) / 2) * w
            if math.isnan(v):
                continue
            ab = r["status"] != "completed"
            info["values"][(key, lab)] = v
            if ab:
                info["aborted"].append((key, lab))
            ax.barh(y, v, w, color=colors[k % len(colors)], hatch="//" if ab else None,
                    edgecolor="k" if ab else None, label=None if lab in legend else lab)
            legend.add(lab)
            if ab:
                ax.annotate(aborted_text(r), (v, y), xytext=(3, 0), textcoords="offset points",
                            va="center", fontsize=7)
    ax.set_xlim(0.0, 1.45 * max(list(info["values"].values()) + [1.0]))
    ax.set_yticks(range(len(keys)))
    ax.set_yticklabels(keys, fontsize=7)
    ax.set_xlabel("max |β| [deg]")
    title = "Max sideslip per scenario (hatched: the run did not complete)"
    fig.suptitle(title, fontsize=9)  # centred on the figure: the row labels make the axes narrow
    ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, frameon=False)
    info["title"] = title
    return finish(fig, ax, path, info, len(keys))


def parse_args(argv=None):
    """The command line (see the module's docstring)."""
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
    return p.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    scw = scwexp.find_scw()
    is_default_out = args.out is None
    # Absolute: scw runs in the repository (scwexp.run), and its output paths must name the
    # same files as ours whatever the folder the script was started from.
    out = scwexp.results_dir("compare") if is_default_out else os.path.abspath(args.out)
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
    lap_time_plot(rows, labels, lap_png)
    sideslip_plot(rows, labels, beta_png)
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
        scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
