"""The mechanism at the knife edge (issue 25 part 3): from the traced first lap of each study-2
configuration at the GG where `none` first aborts, the time from the start of the rear axle's
final saturation to |β| = 20°, when ESC and CS first act and what they deliver, against a simple
bound of the yaw moment that would be needed in that time.

Definitions (stated in the report):
- t20: the first time |β| ≥ 20°, or the abort when the run ends otherwise (lateral error, off
  track: the car was lost before |β| reached 20°), or the end of a completed run;
- t_sat: the first rear saturation of the final divergence: the time from which the rear
  axle's mean |slip angle| stays at or beyond the rear tyre's peak slip angle (Magic Formula,
  nominal load) until t20;
- ESC's brake moment arrives when, with ESC active, a wheel's applied pressure first exceeds
  both its value when ESC switched on and the motion controller's request by 10 bar;
- the actuator's response t_act: the brake's dead time + lag (the vehicle file's, or ~0 for
  paper_sim), the time before a brake command can build a yaw moment;
- the bound: M_needed = Iz · Δr_max / (t20 − t_sat − t_act), with Δr_max the largest yaw-rate
  excess |r − r_ref| in [t_sat, t20]: the constant moment that removes that excess in the time
  left once the brakes respond; infinite when no time is left.
"""

import glob
import json
import math
import os
import subprocess

from scwexp.track import place
from scwexp.paths import ROOT
from scwexp.results import read_csv, write_json

# Open-Car-Dynamics' published actuation (docs/plant-calibration.md): brakes at once, steering
# 60 ms dead time + 60 ms PT1, 0.5 rad/s.
PAPER_SIM = {"brake_s": 0.001, "steer_s": 0.12, "steer_rate": 0.5}
# The same simulator as its IV-2024 code had it: brakes 10 ms + PT1 30 ms (40 ms to 63 %),
# steering 50 ms + PT1 50 ms, 1.0 rad/s.
PAPER_SIM_V1 = {"brake_s": 0.04, "steer_s": 0.10, "steer_rate": 1.0}
SIM_ACTUATORS = {"paper_sim": PAPER_SIM, "paper_sim_v1": PAPER_SIM_V1}


def vehicle_constants(scw):
    """Iz, the actuator times and the rear tyre's peak slip angle (Magic Formula, nominal
    load, no camber) of the built-in vehicle file."""
    out = subprocess.run([scw, "vehicle", "init", "-o", "/dev/stdout"], capture_output=True,
                         text=True, cwd=ROOT).stdout
    vals, path = {}, []
    for line in out.splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        depth = (len(line) - len(line.lstrip())) // 2
        key, _, val = line.strip().partition(":")
        path = path[:depth] + [key]
        try:
            vals[".".join(path)] = float(val.split("#")[0])
        except ValueError:
            pass
    iz = next((v for k, v in vals.items() if k.endswith("yaw_inertia")), math.nan)
    return {"iz": iz, "half_track_front": 0.5 * vals.get("track_front", math.nan),
            "brake_s": vals.get("brakes.delay", math.nan) + vals.get("brakes.time_constant", 0),
            "steer_s": vals.get("steering.delay", math.nan) +
            vals.get("steering.time_constant", 0.0),
            "alpha_peak_rad": peak_slip_angle({k.split(".")[-1]: v for k, v in vals.items()
                                               if k.startswith("tires.rear.")})}


def peak_slip_angle(t):
    """Slip angle of the lateral force peak at nominal load: B·x − E·(B·x − atan(B·x)) =
    tan(π / (2C)) with C = pcy1, D = pdy1·λμy·Fz0, K = pky1·λKy·Fz0·sin(2·atan(1/pky2)),
    B = K / (C·D), E = pey1."""
    c = t.get("pcy1", math.nan) * t.get("lcy", 1.0)
    d = t.get("pdy1", math.nan) * t.get("lmuy", 1.0)
    k = abs(t.get("pky1", math.nan)) * t.get("lky", 1.0) * \
        math.sin(2 * math.atan(1 / t.get("pky2", math.nan)))
    b, e = k / (c * d), t.get("pey1", 0.0)
    target = math.tan(math.pi / (2 * c))
    lo, hi = 0.0, 20.0
    for _ in range(60):
        u = 0.5 * (lo + hi)
        if u - e * (u - math.atan(u)) < target:
            lo = u
        else:
            hi = u
    return lo / b


