#!/usr/bin/env python3
"""Study 2 over sensor-noise seeds: P(loss | GG) per configuration with Wilson 95 % intervals, the
GG where it crosses 10 % and 50 % (with intervals) and claim (b) in the statistical form written
before the first seeded run (experiments/statistical_criteria.md). Same setup as study 2's main
perturbation (PMPC, 3 laps, rear μy 0.80 in the car only, wheel-lock abort off), plus
sensor_noise=true and seed=1..N; every run of the grid is kept (no stop at the first abort).

    python3 experiments/seeded_limit.py [--seeds 10] [--gg 1.0:0.05:1.6] [--set plant.actuators=paper_sim]
        [--stability FILE --label NAME] [--results DIR] [--processes 2]

Writes <results>/study2_seeded/ (run_all.sh: --results is the column's folder): sweep_seeded.csv.gz (every run),
summary.json (curves, crossings, claim (b), activations, wall and CPU time), seeded.md (the
table), seeded.png. Re-analyse without running: scwexp.results.load(folder).sweep_loss_curve("none").
Time: about 12 min per column on 2 idle cores (10 seeds, 13 GG values, 4 configurations).
"""

import argparse
import gzip
import os
import shutil

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402
from scwexp import seeded  # noqa: E402
from scwexp.studies import (STUDY2_BASE_SETS, STUDY2_CONFIGS, STUDY2_CONTROLLER,  # noqa: E402
                            STUDY2_MAIN_PERT, STUDY2_PERT)

STUDY = "study2_seeded"
SUBSYSTEM = {"esc": "esc_count", "cs": "cs_count", "esc+cs": "esc_count"}


def table(summary, rows):
    """The markdown: one row per configuration and GG (short cells), then the crossings and
    claim (b)."""
    out = ["| config | GG | lost / n | P(loss) [95 %] | ESC / CS acted (completed) |",
           "| --- | --- | --- | --- | --- |"]
    for c, _, label, _ in STUDY2_CONFIGS:
        for gg, n, k, p, lo, hi in summary[c]["curve"]:
            e, d = seeded.activations(rows, c, gg, "esc_count")
            s, _ = seeded.activations(rows, c, gg, "cs_count")
            out.append(f"| {label} | {gg:.2f} | {k} / {n} | {p:.2f} [{lo:.2f}, {hi:.2f}] | "
                       f"{e} / {s} ({d}) |")
    out += ["", "| config | GG_10 [95 %] | GG_50 [95 %] | abort statuses |", "| --- | --- | --- | --- |"]
    for c, _, label, _ in STUDY2_CONFIGS:
        s = summary[c]
        st = ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items())) or "-"
        out.append(f"| {label} | {seeded.fmt_limit(s['limits']['0.1'])} | "
                   f"{seeded.fmt_limit(s['limits']['0.5'])} | {st} |")
    return "\n".join(out)


def figure(summary, path, title):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for c, _, label, color in STUDY2_CONFIGS:
        cv = summary[c]["curve"]
        x = [p[0] for p in cv]
        ax.plot(x, [p[3] for p in cv], "-o", color=color, label=label, ms=3)
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    scwexp.add_common_args(ap, gg="1.0:0.05:1.6")
    ap.add_argument("--seeds", type=int, default=seeded.MIN_SEEDS,
                    help=f"sensor-noise seeds 1..N per configuration and GG (default {seeded.MIN_SEEDS})")
    args = ap.parse_args()
    scwexp.apply_common_args(args)
    if args.seeds < 1:
        ap.error("--seeds must be at least 1")
    scw = scwexp.find_scw()
    info = scwexp.column_info(args)
    out = scwexp.results_dir(STUDY)
    os.makedirs(out, exist_ok=True)
    timer = scwexp.Timer()
    sets = [f"laps={args.laps}", f"motion.controller={STUDY2_CONTROLLER}",
            f"{STUDY2_PERT[0]}={STUDY2_MAIN_PERT}", "sensor_noise=true"] + STUDY2_BASE_SETS + args.set
    configs = [f"{n}:{ov}" for n, ov, _, _ in STUDY2_CONFIGS]
    csv_path = os.path.join(out, "sweep_seeded.csv")
    cmd = scwexp.mpc_sweep_cmd(scw, args, sets, [f"gg_scale={args.gg}", f"seed=1:1:{args.seeds}"],
                               configs, csv_path, processes=args.processes)
    cmd.remove("--stop-at-first-abort")
    if not os.path.exists(csv_path) and os.path.exists(csv_path + ".gz"):
        with gzip.open(csv_path + ".gz", "rb") as src, open(csv_path, "wb") as dst:
            shutil.copyfileobj(src, dst)  # a finished run's table: reused when the command is the same
    scwexp.reuse_or_run(cmd, csv_path, os.path.join(out, "scw_seeded.log"))
    rows = scwexp.read_csv(csv_path)
    names = [n for n, _, _, _ in STUDY2_CONFIGS]
    summary = seeded.summarise(rows, names)
    verdict = seeded.claim_b(rows, summary, SUBSYSTEM)
    title = (f"Study 2, {args.seeds} sensor-noise seeds: {info['set_label']}, "
             f"{info['actuators']} actuators, rear μy {STUDY2_MAIN_PERT}")
    figure(summary, os.path.join(out, "seeded.png"), title)
    md = table(summary, rows)
    lines = [f"# {title}", "", md, "", "Claim (b), statistical form (GG_50(c) ≥ GG_50(none) + "
             f"0.05; none's losses mostly sideslip: {verdict['premise_sideslip']}; "
             f"evaluable (≥ {seeded.MIN_SEEDS} seeds): {verdict['evaluable']}):", "",
             "| config | GG_50 | acted at none's GG_50 | holds | with confidence |",
             "| --- | --- | --- | --- | --- |"]
    for c in SUBSYSTEM:
        v = verdict[c]
        lines.append(f"| {c} | {seeded.fmt_limit(v['gg50'])} | {v['acted']} of {v['completed']} "
                     f"at {v['p5_gg']} | {'yes' if v['holds'] else 'no'} | "
                     f"{'yes' if v['with_confidence'] else 'no'} |")
    with open(os.path.join(out, "seeded.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    with open(csv_path, "rb") as src, gzip.GzipFile(csv_path + ".gz", "wb", mtime=0) as dst:
        shutil.copyfileobj(src, dst)
    os.remove(csv_path)
    scwexp.write_json(os.path.join(out, "summary.json"), {
        "study": STUDY, "column": info, "seeds": args.seeds, "sets": sets,
        "perturbation": {"key": "seed", "values": list(range(1, args.seeds + 1))},
        "summary": summary, "claim_b": verdict,
        "wall_time_s": timer.seconds(), "cpu_time_s": timer.cpu_seconds()})
    print("\n".join(lines))
    print(f"{STUDY}: {timer.seconds():.0f} s wall, {timer.cpu_seconds():.0f} s CPU; outputs in {out}")


if __name__ == "__main__":
    main()
