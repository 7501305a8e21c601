"""Trace figures (the paper's time-series figure, Fig. "first lap at GG = 1.4"): one or more traces
(scw simulate --trace, scw sweep --trace-dir) over the distance driven or time, with the
reference, the stability controller's outputs and the interventions of ESC, CS, ABS and TC; the
traces' loading and checks (TraceError) and the title from the run's meta file or summary.
experiments/plot_trace.py is its command line and describes the figure."""

import csv
import math
import os

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402

# Columns every scw trace has (tuning/sim/closed_loop.cc: TraceHeader); the rest are optional.
REQUIRED = ["t_s", "lap", "s_m", "vx_mps", "lateral_error_m", "heading_error_deg", "beta_deg"]
WHEELS = [("fl", "front left", "tab:blue"), ("fr", "front right", "tab:cyan"),
          ("rl", "rear left", "tab:red"), ("rr", "rear right", "tab:orange")]
INTERVENTIONS = [("esc_active", "ESC", "tab:red"), ("cs_active", "CS", "tab:blue"),
                 ("abs_active", "ABS", "tab:orange"), ("tc_active", "TC", "tab:green")]
REASONS = {
    "sideslip": "|β| above the abort threshold",
    "lateral_error": "lateral error above the abort threshold",
    "wheel_lock": "a wheel locked",
    "wheel_spin": "a wheel spun",
    "off_track": "left the track",
    "non_finite": "NaN/inf in the simulation",
    "timeout": "simulated time limit reached",
    "invalid_params": "parameter set rejected",
}


FIG_H = 22.0  # figure height [in]


class TraceError(ValueError):
    """A file that is not a usable scw trace or summary (reported without a traceback)."""


