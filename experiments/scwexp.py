"""Shared helpers of the experiment scripts: find and run `scw`, read its CSV output, analyse
sweep series and keep the per-study summaries the report is built from.

Only the Python standard library, numpy and matplotlib (Debian's python3-numpy and
python3-matplotlib) are used; plots use the non-interactive Agg backend.
"""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
import matplotlib  # noqa: E402

matplotlib.use("Agg")

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")

# Where the scw binary is looked for when SCW_BIN is not set (first existing wins).
BINARY_CANDIDATES = [
    "build/release/tuning/scw",
    "build/ci/tuning/scw",
    "build/exp/tuning/scw",
    "build/dev/tuning/scw",
    "build/lead-full/tuning/scw",
]

# The paper's series stop at the first abort; these statuses mean "the car lost it".
SPIN_STATUSES = ("sideslip", "wheel_spin")


def find_scw():
    """The scw binary: $SCW_BIN, else the first of BINARY_CANDIDATES, else `scw` on PATH."""
    env = os.environ.get("SCW_BIN")
    if env:
        if not (os.path.isfile(env) and os.access(env, os.X_OK)):
            sys.exit(f"error: SCW_BIN={env} is not an executable file")
        return env
    for rel in BINARY_CANDIDATES:
        path = os.path.join(ROOT, rel)
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    path = shutil.which("scw")
    if path:
        return path
    sys.exit("error: scw not found; build it (cmake --build build/release --target scw) or set "
             "SCW_BIN=/path/to/scw")


def results_dir(study):
    path = os.path.join(RESULTS, study)
    os.makedirs(path, exist_ok=True)
    return path


def run(cmd, log=None, check=True):
    """Runs a command (list), echoing it; returns the CompletedProcess. stdout/stderr go to `log`
    (a path) when given, else through."""
    print("+ " + " ".join(cmd), flush=True)
    if log:
        with open(log, "w") as f:
            proc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=ROOT)
    else:
        proc = subprocess.run(cmd, cwd=ROOT)
    if check and proc.returncode != 0:
        extra = f" (log: {log})" if log else ""
        if log:
            with open(log) as f:
                sys.stderr.write(f.read()[-3000:])
        sys.exit(f"error: command failed with exit code {proc.returncode}{extra}")
    return proc


def list_controllers(scw):
    """Motion controllers the binary knows (scw sweep --list-controllers)."""
    out = subprocess.run([scw, "sweep", "--list-controllers"], capture_output=True, text=True,
                         cwd=ROOT)
    if out.returncode != 0:
        return ["pure_pursuit"]
    return [line.strip() for line in out.stdout.splitlines() if line.strip()]


def threads_arg(args):
    return ["--threads", str(args.threads)]


def to_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    """Rows as dicts; numeric-looking fields converted to float."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in list(r.items()):
            f = to_float(v)
            if not math.isnan(f) or v in ("nan", "NaN"):
                r[k] = f
    return rows


def series(rows, config, key="gg_scale"):
    """The rows of one configuration sorted by `key`."""
    out = [r for r in rows if r["config"] == config]
    return sorted(out, key=lambda r: r[key])


def analyse_series(rows, key="gg_scale"):
    """Key numbers of one series (one configuration over increasing `key`), as the paper reads
    its figures: the largest value completed before the first abort, the first abort (value and
    reason) and the value with the minimum mean lap time among the completed runs."""
    completed = [r for r in rows if r["status"] == "completed"]
    aborted = [r for r in rows if r["status"] != "completed"]
    res = {
        "values": [r[key] for r in rows],
        "max_stable": completed[-1][key] if completed else None,
        "first_abort": aborted[0][key] if aborted else None,
        "first_abort_status": aborted[0]["status"] if aborted else None,
        "min_lap_value": None,
        "min_lap_time_s": None,
    }
    if completed:
        best = min(completed, key=lambda r: r["mean_lap_time_s"])
        res["min_lap_value"] = best[key]
        res["min_lap_time_s"] = best["mean_lap_time_s"]
    return res


def row_at(rows, config, value, key="gg_scale"):
    for r in rows:
        if r["config"] == config and abs(r[key] - value) < 1e-9:
            return r
    return None


def write_summary(study, summary):
    path = os.path.join(results_dir(study), "summary.json")
    with open(path + ".tmp", "w") as f:
        json.dump(summary, f, indent=2)
    os.replace(path + ".tmp", path)
    return path


def read_summary(study):
    path = os.path.join(RESULTS, study, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def fmt(x, digits=2):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    return f"{x:.{digits}f}"


class Timer:
    def __init__(self):
        self.t0 = time.monotonic()

    def seconds(self):
        return time.monotonic() - self.t0


def sweep_cmd(scw, args, sets, vary, configs, out_csv, extra=()):
    """The scw sweep command line (stop at the first abort as the paper does)."""
    cmd = [scw, "sweep", "--stop-at-first-abort", "-o", out_csv] + threads_arg(args)
    if sets:
        cmd += ["--set"] + list(sets)
    for v in vary:
        cmd += ["--vary", v]
    for c in configs:
        cmd += ["--config", c]
    if getattr(args, "stability", None):
        cmd += ["--stability", args.stability]
    return cmd + list(extra)


def mpc_sweep_cmd(scw, args, sets, vary, configs, out_csv, processes=None, extra=()):
    """sweep_cmd for the Ipopt-based motion controllers (pmpc, nmpc): the runs go to worker
    processes (`scw sweep --processes N`), since their Ipopt calls are serialised within one
    process and threads do not help. The table is the same as with sweep_cmd. processes: the
    number of workers (default: --threads, 0 meaning all cores)."""
    if processes is None:
        processes = getattr(args, "threads", 0) or os.cpu_count() or 1
    cmd = sweep_cmd(scw, args, sets, vary, configs, out_csv, extra)
    i = cmd.index("--threads")
    cmd[i:i + 2] = ["--processes", str(max(1, int(processes)))]
    return cmd


def add_common_args(parser, gg="1.0:0.05:1.8", laps=3):
    parser.add_argument("--gg", default=gg,
                        help=f"GG values: start:step:stop or a comma list (default {gg})")
    parser.add_argument("--laps", type=int, default=laps, help=f"laps per run (default {laps})")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
    parser.add_argument("--stability", help="stability params file (default: the car's)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="extra scenario override for every run (repeatable)")
    parser.add_argument("--no-report", action="store_true",
                        help="do not regenerate experiments/results/report.md")


def mark_aborts(ax, rows, key, field, color, linestyle="-"):
    """An 'x' at the aborted run of a series (the last reported one)."""
    for r in rows:
        if r["status"] != "completed" and not math.isnan(r[field]):
            ax.plot([r[key]], [r[field]], marker="x", color=color, markersize=9, linestyle="none")


def update_report(args):
    if getattr(args, "no_report", False):
        return
    import report  # noqa: E402  (same folder)
    report.main([])
