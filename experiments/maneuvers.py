#!/usr/bin/env python3
"""The standard open-loop maneuvers (scw maneuver, docs/maneuvers.md) for stability control off and
on, for the car's shipped set and any given sets, under one or more plant models: a table per
maneuver and the sine-with-dwell figures (yaw rate against time per amplitude, the yaw-rate ratios
against amplitude).

    python3 experiments/maneuvers.py [PARAMS.yaml ...] [--labels A,B] [--model LABEL[:k=v,...]]
        [--set key=value ...] [--out DIR] [--publish DIR] [--no-report]

PARAMS: stability params files compared with the shipped set (label = file name, or --labels).
--model: a plant model, as scenario overrides applied to every run (repeatable; default: one model
`vehicle` = the vehicle file as it is). The actuator model of the fidelity work is meant as
`--model paper_sim:plant.actuators=paper_sim` once the scenario's `plant:` section exists.
--set: overrides for every run (e.g. --set vehicle=params/vehicles/av21.yaml).

Writes experiments/results/maneuvers/ (or --out): maneuvers.md, maneuvers.csv, the figures
swd_*.png, summary.json and every run's JSON (runs/); report.py links the figures. --publish DIR
writes DIR/maneuvers.md with its figures in DIR/maneuvers/ (the reference: --publish
experiments/reference-results).

The suite: every standard maneuver of `scw maneuver`, the sine with dwell at 80 km/h and at
40 m/s (RACE_SPEED), each with SC off (`--subsystems none`) and on. Time: ~20 s.
"""

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402

from scwexp import plots  # noqa: E402,F401  (the Agg backend, before pyplot)
import matplotlib.pyplot as plt  # noqa: E402

RACE_SPEED = 40.0  # [m/s] the second speed of the sine with dwell

# The suite: (label, maneuver, extra overrides).
SUITE = [
    ("sine_with_dwell_80kmh", "sine_with_dwell", []),
    ("sine_with_dwell_%gmps" % RACE_SPEED, "sine_with_dwell",
     ["maneuver.speed=%g" % RACE_SPEED]),
    ("step_steer", "step_steer", []),
    ("steady_state_circular", "steady_state_circular", []),
    ("braking_in_turn", "braking_in_turn", []),
    ("power_off_in_turn", "power_off_in_turn", []),
    ("power_on_in_turn", "power_on_in_turn", []),
    ("split_mu_braking", "split_mu_braking", []),
    ("split_mu_acceleration", "split_mu_acceleration", []),
    ("mu_jump_acceleration", "mu_jump_acceleration", []),
]

# The values shown per maneuver (keys of the runs' `values`; several runs: one per run, "/").
COLUMNS = {
    "step_steer": ["yaw_rate_response_time_s", "yaw_rate_peak_time_s", "yaw_rate_overshoot_pct",
                   "yaw_rate_gain_1ps", "lateral_acceleration_response_time_s"],
    "steady_state_circular": ["understeer_gradient_mrad_per_mps2",
                              "balance_gradient_mrad_per_mps2", "max_lateral_acceleration_mps2"],
    "braking_in_turn": ["mean_ax_1s_mps2", "yaw_rate_ratio_1s", "yaw_rate_vs_circle_1s",
                        "sideslip_change_1s_deg", "max_abs_sideslip_after_t0_deg"],
    "power_off_in_turn": ["yaw_rate_ratio_1s", "yaw_rate_vs_circle_1s", "sideslip_change_1s_deg",
                          "max_abs_sideslip_after_t0_deg"],
    "power_on_in_turn": ["yaw_rate_ratio_1s", "yaw_rate_vs_circle_1s", "sideslip_change_1s_deg",
                         "max_abs_sideslip_after_t0_deg", "max_slip_rear_after_t0_pct"],
    "split_mu_braking": ["stopping_distance_m", "mean_deceleration_mps2", "max_yaw_deviation_deg",
                         "max_steering_correction_handwheel_deg"],
    "split_mu_acceleration": ["mean_ax_mps2", "max_slip_rear_pct", "max_yaw_deviation_deg",
                              "max_steering_correction_handwheel_deg", "tc_time_s"],
    "mu_jump_acceleration": ["max_slip_rear_after_jump_pct", "mean_ax_after_jump_mps2",
                             "max_yaw_deviation_deg", "tc_time_s"],
}

SC = [("SC off", "none"), ("SC on", "all")]