# How far before `none`'s rear saturation and after its loss a completed run is read [m].
CATCH_MARGIN_M = 30.0


def front_brake_moment(r, half_track):
    """The yaw moment [N·m] the front axle's longitudinal tyre forces make about the CoG,
    (t_f / 2)(F_x,fr − F_x,fl) cos δ (> 0 turns left, as ESC's command): what ESC's differential
    front braking delivers; None for a trace without the forces (before issue 48's test 6)."""
    if half_track is None or "fx_fl_N" not in r or r["fx_fl_N"] is None:
        return None
    return half_track * (r["fx_fr_N"] - r["fx_fl_N"]) * math.cos(r["steer_meas_rad"])


def delivered(rows, half_track):
    """(largest |delivered| while ESC acts, the delivered moment at the tick of ESC's largest
    command, that command) over `rows`; None without the forces or without ESC acting."""
    act = [r for r in rows if r["esc_active"] > 0.5]
    if not act or front_brake_moment(act[0], half_track) is None:
        return None
    peak = max(act, key=lambda r: abs(r["yaw_moment_Nm"]))
    return (max(abs(front_brake_moment(r, half_track)) for r in act),
            front_brake_moment(peak, half_track), peak["yaw_moment_Nm"])


def catch_at(rows, at):
    """What a run that completed did where `none` lost the car: at = (lap, s from, s to) of
    `none`'s window from rear saturation to the loss; the rows of that lap within it (widened
    by CATCH_MARGIN_M) give when ESC and CS first acted (as metres from `none`'s loss point),
    the largest yaw moment, extra brake pressure and countersteer, and the largest |β|."""
    lap, s0, s1 = at
    w = [r for r in rows if int(r.get("lap", 0)) == int(lap) and
         s0 - CATCH_MARGIN_M <= r["s_m"] <= s1 + CATCH_MARGIN_M]
    if not w:
        return None
    first = {k: next((r["s_m"] - s1 for r in w if r[f"{k}_active"] > 0.5), None)
             for k in ("esc", "cs")}
    dt = rows[1]["t_s"] - rows[0]["t_s"] if len(rows) > 1 else 0.0  # the trace's sample time
    wheels = ("fl", "fr", "rl", "rr")
    return {"lap": int(lap), "s_from": s0, "s_to": s1, "esc_from_m": first["esc"],
            "cs_from_m": first["cs"],
            "esc_s": dt * sum(1 for r in w if r["esc_active"] > 0.5),
            "cs_s": dt * sum(1 for r in w if r["cs_active"] > 0.5),
            "m_cmd_max": max(abs(r["yaw_moment_Nm"]) for r in w),
            "p_extra_max": max(max(r[f"p_out_{x}_bar"] - r[f"p_req_{x}_bar"] for x in wheels)
                               for r in w),
            "steer_corr_max_deg": math.degrees(max(abs(r["steer_out_rad"] - r["steer_req_rad"])
                                                   for r in w)),
            "beta_max_deg": max(abs(r["beta_deg"]) for r in w)}


def analyse_all(files, iz, t_act, alpha_peak, statuses, half_track=None):
    """analyse() of every configuration's trace; `none` first, and a configuration that
    completes is also read where `none` lost the car (catch_at)."""
    res = {}
    if "none" in files:
        res["none"] = analyse(files["none"], iz, t_act, alpha_peak, statuses.get("none"))
    n0 = res.get("none")
    at = (n0["lap"], n0["s_sat_m"], n0["s_m"]) if n0 and n0["spun"] else None
    for n, f in files.items():
        if n != "none":
            res[n] = analyse(f, iz, t_act, alpha_peak, statuses.get(n), at=at,
                             half_track=half_track)
    return res


