"""Shared helpers of the experiment scripts: find and run `scw`, read its CSV output, analyse
sweep series and keep the per-study summaries the report is built from.

Only the Python standard library, numpy and matplotlib (Debian's python3-numpy and
python3-matplotlib) are used; plots use the non-interactive Agg backend.
"""

import csv
import json
import math
import os
import resource
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
ROOT_RESULTS = RESULTS

# The GG axis of every study and of the claims map (issue 25 part 6), fixed before any run and
# the same for every configuration, parameter set and actuator model: start 1.0 (70 % of the
# combined limits), step 0.05, stop 1.8. Each series' first abort is then resolved finer by
# bisection between its last completed GG and its first abort (REFINE_LEVELS halvings:
# 0.025 with 1); the bisected runs are part of the series.
GG_AXIS = "1.0:0.05:1.8"
GG_STEP = 0.05
REFINE_LEVELS = 1

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


def set_results(path):
    """Writes the studies' outputs under `path` instead of experiments/results (run_all.sh
    gives every parameter set and actuator model a directory of its own)."""
    global RESULTS
    RESULTS = os.path.abspath(path)
    os.makedirs(RESULTS, exist_ok=True)
    return RESULTS


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


def write_json(path, obj):
    """Writes obj to path as JSON through a temporary file: a reader sees the old or the new
    file, never half of one."""
    with open(path + ".tmp", "w") as f:
        json.dump(obj, f, indent=2)
    os.replace(path + ".tmp", path)
    return path


def write_summary(study, summary):
    return write_json(os.path.join(results_dir(study), "summary.json"), summary)


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
    """Wall time, and the CPU time of the finished child processes (scw and its workers) since
    the start: the wall time depends on what else the machine runs, the CPU time much less."""

    def __init__(self):
        self.t0 = time.monotonic()
        self.c0 = self._children_cpu()

    @staticmethod
    def _children_cpu():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    def seconds(self):
        return time.monotonic() - self.t0

    def cpu_seconds(self):
        return self._children_cpu() - self.c0


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


# Columns of a sweep row kept per run in summary.json (the report is computed from these).
RUN_FIELDS = ("gg_scale", "refined", "status", "progress", "laps_completed", "mean_lap_time_s",
              "max_abs_sideslip_deg", "max_slip_front_pct", "max_slip_rear_pct",
              "max_abs_lateral_error_m", "max_speed_mps", "esc_count", "cs_count", "abs_count",
              "tc_count", "esc_time_s", "cs_time_s", "abs_time_s", "tc_time_s", "end_lap",
              "end_s_m", "max_esc_margin", "steer_hf_rms_deg")
ACTIVATION_KEYS = ("esc_count", "cs_count", "abs_count", "tc_count")
# The terms of ESC's activation condition (sweep columns): |β|/B_a, |e_β,f|/Eβ_a, |e_ψ,f|/Eψ_a,
# each at its largest while the oversteer signs held, and their short names.
ESC_TERMS = ("max_esc_beta_ratio", "max_esc_beta_error_ratio", "max_esc_yaw_rate_error_ratio")
ESC_TERM_NAMES = ("β", "e_β", "e_ψ")


def esc_terms_text(row):
    """The three terms of a run's ESC margin, e.g. "β 2.41 · e_β 0.37 · e_ψ 3.51" ("" if the
    table has none)."""
    vals = [to_float(row.get(k)) for k in ESC_TERMS]
    if any(v != v for v in vals):
        return ""
    return " · ".join(f"{n} {v:.2f}" for n, v in zip(ESC_TERM_NAMES, vals))


def esc_binding_terms(row):
    """The names of the terms that stayed below 1 in a run: each alone kept ESC off."""
    vals = [to_float(row.get(k)) for k in ESC_TERMS]
    return [n for n, v in zip(ESC_TERM_NAMES, vals) if v == v and v < 1.0]

# Abort statuses of study 1 that are the paper's test end (a tyre locks or spins); every other
# abort there is a safety stop (sideslip, lateral error, off track, timeout).
SLIP_STATUSES = ("wheel_lock", "wheel_spin")


def pack_series(rows, key="gg_scale"):
    """analyse_series of one series plus its runs (RUN_FIELDS of each row, in GG order)."""
    rows = sorted(rows, key=lambda r: r[key])
    a = analyse_series(rows, key)
    a["runs"] = [{k: r.get(k) for k in RUN_FIELDS} for r in rows]
    if a["first_abort"] is not None:
        ab = next(r for r in rows if r["status"] != "completed")
        a["first_abort_s_m"] = ab.get("end_s_m")
        a["first_abort_lap"] = ab.get("end_lap")
    return a