def fmt(x, digits=2):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{digits}f}"


def parse_model(text):
    label, _, rest = text.partition(":")
    return label, [kv for kv in rest.split(",") if kv]


def swd_summary(res):
    """A, the largest ratios over the amplitudes, the smallest displacement from 5 A on."""
    runs = res["runs"]
    r1 = [r["values"].get("ratio_1_00_pct") for r in runs]
    r2 = [r["values"].get("ratio_1_75_pct") for r in runs]
    disp = [r["values"].get("lateral_displacement_m") for r in runs if r["level"] >= 5.0 - 1e-9]
    nums = lambda xs: [x for x in xs if x is not None]  # noqa: E731
    first_fail = next((r["label"] for r in runs if any(not c["passed"] for c in r["criteria"])),
                      "-")
    return {
        "A_deg": fmt(res["setup"].get("A_deg"), 3),
        "max ratio 1.00 s [%]": fmt(max(nums(r1), default=None), 1),
        "max ratio 1.75 s [%]": fmt(max(nums(r2), default=None), 1),
        "min displacement (>= 5 A) [m]": fmt(min(nums(disp), default=None)),
        "first failing amplitude": first_fail,
    }


def generic_summary(res, keys):
    out = {}
    for k in keys:
        vals = [r["values"].get(k) for r in res["runs"]]
        out[k] = " / ".join(fmt(v) for v in vals)
    return out


def interventions(res):
    s = [0, 0, 0, 0]
    for r in res["runs"]:
        m = r["metrics"]
        for i, k in enumerate(("esc_count", "cs_count", "abs_count", "tc_count")):
            s[i] += m.get(k, 0)
    return "/".join(str(x) for x in s)


