#!/usr/bin/env python3
"""A map of what decides each claim (issue 25 part 2): the unknowns of the plant varied one at a
time and pairwise within stated, plausible ranges, each claim (a)-(d) evaluated on one
perturbation per study (study 1: sensor-noise seed 1; study 2: rear μy 0.80), the car's shipped
stability set (or --stability: a map per set, in claims_map_<set>/), 3 laps, the studies' GG axis
with the first abort bisected.

The unknowns and their ranges (docs/plant-calibration.md, docs/scenarios.md `plant:`):
- brake dead time at the vehicle's fixed 150 ms total response: 0, 40, 80, 116 (the vehicle
  file), 121 ms (the mechanism's limit: the rate limit alone needs 29 ms of the 150), and "no
  brake dynamics" (the vehicle file's brakes with no dead time, no lag and the largest rate);
- steering dead time 0 / 30 (the vehicle file) / 60 ms;
- the rear tyre's force beyond its peak: plant.rear_tire_falloff 0 (no loss) / 1 (the file) /
  1.5;
- yaw inertia × 0.8 / 1 / 1.2;
- the GG resolution: the axis without (0.05) and with the bisected first abort (0.025);
- pairwise: brake dead time {0, 40, 116 ms, no brake dynamics} × steering dead time {0, 30, 60
  ms} (the heat map);
- for reference, the paper's simulator's actuators (plant.actuators=paper_sim), also with its
  steering dead time at 0 and 30 ms instead of 60 (its PT1 and rate limit kept): which part of
  the steering actuator decides claim (b); and the same simulator as its IV-2024 code had it
  (plant.actuators=paper_sim_v1: brakes 10 ms + PT1 30 ms, steering 50 ms + PT1 50 ms at
  1.0 rad/s), the other published reading of the paper's simulator;
- how the study-2 grip reduction acts (plant.grip_scaling=curve: the rear's side force -20 % at
  every slip angle, its cornering stiffness too, as the paper's simulator's per-wheel friction
  scaling multiplies the tyre force; the vehicle file's reading scales only the friction
  coefficient, the peak). Without stability control that car is lost at GG 1.0 already, so this
  family's axis starts at 0.7 (same step, same for every configuration): the paper's axis starts
  at "conservative targets";
- the lateral-acceleration request the PMPC publishes as the ESC's yaw reference
  (motion.pmpc.esc_target=commanded: the one its steering follows, plan plus ancillary feedback;
  steering: none, so ESC takes its curvature from the steering request through its single-track
  model, the paper's other reference; the default is the plan's), which the paper does not
  state for studies 1-2 (it names a_y for study 3);
- claim (d)'s remaining candidates, on the axis GG 0.7:0.05:1.8 (a car more oversteering than
  the vehicle file is lost at 1.0): the rear axle's cornering stiffness (tires.rear.lky 0.8 /
  0.9 against the file's 1.0: the compliance the file assumes for the front axle, applied to the
  rear; ESC's sideslip reference assumes its own, tire_stiffness_rear); the load transfer as
  the body's roll and pitch modes, second order at 3 / 7 Hz with damping ratio 0.4 against the
  file's first-order lag of 0.04 s (chassis.load_transfer_frequency; the paper's simulator models
  them as body degrees of freedom; 7.4 / 6.5 Hz and 0.39 / 0.40 from the AV-21 suspension data,
  3 Hz a soft car; on the studies' axis); the front share of
  the lateral load transfer (chassis.roll_stiffness_share_front 0.4 / 0.6 against 0.5); the
  PMPC's lateral feedback (motion.pmpc.lookahead_time 0.3 / 1.0 s against 0.6), a motion
  controller choice, not the plant's; and a yaw-rate feedback in the PMPC's steering
  (motion.pmpc.yaw_rate_gain 0.1 / 0.15 / 0.3 s against none), also a controller
  choice, with the vehicle file's actuators and with the paper's simulator's (pairwise: one
  change from the scored column "paper's sim"); the steering loop limit-cycles at 3-5 Hz from
  k = 0.2 s (0.15 s with the simulator's 60 ms steering dead time), which the report reads from
  `none`'s steer_hf_rms_deg and sets aside; and the TUM tube MPC's lower-level lateral
  controller, a feedback of the lateral-acceleration error into the steering
  (motion.pmpc.lat_accel_gain 1.5 / 3 m against none; 3 m is the TUM stack's loop-analysis
  value), with both actuator models;
- all of the paper's setup that public sources give, at once (paper_setup: the simulator's
  actuators, the grip reduction on the whole tyre curve, roll/pitch modes at 7 Hz and the
  lateral-acceleration feedback at 1.5 m, as 3 m limit-cycles there; on the long axis):
  whether a claim, claim (d) above all, is a combination effect no single choice shows.

The PMPC's lookahead time (pmpc_lookahead) runs only when --families names it (ON_REQUEST), so
the shipped set's map stays within 30 min on 2 cores.

Every variant runs in a few `scw sweep` calls, the studies' configurations as named
configurations of one sweep (study-specific keys in each), the variant as a varied key, runs in
--processes workers, each series stopped at its first abort and then bisected once.

Writes experiments/results/claims_map/: sweep_*.csv, claims_map.png (pass/fail with the margin
per claim over brake × steering dead time), claims_map_one_at_a_time.png, summary.json (read by
report.py).

    python3 experiments/claims_map.py [--processes 2] [--laps 3] [--stability FILE] [--quick]
        [--families a,b] [--reuse]

A variant whose `none` steers with more than 0.35° RMS above 1.6 Hz in a completed run (sweep
column steer_hf_rms_deg) is marked limit-cycling and set aside when the report names what flips a
claim. The vehicle-file values are varied as edited copies of the built-in file (`vehicle`;
VEHICLE_EDITS). --quick: brake dead time 0 and 116 ms only; --reuse: a sweep whose table and
recorded command exist is read, not run (an interrupted map goes on where it stopped).

Time on 2 cores (idle 2-vCPU AMD EPYC, 2026-11-30, main ef88433): the shipped set's map from
scratch 28.0 min wall, 53.8 CPU-min (44 variants, 42 sweeps; every table identical to a run with
reuse); the tuned sets' maps (the families run_all.sh gives a given set) about 23 min
(tuned_paper_sim_seed1) and 20 min (tuned_seed1). Since 2026-12-05 pmpc_lookahead runs only on
request. Earlier measurements: the history of experiments/README.md.
"""

