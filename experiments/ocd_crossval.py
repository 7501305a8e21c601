#!/usr/bin/env python3
"""Cross-validation of scw's plant against Open-Car-Dynamics (issue 49 item 4, docs/ocd-plant.md):
the same inputs on both plants (plant.model=scw and plant.model=ocd, the same vehicle file mapped
onto OCD), the standard maneuvers with stability control off (the plants alone) and closed-loop
laps of Yas Marina North, side by side.

    python3 experiments/ocd_crossval.py [--out DIR] [--gg 1.0:0.05:1.8] [--no-laps]

Needs a build with Open-Car-Dynamics (SCW_WITH_OCD). Writes DIR (default
experiments/results/ocd_crossval/): crossval.md (the table, differences over 5 % marked),
crossval.csv, overlay figures (ocd_*.png, with matplotlib) and every run's JSON/summary (runs/).
About 2 minutes on a quiet 2-core machine.
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402

PLANTS = ("scw", "ocd")

# (row label, maneuver, extra overrides, value keys shown). Stability control off: the plants alone.
MANEUVERS = [
    ("step steer (ISO 7401), 80 km/h, 4 m/s^2", "step_steer", [],
     ["yaw_rate_gain_1ps", "yaw_rate_response_time_s", "yaw_rate_peak_time_s",
      "yaw_rate_overshoot_pct", "lateral_acceleration_response_time_s",
      "steady_lateral_acceleration_mps2"]),
    ("step steer (ISO 7401), 40 m/s, 4 m/s^2", "step_steer", ["maneuver.speed=40"],
     ["yaw_rate_gain_1ps", "yaw_rate_response_time_s", "yaw_rate_peak_time_s",
      "yaw_rate_overshoot_pct", "lateral_acceleration_response_time_s"]),
    ("steady-state circular (ISO 4138)", "steady_state_circular", [],
     ["understeer_gradient_mrad_per_mps2", "max_lateral_acceleration_mps2"]),
    ("sine with dwell (FMVSS 126), 80 km/h", "sine_with_dwell", [], "swd"),
    ("sine with dwell (FMVSS 126), 40 m/s", "sine_with_dwell", ["maneuver.speed=40"], "swd"),
    ("braking in a turn (ISO 7975)", "braking_in_turn", [],
     ["mean_ax_1s_mps2", "yaw_rate_ratio_1s", "sideslip_change_1s_deg"]),
]


def pct(a, b):
    """(b - a) / |a| in per cent; None where undefined or both are zero to rounding (the yaw-rate
    ratios of a car that stops yawing after the dwell: 1e-12 % against 1e-16 %)."""
    if a is None or b is None or not math.isfinite(a) or not math.isfinite(b):
        return None
    if max(abs(a), abs(b)) < 1e-3:
        return None
    return 100.0 * (b - a) / abs(a)


def run_maneuver(scw, out, plant, name, extra):
    tag = "_".join([name] + [e.replace("=", "") for e in extra])
    path = os.path.join(out, "runs", f"{tag}__{plant}.json")
    cmd = [scw, "maneuver", name, "--subsystems", "none", "--json", path, "--set",
           f"plant.model={plant}"] + [x for e in extra for x in ("--set", e)]
    proc = subprocess.run(cmd, cwd=scwexp.ROOT, capture_output=True, text=True)
    if proc.returncode not in (0, 1) or not os.path.exists(path):
        sys.stderr.write(proc.stdout[-2000:] + proc.stderr[-2000:])
        sys.exit(f"error: {' '.join(cmd)} failed with exit code {proc.returncode}")
    with open(path) as f:
        return json.load(f)


def swd_rows(res):
    """A, and at 5 A and 10 A the yaw-rate ratios, the first yaw-rate peak and the lateral
    displacement: the car's own response (no stability control)."""
    runs = res["runs"]
    by_level = {round(r["level"], 3): r for r in runs}
    rows = {"A_deg": res["setup"].get("A_deg")}
    for level in (5.0, 10.0):
        r = by_level.get(level)
        if r is None:
            continue
        v = r["values"]
        rows[f"ratio_1_00_pct at {level:g} A"] = v.get("ratio_1_00_pct")
        rows[f"ratio_1_75_pct at {level:g} A"] = v.get("ratio_1_75_pct")
        rows[f"first_peak_yaw_rate_degps at {level:g} A"] = v.get("peak_yaw_rate_degps")
        rows[f"lateral_displacement_m at {level:g} A"] = v.get("lateral_displacement_m")
    return rows


