"""The paper's claims as pure functions over series (scwexp.results.pack_series: max_stable,
first_abort, runs, ...): each claim's criterion, written before the numbers (CRITERIA), item by
item with the numbers that decide it; claims (a)-(d) scored, (e) and (f) checked. Also what
marks a claims-map variant whose motion controller limit-cycles. No files, no scw runs."""

import math

from scwexp.track import place
from scwexp.results import ACTIVATION_KEYS, SLIP_STATUSES, to_float


STEP = 0.05   # GG step of the studies
EPS = 1e-6
GG_D = 1.3    # claim (d): the paper's GG
CLAIM_D_COST = (0.05, 0.40)  # claim (d): the range Δ(ESC) must fall in [s]


# ---------------------------------------------------------------------------------------------
# Reading a series (pack_series: max_stable, first_abort, ..., runs)

def done_runs(a):
    return [r for r in a["runs"] if r["status"] == "completed"]


def abort_run(a):
    return next((r for r in a["runs"] if r["status"] != "completed"), None)


def stable(a):
    """Max stable GG; a series without a completed run counts as one step below the range."""
    if a["max_stable"] is not None:
        return a["max_stable"]
    return (a["runs"][0]["gg_scale"] - STEP) if a["runs"] else -1.0


def abort_gg(a):
    """First abort GG; a series that never aborts counts as one step above its last run."""
    if a["first_abort"] is not None:
        return a["first_abort"]
    return (a["runs"][-1]["gg_scale"] + STEP) if a["runs"] else math.inf


def run_at(a, gg):
    return next((r for r in a["runs"] if abs(r["gg_scale"] - gg) < EPS), None)


def best_run(a):
    d = done_runs(a)
    return min(d, key=lambda r: r["mean_lap_time_s"]) if d else None


def acts(r):
    """ESC/CS/ABS/TC activation counts of one run."""
    return "/".join(str(int(r[k] or 0)) for k in ACTIVATION_KEYS)


def g(x):
    """A GG value: two decimals, three for the bisected ones (1.025)."""
    if x is None:
        return "–"
    t = f"{x:.3f}"
    return t[:-1] if t.endswith("0") else t


def t3(x):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.3f}"


def status_text(status, study1=False):
    if study1 and status not in ("completed",) + SLIP_STATUSES:
        return f"safety stop ({status})"
    return status


def where(r, corners):
    if r is None:
        return "–"
    s = r.get("end_s_m")
    lap = r.get("end_lap")
    if s is None or (isinstance(s, float) and math.isnan(s)):
        return "–"
    lap_txt = f", lap {int(lap) + 1}" if lap is not None and not math.isnan(lap) else ""
    return f"s = {s:.0f} m ({place(s, corners)}{lap_txt})"


def abort_text(a, corners, study1=False):
    r = abort_run(a)
    if r is None:
        return f"none up to {g(a['runs'][-1]['gg_scale']) if a['runs'] else '–'}"
    return (f"{g(r['gg_scale'])} {status_text(r['status'], study1)} at {where(r, corners)}, "
            f"activations {acts(r)}")


def active_count(runs, key):
    return sum(1 for r in runs if (r[key] or 0) > 0)


# ---------------------------------------------------------------------------------------------
# The claims: each check returns (ok, [(criterion, ok, text)]); ok is None if not evaluable.

def check(items):
    oks = [ok for _, ok, _ in items]
    return all(oks), items


