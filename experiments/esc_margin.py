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
band between ESC's activation and the loss of the car is empty. Each run also gives the margin's
three terms (|β|/B_a, |e_β,f|/Eβ_a, |e_ψ,f|/Eψ_a at their largest while the oversteer signs
held): the one below 1 is the condition that kept ESC off. Then `none`'s first abort is
bisected further (--resolution, default 0.001 GG) and `none` and ESC are run at the last GG
`none` completes: whether a finer GG axis would find laps `none` completes with ESC acting.
Last, `none` and ESC are run on a grid (--scan-step, default 0.0025 GG) between `none`'s last
completed GG of the study and its first abort: the loss need not be monotone in GG at this
scale (a GG lost between two completed ones was seen at 0.001 apart), so a bisection finds one
edge, the scan shows the band. Finally a diagnostic (--threshold-probe, default x0.5 and x0.3):
all four configurations at the judged GG with ESC's sideslip-error thresholds scaled in the
column's own set: whether ESC, once it acts in a lap `none` completes, costs what (d) asks. The
scaled sets are written beside the results and never go to the car; no set is changed. And a
second diagnostic (--falloff-probe, default 0 and 1.5): `none` at its last completed GG and at
its first abort with the rear tyre's loss beyond its peak scaled (plant.rear_tire_falloff; the
curve up to the peak unchanged) beside the vehicle file's (1): if its completed lap stays the
same and it is lost at the abort whatever the loss, the rear never slid past its peak in a lap
`none` completes, and what makes the limit a cliff is the peak force itself.