def run_one(scw, out_dir, model, set_label, params, sc_switch, entry, extra_sets):
    label, name, overrides = entry
    stem = f"{model[0]}__{set_label}__{sc_switch}__{label}"
    path = os.path.join(out_dir, "runs", stem + ".json")
    cmd = [scw, "maneuver", name, "--subsystems", sc_switch, "--json", path]
    if params:
        cmd += ["--stability", params]
    sets = list(model[1]) + list(extra_sets) + list(overrides)
    if sets:
        cmd += ["--set"] + sets
    t0 = time.monotonic()
    proc = subprocess.run(cmd, cwd=scwexp.ROOT, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if proc.returncode not in (0, 1) or not os.path.exists(path):
        sys.stderr.write(proc.stdout[-2000:] + proc.stderr[-2000:])
        sys.exit(f"error: {' '.join(cmd)} failed with exit code {proc.returncode}")
    with open(path) as f:
        res = json.load(f)
    return res, wall, cmd


def swd_figures(results, out_dir, models, sets):
    """Per sine-with-dwell speed: yaw rate against time per amplitude (a panel per set and SC),
    and the two ratios against amplitude (all sets and SC in one panel)."""
    figs = []
    for label, name, _ in SUITE:
        if name != "sine_with_dwell":
            continue
        for model in models:
            keys = [(s, sc) for s in sets for sc, _ in SC]
            fig, axes = plt.subplots(1, len(keys), figsize=(3.3 * len(keys), 3.2), sharey=True,
                                     constrained_layout=True, squeeze=False)
            for ax, (s, sc) in zip(axes[0], keys):
                res = results[(model, s, sc, label)]
                runs = res["runs"]
                cmap = plt.get_cmap("viridis")
                for i, r in enumerate(runs):
                    t = r["signals"]["t_s"]
                    y = [math.nan if v is None else v for v in r["signals"]["yaw_rate_degps"]]
                    ax.plot(t, y, color=cmap(i / max(1, len(runs) - 1)), lw=0.8,
                            label=r["label"] if i in (0, len(runs) - 1) else None)
                ax.set_title(f"{s}, {sc}", fontsize=8)
                ax.set_xlabel("time since steer began [s]")
                ax.set_xlim(-0.2, 4.0)
                ax.grid(True, alpha=0.3)
            axes[0][0].set_ylabel("yaw rate [deg/s]")
            axes[0][0].legend(fontsize=6)
            fig.suptitle(f"sine with dwell at {res['setup'].get('speed_mps', 0):.1f} m/s "
                         f"({model}): yaw rate per amplitude (light = larger)", fontsize=9)
            f1 = f"swd_yaw_rate_{label}_{model}.png"
            fig.savefig(os.path.join(out_dir, f1), dpi=100, metadata={"Software": None})
            plt.close(fig)

            fig, axes = plt.subplots(1, 2, figsize=(9, 3.2), constrained_layout=True)
            for (s, sc) in keys:
                res = results[(model, s, sc, label)]
                lv = [r["level"] for r in res["runs"]]
                for ax, key in zip(axes, ("ratio_1_00_pct", "ratio_1_75_pct")):
                    vals = [r["values"].get(key) for r in res["runs"]]
                    vals = [math.nan if v is None else v for v in vals]
                    ax.plot(lv, vals, "o-" if sc == "SC on" else "s--", ms=3, label=f"{s}, {sc}")
            for ax, key, limit in zip(axes, ("1.00 s", "1.75 s"), (35.0, 20.0)):
                ax.axhline(limit, color="r", lw=0.8, ls=":")
                ax.set_xlabel("amplitude [A]")
                ax.set_ylabel(f"yaw-rate ratio at COS + {key} [%]")
                ax.grid(True, alpha=0.3)
            axes[0].legend(fontsize=7)
            fig.suptitle(f"sine with dwell at {res['setup'].get('speed_mps', 0):.1f} m/s "
                         f"({model}): ratios against amplitude (limits dotted)", fontsize=9)
            f2 = f"swd_ratios_{label}_{model}.png"
            fig.savefig(os.path.join(out_dir, f2), dpi=100, metadata={"Software": None})
            plt.close(fig)
            figs += [(label, model, f1), (label, model, f2)]
    return figs


def maneuver_tables(results, walls, models, sets):
    """The markdown table per maneuver (a row per plant model, set and SC off/on) and the same
    rows for maneuvers.csv."""
    md, csv_rows = [], []
    for label, name, overrides in SUITE:
        first = results[(models[0][0], sets[0][0], SC[0][0], label)]
        md += [f"## {label}", "", f"{first['standard']}" +
               (f" (`{' '.join(overrides)}`)" if overrides else "") + ". Setup: " +
               ", ".join(f"{k} {fmt(v, 3)}" for k, v in first["setup"].items()) + ".", ""]
        header = None
        for model in models:
            for set_label, _ in sets:
                for sc_label, _ in SC:
                    res = results[(model[0], set_label, sc_label, label)]
                    cols = (swd_summary(res) if name == "sine_with_dwell"
                            else generic_summary(res, COLUMNS[name]))
                    cols["criteria failed"] = f"{res['criteria_failed']} of {res['criteria_checked']}"
                    cols["ESC/CS/ABS/TC"] = interventions(res)
                    cols["wall [s]"] = fmt(walls[(model[0], set_label, sc_label, label)])
                    if header is None:
                        header = ["model", "set", "SC"] + list(cols)
                        md += ["| " + " | ".join(header) + " |",
                               "|" + "---|" * len(header)]
                    md.append("| " + " | ".join([model[0], set_label, sc_label] +
                                                [str(v) for v in cols.values()]) + " |")
                    csv_rows.append({"maneuver": label, "model": model[0], "set": set_label,
                                     "sc": sc_label, **cols})
        if len(results[(models[0][0], sets[0][0], SC[0][0], label)]["runs"]) > 1 and \
                name != "sine_with_dwell":
            levels = [r["label"] for r in first["runs"]]
            md += ["", f"Several runs: values per run in the order {', '.join(levels)}."]
        md.append("")
    return md, csv_rows


def write_csv(path, csv_rows):
    """maneuvers.csv: every row's fields, in the order they first appear."""
    fields = []
    for r in csv_rows:
        for k in r:
            if k not in fields:
                fields.append(k)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(csv_rows)


def parse_args(argv=None):
    """The command line (see the module's docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("params", nargs="*", help="stability params files to compare")
    ap.add_argument("--labels", help="comma-separated labels of the params files")
    ap.add_argument("--model", action="append", default=[],
                    help="LABEL[:key=value,...] plant model as scenario overrides (repeatable)")
    ap.add_argument("--set", dest="sets", nargs="+", action="extend", default=[],
                    help="scenario overrides for every run")
    ap.add_argument("--out", default=None, help="output folder")
    ap.add_argument("--publish", metavar="DIR", help="copy maneuvers.md and its figures to DIR")
    ap.add_argument("--no-report", action="store_true",
                    help="do not regenerate results/report.md afterwards")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)

    scw = scwexp.find_scw()
    out_dir = args.out or scwexp.results_dir("maneuvers")
    os.makedirs(os.path.join(out_dir, "runs"), exist_ok=True)
    labels = args.labels.split(",") if args.labels else [
        os.path.splitext(os.path.basename(p))[0] for p in args.params]
    if len(labels) != len(args.params):
        sys.exit("error: --labels needs one label per params file")
    sets = [("shipped", None)] + list(zip(labels, [os.path.abspath(p) for p in args.params]))
    models = [parse_model(m) for m in (args.model or ["vehicle"])]

    results, walls, rows = {}, {}, []
    t_all = time.monotonic()
    for model in models:
        for set_label, params in sets:
            for sc_label, sc_switch in SC:
                for entry in SUITE:
                    res, wall, cmd = run_one(scw, out_dir, model, set_label, params, sc_switch,
                                             entry, args.sets)
                    key = (model[0], set_label, sc_label, entry[0])
                    results[key] = res
                    walls[key] = wall
                    rows.append((key, res, wall, cmd))
    total_wall = time.monotonic() - t_all

    # The table per maneuver.
    md = ["# Standard maneuvers: stability control off and on", "",
          "Generated by `experiments/maneuvers.py` (`scw maneuver`, docs/maneuvers.md): each "
          "maneuver is an open-loop robot program on the plant with the stability controller in "
          "the loop and no motion controller. SC off = `--subsystems none` (ESC, CS, ABS and TC "
          "off), SC on = all four as the set enables them. Every outcome is reported as it came "
          "out; no outcome is asserted by a test.", "",
          f"Sets: {', '.join(s for s, _ in sets)}"
          + "".join(f" (`{os.path.relpath(p, scwexp.ROOT)}`)" for _, p in sets if p) + ". "
          f"Plant models: {', '.join(m[0] + (' (' + ', '.join(m[1]) + ')' if m[1] else ' (the vehicle file)') for m in models)}."
          + (f" Overrides for every run: `{' '.join(args.sets)}`." if args.sets else "")
          + " The SC-off rows drive the plant with no controller acting, so they are the same for "
          "every set. A params file's provenance (for a tuned set: the scw tune run) is in its "
          "header.", "",
          f"Wall time: {total_wall:.1f} s for {len(rows)} maneuver runs "
          f"(longest {max(walls.values()):.2f} s, including the start of `scw`).", ""]
    tables, csv_rows = maneuver_tables(results, walls, models, sets)
    md += tables

    figs = swd_figures(results, out_dir, [m[0] for m in models], [s for s, _ in sets])
    md += ["## Sine with dwell: figures", ""]
    for label, model, f in figs:
        md += [f"![{label} ({model})]({f})", ""]
    md += ["## Commands", "", "The suite: `python3 experiments/maneuvers.py " +
           " ".join(os.path.relpath(a, scwexp.ROOT) if os.path.exists(a) else a
                    for a in (argv if argv is not None else sys.argv[1:])) + "`; its first runs:",
           "", "```"]
    md += [" ".join(os.path.relpath(c, scwexp.ROOT) if os.path.isabs(c) else c for c in cmd)
           for _, _, _, cmd in rows[:len(SUITE) * 2]]
    md += ["...", "```", ""]
    with open(os.path.join(out_dir, "maneuvers.md"), "w") as f:
        f.write("\n".join(md))
    write_csv(os.path.join(out_dir, "maneuvers.csv"), csv_rows)
    summary = {"wall_s": total_wall, "runs": len(rows), "figures": [f for _, _, f in figs],
               "markdown": os.path.join(out_dir, "maneuvers.md"),
               "max_wall_s": max(walls.values()),
               "sets": [s for s, _ in sets], "models": [m[0] for m in models]}
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print(f"wrote {os.path.join(out_dir, 'maneuvers.md')} ({len(rows)} runs, {total_wall:.1f} s)")
    if args.publish:
        # DIR/maneuvers.md with its figures in DIR/maneuvers/ (the layout report.py publishes).
        os.makedirs(os.path.join(args.publish, "maneuvers"), exist_ok=True)
        text = "\n".join(md).replace("](swd_", "](maneuvers/swd_")
        with open(os.path.join(args.publish, "maneuvers.md"), "w") as f:
            f.write(text)
        for _, _, f in figs:
            shutil.copy(os.path.join(out_dir, f), os.path.join(args.publish, "maneuvers", f))
    if not args.out:
        scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
