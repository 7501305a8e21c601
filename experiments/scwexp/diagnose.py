"""The diagnosis of an aborted run: re-run with `scw simulate --trace` (the same scenario keys,
so the same run) and its last seconds described."""

import os

from scwexp import paths, runner
from scwexp.results import read_csv


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
    proc = runner.run(cmd, log=path_stem + ".log", check=False)
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
        "trace": os.path.relpath(trace, paths.RESULTS),
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