import argparse
import os
import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import claims, plots  # noqa: E402
from scwexp.claims_map import (  # noqa: E402
    COLUMNS, CONFIGS, DEFAULT_FAMILIES, FAMILIES, MARGIN_NAMES, NO_DYN, ON_REQUEST, QUICK, STEERS,
    THRESH, against_none, changes_of, evaluate, expand_vehicle_edits, label_of, map_study,
    nearest_column, no_brake_dynamics_vehicle, pack, split)


def run_family(scw, args, out, fam, base_sets, configs, names, variants, commands, axes):
    """One family of the map: its sweep (reused with --reuse), the first aborts bisected and
    probed, and a variant per value (appended to `variants`; the sweeps' commands to
    `commands`, a family's own GG axis to `axes`). Returns the vehicle file's own runs at the
    axis step and its variant, (coarse rows, variant), when this family has them, else None."""
    base = None
    tag, flabel, vary = fam[:3]
    axis = fam[3] if len(fam) > 3 else args.gg
    if axis != args.gg:
        axes[flabel] = axis
    sets = list(base_sets)
    if tag == "no_brake_dyn":
        veh = no_brake_dynamics_vehicle(scw, os.path.join(out, "vehicle_no_brake_dyn.yaml"))
        sets.append(f"vehicle={veh}")
    vary = expand_vehicle_edits(scw, out, vary)
    keys = [v.split("=", 1)[0] for v in vary]
    csv_path = os.path.join(out, f"sweep_{tag}.csv")
    cmd = scwexp.mpc_sweep_cmd(scw, args, sets, [f"gg_scale={axis}"] + vary, configs,
                               csv_path, processes=args.processes)
    scwexp.reuse_or_run(cmd, csv_path, os.path.join(out, f"scw_{tag}.log"), args.reuse)
    rows = scwexp.read_csv(csv_path)
    commands.append(" ".join(cmd))
    # bisect the first aborts: one series per (config, variant); the variant's keys are
    # folded into the configuration's overrides
    groups = list(split(rows, keys).items())
    cfgs, sub = [], []
    for i, (vals, by_cfg) in enumerate(groups):
        extra = ",".join(f"{k}={v}" for k, v in zip(keys, vals))
        cfgs += [f"{n}#{i}:{o},{extra}" for n, o in CONFIGS]
        sub += [dict(r, config=f"{c}#{i}") for c, rs in by_cfg.items() for r in rs]
    coarse = sub  # the axis' own runs: the GG-resolution variant reads them
    if scwexp.REFINE_LEVELS > 0:
        sub, rc = scwexp.refine_first_aborts(scw, args, sets, cfgs, sub, None, csv_path,
                                             os.path.join(out, f"scw_{tag}.log"),
                                             reuse=args.reuse, probe=against_none)
        commands += rc

    def unfold(rs):
        out_rows = []
        for r in rs:
            name, i = r["config"].split("#")
            vals = groups[int(i)][0]
            out_rows.append(dict(r, config=name, **dict(zip(keys, vals))))
        return split(out_rows, keys)
    coarse_by = unfold(coarse)
    for vals, by_cfg in unfold(sub).items():
        lab = label_of(keys, vals)
        if tag == "no_brake_dyn":
            lab = NO_DYN + ("" if float(vals[0]) == 0.03 else ", " + lab)
        s1 = pack(by_cfg, names[:2])
        s2 = pack(by_cfg, names[2:])
        v = {"family": flabel, "label": lab, "claims": evaluate(s1, s2),
             "series": {**s1, **s2}, "command": " ".join(cmd),
             "changes": changes_of(tag, keys, vals)}
        act, from_col = nearest_column(keys, vals)
        if from_col is not None:  # a variant of the paper's simulator's column
            v["column_actuators"], v["column_changes"] = act, from_col
        if tag == "brake_steer" and len(keys) == 2:
            v["grid"] = (float(vals[0]), float(vals[1]))
        elif tag == "no_brake_dyn":
            v["grid"] = ("nodyn", float(vals[0]))
        if tag == "brake_steer" and float(vals[0]) == 0.116 and \
                (len(keys) == 1 or float(vals[1]) == 0.03):
            base = (coarse_by[vals], v)
            v["label"] = "vehicle file (brake 116 ms, steering 30 ms)"
        variants.append(v)
    return base


