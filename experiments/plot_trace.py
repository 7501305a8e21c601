#!/usr/bin/env python3
"""Turns trace CSVs (scw simulate --trace, scw sweep --trace-dir) into the paper's time-series
figure (Fig. "first lap at GG = 1.4"): lateral error, speed, heading error and sideslip over the
distance driven (or time), with the stability interventions shaded.

One trace: ESC, CS, ABS and TC activity shaded in every panel. Several traces (overlaid, e.g.
the four configurations of study 2): one extra panel with a row of intervention bars per trace
(ESC dark, CS light).

    python3 experiments/plot_trace.py TRACE.csv [TRACE2.csv ...] -o FIG.png
        [--labels a,b,...] [--x distance|time] [--lap N] [--title TEXT]
"""

import argparse
import csv
import math
import os
import sys

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PANELS = [
    ("lateral_error_m", "lateral error [m]"),
    ("vx_mps", "speed [m/s]"),
    ("heading_error_deg", "heading error [deg]"),
    ("beta_deg", "sideslip β [deg]"),
]
INTERVENTIONS = [("esc_active", "ESC", "tab:red"), ("cs_active", "CS", "tab:blue"),
                 ("abs_active", "ABS", "tab:orange"), ("tc_active", "TC", "tab:green")]


def load(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        data = [[float(x) if x not in ("", "nan") else math.nan for x in row] for row in reader]
    if not data:
        raise SystemExit(f"error: {path} has no rows")
    arr = np.array(data, dtype=float)
    cols = {name: arr[:, i] for i, name in enumerate(header)}
    missing = [c for c, _ in PANELS if c not in cols] + [c for c in ("t_s", "s_m") if c not in cols]
    if missing:
        raise SystemExit(f"error: {path} lacks the columns {', '.join(missing)} (not a scw trace?)")
    return cols


def distance(cols):
    """Distance driven [m]: the track position unwrapped at each new lap."""
    s = cols["s_m"]
    if "lap" in cols and len(s):
        lap = cols["lap"]
        length = np.nanmax(s)
        return s - s[0] + (lap - lap[0]) * length
    return s - s[0]


def spans(t, active):
    """(start, end) of the intervals where `active` is set."""
    out, start = [], None
    for i, a in enumerate(active > 0.5):
        if a and start is None:
            start = t[i]
        if not a and start is not None:
            out.append((start, t[i]))
            start = None
    if start is not None:
        out.append((start, t[-1]))
    return out


def select_lap(cols, lap):
    if lap is None or "lap" not in cols:
        return cols
    keep = cols["lap"] == lap
    if not keep.any():
        raise SystemExit(f"error: the trace has no lap {lap}")
    return {k: v[keep] for k, v in cols.items()}


def plot(paths, out, labels=None, x="distance", lap=None, title=None):
    traces = [select_lap(load(p), lap) for p in paths]
    labels = labels or [os.path.splitext(os.path.basename(p))[0] for p in paths]
    multi = len(traces) > 1
    n_rows = len(PANELS) + (1 if multi else 0)
    heights = [1] * len(PANELS) + ([0.25 * len(traces) + 0.2] if multi else [])
    fig, axes = plt.subplots(n_rows, 1, figsize=(9, 2.0 * len(PANELS) + (0.6 if multi else 0)),
                             sharex=True, gridspec_kw={"height_ratios": heights})
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (cols, label) in enumerate(zip(traces, labels)):
        xs = distance(cols) if x == "distance" else cols["t_s"]
        color = colors[k % len(colors)] if multi else "k"
        for ax, (col, _) in zip(axes, PANELS):
            ax.plot(xs, cols[col], color=color, lw=1.0, label=label)
        if not multi:
            for col, name, c in INTERVENTIONS:
                if col not in cols:
                    continue
                first = True
                for a, b in spans(xs, cols[col]):
                    for ax in axes[:len(PANELS)]:
                        ax.axvspan(a, b, color=c, alpha=0.15, lw=0,
                                   label=name if first and ax is axes[0] else None)
                    first = False
        else:
            bar = axes[-1]
            y = len(traces) - 1 - k
            for col, shade in (("esc_active", 0.9), ("cs_active", 0.35)):
                if col in cols:
                    for a, b in spans(xs, cols[col]):
                        bar.axvspan(a, b, ymin=(y + 0.15) / len(traces),
                                    ymax=(y + 0.85) / len(traces), color=color, alpha=shade, lw=0)
    for ax, (_, ylabel) in zip(axes, PANELS):
        ax.set_ylabel(ylabel, fontsize=9)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, ncol=4, loc="upper right")
    if multi:
        bar = axes[-1]
        bar.set_yticks([(len(traces) - 1 - k + 0.5) / len(traces) for k in range(len(traces))])
        bar.set_yticklabels(labels, fontsize=8)
        bar.set_ylim(0, 1)
        bar.set_ylabel("ESC (dark)\nCS (light)", fontsize=8)
    axes[-1].set_xlabel("distance driven [m]" if x == "distance" else "time [s]")
    if title:
        axes[0].set_title(title)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("traces", nargs="+", help="trace CSV files")
    p.add_argument("-o", "--out", help="output PNG (default: the first trace with .png)")
    p.add_argument("--labels", help="comma-separated labels (default: file names)")
    p.add_argument("--x", choices=["distance", "time"], default="distance")
    p.add_argument("--lap", type=int, help="only this lap (0-based, the trace's lap column)")
    p.add_argument("--title")
    args = p.parse_args(argv)
    labels = args.labels.split(",") if args.labels else None
    if labels and len(labels) != len(args.traces):
        p.error(f"--labels has {len(labels)} names for {len(args.traces)} traces")
    for t in args.traces:
        if not os.path.isfile(t):
            p.error(f"no such trace file: {t}")
    out = args.out or os.path.splitext(args.traces[0])[0] + ".png"
    plot(args.traces, out, labels, args.x, args.lap, args.title)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
