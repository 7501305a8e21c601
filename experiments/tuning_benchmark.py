#!/usr/bin/env python3
"""Which optimiser should `scw tune` use? Runs the real tuning problem with several NLopt methods
and seeds, and compares the training and held-out costs they reach against the evaluations spent.

Every run is a plain `scw tune` (so everything the default tune does — the screen that freezes
parameters, the search plant step — is part of what is measured) with `--no-sensitivity` (the
sensitivity runs after the search and does not change what the optimiser finds). Per method and
seed the script keeps the best training cost after every evaluation (evaluations.csv, at the
search step) and the comparison's training and held-out totals of the tuned set (comparison.csv,
at the vehicle's own step).

Outputs (in --out, default experiments/results/tuning_benchmark):
  runs/<method>/seed<k>/          the run folders
  summary.csv                     one row per method and seed
  convergence.png                 best training cost against evaluations: median and range over
                                  the seeds, one line per method
  tuning-benchmark.md             the table: per method the seeds' training costs, their spread
                                  (max/min - 1), the gap of their mean to the best cost any run
                                  found, held-out costs, wall time

Usage:
  experiments/tuning_benchmark.py                      # default set, 180 evaluations, 5 seeds
  experiments/tuning_benchmark.py --methods crs2+sbplx,mlsl --seeds 1,2
  experiments/tuning_benchmark.py --scenarios params/scenarios/robust_set.yaml --max-evals 60
  experiments/tuning_benchmark.py --reference-evals 900  # adds crs2+sbplx at 5x the budget
The runs are independent; --jobs N runs N tunes at once, each with --threads 1 (the results are
the same for any thread count). Besides the wall time the script records each tune's CPU time
(user + system, from wait4), which does not depend on what else the machine runs.

Deterministic methods (no random numbers: Subplex from the shipped set, DIRECT-L) give the same
run for every seed; they run on the first two seeds only, and the table says whether the two agree
bit for bit.

Defaults: Subplex alone; CRS2, ESCH, ISRES and DIRECT-L each followed by Subplex; MLSL-LDS;
`lhs+sbplx --batch 4`; a Subplex restart; seeds 1-5, 180 evaluations. Finished runs are reused.
experiments/robust_quarter.yaml is the robust scenario set at a quarter of its size, for
reduced-budget runs.

Time on 2 cores: the default set ~160 s CPU per tune, 34 tunes and two at 900 evaluations about
2 h; the robust quarter at 90 evaluations 320-360 s CPU per tune.
"""

import argparse
import concurrent.futures
import csv
import math
import os
import shlex
import statistics
import subprocess
import sys
import time

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
import scwexp  # noqa: E402

DEFAULT_METHODS = [
    "sbplx",  # Subplex alone, from the shipped set
    "crs2+sbplx",
    "esch+sbplx",
    "isres+sbplx",
    "direct_l+sbplx",
    "mlsl",
    "lhs+sbplx/4",  # LHS design, then 4 Subplex searches from the 4 best points (--batch 4)
    "sbplx+sbplx",  # Subplex from the shipped set, restarted from its best point at 60 %
]


# Methods that draw no random numbers: the seed cannot change their run.
# MLSL-LDS samples a Sobol sequence: its five seeds gave identical runs (docs/tuning-benchmark.md).
DETERMINISTIC = {"sbplx", "sbplx+sbplx", "neldermead", "bobyqa", "cobyla", "direct_l",
                 "direct_l+sbplx", "mlsl"}


def parse_method(spec):
    """'lhs+sbplx/4' -> ('lhs+sbplx', 4)."""
    if "/" in spec:
        alg, batch = spec.split("/", 1)
        return alg, int(batch)
    return spec, 1


def read_best_curve(path):
    """best_cost after every evaluation of an evaluations.csv."""
    with open(path, newline="") as f:
        return [float(row["best_cost"]) for row in csv.DictReader(f)]


def read_totals(path):
    """(training total, held-out total) of the tuned set from a comparison.csv (None if absent)."""
    totals = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row.get("set") == "tuned":
                totals.setdefault(row["group"], float(row["total_cost"]))
    return totals.get("training"), totals.get("held_out")