def analyse(trace_csv, iz, t_act, alpha_peak, status=None, at=None, half_track=None):
    """The knife-edge numbers of one traced run; status: how the run ended (an abort other
    than sideslip ends the window at the trace's end: the car was lost before |β| = 20°); at:
    `none`'s loss window (catch_at), read when this run completed."""
    rows = read_csv(trace_csv)
    if not rows:
        return None
    t20 = next((r["t_s"] for r in rows if abs(r["beta_deg"]) >= 20.0), None)
    spun = t20 is not None or (status is not None and status != "completed")
    if t20 is None:
        t20 = rows[-1]["t_s"]
    upto = [r for r in rows if r["t_s"] <= t20]
    ar = [0.5 * (abs(r["alpha_rl_rad"]) + abs(r["alpha_rr_rad"])) for r in upto]
    i = len(ar) - 1
    while i > 0 and ar[i - 1] >= alpha_peak:
        i -= 1
    saturated = ar[-1] >= alpha_peak
    t_sat = upto[i]["t_s"]
    win = [r for r in upto if r["t_s"] >= t_sat]
    dr = max((abs(r["yaw_rate_radps"] - r["yaw_rate_ref_radps"]) for r in win), default=0.0)
    first = {}
    for k in ("esc", "cs"):
        first[k] = next((r["t_s"] for r in upto if r[f"{k}_active"] > 0.5 and
                         r["t_s"] >= t_sat - 1.0), None)
    m_cmd = max((abs(r["yaw_moment_Nm"]) for r in win), default=0.0)
    p_out = max((max(r[f"p_out_{w}_bar"] - r[f"p_req_{w}_bar"] for w in ("fl", "fr", "rl", "rr"))
                 for r in win), default=0.0)
    steer_corr = max((abs(r["steer_out_rad"] - r["steer_req_rad"]) for r in win), default=0.0)
    left = t20 - t_sat - t_act
    need = iz * dr / left if left > 0 else math.inf
    # when the brakes deliver: the first time the applied pressure of a wheel exceeds the
    # motion controller's request by 10 bar (ESC's brake intervention arriving at the wheel)
    wheels = ("fl", "fr", "rl", "rr")
    t_del = None
    if first["esc"] is not None:
        r0 = next(r for r in upto if r["t_s"] >= first["esc"])
        t_del = next((r["t_s"] for r in upto if r["t_s"] >= first["esc"] and
                      r["esc_active"] > 0.5 and
                      max(r[f"p_out_{w}_bar"] - max(r0[f"p_out_{w}_bar"], r[f"p_req_{w}_bar"])
                          for w in wheels) >= 10.0), None)
    return {"status": status, "spun": spun, "beta20": any(abs(r["beta_deg"]) >= 20.0 for r in rows),
            "saturated": saturated, "t_delivered": t_del,
            "alpha_peak_deg": math.degrees(alpha_peak), "t20": t20, "t_sat": t_sat, "window_s": t20 - t_sat,
            "alpha_r_sat_deg": math.degrees(ar[i]), "alpha_r_end_deg": math.degrees(ar[-1]),
            "s_m": upto[-1]["s_m"], "v_mps": upto[-1]["vx_mps"], "dr_max": dr,
            "first_esc": first["esc"], "first_cs": first["cs"], "m_cmd_max": m_cmd,
            "p_extra_max": p_out, "steer_corr_max_deg": math.degrees(steer_corr),
            "t_act": t_act, "m_needed": need, "lap": int(upto[-1].get("lap", 0)),
            "s_sat_m": upto[i]["s_m"], "delivered": delivered(upto, half_track),
            "catch": catch_at(rows, at) if at and not spun else None}