def values_of(res, keys):
    if keys == "swd":
        return swd_rows(res)
    out = {}
    runs = res["runs"]
    for k in keys:
        if len(runs) == 1:
            out[k] = runs[0]["values"].get(k)
        else:
            for r in runs:
                out[f"{k} ({r['label']})"] = r["values"].get(k)
    return out


def run_lap(scw, out, plant, gg):
    path = os.path.join(out, "runs", f"lap_gg{gg:g}__{plant}.yaml")
    cmd = [scw, "simulate", "--set", f"plant.model={plant}", "--set", "laps=1", "--set",
           f"gg_scale={gg:g}", "--summary", path]
    proc = subprocess.run(cmd, cwd=scwexp.ROOT, capture_output=True, text=True)
    if proc.returncode not in (0, 1) or not os.path.exists(path):
        sys.stderr.write(proc.stdout[-2000:] + proc.stderr[-2000:])
        sys.exit(f"error: {' '.join(cmd)} failed with exit code {proc.returncode}")
    summary = {}
    with open(path) as f:
        for line in f:
            key, _, val = line.partition(":")
            val = val.strip().strip('"')
            if val.startswith("[") and val.endswith("]"):
                summary[key] = [float(x) for x in val[1:-1].split(",") if x.strip()]
            else:
                try:
                    summary[key] = float(val)
                except ValueError:
                    summary[key] = val
    return summary


def gg_axis(text):
    a, s, b = (float(x) for x in text.split(":"))
    n = int(round((b - a) / s))
    return [round(a + i * s, 6) for i in range(n + 1)]


