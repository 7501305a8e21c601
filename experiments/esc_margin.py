#!/usr/bin/env python3
"""How close ESC comes to acting where claim (d) is judged (issue 25, claim (d)): for every
scored column (parameter set × actuator model) of study 2, at the main perturbation (rear μy
0.80), the car without lateral stability control (`none`) and with ESC alone are run at
- the GG where (d) is judged: 1.3, or the highest GG all four configurations complete, and
- `none`'s first abort,
and each run's `max_esc_margin` is read (scw sweep column: the closest approach to ESC's
activation condition, controller::EscActivationMargin; above 1 the condition held, computed with
ESC off too). Claim (d) needs ESC to act where `none` also completes: a margin below 1 in
`none`'s completed run says ESC's thresholds were never reached there, so ESC cannot cost lap
time at that GG whatever its gains; a margin above 1 only in the run `none` loses says that the
band between ESC's activation and the loss of the car is empty.

Reads results/columns/*/study2_lateral/summary.json (run experiments/run_all.sh first), one
`scw sweep` per column; writes results/esc_margin/summary.json (read by report.py).

    python3 experiments/esc_margin.py [--processes 2] [--reuse]
"""

import argparse
import os
import sys

import scwexp  # first: picks Debian's numpy/matplotlib, Agg backend
import report  # noqa: E402

STUDY = "esc_margin"
S2 = ["plan_with_nominal_grip=true", "abort.lock_slip_pct=100"]
CONFIGS = ("none", "esc", "cs", "esc+cs")


def judged_gg(series):
    """The GG claim (d) is judged at (report.claim_d_gg), None without all four configurations."""
    if any(k not in series for k in CONFIGS):
        return None
    return report.claim_d_gg(series)


def stability_path(column):
    """The stability file of a column (its `stability` text starts with the path)."""
    text = (column.get("stability") or "").split(" ")[0]
    return text if text and text != "params/stability/default.yaml" else None


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--reuse", action="store_true",
                   help="read a column's table from a previous run when its recorded command is "
                        "the same")
    args = p.parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    rows_out, commands = [], []
    cols = [(n, ss["study2_lateral"]) for n, _, ss in report.find_columns(scwexp.RESULTS)
            if ss.get("study2_lateral")]
    if not cols:
        sys.exit("error: no study-2 columns in results/columns (run experiments/run_all.sh)")
    for name, s2 in cols:
        col = s2["column"]
        main_pert = s2["perturbation"]["main"]
        series = s2["runs"][main_pert]
        gg_d = judged_gg(series)
        gg_a = series["none"].get("first_abort")
        configs = []
        for tag, gg in (("judged", gg_d), ("none_abort", gg_a)):
            if gg is None:
                continue
            configs += [f"none.{tag}:subsystems.esc=false,subsystems.cs=false,gg_scale={gg}",
                        f"esc.{tag}:subsystems.esc=true,subsystems.cs=false,gg_scale={gg}"]
        if not configs:
            continue
        sets = [f"laps={args.laps}", "motion.controller=pmpc"] + S2 + [
            f"plant.actuators={col['actuators']}",
            f"{s2['perturbation']['key']}={main_pert}"] + args.set
        csv_path = os.path.join(out, f"sweep_{name}.csv")
        stab = stability_path(col)
        # Ipopt serialises within a process: the runs go to worker processes
        cmd = [scw, "sweep", "-o", csv_path, "--processes", str(args.processes or 2), "--set"] \
            + sets
        for c in configs:
            cmd += ["--config", c]
        if stab:
            cmd += ["--stability", stab]
        scwexp.reuse_or_run(cmd, csv_path, os.path.join(out, f"scw_{name}.log"), args.reuse)
        commands.append(" ".join(cmd))
        for r in scwexp.read_csv(csv_path):
            cfg, tag = r["config"].split(".", 1)
            rows_out.append({"column": name, "set_label": col["set_label"],
                             "actuators": col["actuators"], "config": cfg, "at": tag,
                             "gg": gg_d if tag == "judged" else gg_a, "status": r["status"],
                             "max_esc_margin": r.get("max_esc_margin"),
                             "esc_count": r.get("esc_count"),
                             "max_abs_sideslip_deg": r.get("max_abs_sideslip_deg"),
                             "mean_lap_time_s": r.get("mean_lap_time_s")})
    summary = {"study": STUDY, "rows": rows_out, "commands": commands,
               "text": text_of(rows_out), "wall_time_s": timer.seconds(),
               "cpu_time_s": timer.cpu_seconds(),
               "reused": [os.path.basename(x) for x in scwexp.REUSED]}
    scwexp.write_summary(STUDY, summary)
    print("\n".join(summary["text"]))
    report.update(args)
    return 0


def text_of(rows):
    """The report's table: per column, `none` and ESC at the judged GG and at `none`'s abort."""
    def cell(r):
        if r is None:
            return "–"
        m = scwexp.to_float(r["max_esc_margin"])
        return (f"{r['status']} · margin {m:.2f} · ESC {int(scwexp.to_float(r['esc_count']))}×"
                if m == m else f"{r['status']}")
    cols = []
    for r in rows:
        if r["column"] not in cols:
            cols.append(r["column"])
    lines = ["| column | (d) judged at GG | `none` there | ESC only there | `none`'s first abort "
             "GG | `none` there | ESC only there |", "|---|---|---|---|---|---|---|"]
    for c in cols:
        rs = {(r["config"], r["at"]): r for r in rows if r["column"] == c}
        any_r = next(r for r in rows if r["column"] == c)
        gd = next((r["gg"] for r in rows if r["column"] == c and r["at"] == "judged"), None)
        ga = next((r["gg"] for r in rows if r["column"] == c and r["at"] == "none_abort"), None)
        lines.append(f"| {any_r['set_label']}, {any_r['actuators']} | {scwexp.fmt(gd, 3)} | "
                     f"{cell(rs.get(('none', 'judged')))} | {cell(rs.get(('esc', 'judged')))} | "
                     f"{scwexp.fmt(ga, 3)} | {cell(rs.get(('none', 'none_abort')))} | "
                     f"{cell(rs.get(('esc', 'none_abort')))} |")
    return lines


if __name__ == "__main__":
    sys.exit(main())
