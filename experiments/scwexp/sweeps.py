"""A study's sweep (issue 25 part 6): the GG axis fixed before any run, each series stopped at its
first abort, then that abort bisected between the last completed GG and the abort, and the probe
runs a criterion needs at another series' first abort."""

import os

from scwexp import runner
from scwexp.results import read_csv
from scwexp.runner import mpc_sweep_cmd, reuse_or_run, sweep_cmd


# The GG axis of every study and of the claims map (issue 25 part 6), fixed before any run and
# the same for every configuration, parameter set and actuator model: start 1.0 (70 % of the
# combined limits), step 0.05, stop 1.8. Each series' first abort is then resolved finer by
# bisection between its last completed GG and its first abort (REFINE_LEVELS halvings:
# 0.025 with 1); the bisected runs are part of the series.
GG_AXIS = "1.0:0.05:1.8"
GG_STEP = 0.05
REFINE_LEVELS = 1


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
    runner.run(cmd, log=log)
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
        jobs = _probe_jobs(overrides, pvals, probe, series)
        if jobs:
            rows = run_jobs(jobs, "_probe")
    return rows, commands


def _probe_jobs(names, pvals, probe, series):
    """The (series, perturbation, GG) runs of refine_first_aborts' probe: each configuration at
    its reference's first-abort GG where it has no run there and did not abort below it.
    series(name, pv): a series' rows."""
    jobs = []
    for name in names:
        ref = probe(name)
        if ref is None or ref not in names:
            continue
        for pv in pvals:
            ab = _first_abort_gg(series(ref, pv))
            own = series(name, pv)
            if ab is None or any(abs(float(r["gg_scale"]) - ab) < 1e-9 for r in own):
                continue
            mine = _first_abort_gg(own)
            if mine is None or mine > ab:
                jobs.append((name, pv, ab))
    return jobs
