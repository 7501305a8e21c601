#!/usr/bin/env python3
"""Predicted speed-up of scw's dynamic job schedule on many workers (docs/scaling.md).

Input: per-job wall times measured on one core (`scw bench --evaluator --scenarios SET
--job-times jobs.csv`: one row per training scenario, column wall_s). Model: one evaluation of a
batch of B candidate sets is B x (number of scenarios) jobs; W workers take the next job of the
queue whenever they become free (the dynamic hand-out of the MPI backend and of the thread
pool), each hand-out costs `latency` seconds of the worker's time; the batch ends when its last
job ends (the optimiser waits for the whole batch). Speed-up = (sum of job times) / makespan,
efficiency = speed-up / W. Orders: the file's order (what scw did before) and longest first
(LPT: what the evaluator does, with each scenario's wall time of the previous batch).

Usage: scaling_model.py jobs.csv [--workers 1,2,16,64,256] [--batch 1,2,4] [--latency 2e-4]
                                  [--markdown]
"""
import argparse
import csv
import heapq
import sys


def makespan(jobs, workers, latency):
    """List scheduling: each job goes to the worker that becomes free first (ties: lowest id)."""
    free = [(0.0, w) for w in range(workers)]
    heapq.heapify(free)
    end = 0.0
    for t in jobs:
        start, w = heapq.heappop(free)
        finish = start + latency + t
        end = max(end, finish)
        heapq.heappush(free, (finish, w))
    return end


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "wall_s" not in rows[0]:
        sys.exit(f"{path}: expected a CSV with a wall_s column (scw bench --job-times)")
    times = []
    for i, r in enumerate(rows, start=2):
        try:
            t = float(r["wall_s"])
        except ValueError:
            sys.exit(f"{path}: line {i}: wall_s is not a number: {r['wall_s']!r}")
        if not (t >= 0.0 and t < float("inf")):
            sys.exit(f"{path}: line {i}: wall_s must be finite and >= 0, got {t}")
        times.append(t)
    return times


def table(times, workers, batches, latency):
    rows = []
    for b in batches:
        jobs = times * b
        serial = sum(jobs)
        for order in ("as listed", "longest first"):
            queue = jobs if order == "as listed" else sorted(jobs, reverse=True)
            for w in workers:
                span = makespan(queue, w, latency)
                rows.append((b, order, w, len(jobs), span, serial / span, serial / span / w))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("jobs_csv")
    ap.add_argument("--workers", default="1,2,16,64,256")
    ap.add_argument("--batch", default="1,2,4", help="candidate sets evaluated per batch")
    ap.add_argument("--latency", type=float, default=2e-4,
                    help="seconds per job hand-out (message round trip), default 0.2 ms")
    ap.add_argument("--markdown", action="store_true")
    a = ap.parse_args()
    times = load(a.jobs_csv)
    workers = [int(x) for x in a.workers.split(",")]
    batches = [int(x) for x in a.batch.split(",")]
    if any(w < 1 for w in workers) or any(b < 1 for b in batches):
        sys.exit("--workers and --batch take whole numbers >= 1")
    s = sorted(times)
    print(f"{len(times)} jobs: total {sum(times):.3f} s, mean {sum(times) / len(times):.4f} s, "
          f"min {s[0]:.4f}, median {s[len(s) // 2]:.4f}, max {s[-1]:.4f} s; "
          f"hand-out latency {a.latency * 1e3:.2f} ms")
    rows = table(times, workers, batches, a.latency)
    if a.markdown:
        print("\n| candidates per batch | order | workers | jobs | makespan [s] | speed-up | "
              "efficiency |")
        print("| ---: | --- | ---: | ---: | ---: | ---: | ---: |")
        for b, order, w, n, span, sp, eff in rows:
            print(f"| {b} | {order} | {w} | {n} | {span:.4f} | {sp:.1f} | {eff * 100:.0f} % |")
    else:
        for b, order, w, n, span, sp, eff in rows:
            print(f"batch {b:2d}  {order:13s}  W={w:4d}  jobs {n:5d}  makespan {span:8.4f} s  "
                  f"speed-up {sp:6.1f}  efficiency {eff * 100:5.1f} %")


if __name__ == "__main__":
    main()