def perturbed_series(rows, configs, pert_key, pert_values):
    """{str(pert value): {config: pack_series}} of a sweep varied over gg_scale and pert_key."""
    out = {}
    for v in pert_values:
        sel = [r for r in rows if abs(float(r[pert_key]) - float(v)) < 1e-9]
        out[str(v)] = {c: pack_series([r for r in sel if r["config"] == c]) for c in configs}
    return out


def study_sweep(scw, args, sets, configs, out_csv, log, pert=None, mpc=True, gg=None,
                extra=(), refine=True, probe=None):
    """One scw sweep of a study: gg_scale (first, the series' key) and optionally a
    perturbation key (pert = (key, [values])); MPC sweeps go to --processes workers. Returns
    (command, rows). refine: bisect each series' first abort (refine_first_aborts, with its
    `probe`)."""
    vary = [f"gg_scale={gg or args.gg}"]
    if pert:
        vary.append(f"{pert[0]}=" + ",".join(str(v) for v in pert[1]))
    if os.path.exists(out_csv):
        os.remove(out_csv)  # never read a previous run's table
    if mpc:
        cmd = mpc_sweep_cmd(scw, args, sets, vary, configs, out_csv,
                            processes=getattr(args, "processes", None), extra=extra)
    else:
        cmd = sweep_cmd(scw, args, sets, vary, configs, out_csv, extra)
    run(cmd, log=log)
    rows = read_csv(out_csv)
    if refine and REFINE_LEVELS > 0:
        rows, rcmds = refine_first_aborts(scw, args, sets, configs, rows, pert, out_csv, log,
                                          mpc=mpc, probe=probe)
        cmd = cmd + [f"(+ {len(rcmds)} bisection and probe sweep(s) of the first aborts)"] \
            if rcmds else cmd
    return cmd, rows


def series_bounds(rows):
    """(last completed GG, first abort GG) of one series' rows (any order), or None when the
    series has no abort or no completed run below it."""
    rows = sorted(rows, key=lambda r: r["gg_scale"])
    ab = next((r for r in rows if r["status"] != "completed"), None)
    if ab is None:
        return None
    done = [r for r in rows if r["status"] == "completed" and r["gg_scale"] < ab["gg_scale"]]
    if not done:
        return None
    return done[-1]["gg_scale"], ab["gg_scale"]


def _first_abort_gg(rows):
    """The GG of a series' first abort, or None."""
    ab = [float(r["gg_scale"]) for r in rows if r["status"] != "completed"]
    return min(ab) if ab else None


def cut_at_first_abort(rows):
    """A series' rows in GG order up to and including its first abort."""
    out = []
    for r in sorted(rows, key=lambda r: r["gg_scale"]):
        out.append(r)
        if r["status"] != "completed":
            break
    return out


