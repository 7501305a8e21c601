# Figure of one `scw maneuver` result (drawn by `scw maneuver --plot`, the script embedded in scw).
# Usage: python3 - RESULT.json OUT.png   (exit 3 when matplotlib is missing)
import json
import math
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(3)


def series(run, key):
    return [math.nan if v is None else v for v in run["signals"][key]]


def main():
    src, out = sys.argv[1], sys.argv[2]
    with open(src) as f:
        r = json.load(f)
    runs = r["runs"]
    swd = r["maneuver"] == "sine_with_dwell"
    panels = [("steer_deg", "road-wheel steer [deg]"), ("yaw_rate_degps", "yaw rate [deg/s]"),
              ("beta_deg", "sideslip [deg]"), ("speed_mps", "speed [m/s]")]
    rows = len(panels) + (1 if swd else 0)
    fig, axes = plt.subplots(rows, 1, figsize=(8, 2.2 * rows), constrained_layout=True)
    cmap = plt.get_cmap("viridis")
    for i, run in enumerate(runs):
        color = cmap(i / max(1, len(runs) - 1))
        t = series(run, "t_s")
        for ax, (key, label) in zip(axes, panels):
            ax.plot(t, series(run, key), color=color, lw=1.0, label=run["label"])
            ax.set_ylabel(label)
    for ax in axes[:len(panels)]:
        ax.grid(True, alpha=0.3)
        ax.axvline(0.0, color="k", lw=0.6, ls=":")
    axes[len(panels) - 1].set_xlabel("time since the program began [s]")
    if len(runs) <= 14:
        axes[0].legend(fontsize=6, ncol=4, loc="upper right")
    if swd:
        ax = axes[-1]
        lv = [run["level"] for run in runs]
        for key, limit, style in (("ratio_1_00_pct", 35.0, "o-"), ("ratio_1_75_pct", 20.0, "s-")):
            vals = [run["values"].get(key) for run in runs]
            vals = [math.nan if v is None else v for v in vals]
            line, = ax.plot(lv, vals, style, label=key.replace("_pct", " [%]"))
            ax.axhline(limit, color=line.get_color(), ls="--", lw=0.8)
        ax.set_xlabel("amplitude [A]")
        ax.set_ylabel("yaw-rate ratio [%]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    verdict = "%d of %d criteria failed" % (r["criteria_failed"], r["criteria_checked"])
    fig.suptitle("%s (%s): %s" % (r["maneuver"], r["standard"], verdict), fontsize=9)
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110, metadata={"Software": None})
    os.replace(tmp, out)


try:
    main()
except Exception as e:  # the CLI shows the last line
    print("maneuver_plot: %s" % e)
    sys.exit(1)