def describe(name, label, x, corners, status=None):
    if x is None:
        return f"{label}: no trace"
    def rel(t):
        return "never" if t is None else f"{t - x['t_sat']:+.2f} s"
    lost = f"|β| = 20° at t = {x['t20']:.2f} s" if x["beta20"] else \
        f"{status} at t = {x['t20']:.2f} s (|β| < 20°)"
    head = (f"{label}: " + (lost if x["spun"] else "completed, |β| < 20°")
            + f" ({place(x['s_m'], corners)}, {x['v_mps']:.0f} m/s)")
    c = x.get("catch")
    if c:
        def at_m(d):
            return "never there" if d is None else \
                f"from {-d:.0f} m before that point" if d < 0 else \
                f"from {d:.0f} m after that point"
        acted = []
        if name in ("esc", "esc+cs"):
            acted.append(f"ESC acts {at_m(c['esc_from_m'])} "
                         f"({c['esc_s']:.2f} s active), commands up to "
                         f"{c['m_cmd_max']:.0f} N·m, brake pressure up to "
                         f"{c['p_extra_max']:.0f} bar above the request")
        if name in ("cs", "esc+cs"):
            acted.append(f"CS acts {at_m(c['cs_from_m'])} "
                         f"({c['cs_s']:.2f} s active), countersteer up to "
                         f"{c['steer_corr_max_deg']:.1f}°")
        return (head + f"; where `none` lost the car (lap {c['lap'] + 1}, s = {c['s_from']:.0f}–"
                f"{c['s_to']:.0f} m, its loss point at the end): " + "; ".join(acted) +
                f"; |β| up to {c['beta_max_deg']:.1f}° there")
    if x["saturated"]:
        head += (f"; the rear slip angle stays beyond its peak ({x['alpha_peak_deg']:.1f}°) from "
                 f"t_sat = {x['t_sat']:.2f} s on (up to {x['alpha_r_end_deg']:.1f}°): "
                 f"{x['window_s']:.2f} s from rear saturation to "
                 + ("the loss" if x["spun"] else "the end of the run"))
    else:
        head += f"; the rear axle is below its peak slip angle ({x['alpha_peak_deg']:.1f}°) at the end"
    parts = [f"ESC first acts {rel(x['first_esc'])} from t_sat, CS {rel(x['first_cs'])}"]
    if name in ("esc", "esc+cs"):
        parts.append(f"ESC commands up to {x['m_cmd_max']:.0f} N·m; its brake pressure reaches "
                     f"the wheel (≥ 10 bar above the request) {rel(x['t_delivered'])} from t_sat, "
                     f"up to {x['p_extra_max']:.0f} bar")
        d = x.get("delivered")
        if d:
            parts.append(f"the front tyres deliver up to {d[0]:.0f} N·m while ESC acts "
                         f"({d[1]:.0f} N·m at its largest command of {d[2]:.0f} N·m)")
    if name in ("cs", "esc+cs"):
        parts.append(f"countersteer up to {x['steer_corr_max_deg']:.1f}° at the road wheels")
    need = x["m_needed"]
    if x["spun"] and x["saturated"]:
        if math.isinf(need):
            parts.append(f"needed: impossible by braking — the window is shorter than the brake "
                         f"response ({x['t_act'] * 1000:.0f} ms)")
        else:
            parts.append(f"needed ≥ {need:.0f} N·m within {x['window_s'] - x['t_act']:.2f} s "
                         f"after the brake response of {x['t_act'] * 1000:.0f} ms (yaw-rate "
                         f"excess {x['dr_max']:.2f} rad/s)")
    return head + "; " + "; ".join(parts)