def refine_first_aborts(scw, args, sets, configs, rows, pert, out_csv, log, mpc=True,
                        levels=None, reuse=False, probe=None):
    """Resolves each series' first abort finer (issue 25 part 6): `levels` rounds of bisection
    between the last completed GG and the first abort, all series of a round in one `scw sweep`
    (one named configuration per bisected run: the series' overrides plus gg_scale and the
    perturbation). Returns the merged rows, each series cut at its (new) first abort; bisected
    rows carry refined=1 and the sweep's config name replaced by the series' own. reuse: read
    a bisection sweep's table from a previous run with the same command instead of running it
    (reuse_or_run). probe: a function from a configuration's name to the name of the series it
    is judged against (e.g. ESC against `none`), or None; after the bisection every such series
    that has no run at its reference's first-abort GG, and had not aborted below it, is run there
    (one more sweep, `_probe`), so that a criterion asking what a subsystem did at that GG (P5)
    is decided by a run, not by a missing one."""
    levels = REFINE_LEVELS if levels is None else levels
    pkey, pvals = pert if pert else (None, [None])
    overrides = dict(c.split(":", 1) if ":" in c else (c, "") for c in configs)
    laps = next((x.split("=", 1)[1] for x in sets if x.startswith("laps=")), "3")
    base = [x for x in sets if not x.startswith("laps=")]
    rows = [dict(r, refined=r.get("refined", 0)) for r in rows]
    commands = []

    def series(name, pv, rows_=None):
        return [r for r in (rows if rows_ is None else rows_) if r["config"] == name and
                (pkey is None or abs(float(r[pkey]) - float(pv)) < 1e-9)]

    def run_jobs(jobs, suffix):
        """Runs (series, perturbation, GG) jobs in one sweep; returns all rows with the new ones
        merged, every series cut again at its first abort."""
        cfgs = []
        for i, (name, pv, gg) in enumerate(jobs):
            # every digit of the bisected GG (round to 1e-6 above), not `:g`'s six significant
            # ones: the run must be at the GG its row is recorded with
            gg_text = f"{gg:.6f}".rstrip("0").rstrip(".")
            ov = [x for x in overrides[name].split(",") if x] + [f"gg_scale={gg_text}"]
            if pkey is not None:
                ov.append(f"{pkey}={pv}")
            cfgs.append(f"r{i}:" + ",".join(ov))
        csv_path = f"{out_csv[:-4]}{suffix}.csv"
        vary = [f"laps={laps}"]
        if mpc:
            cmd = mpc_sweep_cmd(scw, args, base, vary, cfgs, csv_path,
                                processes=getattr(args, "processes", None))
        else:
            cmd = sweep_cmd(scw, args, base, vary, cfgs, csv_path)
        reuse_or_run(cmd, csv_path, f"{log[:-4]}{suffix}.log", reuse)
        commands.append(" ".join(cmd))
        new = read_csv(csv_path)
        for r in new:
            name, pv, gg = jobs[int(r["config"][1:])]
            r["config"], r["gg_scale"], r["refined"] = name, gg, 1
            if pkey is not None:
                r[pkey] = float(pv)
        merged = rows + new
        return [r for name in overrides for pv in pvals
                for r in cut_at_first_abort(series(name, pv, merged))]

    for level in range(levels):
        jobs = []
        for name in overrides:
            for pv in pvals:
                b = series_bounds(series(name, pv))
                if b:
                    jobs.append((name, pv, round((b[0] + b[1]) / 2, 6)))
        if not jobs:
            break
        rows = run_jobs(jobs, f"_refine{level + 1}")
    if probe:
        jobs = []
        for name in overrides:
            ref = probe(name)
            if ref is None or ref not in overrides:
                continue
            for pv in pvals:
                ab = _first_abort_gg(series(ref, pv))
                own = series(name, pv)
                if ab is None or any(abs(float(r["gg_scale"]) - ab) < 1e-9 for r in own):
                    continue
                mine = _first_abort_gg(own)
                if mine is None or mine > ab:
                    jobs.append((name, pv, ab))
        if jobs:
            rows = run_jobs(jobs, "_probe")
    return rows, commands


REUSED = []  # tables reuse_or_run read from an earlier run instead of running


def reuse_or_run(cmd, csv_path, log, reuse=False):
    """Runs a sweep writing csv_path, and records its command beside the table
    (csv_path + ".cmd"). With reuse, a table whose recorded command equals this one (the binary
    path aside) is read as it is, without running: sweeps of an interrupted or earlier run with
    the same settings are not repeated."""
    key = "\n".join(cmd[1:])
    side = csv_path + ".cmd"
    if reuse and os.path.exists(csv_path) and os.path.exists(side):
        with open(side) as f:
            if f.read() == key:
                print(f"reusing {os.path.relpath(csv_path, ROOT)} (same command)", flush=True)
                REUSED.append(csv_path)
                return True
    for path in (csv_path, side):
        if os.path.exists(path):
            os.remove(path)
    run(cmd, log=log)
    with open(side, "w") as f:
        f.write(key)
    return False


def brake_40ms_vehicle(scw, path):
    """The built-in vehicle with a 40 ms brake response (brakes.delay 0.006 s: dead time 6 ms +
    the unchanged 32 ms lag and 1800 bar/s rate limit; docs/plant-calibration.md)."""
    run([scw, "vehicle", "init", "-o", path], log=path + ".log")
    with open(path) as f:
        text = f.read()
    lines, in_brakes, done = text.splitlines(), False, False
    for i, line in enumerate(lines):
        if not line.startswith(" "):
            in_brakes = line.startswith("brakes:")
        elif in_brakes and line.strip().startswith("delay:"):
            lines[i] = line[:len(line) - len(line.lstrip())] + "delay: 0.006"
            done = True
    if not done:
        sys.exit(f"error: no brakes.delay in {path}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


# Named places of Yas Marina North (the spec's names; corners from `scw track info`).
CORNER_NAMES = {1: "T1", 5: "hairpin", 7: "chicane", 8: "chicane"}


def track_corners(scw, sets=()):
    """Corners (number, from, to) of the scenario's track, parsed from `scw track info`."""
    track = next((s.split("=", 1)[1] for s in sets if s.startswith("track=")), None)
    cmd = [scw, "track", "info"] + (["--track", track] if track else [])
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT).stdout
    corners = []
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 6 and f[0].isdigit() and f[1] in ("left", "right"):
            corners.append({"n": int(f[0]), "dir": f[1], "from": float(f[2]),
                            "to": float(f[3]), "r_min": float(f[4])})
    return corners


