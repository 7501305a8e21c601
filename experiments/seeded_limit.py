#!/usr/bin/env python3
"""Study 2 over sensor-noise seeds: P(loss | GG) per configuration with Wilson 95 % intervals, the
GG where it crosses 10 % and 50 % (with intervals) and claim (b) in the statistical form written
before the first seeded run (experiments/statistical_criteria.md). Same setup as study 2's main
perturbation (PMPC, 3 laps, rear μy 0.80 in the car only, wheel-lock abort off), plus
sensor_noise=true and seed=1..N; every run of the grid is kept (no stop at the first abort).

    python3 experiments/seeded_limit.py [--seeds 10] [--gg 1.0:0.05:1.6] [--set plant.actuators=paper_sim]
        [--stability FILE --label NAME] [--results DIR] [--processes 2] [--reuse]

Writes <results>/study2_seeded/ (run_all.sh: --results is the column's folder): sweep_seeded.csv.gz (every run),
summary.json (curves, crossings, claim (b), activations, wall and CPU time), seeded.md (the
table), seeded.png. Re-analyse without running: scwexp.results.load(folder).sweep_loss_curve("none").
Time: about 12 min per column on 2 idle cores (10 seeds, 13 GG values, 4 configurations).
"""

import argparse
import gzip
import json
import os
import shutil

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import seeded  # noqa: E402
from scwexp.studies import (STUDY2_BASE_SETS, STUDY2_CONFIGS, STUDY2_CONTROLLER,  # noqa: E402
                            STUDY2_MAIN_PERT, STUDY2_PERT, STUDY3_BASE_SETS, STUDY3_COLORS,
                            STUDY3_VARIANTS)

# What must act for P5, as in the deterministic criterion (scwexp.claims.claim_b).
SUBSYSTEM = {"esc": "esc_count", "cs": "cs_count", "esc+cs": ("esc_count", "cs_count")}


def study_setup(args):
    """(folder name, scenario overrides, configurations as (name, overrides, label, colour))."""
    common = [f"laps={args.laps}", f"{STUDY2_PERT[0]}={STUDY2_MAIN_PERT}", "sensor_noise=true"]
    if args.study == 2:
        return ("study2_seeded", common + [f"motion.controller={STUDY2_CONTROLLER}"]
                + STUDY2_BASE_SETS + args.set, STUDY2_CONFIGS)
    configs = []
    for ctrl in args.controllers.split(","):
        for v, ov, label, _ in STUDY3_VARIANTS:
            configs.append((f"{ctrl}_{v}", f"motion.controller={ctrl},{ov}", f"{ctrl} {label}",
                            STUDY3_COLORS.get(ctrl, "k")))
    return "study3_seeded", common + STUDY3_BASE_SETS + args.set, configs


def claims(args, rows, summary):
    """{claim key: verdicts} of the study (study 2: b; study 3: e per controller)."""
    if args.study == 2:
        return {"b": seeded.claim_b(rows, summary, SUBSYSTEM)}
    return {f"e:{c}": seeded.claim_e(rows, summary, c) for c in args.controllers.split(",")}


def table(summary, rows, configs):
    """The markdown: one row per configuration and GG (short cells), then the crossings."""
    out = ["| config | GG | lost / n | P(loss) [95 %] | ESC / CS acted (completed) |",
           "| --- | --- | --- | --- | --- |"]
    for c, _, label, _ in configs:
        for gg, n, k, p, lo, hi in summary[c]["curve"]:
            e, d = seeded.activations(rows, c, gg, "esc_count")
            s, _ = seeded.activations(rows, c, gg, "cs_count")
            out.append(f"| {label} | {gg:.2f} | {k} / {n} | {p:.2f} [{lo:.2f}, {hi:.2f}] | "
                       f"{e} / {s} ({d}) |")
    out += ["", "| config | GG_10 [95 %] | GG_50 [95 %] | abort statuses |",
            "| --- | --- | --- | --- |"]
    for c, _, label, _ in configs:
        s = summary[c]
        st = ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items())) or "-"
        lo = s.get("low_open", {})
        out.append(f"| {label} | {seeded.fmt_limit(s['limits']['0.1'], lo.get('0.1'))} | "
                   f"{seeded.fmt_limit(s['limits']['0.5'], lo.get('0.5'))} | {st} |")
    return out


def claim_lines(verdicts):
    """The claims' verdicts as a table: one row per configuration each claim judges."""
    out = ["| claim | config | GG_50 | base GG_50 | acted at base GG_50 | holds | with confidence |",
           "| --- | --- | --- | --- | --- | --- | --- |"]
    for key, v in verdicts.items():
        for c, r in v.items():
            if not isinstance(r, dict):
                continue
            out.append(f"| ({key}) | {c} | {seeded.fmt_limit(r['gg50'])} | "
                       f"{seeded.fmt_limit(r['base_gg50'])} | {r['acted']} of {r['completed']} "
                       f"at {r['p5_gg']} | {'yes' if r['holds'] else 'no'} | "
                       f"{'yes' if r['with_confidence'] else 'no'} |")
    notes = [f"({k}): evaluable (≥ {seeded.MIN_SEEDS} seeds) {v['evaluable']}"
             + (f", none's losses mostly sideslip {v['premise_sideslip']}"
                if "premise_sideslip" in v else "") for k, v in verdicts.items()]
    return out + ["", "; ".join(notes) + "."]


