#!/usr/bin/env python3
"""Turns trace CSVs (scw simulate --trace, scw sweep --trace-dir) into the paper's time-series
figure (Fig. "first lap at GG = 1.4"), over the distance driven (or time):

  speed (actual, and the target speed of the reference dashed), lateral error, heading error,
  sideslip β, yaw rate against ESC's yaw-rate reference, ESC's yaw-moment demand, steering
  (requested dashed, the stability controller's output solid: countersteer is the difference),
  throttle (requested dashed, output solid: TC's cut is the difference), longitudinal wheel slip,
  brake pressure (requested dashed, applied solid) and the interventions of all four subsystems
  (ESC, CS, ABS, TC);

with lap boundaries, grey bands where a scenario event (a throttle or steering fault, a rear-grip
loss, a gust: the trace's `events` column) was active and, where the run aborted, the abort point
and its reason. The title names
the scenario, the track it was driven on, the overrides and the parameter set.

One trace: every wheel's slip and pressure, one row per subsystem in the intervention panel.
Several traces (overlaid, e.g. the four configurations of study 2): one colour per trace; the
slip panel shows the wheel with the largest |slip| at each instant and the pressure panel the sum
over the four wheels; one row per trace in the intervention panel with a lane per subsystem.

The title comes from the trace itself: scw simulate --trace T.csv writes T.csv.meta.yaml beside
it (scenario, track, overrides, parameter files, and how the run ended). Without it (a trace of an
older scw, or of scw sweep --trace-dir), the run summary (scw simulate --summary S.yaml) is used,
given with --summary or found beside the trace as <trace>.yaml, <trace>_summary.yaml or
<trace>.summary.yaml (it names the scenario, not the track); --params names the parameter set
instead of the recorded file.

    python3 experiments/plot_trace.py TRACE.csv [TRACE2.csv ...] -o FIG.png
        [--summary S.yaml ...] [--params NAME] [--labels a,b,...] [--x distance|time]
        [--lap N] [--title TEXT]

Exit codes: 0 written; 2 bad arguments or a file that is not a scw trace (with a message, no
traceback).
"""


import argparse
import os
import sys

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
from scwexp.trace_plot import TraceError, plot  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("traces", nargs="+", help="trace CSV files (scw simulate --trace)")
    p.add_argument("-o", "--out", help="output PNG (default: the first trace with .png)")
    p.add_argument("--summary", action="append",
                   help="run summary of a trace (scw simulate --summary), once per trace in "
                        "order (default: <trace>.yaml, <trace>_summary.yaml or "
                        "<trace>.summary.yaml beside it)")
    p.add_argument("--params", help="name of the stability parameter set, for the title")
    p.add_argument("--labels", help="comma-separated legend labels (default: from the summary "
                                    "or the sweep's file name)")
    p.add_argument("--x", choices=["distance", "time"], default="distance")
    p.add_argument("--lap", type=int, help="only this lap (0-based, the trace's lap column)")
    p.add_argument("--title", help="title instead of scenario, parameters and end of the run")
    args = p.parse_args(argv)
    labels = args.labels.split(",") if args.labels else None
    if labels and len(labels) != len(args.traces):
        p.error(f"--labels has {len(labels)} names for {len(args.traces)} traces")
    if args.summary and len(args.summary) != len(args.traces):
        p.error(f"--summary given {len(args.summary)} times for {len(args.traces)} traces")
    for t in args.traces + (args.summary or []):
        if not os.path.isfile(t):
            p.error(f"no such file: {t}" if not os.path.exists(t) else f"not a regular file: {t}")
    out = args.out or os.path.splitext(args.traces[0])[0] + ".png"
    try:
        _, title, drawn = plot(args.traces, out, labels, args.x, args.lap, args.title,
                               args.summary, args.params)
    except TraceError as e:
        print(f"plot_trace.py: error: {e}", file=sys.stderr)
        return 2
    print(f"wrote {out}")
    print("title: " + title.replace("\n", " | "))
    print("panels: " + ", ".join(drawn))
    return 0


if __name__ == "__main__":
    sys.exit(main())