def claim_a(ser):
    on, off = ser.get("sc_on"), ser.get("sc_off")
    if not on or not off or not on["runs"] or not off["runs"]:
        return None, [("data", None, "study 1 lacks a configuration")]
    items = []
    items.append(("max stable GG on ≥ off + 0.10", stable(on) >= stable(off) + 0.10 - EPS,
                  f"on {g(on['max_stable'])}, off {g(off['max_stable'])}"))
    ab = abort_run(off)
    items.append(("SC off's first abort is a lock or spin",
                  ab is not None and ab["status"] in SLIP_STATUSES,
                  f"off: {abort_text(off, CORNERS, True)}"))
    bon, boff = best_run(on), best_run(off)
    ok = bon is not None and boff is not None and \
        bon["mean_lap_time_s"] <= boff["mean_lap_time_s"] - 0.3 + EPS
    items.append(("best lap on ≤ off − 0.3 s", ok,
                  f"on {t3(bon and bon['mean_lap_time_s'])} s (GG {g(bon and bon['gg_scale'])}),"
                  f" off {t3(boff and boff['mean_lap_time_s'])} s "
                  f"(GG {g(boff and boff['gg_scale'])})"))
    d = done_runs(on)
    steps, peaks = [], []
    for key in ("max_slip_front_pct", "max_slip_rear_pct"):
        vals = [r[key] for r in d]
        steps.append(max([b - a for a, b in zip(vals, vals[1:])] + [0.0]))
        peaks.append(max(vals) if vals else math.nan)
    ok = bool(d) and max(steps) <= 10.0 + EPS and max(peaks) <= 25.0 + EPS
    items.append(("SC on, completed runs: slip rises ≤ 10 points per step, stays ≤ 25 %", ok,
                  f"largest rise front {steps[0]:.1f} / rear {steps[1]:.1f} points, peak front "
                  f"{peaks[0]:.1f} / rear {peaks[1]:.1f} %"))
    doff = done_runs(off)
    if ab is not None and doff:
        last = doff[-1]
        jf = ab["max_slip_front_pct"] - last["max_slip_front_pct"]
        jr = ab["max_slip_rear_pct"] - last["max_slip_rear_pct"]
        items.append(("SC off jumps ≥ 50 points at its abort", max(jf, jr) >= 50.0 - EPS,
                      f"front {last['max_slip_front_pct']:.1f} → {ab['max_slip_front_pct']:.1f}"
                      f", rear {last['max_slip_rear_pct']:.1f} → {ab['max_slip_rear_pct']:.1f} %"))
    else:
        items.append(("SC off jumps ≥ 50 points at its abort", False,
                      "SC off has no abort or no completed run"))
    n = sum(1 for r in d if (r["abs_count"] or 0) + (r["tc_count"] or 0) > 0)
    items.append(("ABS or TC active in ≥ 2 completed SC-on runs", n >= 2,
                  f"{n} of {len(d)} (ABS in {active_count(d, 'abs_count')}, TC in "
                  f"{active_count(d, 'tc_count')})"))
    deciding = [r for r in d if r["gg_scale"] >= abort_gg(off) - EPS]
    n = sum(1 for r in deciding if (r["abs_count"] or 0) + (r["tc_count"] or 0) > 0)
    items.append(("P5: ABS or TC acted in the deciding runs (SC on, completed, GG ≥ SC off's "
                  "first abort)", n > 0,
                  f"{n} of {len(deciding)}: " +
                  (", ".join(f"GG {g(r['gg_scale'])} {acts(r)}" for r in deciding) or "none")))
    return check(items)


def claim_b(ser):
    none = ser.get("none")
    others = [k for k in ("esc", "cs", "esc+cs") if k in ser]
    if not none or len(others) < 3:
        return None, [("data", None, "study 2 lacks configurations")]
    items = []
    na = abort_gg(none)
    ok = all(abort_gg(ser[k]) >= na + STEP - EPS for k in others)
    items.append(("`none` aborts ≥ one step below each of ESC, CS, ESC + CS", ok,
                  f"first abort: none {g(none['first_abort'])}, " +
                  ", ".join(f"{k} {g(ser[k]['first_abort'])}" for k in others)))
    ab = abort_run(none)
    items.append(("`none` aborts on sideslip", ab is not None and ab["status"] == "sideslip",
                  f"none: {abort_text(none, CORNERS)}"))
    parts, ok = [], True
    need = {"esc": ("esc_count",), "cs": ("cs_count",), "esc+cs": ("esc_count", "cs_count")}
    for k in others:
        r = run_at(ser[k], na)
        acted = r is not None and r["status"] == "completed" and \
            any((r[c] or 0) > 0 for c in need[k])
        ok = ok and acted
        parts.append(f"{k} at GG {g(na)}: " + (f"{r['status']}, {acts(r)}" if r else "no run"))
    items.append(("P5: the configuration's subsystem acted at `none`'s abort GG", ok,
                  "; ".join(parts)))
    return check(items)