def figure(summary, configs, path, title):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for c, _, label, color in configs:
        cv = summary[c]["curve"]
        x = [p[0] for p in cv]
        style = "--o" if c.endswith("_sc") else "-o"
        ax.plot(x, [p[3] for p in cv], style, color=color, label=label, ms=3)
        ax.fill_between(x, [p[4] for p in cv], [p[5] for p in cv], color=color, alpha=0.12)
    for q in seeded.LEVELS:
        ax.axhline(q, color="k", lw=0.6, ls=":")
    ax.set_xlabel("GG scale")
    ax.set_ylabel("P(loss), Wilson 95 %")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_sweep(scw, args, out, sets, configs):
    """The seeded sweep (with --reuse, the table the same command made before); (rows, reused)."""
    csv_path = os.path.join(out, "sweep_seeded.csv")
    cmd = scwexp.mpc_sweep_cmd(scw, args, sets, [f"gg_scale={args.gg}", f"seed=1:1:{args.seeds}"],
                               [f"{n}:{ov}" for n, ov, _, _ in configs], csv_path,
                               processes=args.processes)
    cmd.remove("--stop-at-first-abort")
    if not os.path.exists(csv_path) and os.path.exists(csv_path + ".gz"):
        with gzip.open(csv_path + ".gz", "rb") as src, open(csv_path, "wb") as dst:
            shutil.copyfileobj(src, dst)  # a finished run's table: reused when the command is the same
    reused = scwexp.reuse_or_run(cmd, csv_path, os.path.join(out, "scw_seeded.log"),
                                 reuse=args.reuse)
    rows = scwexp.read_csv(csv_path)
    with open(csv_path, "rb") as src, gzip.GzipFile(csv_path + ".gz", "wb", mtime=0) as dst:
        shutil.copyfileobj(src, dst)
    os.remove(csv_path)
    return rows, reused


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    scwexp.add_common_args(ap, gg="1.0:0.05:1.6")
    ap.add_argument("--study", type=int, choices=(2, 3), default=2, help="study 2 or 3 (default 2)")
    ap.add_argument("--controllers", default="pure_pursuit,pmpc",
                    help="study 3's motion controllers (default pure_pursuit,pmpc)")
    ap.add_argument("--seeds", type=int, default=seeded.MIN_SEEDS,
                    help=f"sensor-noise seeds 1..N per configuration and GG (default {seeded.MIN_SEEDS})")
    ap.add_argument("--reuse", action="store_true",
                    help="re-analyse the table a run with the same command left, without scw")
    args = ap.parse_args()
    scwexp.apply_common_args(args)
    if args.seeds < 1:
        ap.error("--seeds must be at least 1")
    scw = scwexp.find_scw()
    info = scwexp.column_info(args)
    study, sets, configs = study_setup(args)
    out = scwexp.results_dir(study)
    timer = scwexp.Timer()
    rows, reused = run_sweep(scw, args, out, sets, configs)
    summary = seeded.summarise(rows, [n for n, _, _, _ in configs])
    verdicts = claims(args, rows, summary)
    title = (f"Study {args.study}, {args.seeds} sensor-noise seeds: {info['set_label']}, "
             f"{info['actuators']} actuators" + (f", {info['plant']}" if info["plant"] != "scw"
                                                 else "") + f", rear μy {STUDY2_MAIN_PERT}")
    figure(summary, configs, os.path.join(out, "seeded.png"), title)
    lines = [f"# {title}", ""] + table(summary, rows, configs) + [""] + claim_lines(verdicts)
    with open(os.path.join(out, "seeded.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    doc = {"study": study, "column": info, "seeds": args.seeds, "sets": sets,
           "configs": {n: label for n, _, label, _ in configs},
           "perturbation": {"key": "seed", "values": list(range(1, args.seeds + 1))},
           "summary": summary, "claims": verdicts,
           "wall_time_s": timer.seconds(), "cpu_time_s": timer.cpu_seconds()}
    old = os.path.join(out, "summary.json")
    if reused and os.path.exists(old):  # the time is that of the run that made the table
        with open(old, encoding="utf-8") as f:
            prev = json.load(f)
        doc.update({k: prev[k] for k in ("wall_time_s", "cpu_time_s") if k in prev})
    if "b" in verdicts:
        doc["claim_b"] = verdicts["b"]
    scwexp.write_json(os.path.join(out, "summary.json"), doc)
    print("\n".join(lines))
    print(f"{study}: {timer.seconds():.0f} s wall, {timer.cpu_seconds():.0f} s CPU; outputs in {out}")


if __name__ == "__main__":
    main()
