# Figure of one `scw maneuver` result (drawn by `scw maneuver --plot`, the script embedded in scw).
# Usage: python3 - RESULT.json OUT.png   (exit 3 when matplotlib is missing)
#
# The title says what was run (maneuver, standard, speed, stability control on or off with the
# subsystems, the params and vehicle files) and the verdict; the pass limits are drawn as labelled
# lines in the panels of the values they bound and listed under the title; the run colours have a
# legend (a few runs) or a colour bar of the series variable (many runs, e.g. the amplitudes of a
# sine with dwell); the notes of the result (a subsystem that never acted) are printed at the foot.
import json
import math
import os
import sys
import textwrap

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
except ImportError:
    sys.exit(3)

# At most this many runs get a legend entry each; more get a colour bar.
LEGEND_RUNS = 8


def series(run, key):
    return [math.nan if v is None else v for v in run["signals"][key]]


def number(x, digits=2):
    return "%.*f" % (digits, x) if isinstance(x, (int, float)) else "?"


def short(path):
    return path if path in ("", "built-in") else os.path.basename(path)


def limit_text(lim):
    sign = "<=" if lim["bound"] == "max" else ">="
    return "%s %s %g (%s; %s)" % (lim["key"], sign, lim["limit"], lim["source"], lim["runs"])


def header(r):
    """Title lines: what was run, under which conditions, and the verdict."""
    setup = r.get("setup", {})
    cond = r.get("conditions", {})
    v = setup.get("speed_mps")
    speed = " at %s m/s (%s km/h)" % (number(v, 1), number(v * 3.6, 0)) if v is not None else ""
    first = "%s (%s)%s" % (r["maneuver"], r["standard"], speed)
    if cond:
        second = "stability control %s (%s); params: %s; vehicle: %s" % (
            cond.get("stability_control", "?"), cond.get("subsystems", "?"),
            short(cond.get("stability", "?")), short(cond.get("vehicle", "?")))
    else:
        second = "conditions not recorded"
    third = "%d of %d criteria failed" % (r["criteria_failed"], r["criteria_checked"])
    return [first, second, third]


def limits_of(r, keys):
    return [lim for lim in r.get("limits", []) if lim["key"] in keys]


def summary_panel(ax, runs, r, keys, styles, ylabel):
    """Values of the runs over the series variable, with each limit as a labelled line and the
    runs that failed it circled in red."""
    lv = [run["level"] for run in runs]
    for key, style in zip(keys, styles):
        vals = [run["values"].get(key) for run in runs]
        vals = [math.nan if v is None else v for v in vals]
        line, = ax.plot(lv, vals, style, ms=4, label=key)
        for lim in limits_of(r, [key]):
            # Over the runs the limit applies to (FMVSS 126's displacement: from 5 A on).
            at = [run["level"] for run in runs
                  if any(c["key"] == key and c["limit"] == lim["limit"]
                         for c in run.get("criteria", []))] or lv
            ax.hlines(lim["limit"], min(at), max(at), color=line.get_color(), ls="--", lw=0.9,
                      label="limit %s %g (%s; %s)" % ("<=" if lim["bound"] == "max" else ">=",
                                                      lim["limit"], lim["source"], lim["runs"]))
        failed = [(run["level"], c["value"]) for run in runs for c in run.get("criteria", [])
                  if c["key"] == key and not c["passed"] and c["value"] is not None]
        if failed:
            ax.plot([f[0] for f in failed], [f[1] for f in failed], "o", mfc="none", mec="red",
                    ms=9, mew=1.2, label="%s failed" % key)
    ax.set_xlabel(r.get("series") or "run")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, loc="best")


def main():
    src, out = sys.argv[1], sys.argv[2]
    with open(src) as f:
        r = json.load(f)
    runs = r["runs"]
    swd = r["maneuver"] == "sine_with_dwell"
    panels = [("steer_deg", "road-wheel steer [deg]"), ("yaw_rate_degps", "yaw rate [deg/s]"),
              ("beta_deg", "sideslip [deg]"), ("speed_mps", "speed [m/s]")]
    if not swd and all("slip_rear_pct" in run["signals"] for run in runs):
        panels.append(("slip_rear_pct", "rear slip [%]\n(< 0 braking)"))
    summaries = []
    if swd:
        summaries = [(["ratio_1_00_pct", "ratio_1_75_pct"], ["o-", "s-"], "yaw-rate ratio [%]"),
                     (["lateral_displacement_m"], ["d-"], "lateral displacement\n"
                                                          "at BOS + 1.07 s [m]")]
    notes = r.get("notes", [])
    limit_lines = textwrap.wrap("pass limits: " + "; ".join(limit_text(lim)
                                                           for lim in r["limits"]), 130) \
        if r.get("limits") else []
    rows = len(panels) + len(summaries)
    top = header(r)
    fig, axes = plt.subplots(rows, 1, figsize=(8.5, 2.2 * rows + 0.9), constrained_layout=True)
    cmap = plt.get_cmap("viridis")
    levels = [run["level"] for run in runs]
    lo, hi = min(levels), max(levels)
    norm = Normalize(vmin=lo, vmax=hi if hi > lo else lo + 1.0)
    many = len(runs) > LEGEND_RUNS
    for i, run in enumerate(runs):
        color = cmap(norm(run["level"])) if many else cmap(i / max(1, len(runs) - 1))
        t = series(run, "t_s")
        for ax, (key, label) in zip(axes, panels):
            ax.plot(t, series(run, key), color=color, lw=1.0, label=run["label"])
            ax.set_ylabel(label)
    for ax in axes[:len(panels)]:
        ax.grid(True, alpha=0.3)
        ax.axvline(0.0, color="k", lw=0.6, ls=":")
    axes[len(panels) - 1].set_xlabel("time since the program began [s]")
    if many:
        sm = ScalarMappable(norm=norm, cmap=cmap)
        sm.set_array([])
        bar = fig.colorbar(sm, ax=list(axes[:len(panels)]), fraction=0.04, pad=0.01)
        bar.set_label("run colour: " + (r.get("series") or "run"), fontsize=8)
    else:
        axes[0].legend(fontsize=6, ncol=4, loc="upper right", title="runs", title_fontsize=6)
    for ax, (keys, styles, ylabel) in zip(axes[len(panels):], summaries):
        summary_panel(ax, runs, r, keys, styles, ylabel)
    fig.suptitle("\n".join(top + limit_lines), fontsize=8)
    if notes:
        text = "\n".join(textwrap.fill("note: " + n, 150) for n in notes)
        fig.supxlabel(text, fontsize=7, color="darkred", ha="left", x=0.01)
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110, metadata={"Software": None})
    os.replace(tmp, out)
    # What was drawn, for the tests (the CLI passes the last line of a failure only).
    print("title: " + " | ".join(top + limit_lines))
    print("colours: " + ("colour bar" if many else "legend"))
    print("notes: %d" % len(notes))


try:
    main()
except Exception as e:  # the CLI shows the last line
    print("maneuver_plot: %s" % e)
    sys.exit(1)