def claim_c(ser):
    if any(k not in ser for k in ("none", "esc", "cs", "esc+cs")):
        return None, [("data", None, "study 2 lacks configurations")]
    items = []
    for k in ("esc", "esc+cs"):
        a = ser[k]
        b = best_run(a)
        if b is None:
            items.append((f"`{k}`: best lap below max stable", False, "no completed run"))
            continue
        top = run_at(a, a["max_stable"])
        below = b["gg_scale"] <= a["max_stable"] - STEP + EPS
        slower = top["mean_lap_time_s"] >= b["mean_lap_time_s"] + 0.05 - EPS
        above = [r for r in done_runs(a) if r["gg_scale"] > b["gg_scale"] + EPS]
        esc_all = bool(above) and all((r["esc_count"] or 0) > 0 for r in above)
        items.append((f"`{k}`: best GG ≤ max stable − 0.05 and lap at max stable ≥ best + "
                      "0.05 s", below and slower,
                      f"best {t3(b['mean_lap_time_s'])} s at GG {g(b['gg_scale'])}, max stable "
                      f"{g(a['max_stable'])} with {t3(top['mean_lap_time_s'])} s"))
        items.append((f"`{k}`: ESC active in every completed run above the best", esc_all,
                      ", ".join(f"GG {g(r['gg_scale'])} ESC {int(r['esc_count'] or 0)}"
                                for r in above) or "no completed run above the best"))
    for k in ("none", "cs"):
        a = ser[k]
        b = best_run(a)
        ok = b is not None and abs(b["gg_scale"] - a["max_stable"]) < EPS
        items.append((f"`{k}`: best-lap GG = max stable GG", ok,
                      f"best at GG {g(b and b['gg_scale'])}, max stable {g(a['max_stable'])}"))
    return check(items)


def claim_d_gg(ser):
    """The GG claim (d) is judged at: GG_D if all four configurations complete it, else the
    highest GG at which every configuration has a completed run (None if there is none)."""
    common = None
    ggs = sorted({r["gg_scale"] for r in done_runs(ser["none"])})
    for x in ggs:
        if all((run_at(ser[k], x) or {}).get("status") == "completed" for k in ser):
            common = x if common is None or x > common else common
    return GG_D if all((run_at(ser[k], GG_D) or {}).get("status") == "completed"
                       for k in ("none", "esc", "cs", "esc+cs")) else common


def claim_d(ser):
    if any(k not in ser for k in ("none", "esc", "cs", "esc+cs")):
        return None, [("data", None, "study 2 lacks configurations")]
    at = claim_d_gg(ser)
    if at is None:
        return False, [("all four complete at a common GG", False, "no common completed GG")]
    shift = "" if abs(at - GG_D) < EPS else f" (not all complete at {GG_D}: shifted)"
    r = {k: run_at(ser[k], at) for k in ("none", "esc", "cs", "esc+cs")}
    d_esc = r["esc"]["mean_lap_time_s"] - r["none"]["mean_lap_time_s"]
    d_both = r["esc+cs"]["mean_lap_time_s"] - r["none"]["mean_lap_time_s"]
    items = [("evaluated at GG 1.3 or the highest GG all four complete", True,
              f"GG {g(at)}{shift}; laps none {t3(r['none']['mean_lap_time_s'])}, ESC "
              f"{t3(r['esc']['mean_lap_time_s'])}, CS {t3(r['cs']['mean_lap_time_s'])}, ESC + CS "
              f"{t3(r['esc+cs']['mean_lap_time_s'])} s"),
             ("Δ(ESC) in 0.05–0.40 s", CLAIM_D_COST[0] - EPS <= d_esc <= CLAIM_D_COST[1] + EPS,
              f"Δ(ESC) {d_esc:+.3f} s"),
             ("0 ≤ Δ(ESC + CS) < Δ(ESC)", -EPS <= d_both < d_esc,
              f"Δ(ESC + CS) {d_both:+.3f} s"),
             ("ESC active at that GG in both ESC configurations",
              (r["esc"]["esc_count"] or 0) > 0 and (r["esc+cs"]["esc_count"] or 0) > 0,
              f"ESC {int(r['esc']['esc_count'] or 0)}× (ESC only), "
              f"{int(r['esc+cs']['esc_count'] or 0)}× (ESC + CS); activations ESC/CS/ABS/TC: " +
              ", ".join(f"{k} {acts(r[k])}" for k in r))]
    return check(items)