def load(path):
    """The trace's columns as float arrays; TraceError for anything that is not a scw trace."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if not header:
                raise TraceError(f"{path} is empty, not a scw trace (scw simulate --trace)")
            missing = [c for c in REQUIRED if c not in header]
            if missing:
                shown = ", ".join(header[:6]) + (", ..." if len(header) > 6 else "")
                raise TraceError(
                    f"{path} is not a scw trace (scw simulate --trace): it lacks the column(s) "
                    f"{', '.join(missing)}; its header is: {shown}")
            data = []
            for line, row in enumerate(reader, start=2):
                if not row:
                    continue
                if len(row) != len(header):
                    raise TraceError(f"{path} line {line}: {len(row)} fields, the header has "
                                     f"{len(header)} (a truncated or foreign file?)")
                try:
                    data.append([float(x) if x not in ("", "nan") else math.nan for x in row])
                except ValueError:
                    bad = next(x for x in row if not _is_number(x))
                    raise TraceError(f"{path} line {line}: '{bad[:40]}' is not a number "
                                     "(not a scw trace?)") from None
    except UnicodeDecodeError:
        raise TraceError(f"{path} is not a text file, not a scw trace") from None
    except csv.Error as e:
        raise TraceError(f"{path} is not a CSV file ({e})") from None
    except OSError as e:
        raise TraceError(f"cannot read {path}: {e.strerror or e}") from None
    if not data:
        raise TraceError(f"{path} has a trace header but no rows")
    arr = np.array(data, dtype=float)
    return {name: arr[:, i] for i, name in enumerate(header)}


def _is_number(x):
    try:
        float(x)
        return True
    except ValueError:
        return x in ("", "nan")


def load_summary(path):
    """The flat `key: value` run summary of scw simulate --summary as a dict of strings."""
    out = {}
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                if ":" not in line or line.startswith((" ", "#")):
                    continue
                k, v = line.split(":", 1)
                v = v.strip()
                if len(v) >= 2 and v[0] == v[-1] and v[0] in "\"'":
                    v = v[1:-1]
                out[k.strip()] = v
    except (OSError, UnicodeDecodeError) as e:
        raise TraceError(f"cannot read the summary {path}: {e}") from None
    if "status" not in out:
        raise TraceError(f"{path} is not a run summary (scw simulate --summary): no status")
    return out


def parameter_set(summary):
    """The stability parameter set a run used, from the trace's meta file: the file's name, or
    the built-in set."""
    value = summary.get("stability", "")
    return value if value.startswith("built-in") else os.path.basename(value)


def run_name(summary):
    """'default on monza (--set track=monza laps=1)': the scenario, the track it was driven on
    and the overrides, as the trace's meta file records them (a run summary has the scenario
    only)."""
    name = summary["scenario"]
    track = summary.get("track_name")
    if track:
        name += f" on {track}"
    overrides = summary.get("overrides", "").strip()
    if overrides.startswith("[") and overrides.endswith("]"):
        items = [x.strip().strip('"') for x in overrides[1:-1].split('", ') if x.strip()]
        if items:
            name += " (--set " + " ".join(items) + ")"
    return name


def find_summary(trace):
    stem = os.path.splitext(trace)[0]
    for cand in (trace + ".meta.yaml", stem + ".yaml", stem + "_summary.yaml",
                 stem + ".summary.yaml"):
        if os.path.isfile(cand):
            return cand
    return None


def readable(path):
    """Legend label from a file name: sweep traces 'config__key-value' → 'config, key = value'."""
    stem = os.path.splitext(os.path.basename(path))[0]
    parts = stem.split("__")
    out = [parts[0]]
    for p in parts[1:]:
        k, sep, v = p.rpartition("-")
        out.append(f"{k} = {v}" if sep and k else p)
    return ", ".join(out)


def distance(cols):
    """Distance driven [m]: the track position unwrapped at each new lap."""
    s = cols["s_m"]
    lap = cols["lap"]
    length = np.nanmax(s)
    return s - s[0] + (lap - lap[0]) * length


def spans(x, active):
    """(start, end) of the intervals where `active` is set."""
    out, start = [], None
    for i, a in enumerate(active > 0.5):
        if a and start is None:
            start = x[i]
        if not a and start is not None:
            out.append((start, x[i]))
            start = None
    if start is not None:
        out.append((start, x[-1]))
    return out


def select_lap(cols, lap):
    if lap is None:
        return cols
    keep = cols["lap"] == lap
    if not keep.any():
        raise TraceError(f"the trace has no lap {lap} (laps {int(np.nanmin(cols['lap']))}-"
                         f"{int(np.nanmax(cols['lap']))}, 0-based)")
    return {k: v[keep] for k, v in cols.items()}


def wheel_cols(cols, pattern):
    names = [pattern.format(w) for w, _, _ in WHEELS]
    return [cols[n] for n in names] if all(n in cols for n in names) else None


def end_text(summary):
    """'completed' or 'abort: <reason> (status) at t = … s, lap …' from a run summary."""
    if summary is None:
        return None, "end of the run unknown (no --summary)"
    status = summary.get("status", "?")
    if status == "completed":
        laps = summary.get("lap_times_s", "").strip("[] ")
        times = ", ".join("%.2f s" % float(t) for t in laps.split(",") if t.strip())
        return False, "completed" + (f" (laps: {times})" if times else "")
    where = []
    if "time_s" in summary:
        where.append("t = %.2f s" % float(summary["time_s"]))
    if "end_lap" in summary:
        where.append("lap %d" % (int(float(summary["end_lap"])) + 1))
    reason = REASONS.get(status, status)
    return True, "abort: %s (%s)%s" % (reason, status, (" at " + ", ".join(where)) if where else "")


def _signals(ax, xs, cols, color, label, multi):
    """One trace's lines in the panels speed to brake pressure."""
    ax["speed"].plot(xs, cols["vx_mps"], color=color, lw=1.0,
                     label=label if multi else "actual")
    if "v_target_mps" in cols:
        ax["speed"].plot(xs, cols["v_target_mps"], color=color if multi else "tab:green",
                         lw=0.9, ls="--", label=None if multi else "target (reference)")
    ax["lateral"].plot(xs, cols["lateral_error_m"], color=color, lw=1.0)
    ax["heading"].plot(xs, cols["heading_error_deg"], color=color, lw=1.0)
    ax["beta"].plot(xs, cols["beta_deg"], color=color, lw=1.0)
    deg = 180.0 / math.pi
    if "yaw_rate_radps" in cols:
        ax["yaw"].plot(xs, cols["yaw_rate_radps"] * deg, color=color, lw=1.0,
                       label=None if multi else "actual")
    if "yaw_rate_ref_radps" in cols:
        ax["yaw"].plot(xs, cols["yaw_rate_ref_radps"] * deg,
                       color=color if multi else "tab:purple", lw=0.9, ls="--",
                       label=None if multi else "ESC reference")
    if "yaw_moment_Nm" in cols:
        ax["moment"].plot(xs, cols["yaw_moment_Nm"] / 1000.0,
                          color=color if multi else "tab:red", lw=1.0)
    # Requested dashed, the stability controller's output solid (one trace: the output in
    # the colour of the subsystem that changes it: countersteer, TC).
    for name, req, cmd, scale, c in (("steer", "steer_req_rad", "steer_out_rad", deg,
                                      "tab:blue"),
                                     ("throttle", "throttle_req", "throttle_out", 100.0,
                                      "tab:green")):
        if req in cols and cmd in cols:
            ax[name].plot(xs, cols[req] * scale, color=color if multi else "0.35", lw=0.9,
                          ls="--", label=None if multi else "requested")
            ax[name].plot(xs, cols[cmd] * scale, color=color if multi else c, lw=1.0,
                          label=None if multi else "output")

    slip = wheel_cols(cols, "slip_{}_pct")
    req, app = wheel_cols(cols, "p_req_{}_bar"), wheel_cols(cols, "p_out_{}_bar")
    if slip is not None:
        if multi:
            s = np.vstack(slip)
            idx = np.nanargmax(np.abs(np.nan_to_num(s)), axis=0)
            ax["slip"].plot(xs, s[idx, np.arange(s.shape[1])], color=color, lw=0.9)
        else:
            for (w, name, c), v in zip(WHEELS, slip):
                ax["slip"].plot(xs, v, color=c, lw=0.9, label=name)
    if req is not None and app is not None:
        if multi:
            ax["brake"].plot(xs, np.sum(req, axis=0), color=color, lw=0.9, ls="--")
            ax["brake"].plot(xs, np.sum(app, axis=0), color=color, lw=1.0)
        else:
            for (w, name, c), r, a in zip(WHEELS, req, app):
                ax["brake"].plot(xs, r, color=c, lw=0.8, ls="--")
                ax["brake"].plot(xs, a, color=c, lw=1.0, label=name)