Reads results/columns/*/study2_lateral/summary.json (run experiments/run_all.sh first), one
`scw sweep` per column; writes results/esc_margin/summary.json (read by report.py).

    python3 experiments/esc_margin.py [--processes 2] [--reuse] [--resolution 0.001]
                                      [--scan-step 0.0025] [--threshold-probe 0.5,0.3]
                                      [--falloff-probe 0,1.5]

Why the grid: `none` with tuned_paper_sim_seed1 on the real car was lost at GG 1.040625 and
completed at 1.0414 and 1.042187; a bisection finds an edge, the grid shows the band. Per column
where `none` completes the report says whether a GG is lost below a completed one, and Δ(ESC) in
every lap `none` completes while ESC acts. The threshold probe's sets are
results/esc_margin/stability_<column>_eb<factor>.yaml. One `scw sweep` per column, plus one per
bisection round and one per column and factor; run_all.sh runs it after the columns; its tables
and sentences are in the report's "Where each claim reproduces".

Time on 2 cores: 6 min for the six reference columns without the probes (2026-11-28), about
8 min with them (2026-11-29, beside a test run; 2-vCPU Intel Xeon @ 2.5 GHz).
"""

import argparse
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp.esc_margin import (  # noqa: E402
    CONFIG_OVERRIDES, DEFAULT_SET, FALLOFF_PROBE, PROBE, RESOLUTION, S2, SCAN_STEP,
    bisection_levels, factors, falloff_configs, falloffs, judged_gg, none_bounds, row_of,
    scaled_beta_error_set, scan_grid, stability_path, text_of)
from scwexp.results import find_columns  # noqa: E402

STUDY = "esc_margin"


def finest_band(scw, args, name, series, sets, stab, out):
    """`none`'s first abort bisected from the study's (last completed GG, first abort) down to
    args.resolution (scwexp.refine_first_aborts, one `scw sweep` per round): the last GG `none`
    completes and the first it loses, or None when the series has no such pair. Claim (d) needs
    ESC to act in a lap `none` completes; if even the last completed GG at this resolution keeps
    ESC's condition below 1, no finer GG axis makes the band between them non-empty."""
    # a summary's runs carry no configuration name; the bisection selects rows by it
    rows = [dict(r, config="none", gg_scale=float(r["gg_scale"]))
            for r in series["none"].get("runs") or []]
    bounds = scwexp.series_bounds(rows)
    if not bounds:
        return None
    levels = bisection_levels(bounds[0], bounds[1], args.resolution)
    sweep_args = argparse.Namespace(processes=args.processes or 2, stability=stab,
                                    threads=getattr(args, "threads", 0))
    rows, commands = scwexp.refine_first_aborts(
        scw, sweep_args, sets,
        ["none:subsystems.esc=false,subsystems.cs=false"], rows, None,
        os.path.join(out, f"fine_{name}.csv"), os.path.join(out, f"fine_{name}.log"),
        mpc=True, levels=levels, reuse=args.reuse)
    lo, hi = scwexp.series_bounds(rows) or bounds
    return {"last_completed": lo, "first_abort": hi, "levels": levels, "commands": commands}


def threshold_probe(scw, args, out, name, col, sets, stab, gg_d, fa, factor, rows_out,
                    commands):
    """All four configurations at the judged GG with ESC's sideslip-error thresholds scaled by
    `factor` in a copy of the column's set (a diagnostic): rows into rows_out."""
    tag = f"eb{round(factor * 100)}"
    probe_set = os.path.join(out, f"stability_{name}_{tag}.yaml")
    scaled_beta_error_set(stab or DEFAULT_SET, factor, probe_set)
    probe_csv = os.path.join(out, f"probe_{name}_{tag}.csv")
    cmd = [scw, "sweep", "-o", probe_csv, "--processes", str(args.processes or 2),
           "--set"] + sets + ["--stability", probe_set]
    for c, ov in CONFIG_OVERRIDES.items():
        cmd += ["--config", f"{c}.{tag}:{ov},gg_scale={gg_d}"]
    scwexp.reuse_or_run(cmd, probe_csv, os.path.join(out, f"scw_probe_{name}_{tag}.log"),
                        args.reuse)
    commands.append(" ".join(cmd))
    for r in scwexp.read_csv(probe_csv):
        cfg = r["config"].split(".", 1)[0]
        rows_out.append(dict(row_of(name, col, cfg, tag, gg_d, fa, r), factor=factor))


def falloff_probe(scw, args, out, name, col, sets, stab, series, fa, rows_out, commands):
    """`none` at its last completed GG and its first abort with the rear tyre's loss beyond its
    peak scaled (--falloff-probe): rows into rows_out."""
    bounds = none_bounds(series)
    if not (args.falloff_probe and bounds):
        return
    fo_csv = os.path.join(out, f"falloff_{name}.csv")
    cmd = [scw, "sweep", "-o", fo_csv, "--processes", str(args.processes or 2),
           "--set"] + sets
    for c in falloff_configs(bounds[0], bounds[1], args.falloff_probe):
        cmd += ["--config", c]
    if stab:
        cmd += ["--stability", stab]
    scwexp.reuse_or_run(cmd, fo_csv, os.path.join(out, f"scw_falloff_{name}.log"),
                        args.reuse)
    commands.append(" ".join(cmd))
    for r in scwexp.read_csv(fo_csv):
        cfg, tag = r["config"].split(".", 1)
        scale, at = tag.split("_", 1)
        rows_out.append(dict(row_of(name, col, cfg, f"falloff_{at}",
                                    bounds[0] if at == "last" else bounds[1], fa, r),
                             falloff=int(scale[2:]) / 100.0))


def parse_args(argv=None):
    """The command line (see the module's docstring)."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--reuse", action="store_true",
                   help="read a column's table from a previous run when its recorded command is "
                        "the same")
    p.add_argument("--resolution", type=float, default=RESOLUTION,
                   help=f"bisect `none`'s first abort down to this GG step and run `none` and ESC "
                        f"at the last GG `none` completes (default {RESOLUTION}; 0: off)")
    p.add_argument("--threshold-probe", type=factors, default=factors(PROBE),
                   help=f"run all four configurations at the judged GG with ESC's sideslip-error "
                        f"thresholds times each factor (default {PROBE}; '': off): whether ESC, "
                        "once it acts where `none` completes, costs what (d) asks; a diagnostic")
    p.add_argument("--falloff-probe", type=falloffs, default=falloffs(FALLOFF_PROBE),
                   help=f"run `none` at its last completed GG and its first abort with the rear "
                        f"tyre's loss beyond its peak scaled by each value, beside 1 (default "
                        f"{FALLOFF_PROBE}; '': off): whether that force decides the cliff")
    p.add_argument("--scan-step", type=float, default=SCAN_STEP,
                   help=f"run `none` and ESC on a grid of this GG step between `none`'s last "
                        f"completed GG and its first abort (default {SCAN_STEP}; 0: off)")
    return p.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    out = scwexp.results_dir(STUDY)
    timer = scwexp.Timer()
    rows_out, commands = [], []
    cols = [(n, ss["study2_lateral"]) for n, _, ss in find_columns(scwexp.RESULTS)
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
            configs += [f"{c}.{tag}:{CONFIG_OVERRIDES[c]},gg_scale={gg}" for c in ("none", "esc")]
        if not configs:
            continue
        sets = [f"laps={args.laps}", "motion.controller=pmpc"] + S2 + [
            f"plant.actuators={col['actuators']}",
            f"{s2['perturbation']['key']}={main_pert}"] + args.set
        csv_path = os.path.join(out, f"sweep_{name}.csv")
        stab = stability_path(col)
        fine = finest_band(scw, args, name, series, sets, stab, out) if args.resolution else None
        if fine:
            commands += fine.pop("commands")
            gg_f = fine["last_completed"]
            configs += [f"none.finest:subsystems.esc=false,subsystems.cs=false,gg_scale={gg_f}",
                        f"esc.finest:subsystems.esc=true,subsystems.cs=false,gg_scale={gg_f}"]
        grid = scan_grid(series, args.scan_step)
        for k, g in enumerate(grid):
            configs += [f"none.scan{k}:subsystems.esc=false,subsystems.cs=false,gg_scale={g}",
                        f"esc.scan{k}:subsystems.esc=true,subsystems.cs=false,gg_scale={g}"]
        # Ipopt serialises within a process: the runs go to worker processes
        cmd = [scw, "sweep", "-o", csv_path, "--processes", str(args.processes or 2), "--set"] \
            + sets
        for c in configs:
            cmd += ["--config", c]
        if stab:
            cmd += ["--stability", stab]
        scwexp.reuse_or_run(cmd, csv_path, os.path.join(out, f"scw_{name}.log"), args.reuse)
        commands.append(" ".join(cmd))
        gg_of = {"judged": gg_d, "none_abort": gg_a,
                 "finest": fine["last_completed"] if fine else None,
                 **{f"scan{k}": g for k, g in enumerate(grid)}}
        fa = fine["first_abort"] if fine else None
        for r in scwexp.read_csv(csv_path):
            cfg, tag = r["config"].split(".", 1)
            rows_out.append(row_of(name, col, cfg, tag, gg_of[tag], fa, r))
        for factor in (args.threshold_probe if gg_d is not None else []):
            threshold_probe(scw, args, out, name, col, sets, stab, gg_d, fa, factor,
                            rows_out, commands)
        falloff_probe(scw, args, out, name, col, sets, stab, series, fa, rows_out,
                      commands)
    summary = {"study": STUDY, "rows": rows_out, "commands": commands,
               "text": text_of(rows_out), "wall_time_s": timer.seconds(),
               "cpu_time_s": timer.cpu_seconds(),
               "reused": [os.path.basename(x) for x in scwexp.REUSED]}
    scwexp.write_summary(STUDY, summary)
    print("\n".join(summary["text"]))
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