def claim_e(ser, ctrl):
    """Study 3: stability control raises the controller's max stable GG (the SC run at the
    unprotected series' first-abort GG completes with ESC or CS acting)."""
    off, sc = ser.get(f"{ctrl}_off"), ser.get(f"{ctrl}_sc")
    if not off or not sc:
        return None, [("data", None, f"no {ctrl} series")]
    r = run_at(sc, abort_gg(off))
    acted = r is not None and r["status"] == "completed" and \
        (r["esc_count"] or 0) + (r["cs_count"] or 0) > 0
    return check([
        ("max stable GG with ESC + CS ≥ without + 0.05", stable(sc) >= stable(off) + STEP - EPS,
         f"without {g(off['max_stable'])} (abort {abort_text(off, CORNERS)}), with "
         f"{g(sc['max_stable'])} (abort {abort_text(sc, CORNERS)})"),
        ("P5: ESC or CS acted in the SC run at the unprotected abort GG", acted,
         f"GG {g(abort_gg(off))}: " + (f"{r['status']}, {acts(r)}" if r else "no run"))])


def claim_f(ser, ctrl):
    """Study 3: with SC the best lap lies below the max stable GG; without SC they coincide."""
    off, sc = ser.get(f"{ctrl}_off"), ser.get(f"{ctrl}_sc")
    if not off or not sc:
        return None, [("data", None, f"no {ctrl} series")]
    bo, bs = best_run(off), best_run(sc)
    return check([
        ("without SC: best-lap GG = max stable GG",
         bo is not None and abs(bo["gg_scale"] - off["max_stable"]) < EPS,
         f"best at {g(bo and bo['gg_scale'])}, max stable {g(off['max_stable'])}"),
        ("with ESC + CS: best-lap GG ≤ max stable − 0.05",
         bs is not None and bs["gg_scale"] <= sc["max_stable"] - STEP + EPS,
         f"best at {g(bs and bs['gg_scale'])}, max stable {g(sc['max_stable'])}")])