def table_and_text(variants, set_label, args, axes):
    """The map's table (a row per variant: each claim's verdict, margin and activations, and
    `none`'s steering above 1.6 Hz) and its paragraph (what was run, where each claim holds)."""
    table = ["| variant | (a) | (b) | (c) | (d) | `none`'s steering above 1.6 Hz |",
             "|---|---|---|---|---|---|"]
    for v in variants:
        cells = []
        for k in ("a", "b", "c", "d"):
            c = v["claims"][k]
            unit = " s" if k == "d" else ""
            cells.append(f"{'**holds**' if c['ok'] else 'fails'} {c['margin']:+.3f}{unit} "
                         f"({c['acts']})" + ("" if c["ok"] else
                                            f"; fails on: {', '.join(c['failed'])[:100]}"))
        hf = claims.steer_hf(v)
        cells.append("–" if hf is None else f"{hf:.2f}° RMS" + claims.cycling_mark(v))
        table.append(f"| {v['label']} | " + " | ".join(cells) + " |")
    holds = {k: [claims.cycling_label(v) for v in variants if v["claims"][k]["ok"]]
             for k in "abcd"}
    text = ("One perturbation per study (study 1 sensor-noise seed 1, study 2 rear μy 0.80), "
            f"the {set_label} stability set, {args.laps} laps, GG "
            f"{args.gg} with the first abort bisected" + "".join(
                f" ({fl}: GG {ax})" for fl, ax in axes.items()) + "; every other plant value as "
            "the vehicle file. Margins: " + "; ".join(f"({k}) {MARGIN_NAMES[k]} (criterion ≥ {THRESH[k]})"
                                          for k in "abcd") + ". A claim holds only with its "
            "whole criterion (P5 included). Holds with: " +
            "; ".join(f"({k}) " + (", ".join(holds[k]) or "no variant") for k in "abcd") + ".")
    return table, text


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    scwexp.add_common_args(p, laps=3)
    p.add_argument("--quick", action="store_true",
                   help="only brake dead time 0 and 116 ms (a test of the script)")
    p.add_argument("--families", help="comma-separated families to run (default: "
                   + ",".join(f[0] for f in DEFAULT_FAMILIES) + "; on request only: "
                   + ",".join(ON_REQUEST) + ")")
    p.add_argument("--reuse", action="store_true",
                   help="read a sweep's table from a previous run instead of running it when "
                        "its recorded command is the same (an interrupted map goes on where it "
                        "stopped)")
    args = p.parse_args(argv)
    scwexp.apply_common_args(args)
    scw = scwexp.find_scw()
    set_label = scwexp.column_info(args)["set_label"]
    study = map_study(set_label)
    out = scwexp.results_dir(study)
    timer = scwexp.Timer()
    names = [n for n, _ in CONFIGS]
    configs = [f"{n}:{o}" for n, o in CONFIGS]
    base_sets = [f"laps={args.laps}", "motion.controller=pmpc"] + args.set
    variants, commands = [], []
    base = None
    fams = QUICK if args.quick else DEFAULT_FAMILIES
    if args.families:
        want = args.families.split(",")
        bad = [w for w in want if w not in [f[0] for f in FAMILIES]]
        if bad:
            sys.exit(f"error: --families: unknown {', '.join(bad)}")
        fams = [f for f in FAMILIES if f[0] in want]
    axes = {}  # a family's own GG axis
    for fam in fams:
        found = run_family(scw, args, out, fam, base_sets, configs, names, variants,
                           commands, axes)
        base = found or base
    if base is not None:
        s1 = pack(base[0], names[:2], refined=False)
        s2 = pack(base[0], names[2:], refined=False)
        variants.append({"family": "GG resolution", "label": "vehicle file, GG step 0.05 "
                         "without the bisected first abort", "claims": evaluate(s1, s2),
                         "series": {**s1, **s2},
                         "changes": ["the first abort resolved only to the axis step 0.05 "
                                     "(no bisection)"]})
    figures = []
    if any("grid" in v for v in variants):
        heat = plots.claims_map_heat_map(variants, os.path.join(out, "claims_map.png"), set_label,
                                         COLUMNS, STEERS, MARGIN_NAMES)
        figures.append(os.path.relpath(heat, out))
    one = [v for v in variants if "grid" not in v or v["grid"][1] == 0.03]
    one_path = plots.claims_map_bars(one, os.path.join(out, "claims_map_one_at_a_time.png"),
                                     set_label, MARGIN_NAMES, THRESH)
    figures.append(os.path.relpath(one_path, out))
    table, text = table_and_text(variants, set_label, args, axes)
    summary = {"study": study, "set_label": set_label, "commands": commands, "variants": variants, "table": table,
               "text": text, "figures": figures, "wall_time_s": timer.seconds(),
               "reused": [os.path.basename(x) for x in scwexp.REUSED],
               "cpu_time_s": timer.cpu_seconds()}
    scwexp.write_summary(study, summary)
    print("\n".join(table))
    print(f"{study}: {timer.seconds():.0f} s wall, {timer.cpu_seconds():.0f} s CPU")
    scwexp.update_report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