def run_one(scw, args, method, seed, max_evals, out_root):
    alg, batch = parse_method(method)
    folder = os.path.join(out_root, "runs", method.replace("/", "_b"), f"seed{seed}")
    if os.path.isfile(os.path.join(folder, "manifest.yaml")) and not args.rerun:
        wall, cpu = float("nan"), float("nan")
        if os.path.isfile(folder + ".time"):
            wall, cpu = (float(v) for v in open(folder + ".time").read().split())
    else:
        os.makedirs(os.path.dirname(folder), exist_ok=True)
        cmd = [scw, "tune", "--algorithm", alg, "--batch", str(batch), "--seed", str(seed),
               "--max-evals", str(max_evals), "--no-sensitivity", "--threads", str(args.threads),
               "--progress", "never", "--out-dir", folder, "--force"]
        if args.scenarios:
            cmd += ["--scenarios", args.scenarios]
        cmd += shlex.split(args.tune_args)
        t0 = time.monotonic()
        with open(folder + ".log", "w") as log:
            proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=scwexp.ROOT)
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = os.waitstatus_to_exitcode(status)
        # kept as written to the .time file, so that a later call reading the file back
        # reports the same figures (rounding the raw value once more could differ)
        wall = round(time.monotonic() - t0, 3)
        cpu = round(usage.ru_utime + usage.ru_stime, 3)
        with open(folder + ".time", "w") as f:
            f.write(f"{wall:.3f} {cpu:.3f}\n")
        if proc.returncode != 0:
            sys.exit(f"error: {' '.join(cmd)} failed (exit {proc.returncode}); see {folder}.log")
    curve = read_best_curve(os.path.join(folder, "evaluations.csv"))
    training, held_out = read_totals(os.path.join(folder, "comparison.csv"))
    manifest = open(os.path.join(folder, "manifest.yaml")).read()
    for line in manifest.splitlines():
        if line.startswith("wall_time_s:") and math.isnan(wall):
            wall = float(line.split(":", 1)[1])
    return {"method": method, "seed": seed, "max_evals": max_evals, "curve": curve,
            "search_best": curve[-1], "training": training, "held_out": held_out,
            "last_improvement": last_improvement(curve), "wall_s": wall, "cpu_s": cpu}


def last_improvement(curve, rel=0.005):
    """Index of the last evaluation that lowered the best cost by more than rel of it."""
    last, best = 0, curve[0]
    for i, c in enumerate(curve):
        if c < best - rel * abs(best):
            last = i
        best = min(best, c)
    return last


def spread(values):
    values = [v for v in values if v is not None]
    return max(values) / min(values) - 1.0 if values and min(values) > 0 else float("nan")