def _interventions(ax, xs, cols, k, multi, n_traces):
    """One trace's intervention spans: a row per subsystem (one trace) or a row per trace
    with a lane per subsystem (several)."""
    n_rows = n_traces if multi else len(INTERVENTIONS)
    for j, (col, name, c) in enumerate(INTERVENTIONS):
        if col not in cols:
            continue
        if multi:
            row = n_rows - 1 - k
            lo = row + 0.1 + 0.2 * (len(INTERVENTIONS) - 1 - j)  # ESC on top
            ymin, ymax = lo / n_rows, (lo + 0.18) / n_rows
        else:
            row = n_rows - 1 - j
            ymin, ymax = (row + 0.15) / n_rows, (row + 0.85) / n_rows
        for a, b in spans(xs, cols[col]):
            ax["int"].axvspan(a, b, ymin=ymin, ymax=ymax, color=c, lw=0)


def _marks(ax, axes, xs, cols, k, color, multi, aborted, ended, summary):
    """Scenario events (first trace only), lap boundaries and the abort point with its reason
    (`ended`: the trace ends where the run ended, not at a selected lap's end)."""
    # Scenario events (faults, rear-grip loss, gusts: the trace's events bit mask) as grey bands
    # behind every panel, for the first trace of an overlay.
    if "events" in cols and k == 0:
        for a0, b0 in spans(xs, (cols["events"] != 0).astype(float)):
            for a in axes:
                a.axvspan(a0, b0, color="0.55", alpha=0.18, lw=0, zorder=0)
            ax["speed"].text(a0, 0.88, " event", fontsize=8, color="0.3", va="top",
                             transform=ax["speed"].get_xaxis_transform())

    # Lap boundaries.
    laps = cols["lap"]
    starts = [0] + [i + 1 for i in np.nonzero(np.diff(laps) > 0)[0]]
    for i in starts:
        if i > 0:
            for a in axes:
                a.axvline(xs[i], color="0.45", ls=":", lw=0.9)
        if k == 0:
            ax["speed"].text(xs[i], 0.97, f" lap {int(laps[i]) + 1}", fontsize=8,
                             color="0.3", va="top", transform=ax["speed"].get_xaxis_transform())
    # The abort point: where the trace ends, with the reason from the summary.
    if aborted and ended:
        for a in axes:
            a.axvline(xs[-1], color=color if multi else "darkred", lw=1.2)
        ax["beta"].plot([xs[-1]], [cols["beta_deg"][-1]], "x", color="darkred", ms=8,
                        mew=2)
        if not multi:
            short = "abort: " + (summary or {}).get("status", "?").replace("_", " ")
            ax["speed"].annotate(short, xy=(xs[-1], 1.0), xycoords=("data", "axes fraction"),
                                 xytext=(-4, -4), textcoords="offset points", ha="right",
                                 va="top", fontsize=8.5, color="darkred",
                                 bbox=dict(boxstyle="round,pad=0.25", fc="white",
                                           ec="darkred", lw=0.8))