def overlay_figures(results, out):
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        print("note: no matplotlib, no figures")
        return []
    figs = []
    panels = [
        ("step steer (ISO 7401), 40 m/s, 4 m/s^2", 0, ["yaw_rate_degps", "ay_mps2"], (-0.2, 1.5)),
        ("sine with dwell (FMVSS 126), 40 m/s", 10.0, ["yaw_rate_degps", "beta_deg"], (-0.2, 3.0)),
        ("braking in a turn (ISO 7975)", 8.0, ["yaw_rate_degps", "beta_deg"], (-0.5, 2.5)),
    ]
    for label, level, sigs, xlim in panels:
        fig, axes = plt.subplots(1, len(sigs), figsize=(4.2 * len(sigs), 3.0),
                                 constrained_layout=True)
        for ax, sig in zip(axes, sigs):
            for plant, style in zip(PLANTS, ("-", "--")):
                res = results[(label, plant)]
                runs = res["runs"]
                run = runs[0] if len(runs) == 1 else min(
                    runs, key=lambda r: abs(r["level"] - level))
                t = run["signals"]["t_s"]
                y = [math.nan if v is None else v for v in run["signals"][sig]]
                ax.plot(t, y, style, lw=1.0, label=f"{plant} ({run['label']})")
            ax.set_xlim(*xlim)
            ax.set_xlabel("time since the program began [s]")
            ax.set_ylabel(sig)
            ax.grid(True, alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.suptitle(f"{label}, stability control off: scw's plant (solid) and "
                     "Open-Car-Dynamics (dashed), same inputs", fontsize=9)
        name = "ocd_" + label.split(" (")[0].replace(" ", "_") + ".png"
        name = name.replace("_a_turn", "_turn")
        fig.savefig(os.path.join(out, name), dpi=100, metadata={"Software": None})
        plt.close(fig)
        figs.append(name)
    return figs


LAP_KEYS = ("lap_time_s", "max_abs_sideslip_deg", "max_abs_lateral_error_m",
            "max_slip_rear_pct", "cs_count", "cs_time_s")


def maneuver_rows(scw, out, results):
    """Every maneuver on both plants: rows (test, metric, scw, ocd); results[(label, plant)]."""
    rows = []
    for label, name, extra, keys in MANEUVERS:
        vals = {}
        for plant in PLANTS:
            res = run_maneuver(scw, out, plant, name, extra)
            results[(label, plant)] = res
            vals[plant] = values_of(res, keys)
        for k in vals["scw"]:
            rows.append((label, k, vals["scw"].get(k), vals["ocd"].get(k)))
        print(f"{label}: done", flush=True)
    return rows


def lap_rows(scw, out, axis_text):
    """Laps up the GG axis on both plants, each to its first abort: rows for the first GG's lap,
    the first abort and the last completed lap, and a sentence on where each plant aborted."""
    axis = gg_axis(axis_text)
    first, aborted, last = {}, {}, {}
    for plant in PLANTS:
        for gg in axis:
            s = run_lap(scw, out, plant, gg)
            lap = (s.get("lap_times_s") or [math.nan])[0]
            if gg == axis[0]:
                first[plant] = dict(s, lap_time_s=lap)
            if s.get("status") != "completed":
                aborted[plant] = (gg, s.get("status"), s.get("end_s_m"))
                break
            last[plant] = (gg, lap)
        print(f"laps on {plant}: done", flush=True)
    label = f"Yas North lap, GG {axis[0]:g}, pure pursuit, SC on"
    rows = [(label, k, first["scw"].get(k), first["ocd"].get(k)) for k in LAP_KEYS]
    fa = {p: aborted.get(p, (None, "none", None)) for p in PLANTS}
    group = f"Yas North laps, GG {axis_text} (first abort)"
    rows.append((group, "first_abort_gg", fa["scw"][0], fa["ocd"][0]))
    rows.append((group, "lap_time_s at the last completed GG (scw/ocd: "
                 + "/".join(f"{last.get(p, (math.nan,))[0]:g}" for p in PLANTS) + ")",
                 last.get("scw", (None, None))[1], last.get("ocd", (None, None))[1]))
    note = "; ".join(f"{p}: {fa[p][1]} at s = {fa[p][2]}" for p in PLANTS)
    return rows, note


def write_tables(out, rows, abort_note, figs):
    with open(os.path.join(out, "crossval.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["test", "metric", "scw", "ocd", "diff_pct"])
        for g, k, a, b in rows:
            d = pct(a, b)
            w.writerow([g, k, "" if a is None else f"{a:.6g}", "" if b is None else f"{b:.6g}",
                        "" if d is None else f"{d:.2f}"])
    with open(os.path.join(out, "crossval.md"), "w") as f:
        f.write("| test | metric | scw | ocd | ocd - scw |\n| --- | --- | --- | --- | --- |\n")
        last = None
        for g, k, a, b in rows:
            d = pct(a, b)
            mark = " **>5 %**" if d is not None and abs(d) > 5.0 else ""
            f.write(f"| {g if g != last else ''} | `{k}` | {scwexp.fmt(a, 3)} | "
                    f"{scwexp.fmt(b, 3)} | {'-' if d is None else f'{d:+.1f} %'}{mark} |\n")
            last = g
        if abort_note:
            f.write(f"\nFirst aborts: {abort_note}.\n")
        for fig in figs:
            f.write(f"\n![{fig}]({fig})\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(scwexp.RESULTS, "ocd_crossval"))
    ap.add_argument("--gg", default="1.0:0.05:1.8",
                    help="GG axis of the laps (each plant stops at its first abort)")
    ap.add_argument("--no-laps", action="store_true")
    args = ap.parse_args(argv)
    scw = scwexp.find_scw()
    os.makedirs(os.path.join(args.out, "runs"), exist_ok=True)
    results = {}
    rows = maneuver_rows(scw, args.out, results)
    abort_note = ""
    if not args.no_laps:
        more, abort_note = lap_rows(scw, args.out, args.gg)
        rows += more
    figs = overlay_figures(results, args.out)
    write_tables(args.out, rows, abort_note, figs)
    with open(os.path.join(args.out, "crossval.md")) as f:
        print(f.read())


if __name__ == "__main__":
    main()