def plot(results, methods, path):
    from scwexp import plots  # noqa: F401  (the Agg backend, before pyplot)
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 5.5))
    for m in methods:
        curves = [r["curve"] for r in results if r["method"] == m]
        if not curves:
            continue
        n = min(len(c) for c in curves)
        med = [statistics.median(c[i] for c in curves) for i in range(n)]
        lo = [min(c[i] for c in curves) for i in range(n)]
        hi = [max(c[i] for c in curves) for i in range(n)]
        line, = ax.plot(range(n), med, label=f"{m} ({len(curves)} seeds)")
        ax.fill_between(range(n), lo, hi, color=line.get_color(), alpha=0.12)
    ax.set_yscale("log")
    ax.set_xlabel("evaluation")
    ax.set_ylabel("best training cost so far [s] (search step)")
    ax.set_title("scw tune: best cost against evaluations, median and range over seeds")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def table(results, methods, best_any):
    rows = ["| method | evaluations | seeds | training cost per seed (1 ms) | spread | mean vs best "
            "found | held-out mean | last improvement (median) | CPU per tune | wall per tune |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for m in methods:
        rs = [r for r in results if r["method"] == m]
        if not rs:
            continue
        tr = [r["training"] for r in rs]
        ho = [r["held_out"] for r in rs if r["held_out"] is not None]
        mean = statistics.mean(tr)
        seeds = f"{len(rs)}"
        if m.split("/")[0] in DETERMINISTIC and len(rs) > 1:
            same = all(r["curve"] == rs[0]["curve"] for r in rs)
            seeds += " (deterministic: " + ("identical" if same else "DIFFER") + ")"
        rows.append(
            f"| {m} | {rs[0]['max_evals']} | {seeds} | "
            + " / ".join(f"{t:.1f}" for t in tr)
            + f" | {100 * spread(tr):.1f} % | {100 * (mean / best_any - 1):+.1f} % | "
            + (f"{statistics.mean(ho):.1f}" if ho else "-")
            + f" | {statistics.median(r['last_improvement'] for r in rs):.0f} | "
            + f"{statistics.median(r['cpu_s'] for r in rs):.0f} s | "
            + f"{statistics.median(r['wall_s'] for r in rs):.0f} s |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--methods", default=",".join(DEFAULT_METHODS),
                    help="comma-separated algorithms (A+B; '/K' for --batch K)")
    ap.add_argument("--seeds", default="1,2,3,4,5")
    ap.add_argument("--max-evals", type=int, default=180)
    ap.add_argument("--reference-evals", type=int, default=0,
                    help="also run --reference-method with this budget (e.g. 5x) as the 'best found' "
                    "reference")
    ap.add_argument("--reference-method", default="crs2+sbplx",
                    help="the method(s) of the --reference-evals runs (comma-separated)")
    ap.add_argument("--scenarios", default="", help="scenario set file (default: built-in)")
    ap.add_argument("--tune-args", default="",
                    help="further arguments of every scw tune (e.g. \"--space S.yaml\")")
    ap.add_argument("--jobs", type=int, default=2, help="tunes at once")
    ap.add_argument("--threads", type=int, default=1, help="threads per tune")
    ap.add_argument("--out", default=os.path.join(scwexp.RESULTS, "tuning_benchmark"))
    ap.add_argument("--rerun", action="store_true", help="rerun runs whose folder is complete")
    args = ap.parse_args()
    scw = scwexp.find_scw()
    methods = [m for m in args.methods.split(",") if m]
    seeds = [int(s) for s in args.seeds.split(",") if s]
    jobs = [(m, s, args.max_evals) for m in methods
            for s in (seeds[:2] if m.split("/")[0] in DETERMINISTIC else seeds)]
    ref_names = []
    if args.reference_evals > 0:
        ref_names = [f"{m}@{args.reference_evals}" for m in args.reference_method.split(",") if m]
        jobs += [(r, s, args.reference_evals) for r in ref_names for s in seeds[:1]]
    os.makedirs(args.out, exist_ok=True)
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = []
        for m, s, n in jobs:
            spec = m.split("@", 1)[0]
            futures.append(pool.submit(run_one, scw, args, spec, s, n,
                                       os.path.join(args.out, m.replace("@", "_at")) if "@" in m
                                       else args.out))
        for (m, _, _), f in zip(jobs, futures):
            r = f.result()
            r["method"] = m
            results.append(r)
            print(f"{m} seed {r['seed']}: training {r['training']:.2f}, held-out "
                  f"{r['held_out']}, last improvement at {r['last_improvement']}", flush=True)
    with open(os.path.join(args.out, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["method", "seed", "max_evals", "search_best", "training", "held_out",
                    "last_improvement", "wall_s", "cpu_s"])
        for r in results:
            w.writerow([r["method"], r["seed"], r["max_evals"], r["search_best"], r["training"],
                        r["held_out"], r["last_improvement"], f"{r['wall_s']:.1f}",
                        f"{r['cpu_s']:.1f}"])
    shown = methods + ref_names
    plot(results, shown, os.path.join(args.out, "convergence.png"))
    best_any = min(r["training"] for r in results)
    md = ["# Tuning benchmark", "",
          f"scw: {scw}; scenarios: {args.scenarios or 'built-in default'}; "
          f"seeds {args.seeds}; `--no-sensitivity{(' ' + args.tune_args) if args.tune_args else ''}`; "
          "costs are the comparison's (vehicle step).",
          f"Best training cost any run found: {best_any:.2f}.", "",
          table(results, shown, best_any), "", "![convergence](convergence.png)", ""]
    with open(os.path.join(args.out, "tuning-benchmark.md"), "w") as f:
        f.write("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()