def _axes(ax, multi, labels, n_traces):
    """Units, grids, the note on a panel the trace lacks, and the intervention rows."""
    units = [("speed", "speed [m/s]"), ("lateral", "lateral error [m]"),
             ("heading", "heading error [deg]"), ("beta", "sideslip β [deg]"),
             ("yaw", "yaw rate [deg/s]"), ("moment", "ESC yaw moment\n[kN·m]"),
             ("steer", "steering (tyre)\n[deg]"), ("throttle", "throttle [%]"),
             ("slip", "longitudinal slip [%]" + ("\n(largest |slip| of\nthe four wheels)"
                                                if multi else "")),
             ("brake", "brake pressure [bar]" + ("\n(sum of the four\nwheels)" if multi else ""))]
    for name, ylabel in units:
        ax[name].set_ylabel(ylabel, fontsize=9)
        ax[name].grid(True, alpha=0.3)
    for name in ("yaw", "moment", "steer", "throttle", "slip", "brake"):
        if not ax[name].lines:
            ax[name].text(0.5, 0.5, "not in this trace", ha="center", va="center",
                          transform=ax[name].transAxes, color="0.4")
    ax["int"].set_ylim(0, 1)
    if multi:
        n = n_traces
        ax["int"].set_yticks([(n - 1 - k + 0.5) / n for k in range(n)])
        ax["int"].set_yticklabels(labels, fontsize=8)
        ax["int"].set_ylabel("interventions\n(lanes: ESC, CS,\nABS, TC)", fontsize=9)
    else:
        n = len(INTERVENTIONS)
        ax["int"].set_yticks([(n - 1 - j + 0.5) / n for j in range(n)])
        ax["int"].set_yticklabels([name for _, name, _ in INTERVENTIONS], fontsize=8)
        ax["int"].set_ylabel("active", fontsize=9)
    ax["int"].grid(True, axis="x", alpha=0.3)


def _title(title, summaries, params, multi, ends, lap):
    """The figure's title: the given one (with the parameter set), else the scenario, the
    parameter set, how the run ended and the lap."""
    if title is None:
        scen = sorted({run_name(s) for s in summaries if s and "scenario" in s})
        what = ("scenario " + ", ".join(scen)) if scen else "scenario: not recorded (--summary)"
        if not params:
            recorded = sorted({parameter_set(s) for s in summaries if s and "stability" in s})
            params = ", ".join(recorded) if recorded else None
        title = f"{what} — parameters: {params or 'not recorded (--params)'}"
        if not multi:
            title += "\n" + ends[0][1]
        if lap is not None:
            title += f" — lap {lap + 1} only"
    elif params:
        title += f" — parameters: {params}"
    return title