def place(s, corners):
    """'braking into T1', 'corner 3', 'exit of corner 3', 'straight' for arc length s [m]."""
    if s is None or (isinstance(s, float) and math.isnan(s)) or not corners:
        return "–"
    best, dist = None, 1e9
    for c in corners:
        d = 0.0 if c["from"] <= s <= c["to"] else min(abs(s - c["from"]), abs(s - c["to"]))
        if d < dist:
            best, dist = c, d
    name = CORNER_NAMES.get(best["n"], f"corner {best['n']}")
    if dist == 0.0:
        return name
    if s < best["from"] and dist <= 150:
        return f"braking into {name}"
    if s > best["to"] and dist <= 120:
        return f"exit of {name}"
    return "straight"


def diagnose_abort(scw, args, sets, config_overrides, gg, path_stem, window=2.0):
    """Re-runs one aborted run with `scw simulate --trace` (the same scenario keys, so the same
    run) and describes the last `window` seconds before the abort: where, speed, peak |β| and
    lateral error, throttle, when each subsystem last became active, and the wheel whose slip
    ended the run (its commanded pressure and whether ESC was active at the pressure peak).
    Returns a dict (text + numbers), or None if the trace could not be made."""
    trace = path_stem + ".csv"
    cmd = [scw, "simulate", "--set"] + list(sets) + [f"gg_scale={gg}"] + \
        [x for x in config_overrides.split(",") if x] + ["--trace", trace]
    if getattr(args, "stability", None):
        cmd += ["--stability", args.stability]
    proc = run(cmd, log=path_stem + ".log", check=False)
    if proc.returncode not in (0, 1) or not os.path.exists(trace):
        return None
    rows = read_csv(trace)
    if not rows:
        return None
    t_end = rows[-1]["t_s"]
    win = [r for r in rows if r["t_s"] >= t_end - window]
    last = rows[-1]
    wheels = ("fl", "fr", "rl", "rr")
    w = max(wheels, key=lambda k: abs(last[f"slip_{k}_pct"]))
    peak = max(win, key=lambda r: r[f"p_out_{w}_bar"])
    since = {}
    for key in ("esc", "cs", "abs", "tc"):
        flag = f"{key}_active"
        if last[flag] > 0.5 or any(r[flag] > 0.5 for r in win):
            t0 = None
            for r in reversed(rows):
                if r[flag] > 0.5:
                    t0 = r["t_s"]
                elif t0 is not None:
                    break
            since[key] = t0
    bmax = max(win, key=lambda r: abs(r["beta_deg"]))
    emax = max(win, key=lambda r: abs(r["lateral_error_m"]))
    res = {
        "t_s": t_end, "s_m": last["s_m"], "lap": int(last["lap"]) + 1, "v_mps": last["vx_mps"],
        "max_beta_deg": abs(bmax["beta_deg"]), "max_beta_t": bmax["t_s"],
        "max_lat_err_m": abs(emax["lateral_error_m"]),
        "max_throttle": max(r["throttle_out"] for r in win),
        "wheel": w.upper(), "wheel_slip_pct": last[f"slip_{w}_pct"],
        "wheel_p_peak_bar": peak[f"p_out_{w}_bar"], "wheel_p_peak_t": peak["t_s"],
        "wheel_p_req_at_peak_bar": peak[f"p_req_{w}_bar"],
        "esc_at_peak": bool(peak["esc_active"] > 0.5), "active_since": since,
        "trace": os.path.relpath(trace, RESULTS),
    }
    act = ", ".join(f"{k.upper()} from t = {v:.2f} s" for k, v in since.items() if v is not None)
    res["text"] = (
        f"abort at t = {t_end:.2f} s, s = {last['s_m']:.0f} m, lap {int(last['lap']) + 1}, "
        f"{last['vx_mps']:.1f} m/s; last {window:g} s: max |β| {abs(bmax['beta_deg']):.1f}° "
        f"(t = {bmax['t_s']:.2f} s), max |lateral error| {abs(emax['lateral_error_m']):.1f} m, "
        f"throttle up to {res['max_throttle']:.2f}; active: {act or 'no subsystem'}; "
        f"{w.upper()} slip {last[f'slip_{w}_pct']:.0f} % at the end, its commanded pressure "
        f"peaked at {res['wheel_p_peak_bar']:.0f} bar (t = {peak['t_s']:.2f} s; motion "
        f"controller's request {res['wheel_p_req_at_peak_bar']:.0f} bar"
        f"{', ESC active' if res['esc_at_peak'] else ''})")
    return res