CRITERIA = {
    "a": ("Study 1: slip control (ABS + TC) allows a higher GG without a tyre locking or "
          "spinning, with lower lap times and gradually rising slip",
          "max stable GG with SC ≥ without + 0.10; SC off's first abort is a wheel lock or spin "
          "(slip < −50 % or > +30 % for ≥ 0.1 s); best lap (the lowest mean lap time of a "
          "completed run) with SC ≥ 0.3 s faster; over the completed SC-on runs the max front and "
          "max rear slip rise by ≤ 10 points per GG step and stay ≤ 25 %, while SC off's slip "
          "jumps by ≥ 50 points from its last completed run to its abort; ABS or TC active in "
          "≥ 2 completed SC-on runs; P5: ABS or TC acted in at least one of the runs that decide "
          "(completed SC-on runs at GG ≥ SC off's first abort)."),
    "b": ("Study 2: without lateral stability control the car spins at the lowest GG",
          "`none` has its first abort at least one GG step (0.05) below each of ESC, CS and "
          "ESC + CS (a series without abort in the range counts as one step above it), and that "
          "abort is `sideslip` (|β| > 20°); P5: at `none`'s abort GG, ESC acted in the ESC-only "
          "run, CS in the CS-only run, ESC or CS in the ESC + CS run."),
    "c": ("Study 2: with ESC the best lap lies below the maximum stable GG; without ESC they "
          "coincide",
          "for ESC and ESC + CS: the best lap's GG ≤ max stable GG − 0.05, the lap at the max "
          "stable GG ≥ best + 0.05 s, and ESC active in every completed run above the best "
          "(P5); for `none` and CS only: the best lap's GG = max stable GG."),
    "d": ("Study 2: at GG 1.3 ESC costs 0.05–0.40 s of lap time against none, ESC + CS less",
          "at GG 1.3, or the highest GG all four configurations complete (stated): Δ(ESC) = "
          "lap(ESC) − lap(none) in 0.05–0.40 s, 0 ≤ Δ(ESC + CS) < Δ(ESC), ESC active (≥ 1 "
          "activation) at that GG in both ESC configurations (P5). Paper: 0.15 s and 0.05 s."),
    "e": ("Study 3: stability control lets every motion controller run a higher GG",
          "per controller: max stable GG with ESC + CS ≥ without + 0.05; P5: ESC or CS acted in "
          "the ESC + CS run at the GG where the unprotected series first aborts."),
    "f": ("Study 3: without SC the best lap coincides with the max stable GG, with SC it lies "
          "below",
          "per controller: without SC the best lap's GG = max stable GG; with ESC + CS the "
          "best lap's GG ≤ max stable GG − 0.05."),
}

CORNERS = []
# The configurations whose runs decide each study-2 claim.
CLAIM_CONFIGS = {"b": ["none", "esc", "cs", "esc+cs"], "c": ["esc", "esc+cs", "none", "cs"],
                 "d": ["esc", "esc+cs"]}


def needed(n):
    """Perturbations a claim must hold in: 2 of 3 (all of fewer than 3)."""
    return 2 if n >= 3 else n


def evaluate(fn, runs, *extra):
    """{pert: (ok, items)} and the overall verdict (≥ 2 of 3)."""
    res = {p: fn(ser, *extra) for p, ser in runs.items()}
    oks = [ok for ok, _ in res.values() if ok is not None]
    if not oks:
        return None, res
    return sum(oks) >= needed(len(res)), res


# A motion controller whose steering limit-cycles is not a model of the paper's PMPC. Measured
# (docs/plant-calibration.md "PMPC yaw-rate feedback"; study 2 `none`, GG 0.7/1.0/1.05, one lap,
# shipped set, both actuator models): the steering request's RMS above ~1.6 Hz (sweep column
# steer_hf_rms_deg) is 0.07-0.28° without the feedback and with k ≤ 0.1 s (≤ 0.15 s with the
# vehicle file's actuators), 0.37-1.4° where the steering loop limit-cycles at 2.5-5 Hz (k ≥ 0.2 s,
# ≥ 0.15 s with the paper's simulator's 60 ms steering dead time). The threshold lies between.
STEER_LIMIT_CYCLE_DEG = 0.35


def steer_hf(v):
    """The largest steer_hf_rms_deg over `none`'s completed study-2 runs of a claims-map variant
    (the motion controller without lateral stability control), or None (no such run, or a
    summary written before the column)."""
    runs = (v.get("series", {}).get("none") or {}).get("runs", [])
    xs = [to_float(r.get("steer_hf_rms_deg")) for r in runs
          if r["status"] == "completed"]
    xs = [x for x in xs if not math.isnan(x)]
    return max(xs) if xs else None


def limit_cycling(v):
    x = steer_hf(v)
    return x is not None and x >= STEER_LIMIT_CYCLE_DEG


def cycling_mark(v):
    """' (limit-cycling)' after a claims-map variant's label or steering figure when its motion
    controller limit-cycles, else ''."""
    return " (limit-cycling)" if limit_cycling(v) else ""


def cycling_label(v):
    """A claims-map variant's label, marked when its motion controller limit-cycles."""
    return v["label"] + cycling_mark(v)