def _legends(fig, ax, multi, labels, ends, colors, title):
    """Legends in words: the lines of each panel (one trace) or the traces once (several)."""
    style = [Line2D([], [], color="0.3", ls="--", lw=0.9, label="requested"),
             Line2D([], [], color="0.3", lw=1.0, label="applied")]
    if multi:
        handles = [Line2D([], [], color=colors[k % len(colors)], lw=1.2,
                          label=lab + ("" if ends[k][0] is None else f" — {ends[k][1]}"))
                   for k, lab in enumerate(labels)]
        handles.append(Line2D([], [], color="0.3", ls="--", lw=0.9, label="target speed"))
        handles += [Patch(color=c, label=nm + " active") for _, nm, c in INTERVENTIONS]
        below_title = 1.0 - (0.15 + 0.22 * (1 + title.count("\n"))) / FIG_H
        fig.legend(handles=handles[:len(labels) + 1], fontsize=8, loc="upper left",
                   frameon=False, bbox_to_anchor=(0.08, below_title))
        fig.legend(handles=handles[len(labels) + 1:], fontsize=8, loc="upper right",
                   frameon=False, ncol=2, bbox_to_anchor=(0.98, below_title))
        ax["brake"].legend(handles=style, fontsize=8, loc="upper right", ncol=2)
    else:
        ax["speed"].legend(fontsize=8, loc="lower left", ncol=2, framealpha=0.9)
        for name in ("yaw", "steer", "throttle"):
            if ax[name].lines:
                ax[name].legend(fontsize=8, loc="lower left", ncol=2, framealpha=0.9)
        ax["slip"].legend(fontsize=8, loc="lower left", ncol=4, framealpha=0.9)
        ax["brake"].legend(handles=[Line2D([], [], color=c, lw=1.0, label=nm)
                                    for _, nm, c in WHEELS] + style,
                           fontsize=8, loc="upper right", ncol=3, framealpha=0.9)


def plot(paths, out, labels=None, x="distance", lap=None, title=None, summaries=None,
         params=None):
    """Draws the figure into `out` (PNG). `summaries`: per trace a summary path, a dict (keys of
    scw simulate --summary: status, time_s, end_lap, scenario) or None; by default the summary
    found beside each trace. `params`: the parameter set's name for the title."""
    traces = [load(p) for p in paths]
    if summaries is None:
        summaries = [find_summary(p) for p in paths]
    summaries = [load_summary(s) if isinstance(s, str) else s for s in summaries]
    for cols in traces:  # the x axis of the whole run, before a lap is selected
        cols["_x"] = distance(cols) if x == "distance" else cols["t_s"]
    ends_at = [cols["t_s"][-1] for cols in traces]
    traces = [select_lap(c, lap) for c in traces]
    multi = len(traces) > 1
    if not labels:
        labels = [s["scenario"] if s and "scenario" in s and not multi else readable(p)
                  for p, s in zip(paths, summaries)]
    ends = [end_text(s) for s in summaries]

    panels = [("speed", 1.0), ("lateral", 0.7), ("heading", 0.7), ("beta", 1.0), ("yaw", 1.0),
              ("moment", 0.8), ("steer", 1.0), ("throttle", 0.8), ("slip", 1.0),
              ("brake", 1.0), ("int", 0.2 + (0.35 if multi else 0.16) * (len(traces) if multi else
                                                                          len(INTERVENTIONS)))]
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, FIG_H), sharex=True,
                             gridspec_kw={"height_ratios": [h for _, h in panels]})
    ax = {name: a for (name, _), a in zip(panels, axes)}
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    xlabel = "distance driven [m]" if x == "distance" else "time [s]"

    n_traces = len(traces)
    for k, (cols, label, (aborted, _)) in enumerate(zip(traces, labels, ends)):
        xs = cols["_x"]
        color = colors[k % len(colors)] if multi else "black"
        _signals(ax, xs, cols, color, label, multi)
        _interventions(ax, xs, cols, k, multi, n_traces)
        _marks(ax, axes, xs, cols, k, color, multi, aborted,
               cols["t_s"][-1] == ends_at[k], summaries[k])

    _axes(ax, multi, labels, n_traces)
    title = _title(title, summaries, params, multi, ends, lap)
    _legends(fig, ax, multi, labels, ends, colors, title)
    axes[-1].set_xlabel(xlabel)

    fig.suptitle(title, fontsize=11, y=1.0 - 0.1 / FIG_H, va="top")
    # Room at the top for the title (and the legends of several traces), in inches.
    header = 0.1 + 0.18 * (1 + title.count("\n")) + (0.16 * (len(labels) + 1) if multi else 0)
    fig.tight_layout(rect=(0, 0, 1, 1.0 - header / FIG_H))
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=110, metadata={"Software": None})
    plt.close(fig)
    drawn = [name for name, _ in panels if name == "int" or ax[name].lines]
    return out, title, drawn