def diagnose_series(scw, args, sets, configs, per_pert_main, pert_key, pert_value, out):
    """diagnose_abort for the first abort of every configuration (name, overrides) of one
    perturbation; {config: dict}."""
    res = {}
    for name, overrides in configs:
        a = per_pert_main.get(name)
        if not a or a["first_abort"] is None:
            continue
        stem = os.path.join(out, "diagnosis", f"{name}_gg{a['first_abort']:g}")
        os.makedirs(os.path.dirname(stem), exist_ok=True)
        d = diagnose_abort(scw, args, list(sets) + [f"{pert_key}={pert_value}"], overrides,
                           a["first_abort"], stem)
        if d:
            d["gg"] = a["first_abort"]
            d["status"] = a["first_abort_status"]
            res[name] = d
    return res


def add_common_args(parser, gg=GG_AXIS, laps=3):
    parser.add_argument("--gg", default=gg,
                        help=f"GG values: start:step:stop or a comma list (default {gg})")
    parser.add_argument("--refine", type=int, default=REFINE_LEVELS,
                        help="bisection rounds of each series' first abort (default "
                             f"{REFINE_LEVELS}: half a step; 0: none)")
    parser.add_argument("--results", metavar="DIR",
                        help="write the outputs under DIR instead of experiments/results")
    parser.add_argument("--label", help="name of the parameter set in the report")
    parser.add_argument("--laps", type=int, default=laps, help=f"laps per run (default {laps})")
    parser.add_argument("--threads", type=int, default=0, help="worker threads (0: all cores)")
    parser.add_argument("--stability", help="stability params file (default: the car's)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="extra scenario override for every run (repeatable)")
    parser.add_argument("--processes", type=int, default=2,
                        help="worker processes of the MPC sweeps (default 2)")
    parser.add_argument("--no-sensitivity", action="store_true",
                        help="skip the unscored sensitivity runs (40 ms brake and the others of the study)")
    parser.add_argument("--no-report", action="store_true",
                        help="do not regenerate experiments/results/report.md")


def apply_common_args(args):
    """The effect of --results and --refine (call before writing anything)."""
    global REFINE_LEVELS
    REFINE_LEVELS = max(0, int(args.refine))
    if args.results:
        set_results(args.results)


def column_info(args):
    """What the report needs to name this run's column: the parameter set and the actuators."""
    act = "vehicle"
    for x in args.set:
        if x.startswith("plant.actuators="):
            act = x.split("=", 1)[1]
    return {"set_label": args.label or (os.path.splitext(os.path.basename(args.stability))[0]
                                        if args.stability else "shipped"),
            "stability": os.path.relpath(os.path.abspath(args.stability), ROOT)
            if args.stability else "params/stability/default.yaml (the car's)",
            "actuators": act, "gg_axis": args.gg, "refine_levels": REFINE_LEVELS}


def finish_study(study, scw, args, sets, summary, timer, per_pert, pert_label, out,
                 main_wall=None):
    """The common end of a study: adds the track's corners, the wall and CPU time and the
    column's settings to `summary` and writes it, then prints one line per perturbation value and
    configuration of `per_pert` ({value: {config: analyse_series(...)}}, the value named by
    `pert_label`, e.g. "seed" or "rear μy") and the total time (and that of the main sweep, when
    given). The study then calls report.update(args) itself: report.py builds on this module."""
    summary["corners"] = track_corners(scw, sets)
    summary["wall_time_s"] = timer.seconds()
    summary["cpu_time_s"] = timer.cpu_seconds()
    summary["column"] = column_info(args)
    write_summary(study, summary)
    for v, ser in per_pert.items():
        for name, a in ser.items():
            print(f"{pert_label} {v} {name}: max stable GG {a['max_stable']}, first abort "
                  f"{a['first_abort']} ({a['first_abort_status']}), min lap "
                  f"{fmt(a['min_lap_time_s'], 3)} s at GG {a['min_lap_value']}")
    main = "" if main_wall is None else f" (main sweep {main_wall:.0f} s)"
    print(f"{study}: {timer.seconds():.0f} s wall{main}; outputs in {out}")


def mark_aborts(ax, rows, key, field, color, linestyle="-"):
    """An 'x' at the aborted run of a series (the last reported one)."""
    for r in rows:
        if r["status"] != "completed" and not math.isnan(r[field]):
            ax.plot([r[key]], [r[field]], marker="x", color=color, markersize=9, linestyle="none")