def verdict_line(res, act):
    """What prevents each configuration from catching the spin, one sentence."""
    spun = {n: x for n, x in res.items() if x and x["spun"]}
    if not spun:
        return "Every configuration completes this run."
    if set(spun) == {"none"}:
        caught = []
        for n, x in res.items():
            c = x and x.get("catch")
            if n == "none" or not c:
                continue
            who = [k.upper() for k, cnt in (("esc", c["esc_s"]), ("cs", c["cs_s"]))
                   if cnt > 0 and k in n.split("+")]
            caught.append(f"{n}: " + (" and ".join(who) + " acted there" if who else
                                      "no subsystem of it acted there (the run differs "
                                      "before that point)"))
        return ("Nothing prevents the catch (" + act + "): only `none` loses the car; where "
                "it did, " + "; ".join(caught) + ".")
    parts = []
    for n, x in spun.items():
        if n == "none":
            continue
        late = x["t_delivered"] is None or x["t_delivered"] > x["t20"] - 0.05
        if not x["saturated"]:
            why = (f"not a spin: {x['status'] or 'the loss'} with the rear axle below its peak "
                   "slip angle (the car left its line; ESC and CS act on yaw, not on path "
                   "error)")
        elif n in ("esc", "esc+cs") and math.isinf(x["m_needed"]):
            why = (f"the {x['window_s']:.2f} s from rear saturation to the loss are shorter than "
                   f"the brake response ({x['t_act'] * 1000:.0f} ms): no brake moment can arrive "
                   "in time")
        elif n in ("esc", "esc+cs") and x["first_esc"] is None:
            why = "ESC never switched on before the spin"
        elif n in ("esc", "esc+cs") and late:
            why = (f"ESC switched on {x['first_esc'] - x['t_sat']:+.2f} s from rear saturation, "
                   f"but its brake pressure reached no wheel before the loss (brake response "
                   f"{x['t_act'] * 1000:.0f} ms, window {x['window_s']:.2f} s)")
        elif n in ("esc", "esc+cs") and x["m_cmd_max"] < x["m_needed"]:
            why = (f"ESC's commanded moment ({x['m_cmd_max']:.0f} N·m) is below the needed "
                   f"{x['m_needed']:.0f} N·m")
        elif n == "cs" and x["first_cs"] is None:
            why = "CS never acted"
        elif n == "cs":
            why = (f"countersteer ({x['steer_corr_max_deg']:.1f}°) turns the front wheels but "
                   "cannot give the saturated rear axle lateral force back")
        else:
            why = (f"ESC switched on {x['first_esc'] - x['t_sat']:+.2f} s and its brake pressure "
                   f"reached a wheel {x['t_delivered'] - x['t_sat']:+.2f} s from rear saturation "
                   f"(brake response {x['t_act'] * 1000:.0f} ms), "
                   f"{x['t20'] - x['t_delivered']:.2f} s before the loss; what it delivered in "
                   "that time did not bring the rear axle back below its peak slip angle "
                   f"(commanded up to {x['m_cmd_max']:.0f} N·m against the bound's "
                   f"{x['m_needed']:.0f} N·m)")
        parts.append(f"{n}: {why}")
    return "What prevents the catch (" + act + "): " + "; ".join(parts) + "."


def with_statuses(study2):
    """The knife-edge results of a study-2 summary, each with how its traced run ended: the
    stored status, else the traced run's (at `none`'s first abort, else at the trace GG)."""
    xt = study2.get("trace_at_none_abort")
    runs = xt["runs"] if xt else study2.get("trace_runs", {})
    return {n: x if x is None else dict(x, status=x.get("status") or
                                        runs.get(n, {}).get("status"))
            for n, x in study2["knife_edge"]["results"].items()}


def reanalyse(study_dir):
    """Recomputes the knife-edge results of a finished study 2 (its summary.json) from the
    traces it kept (traces/gg<G>/<config>__*.csv), with this file's analysis; the summary is
    replaced whole. For a report on traces that were analysed by an older version."""
    path = os.path.join(study_dir, "summary.json")
    with open(path) as f:
        s = json.load(f)
    ke = s.get("knife_edge")
    if not ke:
        return False
    sub = os.path.join(study_dir, "traces", f"gg{ke['gg']:g}")
    files = {n: fs[0] for n in s["configs"]
             for fs in [sorted(glob.glob(os.path.join(sub, f"{n}__*.csv")))] if fs}
    old = with_statuses(s)
    statuses = {n: (old.get(n) or {}).get("status") for n in files}
    peak = next(math.radians(x["alpha_peak_deg"]) for x in old.values() if x)
    ke["results"] = analyse_all(files, ke["iz"], ke["t_act"], peak, statuses,
                                ke.get("half_track"))
    ke.pop("lines", None)  # the old analysis' text; the report describes the results anew
    write_json(path, s)
    return True

