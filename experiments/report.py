#!/usr/bin/env python3
"""Builds experiments/results/report.md from the studies' summary.json files: what was changed
to run the studies as the paper did, the explicit pass criterion of each claim of the paper
(written before the numbers), the verdict per perturbation and overall (a claim holds if it holds
in at least two of three perturbations), the mechanism seen in the data where a claim fails, the
figures with the subsystem activation counts beside them, and the unscored sensitivity runs.

    python3 experiments/report.py                      (after the studies; each study calls it)
    python3 experiments/report.py --publish experiments/reference-results
        (also copies report.md and the figures it links there, same relative paths)
"""

import argparse
import math
import os
import re
import shutil
import sys

import scwexp

STEP = 0.05   # GG step of the studies
EPS = 1e-6
GG_D = 1.3    # claim (d): the paper's GG
CLAIM_D_COST = (0.05, 0.40)  # claim (d): the range Δ(ESC) must fall in [s]


# ---------------------------------------------------------------------------------------------
# Reading a series (scwexp.pack_series: max_stable, first_abort, ..., runs)

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
    return "/".join(str(int(r[k] or 0)) for k in scwexp.ACTIVATION_KEYS)


def g(x):
    """A GG value: two decimals, three for the bisected ones (1.025)."""
    if x is None:
        return "–"
    t = f"{x:.3f}"
    return t[:-1] if t.endswith("0") else t


def t3(x):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.3f}"


def status_text(status, study1=False):
    if study1 and status not in ("completed",) + scwexp.SLIP_STATUSES:
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
    return f"s = {s:.0f} m ({scwexp.place(s, corners)}{lap_txt})"


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
                  ab is not None and ab["status"] in scwexp.SLIP_STATUSES,
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


def verdict(ok, scored=True):
    if ok is None:
        return "**not evaluable**"
    if scored:
        return "**reproduced**" if ok else "**NOT reproduced**"
    return "holds" if ok else "does not hold"


def claim_block(key, runs, pert_label, fn, *extra, scored=True, title=None):
    ok, res = evaluate(fn, runs, *extra)
    n_ok = sum(1 for o, _ in res.values() if o)
    lines = [f"Result: {verdict(ok, scored)} (holds in {n_ok} of {len(res)} "
             f"{pert_label} values; needed {needed(len(res))})", ""]
    lines += ["| " + pert_label + " | criterion | met | numbers |", "|---|---|---|---|"]
    for p, (o, items) in res.items():
        for i, (name, iok, text) in enumerate(items):
            lines.append(f"| {p if i == 0 else ''} | {name} | "
                         f"{'yes' if iok else ('–' if iok is None else '**no**')} | {text} |")
        lines.append(f"| {p} | **all** | **{'yes' if o else 'no'}** | |")
    return ok, n_ok, len(res), lines


# ---------------------------------------------------------------------------------------------
# Tables

def series_table(runs, labels, pert_label, study1=False):
    """One row per perturbation and configuration: key numbers and activations."""
    lines = [f"| {pert_label} | configuration | max stable GG | first abort: GG, reason, where, "
             "activations ESC/CS/ABS/TC | best lap [s] (GG) | completed runs with ESC / CS / ABS "
             "/ TC active | activations in completed runs ESC/CS/ABS/TC |",
             "|---|---|---|---|---|---|---|"]
    for p, ser in runs.items():
        for name, a in ser.items():
            d = done_runs(a)
            b = best_run(a)
            tot = "/".join(str(int(sum(r[k] or 0 for r in d))) for k in scwexp.ACTIVATION_KEYS)
            act = " / ".join(str(active_count(d, k)) for k in scwexp.ACTIVATION_KEYS)
            lines.append(f"| {p} | {labels.get(name, name)} (`{name}`) | {g(a['max_stable'])} | "
                         f"{abort_text(a, CORNERS, study1)} | "
                         f"{t3(b and b['mean_lap_time_s'])} ({g(b and b['gg_scale'])}) | "
                         f"{act} of {len(d)} | {tot} |")
    return lines


def detail_table(ser, labels, metric, study1=False):
    """Per GG and configuration: mean lap (or the abort), the top metric and ESC/CS/ABS/TC."""
    ggs = sorted({r["gg_scale"] for a in ser.values() for r in a["runs"]})
    names = list(ser)
    lines = ["| GG | " + " | ".join(labels.get(n, n) for n in names) + " |",
             "|---|" + "---|" * len(names)]
    for x in ggs:
        cells = []
        for n in names:
            r = run_at(ser[n], x)
            if r is None:
                cells.append("")
                continue
            head = (f"{r['mean_lap_time_s']:.3f} s" if r["status"] == "completed"
                    else f"**{status_text(r['status'], study1)}**")
            cells.append(f"{head} · {metric(r)} · {acts(r)}")
        lines.append(f"| {g(x)} | " + " | ".join(cells) + " |")
    return lines


def slip_metric(r):
    return f"slip {r['max_slip_front_pct']:.1f}/{r['max_slip_rear_pct']:.1f} %"


def beta_metric(r):
    return f"β {r['max_abs_sideslip_deg']:.1f}°"


def diagnosis(s, labels, pert_label):
    d = s.get("diagnosis") or {}
    if not d:
        return []
    out = [f"How each first abort happened ({pert_label} {s.get('diagnosis_perturbation')}; "
           "the aborted run re-run with `scw simulate --trace`, the same scenario):", ""]
    for name, x in d.items():
        out.append(f"- {labels.get(name, name)}, GG {g(x['gg'])}, `{x['status']}` "
                   f"({scwexp.place(x['s_m'], CORNERS)}): {x['text']}.")
    return out + [""]


def mechanism(s, names, labels):
    """Why a claim fails, from the data: how often each subsystem acted in the completed runs
    of the configurations that decide it (all perturbations) and how their first aborts
    happened (the traced re-runs)."""
    out = []
    parts = []
    for n in names:
        d = [r for ser in s["runs"].values() if n in ser for r in done_runs(ser[n])]
        if d:
            parts.append(f"{labels.get(n, n)}: " + ", ".join(
                f"{k.split('_')[0].upper()} {active_count(d, k)}"
                for k in scwexp.ACTIVATION_KEYS) + f" of {len(d)}")
    if parts:
        out.append("- Completed runs in which each subsystem acted (all perturbations): " +
                   "; ".join(parts) + ".")
    diag = s.get("diagnosis") or {}
    for n in names:
        x = diag.get(n)
        if not x:
            continue
        lead = ", ".join(f"{k.upper()} {x['t_s'] - t:.2f} s"
                         for k, t in x["active_since"].items() if t is not None)
        txt = (f"- {labels.get(n, n)}, first abort GG {g(x['gg'])} "
               f"({s['perturbation']['label']} {s.get('diagnosis_perturbation')}): "
               f"`{x['status']}` at s = {x['s_m']:.0f} m ({scwexp.place(x['s_m'], CORNERS)}), "
               f"lap {x['lap']}, {x['v_mps']:.0f} m/s; subsystems last switched on (s before "
               f"the abort): {lead or 'none'}; max |β| {x['max_beta_deg']:.1f}°, max |lateral error| "
               f"{x['max_lat_err_m']:.1f} m in the last 2 s")
        if abs(x["wheel_slip_pct"]) >= 50:
            src = "with ESC active" if x["esc_at_peak"] else "ESC not active"
            txt += (f"; {x['wheel']} {'locked' if x['wheel_slip_pct'] < 0 else 'spun'} "
                    f"(slip {x['wheel_slip_pct']:.0f} %) after a commanded "
                    f"{x['wheel_p_peak_bar']:.0f} bar on that wheel ({src}; the motion "
                    f"controller requested {x['wheel_p_req_at_peak_bar']:.0f} bar)")
        out.append(txt + ".")
    if out:
        out.insert(0, "Why (from the data):")
        out.insert(1, "")
        out.append("")
    return out


def findings(s1, s2, s3):
    """Facts over all scored series: how far the GG got, where and why the series ended, how
    often ESC acted before the first abort, what the traced aborts show."""
    from collections import Counter
    series, esc_runs = [], []
    for s, esc_on in ((s1, lambda n: True), (s2, lambda n: "esc" in n),
                      (s3, lambda n: n.endswith("_sc"))):
        if not s:
            continue
        for p, ser in s["runs"].items():
            for n, a in ser.items():
                series.append((s["study"], p, n, a))
                if esc_on(n):
                    esc_runs += done_runs(a)
    if not series:
        return []
    lf = 0.7
    st = [a["max_stable"] for *_, a in series if a["max_stable"] is not None]
    places = Counter(scwexp.place(a.get("first_abort_s_m"), CORNERS) for *_, a in series
                     if a["first_abort"] is not None)
    statuses = Counter(a["first_abort_status"] for *_, a in series if a["first_abort"])
    out = ["## Findings (computed from all runs of the three studies, sensitivity runs excluded)",
           ""]
    if st:
        out.append(f"- Max stable GG over the {len(series)} series of the studies: {min(st):.2f}–"
                   f"{max(st):.2f}, i.e. {100 * lf * min(st):.0f}–{100 * lf * max(st):.0f} % of "
                   "the combined limits (GG 1.43 = 100 %); "
                   f"{sum(1 for *_, a in series if a['max_stable'] is None)} series did not "
                   "complete GG 1.0.")
    out.append("- First aborts by reason: " + ", ".join(f"{k} {v}" for k, v in
                                                       statuses.most_common()) +
               "; by place: " + ", ".join(f"{k} {v}" for k, v in places.most_common()) + ".")
    if esc_runs:
        n = active_count(esc_runs, "esc_count")
        out.append(f"- ESC acted in {n} of {len(esc_runs)} completed runs with ESC enabled "
                   "(studies 1–3)" + (": its interventions happen almost only in the runs that "
                                      "abort." if n < 0.25 * len(esc_runs) else "."))
    diags = [x for s in (s1, s2) if s for x in (s.get("diagnosis") or {}).values()]
    locks = [x for x in diags if x["wheel_slip_pct"] <= -50 and x["esc_at_peak"]]
    leads = [x["t_s"] - x["active_since"]["esc"] for x in diags
             if x["active_since"].get("esc") is not None]
    if diags:
        txt = (f"- Of the {len(diags)} traced first aborts (studies 1–2), {len(locks)} end with a "
               "wheel locked after an ESC brake command the motion controller did not request")
        if locks:
            txt += (f" ({min(x['wheel_p_peak_bar'] for x in locks):.0f}–"
                    f"{max(x['wheel_p_peak_bar'] for x in locks):.0f} bar)")
        if leads:
            txt += (f"; where ESC acted, it switched on {min(leads):.2f}–{max(leads):.2f} s before "
                    "the abort (brake response 150 ms)")
        out.append(txt + ".")
    return out + [""]


def sens_verdicts(s, fn, *extra):
    """'40 ms brake: holds; ...' for the sensitivity runs of a study that have the series."""
    parts = []
    for tag, v in s.get("sensitivity", {}).items():
        if extra and not any(n.startswith(f"{extra[0]}_") for ser in v["runs"].values()
                             for n in ser):
            continue
        ok, _ = evaluate(fn, v["runs"], *extra)
        parts.append(f"{SENS_NAMES.get(tag, tag)}: {verdict(ok, scored=False)}")
    return "; ".join(parts)


SENS_NAMES = {"brake40ms": "40 ms brake", "old_defaults": "old defaults",
              "no_esc_cs": "ESC + CS off", "esc_hold": "throttle held during ESC"}


def rel(cmd):
    """A command line with the repository root left out of its paths."""
    return cmd.replace(scwexp.ROOT + "/", "")


def figs(paths):
    return [f"![{os.path.splitext(os.path.basename(p))[0]}]({p})" for p in paths]


def timing(s):
    cpu = s.get("cpu_time_s")
    return (f"wall time {s['wall_time_s'] / 60:.1f} min"
            + (f" (CPU {cpu / 60:.1f} min over 2 cores)" if cpu else ""))


# ---------------------------------------------------------------------------------------------

CHANGES = """\
## What had to change to run the studies as the paper did

The car's shipped stability parameters (`params/stability/default.yaml`) are used unchanged in
every run. Everything below was fixed before any claim was evaluated
(design note: `../shared/spec/closed-loop-fidelity.md` §8–9):

1. **Plant recalibrated against public EAV data** (`docs/plant-calibration.md`): tyre friction
   μx ≈ μy ≈ 1.5 at nominal load (the shipped file had μx ≈ 1.0 against μy ≈ 1.4), positive
   understeer gradient at all speeds, brake actuator 150 ms total response (116 ms dead time +
   32 ms lag + rate limit; the paper's "about 150 ms"), LSD; full-limit lap 61.3 s.
2. **The planner and the MPCs use the plant's own combined g-g-v envelope** (drive and brake
   exponents fitted per speed inside the quasi-steady double-track envelope) instead of one
   exponent between pure limits, which asked a rear-driven car for drive it could not deliver at
   corner exits (`docs/plant-calibration.md`, "The planner's envelope").
3. **GG mapping**: `limit_fraction` 0.7, so GG 1.43 is 100 % of the limits and the studied range
   crosses them.
4. **Scenario as the paper**: studies 1 and 2 with the point-mass MPC (`pmpc`; ~1.5 s per lap,
   sweeps in worker processes); the rear-grip reduction only in the simulated car
   (`plan_with_nominal_grip=true`); study 1 ends a series only when a tyre begins to lock or spin
   (slip < −50 % or > +30 % for ≥ 0.1 s: `abort.lock_slip_pct=50`, `abort.spin_slip_pct=30`,
   `abort.slip_time=0.1`, all existing keys); there the lateral-error abort is lifted
   (`abort.max_lateral_error=100`, the largest allowed) and |β| > 20°, leaving the track or the
   time-out end a run as a *safety stop*, reported apart from lock and spin;
   3 perturbations per study, a claim holding in ≥ 2 of 3.
5. Not changed: the car's stability parameters, the ESC's yaw reference (the MPCs publish their
   planned a_y; pure pursuit the car node's feedback curvature × v², `motion.esc_target`).
6. **Two actuator models, both scored** (issue 25): the vehicle file's actuators (the real car)
   and the paper's simulator's (`plant.actuators=paper_sim`); every parameter set is run with
   both, side by side.
"""


def update(args):
    """Regenerates report.md after a study script (unless it ran with --no-report)."""
    if getattr(args, "no_report", False):
        return
    main([])


ACT_NAMES = {"vehicle": "real car (vehicle file's actuators)",
             "paper_sim": "paper's simulator (`plant.actuators=paper_sim`)",
             "paper_sim_v1": "paper's simulator as its IV-2024 code "
                             "(`plant.actuators=paper_sim_v1`)"}
ACT_SHORT = {"vehicle": "real car", "paper_sim": "paper's sim", "paper_sim_v1": "paper's sim v1"}
STUDIES = ("study1_longitudinal", "study2_lateral", "study3_motion")


def find_columns(root):
    """[(name, dir, {study: summary})]: experiments/results/columns/<set>__<actuators>/ as
    run_all.sh writes them (shipped set first, vehicle before paper_sim), else the single
    column of studies run directly into experiments/results/."""
    cols = []
    cdir = os.path.join(root, "columns")
    names = sorted(os.listdir(cdir)) if os.path.isdir(cdir) else []
    for n in names:
        d = os.path.join(cdir, n)
        ss = {st: read_summary_in(d, st) for st in STUDIES}
        if any(ss.values()):
            cols.append((n, d, ss))
    if not cols:
        ss = {st: read_summary_in(root, st) for st in STUDIES}
        if any(ss.values()):
            cols.append(("shipped__vehicle", root, ss))

    def order(c):
        info = column_of(c)
        return (info["set_label"] != "shipped", info["set_label"],
                info["actuators"] != "vehicle", info["actuators"])
    return sorted(cols, key=order)


def read_summary_in(d, study):
    path = os.path.join(d, study, "summary.json")
    if not os.path.exists(path):
        return None
    import json
    with open(path) as f:
        s = json.load(f)
    if study in STUDIES and "runs" not in s:
        return None  # an older layout (before issue 14) is ignored
    return s


def column_of(col):
    """{set_label, actuators, stability, ...} of a column (from its summaries)."""
    name, _, ss = col
    for s in ss.values():
        if s and s.get("column"):
            return s["column"]
    label, _, act = name.partition("__")
    return {"set_label": label, "actuators": act or "vehicle", "stability": "?"}


def col_title(col):
    info = column_of(col)
    return f"{info['set_label']} set, {ACT_SHORT.get(info['actuators'], info['actuators'])}"


def prefixed(paths, prefix):
    return [os.path.join(prefix, p) if prefix else p for p in paths]


# ---------------------------------------------------------------------------------------------
# Compact numbers of a claim for the side-by-side table

def claim_cell(key, s):
    """Verdict, 'n of m' and the deciding numbers with activation counts of one claim in one
    column (main perturbation for the numbers)."""
    fn = {"a": claim_a, "b": claim_b, "c": claim_c, "d": claim_d}[key]
    ok, res = evaluate(fn, s["runs"])
    n_ok = sum(1 for o, _ in res.values() if o)
    main_p = s["perturbation"].get("main", next(iter(s["runs"])))
    ser = s["runs"][main_p]
    pl = s["perturbation"]["label"]
    txt = ""
    if key == "a":
        on, off = ser.get("sc_on"), ser.get("sc_off")
        bon, boff = best_run(on), best_run(off)
        d = done_runs(on)
        deciding = [r for r in d if r["gg_scale"] >= abort_gg(off) - EPS]
        txt = (f"{pl} {main_p}: max stable on/off {g(on['max_stable'])}/{g(off['max_stable'])}, "
               f"first abort {g(on['first_abort'])} {on['first_abort_status'] or ''}/"
               f"{g(off['first_abort'])} {off['first_abort_status'] or ''}; best lap "
               f"{t3(bon and bon['mean_lap_time_s'])}/{t3(boff and boff['mean_lap_time_s'])} s; "
               f"ABS/TC active in {sum(1 for r in d if (r['abs_count'] or 0) + (r['tc_count'] or 0) > 0)}"
               f" of {len(d)} completed SC-on runs, in {sum(1 for r in deciding if (r['abs_count'] or 0) + (r['tc_count'] or 0) > 0)}"
               f" of {len(deciding)} deciding")
    elif key == "b":
        na = abort_gg(ser["none"])
        parts = []
        for k in ("esc", "cs", "esc+cs"):
            r = run_at(ser[k], na)
            parts.append(f"{k} {g(ser[k]['first_abort'])}" +
                         (f" ({acts(r)} at {g(na)})" if r else ""))
        txt = (f"{pl} {main_p}: first abort none {g(ser['none']['first_abort'])} "
               f"{ser['none']['first_abort_status'] or ''}; " + ", ".join(parts))
    elif key == "c":
        parts = []
        for k in ("esc", "esc+cs", "none"):
            a = ser[k]
            b = best_run(a)
            above = [r for r in done_runs(a) if b and r["gg_scale"] > b["gg_scale"] + EPS]
            parts.append(f"{k}: best {g(b and b['gg_scale'])}, max stable {g(a['max_stable'])}"
                         + (f", ESC above best {'/'.join(str(int(r['esc_count'] or 0)) for r in above)}"
                            if above else ""))
        txt = f"{pl} {main_p}: " + "; ".join(parts)
    elif key == "d":
        o, items = res[main_p]
        txt = f"{pl} {main_p}: " + "; ".join(t for _, _, t in items[:3]) + \
            f"; ESC/CS/ABS/TC: {items[3][2].split('activations ESC/CS/ABS/TC: ')[-1]}" \
            if len(items) > 3 else f"{pl} {main_p}: " + items[0][2]
    return ok, n_ok, len(res), txt


# ---------------------------------------------------------------------------------------------
# Part 5: the margin of every series

def margin_of(a):
    """(best GG, max stable, first abort, margin in GG, margin in steps of the axis, lap cost
    [s], ESC activations in the completed runs above the best): the margin is the distance
    from the best lap's GG to the last GG completed before the first abort (0: the next step
    after the best lap aborts, a cliff)."""
    b = best_run(a)
    if b is None or a["max_stable"] is None:
        return None
    top = run_at(a, a["max_stable"])
    above = [r for r in done_runs(a) if r["gg_scale"] > b["gg_scale"] + EPS]
    m = a["max_stable"] - b["gg_scale"]
    return {"best": b["gg_scale"], "stable": a["max_stable"], "abort": a["first_abort"],
            "abort_status": a["first_abort_status"], "margin_gg": m, "margin_steps": m / STEP,
            "cost_s": top["mean_lap_time_s"] - b["mean_lap_time_s"],
            "esc_above": [int(r["esc_count"] or 0) for r in above],
            "lap_best": b["mean_lap_time_s"]}


def margin_table(cols):
    out = ["| column | study | perturbation | configuration | best lap (GG) | max stable | first "
           "abort | margin GG (steps of 0.05) | lap at max stable − best | ESC activations "
           "above the best | Δ lap vs `none` at `none`'s max stable |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    zero, total = 0, 0
    for col in cols:
        for st in STUDIES:
            s = col[2].get(st)
            if not s:
                continue
            for p, ser in s["runs"].items():
                for n, a in ser.items():
                    m = margin_of(a)
                    if m is None:
                        continue
                    total += 1
                    zero += m["margin_gg"] < EPS
                    dn = "–"
                    if st == "study2_lateral" and n != "none" and "none" in ser:
                        ns = ser["none"]["max_stable"]
                        r0, r1 = run_at(ser["none"], ns), run_at(a, ns)
                        if ns is not None and r1 and r1["status"] == "completed":
                            dn = (f"{r1['mean_lap_time_s'] - r0['mean_lap_time_s']:+.3f} s at "
                                  f"{g(ns)} (ESC {int(r1['esc_count'] or 0)})")
                    out.append(
                        f"| {col_title(col)} | {st.split('_')[0]} | {p} | {n} | "
                        f"{t3(m['lap_best'])} ({g(m['best'])}) | {g(m['stable'])} | "
                        f"{g(m['abort'])} {m['abort_status'] or ''} | {m['margin_gg']:.3f} "
                        f"({m['margin_steps']:.1f}) | {m['cost_s']:+.3f} s | "
                        f"{'/'.join(map(str, m['esc_above'])) or '–'} | {dn} |")
    return out, zero, total


# ---------------------------------------------------------------------------------------------
# Figures overlaying the parameter sets (one figure per study and actuator model)

SET_STYLES = ["-", "--", ":", "-."]
CONFIG_COLORS = {"sc_on": "tab:blue", "sc_off": "tab:red", "none": "tab:gray", "esc": "tab:red",
                 "cs": "tab:blue", "esc+cs": "tab:purple", "pure_pursuit_off": "tab:blue",
                 "pure_pursuit_sc": "tab:cyan", "pmpc_off": "tab:orange", "pmpc_sc": "tab:brown",
                 "nmpc_off": "tab:green", "nmpc_sc": "tab:olive"}


def overlay_figures(cols, root):
    import studyplot
    out = []
    acts_ = []
    for c in cols:
        a = column_of(c)["actuators"]
        if a not in acts_:
            acts_.append(a)
    top = {"study1_longitudinal": ([("max_slip_front_pct", None, ", front")],
                                   "max front slip [%]", None),
           "study2_lateral": ([("max_abs_sideslip_deg", None, "")], "max |β| [deg]", 20.0),
           "study3_motion": ([("max_abs_sideslip_deg", None, "")], "max |β| [deg]", 20.0)}
    os.makedirs(os.path.join(root, "overlay"), exist_ok=True)
    for st in STUDIES:
        for act in acts_:
            mine = [c for c in cols if column_of(c)["actuators"] == act and c[2].get(st)]
            if not mine:
                continue
            perts = list(mine[0][2][st]["runs"])
            panels, lines = [], []
            for p in perts:
                merged = {}
                for c in mine:
                    lab = column_of(c)["set_label"]
                    for n, a in c[2][st]["runs"].get(p, {}).items():
                        merged[f"{lab}:{n}"] = a
                panels.append((f"{mine[0][2][st]['perturbation']['label']} {p}", merged))
            for i, c in enumerate(mine):
                lab = column_of(c)["set_label"]
                for n, label in c[2][st]["configs"].items():
                    lines.append((f"{lab}:{n}", f"{label} ({lab})", CONFIG_COLORS.get(n, "k"),
                                  SET_STYLES[i % len(SET_STYLES)]))
            path = os.path.join(root, "overlay", f"{st}_{act}.png")
            studyplot.plot_grid(panels, lines, top[st][0], top[st][1], path,
                                f"{st.replace('_', ' ')}, {ACT_NAMES.get(act, act)}: sets "
                                "overlaid (" + ", ".join(
                                    f"{column_of(c)['set_label']} {SET_STYLES[i % 4]}"
                                    for i, c in enumerate(mine)) + ")", hline=top[st][2])
            out.append(os.path.relpath(path, root))
    return out


def method_section(cols):
    info = [column_of(c) for c in cols]
    sets = []
    for x in info:
        if (x["set_label"], x.get("stability")) not in sets:
            sets.append((x["set_label"], x.get("stability")))
    out = ["## Method: GG axis, actuator models, parameter sets", "",
           f"- **GG axis (issue 25 part 6), fixed before any run, the same for every "
           f"configuration, set and actuator model:** {scwexp.GG_AXIS} (start 1.0 = 70 % of the "
           "combined limits, step 0.05); each series stops at its first abort, which is then "
           f"resolved by {info[0].get('refine_levels', scwexp.REFINE_LEVELS) if info else 1} "
           "round(s) of bisection between the last completed GG and the abort (0.025). A "
           "bisected run belongs to its series like any other; the claims' thresholds (0.05 "
           "GG, 0.05 s, …) are those written before the numbers. Where P5 asks what a "
           "configuration did at another series' bisected first abort, the configuration is "
           "run at that GG too (a probe run), unless it aborted below it.",
           "- **Actuator models**: each study is scored twice, with the vehicle file's actuators "
           "(*real car*: brake 116 ms dead time + 32 ms lag + 1800 bar/s, steering 30 ms + 30 ms) "
           "and with `plant.actuators=paper_sim` (*paper's simulator*: Open-Car-Dynamics' "
           "published actuation, no brake-pressure dynamics, steering 60 ms dead time + 60 ms "
           "PT1 at 0.5 rad/s; `docs/plant-calibration.md`), passed as `--set` to every sweep. "
           "The claims maps add the same simulator as its IV-2024 code had it "
           "(`plant.actuators=paper_sim_v1`: brakes 10 ms + PT1 30 ms, steering 50 ms + PT1 "
           "50 ms at 1.0 rad/s), the other published reading of the paper's simulator, and "
           "two readings the paper leaves open: the study-2 rear grip reduction on the whole "
           "tyre curve (`plant.grip_scaling=curve`, as the simulator's friction input multiplies "
           "the tyre force; the vehicle file scales the friction coefficient only) and the "
           "PMPC's commanded instead of planned lateral acceleration as the ESC's target "
           "(`motion.pmpc.esc_target=commanded`).",
           "- **Time per column** (wall, and the CPU time of scw and its workers, which "
           "depends much less on what else the machine runs): " + "; ".join(
               f"{col_title(c)} {sum(x['wall_time_s'] for x in c[2].values() if x) / 60:.1f} "
               f"min wall, {sum(x.get('cpu_time_s') or 0 for x in c[2].values() if x) / 60:.1f}"
               " min CPU" for c in cols) + ".",
           "- **Parameter sets**: " + "; ".join(f"`{lab}` = `{stab}`" for lab, stab in sets) +
           ". The car's shipped set is never changed."]
    for lab, stab in sets:
        # a params file's provenance: <file>.command.txt beside it (how it was made)
        path = os.path.join(scwexp.ROOT, os.path.splitext(stab or "")[0] + ".command.txt")
        if lab != "shipped" and os.path.exists(path):
            with open(path) as f:
                out.append(f"- **How `{lab}` was made** (`{os.path.relpath(path, scwexp.ROOT)}`"
                           "): " + " ".join(f.read().split()))
    out.append("")
    return out


def column_sections(col, prefix):
    """The detailed sections of one column (as the single-column report had them)."""
    name, _, ss = col
    s1, s2, s3 = (ss.get(st) for st in STUDIES)
    title = col_title(col)
    sections = [f"## Details: {title}", ""]
    if s1:
        lab = s1["configs"]
        pl = s1["perturbation"]["label"]
        ok, n, m, blk = claim_block("a", s1["runs"], pl, claim_a)
        sec = [f"### {title} — study 1, longitudinal: slip control on / off "
               f"({s1['controller']}, nominal grip, sensor noise)", "",
               f"{timing(s1)}; main sweep {s1['wall_time_main_s'] / 60:.1f} min. Command: "
               f"`{rel(s1['command'])}`", ""]
        sec += figs(prefixed(s1["figures"], prefix)) + [""]
        sec += series_table(s1["runs"], lab, pl, study1=True) + [""]
        sec += diagnosis(s1, lab, pl)
        sec += [f"#### Claim (a), {title}", ""] + blk + [""]
        if not ok:
            sec += mechanism(s1, ["sc_on", "sc_off"], lab)
        first = next(iter(s1["runs"]))
        sec += [f"Per GG, seed {first}: mean lap or abort · max front/rear slip · ESC/CS/ABS/TC",
                ""] + detail_table(s1["runs"][first], lab, slip_metric, study1=True) + [""]
        sec += sensitivity(s1, lab, pl, [("(a)", claim_a)], slip_metric, study1=True,
                           prefix=prefix)
        sections += sec
    if s2:
        lab = s2["configs"]
        pl = s2["perturbation"]["label"]
        sec = [f"### {title} — study 2, lateral: none / ESC / CS / ESC + CS "
               f"({s2['controller']}, rear μy reduced in the car only)", "",
               f"{timing(s2)}; main sweep {s2['wall_time_main_s'] / 60:.1f} min. Command: "
               f"`{rel(s2['command'])}`", ""]
        sec += figs(prefixed(s2["figures"][:1], prefix)) + [""]
        sec += series_table(s2["runs"], lab, pl) + [""]
        sec += diagnosis(s2, lab, pl)
        for k, fn in (("b", claim_b), ("c", claim_c), ("d", claim_d)):
            ok, n, m, blk = claim_block(k, s2["runs"], pl, fn)
            sec += [f"#### Claim ({k}), {title}", ""] + blk + [""]
            if not ok:
                sec += mechanism(s2, CLAIM_CONFIGS[k], lab)
        main_p = s2["perturbation"].get("main", next(iter(s2["runs"])))
        sec += [f"Per GG, rear μy {main_p}: mean lap or abort · max |β| · ESC/CS/ABS/TC", ""]
        sec += detail_table(s2["runs"][main_p], lab, beta_metric) + [""]
        tr = s2.get("trace_runs", {})
        if tr:
            sec += [f"First lap at GG {g(s2['trace_gg'])}, rear μy {main_p} (the paper's "
                    "time-series figure): " + "; ".join(
                        f"{lab.get(k, k)}: {r['status']}"
                        + (f" at {where(r, CORNERS)}" if r["status"] != "completed" else "")
                        + f", max |β| {r['max_abs_sideslip_deg']:.1f}°, activations {acts(r)}"
                        for k, r in tr.items()), ""]
        sec += figs(prefixed(s2["figures"][1:], prefix)) + [""]
        xt = s2.get("trace_at_none_abort")
        if xt:
            sec += [f"The run at GG {g(xt['gg'])}, where `none` first aborts (rear μy "
                    f"{main_p}): " + "; ".join(
                        f"{lab.get(k, k)}: {r['status']}"
                        + (f" at {where(r, CORNERS)}" if r["status"] != "completed" else "")
                        + f", max |β| {r['max_abs_sideslip_deg']:.1f}°, activations "
                        f"{acts(r)}" for k, r in xt["runs"].items()), ""]
            sec += figs(prefixed([xt["figure"]], prefix)) + [""]
        sec += sensitivity(s2, lab, pl, [("(b)", claim_b), ("(c)", claim_c), ("(d)", claim_d)],
                           beta_metric, prefix=prefix)
        sections += sec
    if s3:
        lab = s3["configs"]
        pl = s3["perturbation"]["label"]
        walls = ", ".join(f"{c} {w / 60:.1f} min" for c, w in
                          s3.get("wall_time_per_controller_s", {}).items())
        sec = [f"### {title} — study 3, motion controllers without / with ESC + CS", "",
               f"{timing(s3)}; main sweeps: {walls}.", ""]
        for ctrl, why in s3.get("skipped", {}).items():
            sec.append(f"- skipped `{ctrl}`: {why}")
        sec += [""] + figs(prefixed(s3["figures"], prefix)) + [""]
        sec += series_table(s3["runs"], lab, pl) + [""]
        done = [c for c in s3["controllers"] if c not in s3.get("skipped", {})]
        for k, fn in (("e", claim_e), ("f", claim_f)):
            sec += [f"#### Claim ({k}) (not scored), {title}", ""]
            for ctrl in done:
                ok, n, m, blk = claim_block(k, s3["runs"], pl, fn, ctrl, scored=False)
                sec += [f"`{ctrl}`:", ""] + blk + [""]
        sec += ["Commands: " + "; ".join(f"`{rel(c)}`" for c in s3["commands"]), ""]
        sec += sensitivity(s3, lab, pl, [(f"({k}) `{c}`", fn, c) for c in done
                                         for k, fn in (("e", claim_e), ("f", claim_f))],
                           beta_metric, prefix=prefix)
        sections += sec
    return sections


def verdict_table(cols):
    """Claims (a)-(d) (scored) and (e)-(f) (not) × columns: verdict, n of m, numbers."""
    out = ["| claim | " + " | ".join(col_title(c) for c in cols) + " |",
           "|---|" + "---|" * len(cols)]
    results = {}
    for key, st in (("a", "study1_longitudinal"), ("b", "study2_lateral"),
                    ("c", "study2_lateral"), ("d", "study2_lateral")):
        cells = []
        for c in cols:
            s = c[2].get(st)
            if not s:
                cells.append("–")
                continue
            ok, n, m, txt = claim_cell(key, s)
            results[(key, c[0])] = ok
            cells.append(f"{verdict(ok)} ({n} of {m}) — {txt}")
        out.append(f"| ({key}) | " + " | ".join(cells) + " |")
    for key, fn in (("e", claim_e), ("f", claim_f)):
        ctrls = []
        for c in cols:
            s3 = c[2].get("study3_motion")
            if s3:
                ctrls += [x for x in s3["controllers"] if x not in s3.get("skipped", {})
                          and x not in ctrls]
        for ctrl in ctrls:
            cells = []
            for c in cols:
                s3 = c[2].get("study3_motion")
                if not s3 or ctrl in s3.get("skipped", {}) or ctrl not in s3["controllers"]:
                    cells.append("–")
                    continue
                ok, res = evaluate(fn, s3["runs"], ctrl)
                n = sum(1 for o, _ in res.values() if o)
                mp = s3["perturbation"].get("main", next(iter(s3["runs"])))
                items = res[mp][1]
                cells.append(f"{verdict(ok, scored=False)} ({n} of {len(res)}) — rear μy {mp}: "
                             + "; ".join(t for _, _, t in items))
            out.append(f"| ({key}) {ctrl}, unscored | " + " | ".join(cells) + " |")
    return out, results


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--publish", metavar="DIR",
                    help="also copy report.md and the figures it links to DIR (same relative "
                         "paths; figures no longer linked are removed)")
    args = ap.parse_args(argv)
    root = scwexp.ROOT_RESULTS
    cols = find_columns(root)
    cmp_ = read_summary_in(root, "compare") or scwexp.read_summary("compare")
    man = scwexp.read_summary("maneuvers")
    for c in cols:
        for s in c[2].values():
            if s and s.get("corners"):
                CORNERS[:] = s["corners"]
                break
        if CORNERS:
            break

    out = ["# Simulation studies: reproduction report", "",
           "Generated by `experiments/report.py` from the studies' `summary.json` files "
           "(`experiments/run_all.sh [PARAMS.yaml ...]` runs everything for the car's shipped "
           "set and each given set, with both actuator models). Yas Marina North, the built-in "
           "EAV24/25 plant, 3 laps per run, each series (one configuration at one perturbation) "
           "reported up to and including its first abort (paper §IV). GG 1.0 is 70 % of the "
           "plant's combined limits, GG 1.43 is 100 %. Places are arc lengths s on the track with "
           "the corner they belong to (`scw track info`; T1 = corner 1, hairpin = corner 5, "
           "chicane = corners 7–8). Activations are counts of interventions, written "
           "ESC/CS/ABS/TC.", "", CHANGES]
    out += method_section(cols)
    out += ["## Claims and their pass criteria", "",
            "Written before the numbers; a claim holds if its criterion holds in at least two "
            "of the three perturbations of its study. A claim whose responsible subsystem did "
            "not act in the runs that decide it is not reproduced, whatever the numbers (P5).",
            ""]
    for k in ("a", "b", "c", "d"):
        out.append(f"- **({k}) {CRITERIA[k][0]}.** Criterion: {CRITERIA[k][1]}")
    out += ["", "Study 3 is also checked against the paper's statements (not among the scored "
            "claims):", ""]
    for k in ("e", "f"):
        out.append(f"- **({k}) {CRITERIA[k][0]}.** Criterion: {CRITERIA[k][1]}")
    out.append("")

    if cols:
        vt, results = verdict_table(cols)
        out += ["## Results: every claim per parameter set and actuator model", "",
                "Verdict (perturbations in which the criterion holds), then the deciding numbers "
                "of the main perturbation with the activation counts (ESC/CS/ABS/TC). Each "
                "column's criteria item by item are in its details section below.", ""]
        out += vt + [""]
        out += goal_section(results, cols)
        out += findings_all(cols)
        figs_ov = overlay_figures(cols, root)
        out += ["## Figures: the sets overlaid", "",
                "One figure per study and actuator model; colour = configuration, line style = "
                "parameter set (legend); top: the study's metric per GG, bottom: mean lap time "
                "(★ best lap, dotted line and reason at the first abort).", ""]
        out += figs(figs_ov) + [""]
        mt, zero, total = margin_table(cols)
        out += ["## Claim (c) as a quantity: the margin of every series", "",
                "Margin = GG from the best lap to the last GG completed before the first abort "
                "(in steps of 0.05; bisected runs give half steps); 0 means the step after the "
                "best lap aborts: the limit is a cliff. Lap cost = the lap at the max stable GG "
                "minus the best lap (what running past the best lap costs, with the ESC "
                "activations of those runs); study 2 also gives each configuration's lap against "
                "`none` at `none`'s max stable GG.", ""]
        out.append(f"Margin 0 in {zero} of {total} series." + (
            " The limit is a cliff everywhere." if total and zero == total else ""))
        out += [""] + cliff_mechanism(cols, total and zero == total)
        out += [""] + mt + [""]
        out += knife_edge_section(cols, root)
        out += claims_map_section(root)
        for c in cols:
            prefix = os.path.relpath(c[1], root)
            prefix = "" if prefix == "." else prefix
            out += column_sections(c, prefix)
    else:
        out += ["## Results", "", "No study results yet.", ""]
    if cmp_:
        out += ["## Comparison of parameter sets", "", f"Wall time {cmp_['wall_time_s']:.0f} s. "
                f"Sets: {', '.join(cmp_['labels'])}. Table: `{cmp_['markdown']}`.", ""]
        out += figs(cmp_["figures"]) + [""]
    if man and man.get("figures"):
        out += ["## Standard maneuvers", "", f"{man['runs']} open-loop maneuver runs "
                f"(experiments/maneuvers.py, SC off and on; sets: {', '.join(man['sets'])}) in "
                f"{man['wall_s']:.0f} s. Tables: `maneuvers/maneuvers.md`.", ""]
        out += [f"![{f}](maneuvers/{f})" for f in man["figures"]] + [""]
    path = os.path.join(root, "report.md")
    os.makedirs(root, exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(path + ".tmp", path)
    print(f"wrote {path}")
    if args.publish:
        publish(path, args.publish)
    return 0


def findings_all(cols):
    out = []
    for c in cols:
        f = findings(*(c[2].get(st) for st in STUDIES))
        if f:
            out += [f"### Findings, {col_title(c)}", ""] + f[2:]
    return ["## Findings per column (computed from all scored runs)", ""] + out if out else []


def claims_maps(root):
    """Every claims map under `root`: the shipped set's (claims_map/) first, then one per other
    set (claims_map_<set>/), each with its folder name under "dir"."""
    names = sorted(d for d in os.listdir(root) if d.startswith("claims_map")) \
        if os.path.isdir(root) else []
    names.sort(key=lambda d: d != "claims_map")
    maps = []
    for d in names:
        cm = read_summary_in(root, d)
        if cm:
            maps.append(dict(cm, dir=d, set_label=cm.get("set_label", "shipped")))
    return maps


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
    xs = [scwexp.to_float(r.get("steer_hf_rms_deg")) for r in runs
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


def steer_hf_text(v):
    x = steer_hf(v)
    return "–" if x is None else f"steering above 1.6 Hz {x:.2f}° RMS"


def from_column(v):
    """(actuator model of the scored column a claims-map variant is nearest to, its changes
    from that column): the paper's simulator's column for a variant that runs its actuators
    (claims_map.nearest_column), else the real-car column (the vehicle file)."""
    if "column_actuators" in v:
        return v["column_actuators"], v.get("column_changes")
    return "vehicle", v.get("changes")


def goal_section(results, cols):
    """Each of (a)-(d): reproduced where (with its credited subsystem acting, P5 being part of
    every criterion), else what the claims maps (one per parameter set) show flips it."""
    maps = claims_maps(scwexp.ROOT_RESULTS)
    out = ["## Where each claim reproduces", ""]
    for k in ("a", "b", "c", "d"):
        yes = [col_title(c) for c in cols if results.get((k, c[0]))]
        line = f"- **({k})**: "
        if yes:
            line += ("reproduced, with its credited subsystem acting (P5 is part of the "
                     "criterion), in: " + ", ".join(yes) + ".")
        else:
            line += "reproduced in no scored column."
            flips, cycling = [], []
            for cm in maps:
                for v in cm.get("variants", []):
                    if v["claims"].get(k, {}).get("ok"):
                        (cycling if limit_cycling(v) else flips).append((cm, v))
            if cycling:
                line += (" It holds with a limit-cycling motion controller only in: " + "; ".join(
                    f"{v['label']} ({cm['set_label']} set; {steer_hf_text(v)})"
                    for cm, v in cycling[:6]) + ": not a model of the paper's PMPC, set aside.")
            if flips:
                # the fewest changes from the nearest scored column first
                flips.sort(key=lambda p: len(from_column(p[1])[1] or [None, None]))
                cm, v = flips[0]
                line += (" The claims maps (one perturbation, everything else as the vehicle "
                         "file) find it holding with: " +
                         "; ".join(f"{x['label']} ({m['set_label']} set)"
                                   for m, x in flips[:8]) + ".")
                act, ch = from_column(v)
                near = [c for c in cols if column_of(c)["set_label"] == cm["set_label"]
                        and column_of(c)["actuators"] == act]
                if ch is not None and len(ch) == 1 and near:
                    line += (f" **The single modelling choice that flips it: {ch[0]}**, one "
                             f"change from the scored column {col_title(near[0])} ("
                             + ("the vehicle file's actuators" if act == "vehicle" else
                                "the paper's simulator's actuators") + "), where it "
                             + ("holds too." if results.get((k, near[0][0])) else "fails."))
                line += (f" The run that shows it, {v['label']}, {cm['set_label']} set: " +
                         "; ".join(f"{n} ({'yes' if o else 'no'}: {t})"
                                   for n, o, t in v["claims"][k]["items"]) +
                         (f" (sweep: `{rel(v['command'])}`)" if v.get("command") else "") +
                         ".")
                if v.get("family") == "GG resolution":
                    # the same runs with the first abort bisected, as the scored columns have it
                    fine = next((x for x in cm.get("variants", [])
                                 if x["label"].startswith("vehicle file (")), None)
                    if fine:
                        line += (" The same runs with the first abort bisected (the scored "
                                 "columns' axis) give: " + "; ".join(
                                     f"{n} ({'yes' if o else 'no'}: {t})"
                                     for n, o, t in fine["claims"][k]["items"] if o is False)
                                 + ". The claim then rests on the resolution: it holds at the "
                                 "axis step and not once the abort is resolved to half a step.")
            elif maps:
                vs = [(cm, x) for cm in maps for x in cm.get("variants", [])
                      if not math.isnan(x["claims"][k].get("margin", math.nan))
                      and not limit_cycling(x)]
                # closest: the largest margin, then the fewest failing criterion items
                best = max(vs, key=lambda p: (p[1]["claims"][k]["margin"],
                                              -len(p[1]["claims"][k]["failed"]))) if vs else None
                line += (f" No variant of the claims map{'s' if len(maps) > 1 else ''} ("
                         + ", ".join(f"{m['set_label']} set" for m in maps)
                         + ") makes it hold either" + (
                             "; the closest" + (
                                 " with a motion controller that does not limit-cycle"
                                 if any(limit_cycling(x) for cm in maps
                                        for x in cm.get("variants", [])) else "")
                             + f" is {best[1]['label']}, {best[0]['set_label']} set "
                             f"(margin {best[1]['claims'][k]['margin']:+.3f}; fails on: "
                             + ", ".join(f"{n} ({t})" for n, o, t in
                                         best[1]["claims"][k]["items"] if o is False)
                             + ")" if best else "")
                         + ".")
            for cm in maps:
                blockers = map_blockers(cm, k)
                if blockers:
                    line += (f" {cm['set_label'].capitalize()} set's map:" if len(maps) > 1
                             else "") + blockers
        out.append(line)
    return out + [""] + esc_margin_section()


def esc_margin_section():
    """Claim (d) needs ESC to act where `none` also completes: how close ESC's activation
    condition came in those runs (experiments/esc_margin.py), if it was run."""
    s = scwexp.read_summary("esc_margin")
    if not s or not s.get("rows"):
        return []
    rows = s["rows"]

    def margins(cfg, at, completed):
        return [scwexp.to_float(r["max_esc_margin"]) for r in rows
                if r["config"] == cfg and r["at"] == at
                and (r["status"] == "completed") == completed]
    kept = margins("none", "judged", True)
    lost = margins("none", "none_abort", False)
    below = sum(m < 1.0 for m in kept)
    gaps = sorted({round(b["gg"] - a["gg"], 6) for a in rows for b in rows
                   if a["column"] == b["column"] and a["at"] == "judged"
                   and b["at"] == "none_abort" and a["config"] == b["config"] == "none"})
    above = [(r["set_label"], r["actuators"]) for r in rows
             if r["config"] == "none" and r["at"] == "judged" and r["status"] == "completed"
             and scwexp.to_float(r["max_esc_margin"]) >= 1.0]
    esc_there = {(r["set_label"], r["actuators"]): int(scwexp.to_float(r["esc_count"]))
                 for r in rows if r["config"] == "esc" and r["at"] == "judged"}
    out = ["### Claim (d): how close ESC comes to acting where it is judged", "",
           "Study 2, rear μy 0.80, every scored column: `none` and ESC only at the GG where (d) "
           "is judged and at `none`'s first abort, with each run's `max_esc_margin` (the "
           "closest approach to ESC's activation condition: the smallest of |β|/B_a, "
           "|e_β,f|/Eβ_a, |e_ψ,f|/Eψ_a while the oversteer signs hold; above 1 the condition "
           "held; computed with ESC off too; `experiments/esc_margin.py`, "
           f"{s.get('wall_time_s', 0) / 60:.1f} min wall" + (
               f"; {len(s['reused'])} of {len(s.get('commands', []))} sweeps read from an "
               "earlier run of the same commands (`--reuse`), their cost not in this time"
               if s.get("reused") else "") + ").", ""] + s["text"] + [""]
    if kept and lost:
        out.append(
            f"In `none`'s completed run at the judged GG the margin peaks at "
            f"{min(kept):.2f}–{max(kept):.2f}, below 1 in {below} of {len(kept)} columns: "
            "there ESC's thresholds are never reached, so ESC cannot cost lap time whatever "
            "its gains" + ("" if not above else "; above 1 in " + ", ".join(
                f"{a} × {b} (ESC only acts {esc_there.get((a, b), 0)}× there)"
                for a, b in above)) + ". In the run `none` loses, "
            + "/".join(f"{x:g}" for x in gaps) + " GG higher, it reaches "
            f"{min(lost):.2f}–{max(lost):.2f}. The band between ESC's activation and the loss "
            "of the car is narrower than one step of the GG axis: the car without lateral "
            "control either stays well inside ESC's thresholds or is lost, so (d)'s premise, "
            "ESC braking in laps that `none` also completes, hardly arises.")
        out.append("")
    out += (esc_margin_terms_text(rows) + esc_margin_finest_text(rows)
            + esc_margin_scan_text(rows) + esc_margin_probe_text(rows)
            + esc_margin_falloff_text(rows))
    return out


FALLOFF_SAME_LAP = 0.001  # s: a lap "the same" for every loss beyond the peak


def lap_change(d, sign=""):
    """A small lap-time change: in ms, or in µs below 0.01 ms."""
    return f"{d * 1e3:{sign}.2f} ms" if abs(d) >= 1e-5 else f"{d * 1e6:{sign}.2g} µs"


def esc_margin_falloff_text(rows):
    """esc_margin.py's falloff probe (rows at falloff_last / falloff_abort with a `falloff`):
    `none` at its last completed GG and its first abort with the rear tyre's loss beyond its
    peak scaled; per column its lap and its end, and a sentence on what makes the limit a cliff.
    Nothing if not run."""
    fo = [r for r in rows if r.get("falloff") is not None
          and r["at"] in ("falloff_last", "falloff_abort")]
    if not fo:
        return []
    cols = []
    for r in fo:
        if r["column"] not in cols:
            cols.append(r["column"])
    values = sorted({r["falloff"] for r in fo})
    others = [v for v in values if v != 1.0]
    lines = ["| column | `none`'s last completed GG | lap, loss beyond the peak × 1 | "
             + " | ".join(f"× {v:g}: Δ lap" for v in others) + " | first abort GG | "
             + " | ".join(f"× {v:g}" for v in values) + " | ESC/CS/ABS/TC "
             + " · ".join(f"×{v:g}" for v in values) + ": last GG | at the abort |",
             "|---|---|---|" + "---|" * len(others) + "---|" + "---|" * len(values) + "---|---|"]
    same, kept, lost_all, n = 0, 0, 0, 0
    worst = 0.0
    for c in cols:
        at = {(r["at"], r["falloff"]): r for r in fo if r["column"] == c}
        base = at.get(("falloff_last", 1.0))
        if base is None:
            continue
        n += 1
        deltas, texts = [], []
        for v in others:
            x = at.get(("falloff_last", v))
            if x is None or x["status"] != "completed" or base["status"] != "completed":
                texts.append(x["status"] if x else "–")
                continue
            d = scwexp.to_float(x["mean_lap_time_s"]) - scwexp.to_float(base["mean_lap_time_s"])
            deltas.append((d, x["mean_lap_time_s"] == base["mean_lap_time_s"]))
            texts.append("identical" if deltas[-1][1] else lap_change(d, "+"))
        if base["status"] == "completed" and len(deltas) == len(others) \
                and all(abs(d) <= FALLOFF_SAME_LAP for d, _ in deltas):
            kept += 1
            same += all(i for _, i in deltas)
            worst = max([worst] + [abs(d) for d, _ in deltas])
        ends = [at.get(("falloff_abort", v)) for v in values]
        lost_all += all(e is not None and e["status"] != "completed" for e in ends)
        lines.append(f"| {base['set_label']}, {base['actuators']} | {g(base['gg'])} | "
                     + (f"{scwexp.to_float(base['mean_lap_time_s']):.3f} s"
                        if base["status"] == "completed" else base["status"]) + " | "
                     + " | ".join(texts) + f" | {g(ends[0]['gg']) if ends[0] else '–'} | "
                     + " | ".join(e["status"] if e else "–" for e in ends) + " | "
                     + " · ".join(acts(x) if x else "–"
                                  for x in (at.get(("falloff_last", v)) for v in values))
                     + " | " + " · ".join(acts(e) if e else "–" for e in ends) + " |")
    if not n:
        return []
    text = (f"The rear tyre's force beyond its peak (`plant.rear_tire_falloff` "
            f"{' / '.join(f'×{v:g}' for v in values)} of the vehicle file's loss, the curve up "
            "to the peak unchanged; `experiments/esc_margin.py --falloff-probe`), `none` at its "
            "last completed GG and at its first abort: ")
    if kept:
        text += (f"its completed lap is the same for every value in {kept} of {n} columns ("
                 f"bit for bit in {same}, otherwise within {lap_change(worst)})")
    else:
        text += (f"its lap is not the same (within {FALLOFF_SAME_LAP * 1e3:g} ms) for every "
                 "value in any column")
    text += (f", and it is lost at its first abort for every value in {lost_all} of {n}. ")
    if kept == n and lost_all == n:
        text += ("In a lap `none` completes the rear never slides past its peak, and holding "
                 "the peak force (×0) does not save the car one step higher: the cliff is where "
                 "the planner's lateral demand meets the rear's peak force, not the force it "
                 "loses beyond it.")
    else:
        text += ("Where the lap or the end changes, the force beyond the peak takes part in "
                 "the limit.")
    return lines + ["", text, ""]


def esc_margin_terms_text(rows):
    """Which term of ESC's activation condition kept it off in `none`'s completed runs at the
    judged GG (esc_margin.py's term columns), as a sentence, or nothing without them."""
    kept = [r for r in rows if r["config"] == "none" and r["at"] == "judged"
            and r["status"] == "completed" and scwexp.esc_terms_text(r)]
    if not kept:
        return []
    counts = {}
    for r in kept:
        for n in scwexp.esc_binding_terms(r):
            counts[n] = counts.get(n, 0) + 1
    peaks = {n: [scwexp.to_float(r[k]) for r in kept]
             for n, k in zip(scwexp.ESC_TERM_NAMES, scwexp.ESC_TERMS)}
    told = "; ".join(f"{n} below 1 in {counts.get(n, 0)} of {len(kept)}, peaks "
                     f"{min(v):.2f}–{max(v):.2f}" for n, v in peaks.items())
    return [f"Which condition keeps ESC off in those completed runs (each term at its largest "
            f"while the oversteer signs held; below 1, it alone forbids activation): {told}. "
            "|β| = the sideslip, e_β = its excess over ESC's single-track sideslip reference "
            "(`tire_stiffness_rear`), e_ψ = the yaw-rate excess over the motion controller's "
            "a_y request / v.", ""]


def esc_margin_finest_text(rows):
    """`none`'s first abort bisected to esc_margin.py's resolution: the margin at the last GG
    `none` completes and what ESC did there, as a sentence, or nothing if not run."""
    fin = [r for r in rows if r["at"] == "finest"]
    if not fin:
        return []
    none = [r for r in fin if r["config"] == "none" and r["status"] == "completed"]
    esc = [r for r in fin if r["config"] == "esc"]
    if not none:
        return []
    m = [scwexp.to_float(r["max_esc_margin"]) for r in none]
    gaps = sorted({round(r["first_abort_fine"] - r["gg"], 6) for r in none
                   if r.get("first_abort_fine") is not None})
    acts = [int(scwexp.to_float(r["esc_count"])) for r in esc if r["status"] == "completed"]
    lap = {r["column"]: scwexp.to_float(r["mean_lap_time_s"]) for r in none}
    deltas = [scwexp.to_float(r["mean_lap_time_s"]) - lap[r["column"]] for r in esc
              if r["status"] == "completed" and r["column"] in lap]
    lo, hi = CLAIM_D_COST
    opens = [r["column"] for r in esc if r["status"] == "completed" and r["column"] in lap
             and int(scwexp.to_float(r["esc_count"])) > 0
             and lo <= scwexp.to_float(r["mean_lap_time_s"]) - lap[r["column"]] <= hi]
    return [f"With `none`'s first abort bisected to {'/'.join(f'{g:g}' for g in gaps)} GG, at "
            f"the last GG it completes its margin peaks at {min(m):.2f}–{max(m):.2f} (below 1 "
            f"in {sum(x < 1 for x in m)} of {len(m)} columns); ESC only completes there in "
            f"{len(acts)} of {len(esc)} columns and acts in {sum(a > 0 for a in acts)} of them"
            + (f" (Δ(ESC) {min(deltas):+.3f} to {max(deltas):+.3f} s)" if deltas else "")
            + (". A finer GG axis does not open the band (d) needs: nowhere does ESC act there "
               f"and cost {lo:g}–{hi:g} s." if not opens else
               f". There ESC acts and costs {lo:g}–{hi:g} s in: {', '.join(opens)} (the other "
               "parts of (d) are not judged at this GG)."), ""]


def esc_margin_scan_text(rows):
    """esc_margin.py's grid across `none`'s first abort (rows tagged scan0, scan1, …): per
    column, where `none` completes, whether the loss is monotone in GG, and what ESC alone costs
    in the laps `none` completes while ESC acts; a table and a sentence, or nothing if not run."""
    scan = [r for r in rows if str(r["at"]).startswith("scan")]
    if not scan:
        return []
    lo, hi = CLAIM_D_COST
    cols = []
    for r in scan:
        if r["column"] not in cols:
            cols.append(r["column"])
    lines = ["| column | GGs scanned | `none` completes | loss monotone in GG | ESC acts in a lap "
             "`none` completes | Δ(ESC) there [s] | of them in "
             f"{lo:g}–{hi:g} s |", "|---|---|---|---|---|---|---|"]
    all_d, n_acts, n_ok, nonmono = [], 0, 0, []
    for c in cols:
        rs = [r for r in scan if r["column"] == c]
        none = {r["gg"]: r for r in rs if r["config"] == "none"}
        esc = {r["gg"]: r for r in rs if r["config"] == "esc"}
        ggs = sorted(none)
        done = [g for g in ggs if none[g]["status"] == "completed"]
        lost = [g for g in ggs if none[g]["status"] != "completed"]
        mono = not (done and lost and min(lost) < max(done))
        deltas = []
        for g in done:
            e = esc.get(g)
            if e and e["status"] == "completed" and scwexp.to_float(e["esc_count"]) > 0:
                deltas.append((g, scwexp.to_float(e["mean_lap_time_s"])
                               - scwexp.to_float(none[g]["mean_lap_time_s"])))
        inside = [d for _, d in deltas if lo <= d <= hi]
        all_d += [d for _, d in deltas]
        n_acts += len(deltas)
        n_ok += len(done)
        if not mono:
            nonmono.append(c)
        r0 = rs[0]
        below = ", ".join(f"{g:.4f}" for g in lost if not mono and g < max(done))
        lines.append(
            f"| {r0['set_label']}, {r0['actuators']} | {scwexp.fmt(ggs[0], 4)}–"
            f"{scwexp.fmt(ggs[-1], 4)} ({len(ggs)}) | {len(done)} of {len(ggs)} | "
            + ("yes" if mono else f"no: lost at {below} below completed {max(done):.4f}")
            + f" | {len(deltas)} | "
            + (", ".join(f"{d:+.3f} ({g:.4f})" for g, d in deltas) if deltas else "–")
            + f" | {len(inside)} |")
    step = set()
    for c in cols:
        g = sorted(r["gg"] for r in scan if r["column"] == c and r["config"] == "none")
        step |= {round(b - a, 6) for a, b in zip(g, g[1:])}
    step = sorted(step)
    text = (f"On a grid of {'/'.join(f'{x:g}' for x in step)} GG between `none`'s last "
            f"completed GG and its first abort (`none` and ESC only, {len(cols)} columns): "
            f"`none` completes {n_ok} of the {sum(1 for r in scan if r['config'] == 'none')} "
            "runs; "
            + (f"its loss is not monotone in GG in {len(nonmono)} of {len(cols)} columns (a GG "
               "lost below a completed one: at this scale the edge is chaotic, so a bisection "
               "finds an edge, not the edge)" if nonmono else
               "on this grid its loss is monotone in GG in every column")
            + f". ESC acts in {n_acts} laps that `none` completes at "
            "the same GG" + (f", where it changes the lap by {min(all_d):+.3f} to "
                             f"{max(all_d):+.3f} s" if all_d else "")
            + (f"; {sum(lo <= d <= hi for d in all_d)} of them in (d)'s {lo:g}–{hi:g} s"
               if all_d else "") + ".")
    return lines + ["", text, ""]


def esc_margin_probe_text(rows):
    """esc_margin.py's threshold probe (rows with a `factor`): claim (d)'s criterion at the
    judged GG with ESC's sideslip-error thresholds scaled in the column's own set, per column and
    factor; a table and a sentence, or nothing if not run. A diagnostic: no set is changed."""
    probe = [r for r in rows if r.get("factor") is not None]
    if not probe:
        return []
    keys = []
    for r in probe:
        if (r["column"], r["factor"]) not in keys:
            keys.append((r["column"], r["factor"]))
    lines = ["| column | Eβ thresholds × | GG | ESC only: ESC ×, Δ(ESC) | ESC + CS: ESC ×, "
             "Δ(ESC + CS) | (d)'s criterion |", "|---|---|---|---|---|---|"]
    held, acted, deltas = [], 0, []
    for col, f in keys:
        ser = {}
        for r in probe:
            if r["column"] == col and r["factor"] == f:
                run = {k: scwexp.to_float(r.get(k)) for k in
                       ("mean_lap_time_s",) + scwexp.ACTIVATION_KEYS}
                ser[r["config"]] = {"runs": [dict(run, gg_scale=r["gg"], status=r["status"])]}
        r0 = next(r for r in probe if r["column"] == col)
        if any(c not in ser for c in ("none", "esc", "cs", "esc+cs")):
            continue
        ok, items = claim_d(ser)
        runs = {c: ser[c]["runs"][0] for c in ser}

        def cell(c):
            x = runs[c]
            if x["status"] != "completed" or runs["none"]["status"] != "completed":
                return x["status"]
            return (f"{int(x['esc_count'] or 0)}×, "
                    f"{x['mean_lap_time_s'] - runs['none']['mean_lap_time_s']:+.3f} s")
        if runs["esc"]["status"] == "completed" and (runs["esc"]["esc_count"] or 0) > 0 \
                and runs["none"]["status"] == "completed":
            acted += 1
            deltas.append(runs["esc"]["mean_lap_time_s"] - runs["none"]["mean_lap_time_s"])
        if ok:
            held.append(f"{r0['set_label']} × {r0['actuators']} ×{f:g}")
        failed = [n for n, k, _ in items if not k]
        lines.append(f"| {r0['set_label']}, {r0['actuators']} | {f:g} | {g(r0['gg'])} | "
                     f"{cell('esc')} | {cell('esc+cs')} | "
                     + ("**holds**" if ok else "fails on: " + "; ".join(failed)) + " |")
    lo, hi = CLAIM_D_COST
    text = ("A diagnostic, not a change to any set: ESC's sideslip-error thresholds (activate "
            "and deactivate) scaled in each column's own set "
            f"({'/'.join(sorted({f'×{f:g}' for _, f in keys}, reverse=True))}), all four "
            "configurations at the GG where (d) is judged (`experiments/esc_margin.py "
            f"--threshold-probe`). In {acted} of {len(keys)} probes (column × factor) ESC only "
            "then acts in a lap `none` completes" + (f", changing it by {min(deltas):+.3f} to "
                                  f"{max(deltas):+.3f} s" if deltas else "")
            + f"; (d)'s criterion holds in {len(held)} of {len(keys)}"
            + (f": {', '.join(held)}." if held else
               (f". Acting is not enough: where ESC acts in a lap `none` completes it costs "
                f"less than {lo:g} s, so lowering its thresholds does not flip (d) either."
                if deltas and max(deltas) < lo else ".")))
    return lines + ["", text, ""]


def step_gains(vs):
    """Claim (b) asks each of ESC, CS and ESC + CS to abort at least one step (0.05) above
    `none`: in which variants ESC alone and CS alone each gain that step, and in how many both
    do."""
    gains = {"esc": [], "cs": []}
    both = 0
    for v in vs:
        s = v["series"]
        fa = {c: (s.get(c) or {}).get("first_abort") for c in ("none", "esc", "cs")}
        if any(x is None for x in fa.values()):
            continue
        ok = {c: fa[c] - fa["none"] >= STEP - EPS for c in gains}
        for c in gains:
            if ok[c]:
                gains[c].append(f"{v['label']} (+{fa[c] - fa['none']:.3f})")
        both += ok["esc"] and ok["cs"]

    def listed(c):
        return f"{len(gains[c])} ({'; '.join(gains[c])})" if gains[c] else "none"
    return (f" A full step over `none` is gained by ESC alone in {listed('esc')}, by CS alone in "
            f"{listed('cs')}; by both in {both}.")


def map_blockers(cm, k):
    """What keeps claim k from holding over the whole claims map: how often each criterion item
    fails, and for study 2 how ESC alone ends at `none`'s first-abort GG (a spin caught but the
    line lost is a lateral error, not a sideslip)."""
    vs = cm.get("variants", [])
    if not vs:
        return ""
    count = {}
    for v in vs:
        for n, o, _ in v["claims"][k]["items"]:
            if o is False:
                count[n] = count.get(n, 0) + 1
    if not count:
        return ""
    parts = [f"{n} fails in {c} of {len(vs)}" for n, c in
             sorted(count.items(), key=lambda x: -x[1])[:3]]
    text = f" Over the {len(vs)} variants of the map: " + "; ".join(parts) + "."
    if k in ("b", "c"):
        ends, where_s = {}, []
        for v in vs:
            esc, none = v["series"].get("esc"), v["series"].get("none")
            if not esc or not none:
                continue
            r = run_at(esc, abort_gg(none))
            st = r["status"] if r else "no run"
            ends[st] = ends.get(st, 0) + 1
            if st == "lateral_error" and r.get("end_s_m") is not None:
                where_s.append(r["end_s_m"])
        text += (" ESC alone at `none`'s first-abort GG: " + ", ".join(
            f"{status_text(st)} in {c}" for st, c in sorted(ends.items(), key=lambda x: -x[1])))
        if where_s:
            text += (f" (the lateral errors at s = {min(where_s):.0f}–{max(where_s):.0f} m: "
                     "the run ends on the 3 m line-error limit, not on |β| > 20°)")
        text += "."
    if k == "b":
        text += step_gains(vs)
    if k == "c":
        both = [v["label"] for v in vs if all(
            o for n, o, _ in v["claims"]["c"]["items"] if n.startswith("`esc+cs`"))]
        text += (f" The ESC + CS half of the criterion holds in {len(both)} of {len(vs)}" +
                 (f" ({'; '.join(both[:6])})" if both else "") + ".")
    if k == "d":
        acted = sum(1 for v in vs for n, o, _ in v["claims"]["d"]["items"]
                    if n.startswith("ESC active") and o)
        prem = d_premise_runs(vs)
        text += (f" ESC acts at the highest GG all four configurations complete in {acted} of "
                 f"{len(vs)} variants" + (
                     ": it intervenes only in runs that would otherwise be lost, so it costs no "
                     "lap time where `none` also finishes." if not acted and not prem else "."))
        text += none_margin_band(vs) + d_premise_text(prem)
    return text


def none_edge_margins(series):
    """`none`'s ESC activation margin (max_esc_margin: > 1, ESC's condition held, computed with
    ESC off) in its run at the last GG it completes and in its first abort; None where a run or
    the column is missing (a summary written before the margin was kept)."""
    runs = series.get("runs", [])
    fa = series.get("first_abort")
    done = [r for r in runs if r["status"] == "completed" and (fa is None or r["gg_scale"] < fa)]
    lost = next((r for r in runs if fa is not None and abs(r["gg_scale"] - fa) < EPS), None)

    def m(r):
        x = r and r.get("max_esc_margin")
        return float(x) if x is not None and float(x) == float(x) else None
    return (m(max(done, key=lambda r: r["gg_scale"])) if done else None), m(lost)


def none_margin_band(vs):
    """Claim (d)'s premise over a whole map: whether `none` ever meets ESC's activation
    condition in a lap it completes (the band (d) needs), from its runs at the edge."""
    pairs = [(cycling_label(v), *none_edge_margins(v["series"]["none"])) for v in vs
             if v["series"].get("none")]
    done = [(n, a) for n, a, _ in pairs if a is not None]
    lost = [b for _, _, b in pairs if b is not None]
    if not done or not lost:
        return ""
    met = [n for n, a in done if a >= 1]
    text = (f" `none`'s closest approach to ESC's activation condition (margin, > 1: it held) "
            f"at its last completed GG is {min(a for _, a in done):.2f}–"
            f"{max(a for _, a in done):.2f}, ≥ 1 in {len(met)} of {len(done)} variants"
            + (f" ({'; '.join(met[:6])})" if met else "") + "; in its first abort "
            f"{min(lost):.2f}–{max(lost):.2f}, ≥ 1 in {sum(1 for b in lost if b >= 1)} of "
            f"{len(lost)}.")
    if not met and all(b >= 1 for b in lost):
        text += (" Whatever the single choice, ESC's thresholds are met only where the car "
                 "without lateral control is lost, never in a lap it completes.")
    return text


def d_premise_runs(vs):
    """Claim (d)'s premise at any GG of a map, not only where (d) is judged: every run in which
    ESC only acts (≥ 1 activation) and completes a lap `none` completes at the same GG, as
    (variant label, GG, Δ(ESC), Δ(ESC + CS) or None when ESC + CS did not complete, ESC's
    activations in ESC only and in ESC + CS, whether the variant's motion controller
    limit-cycles)."""
    out = []
    for v in vs:
        ser = v["series"]
        if not all(ser.get(n) for n in ("none", "esc", "esc+cs")):
            continue
        for r in done_runs(ser["esc"]):
            n = run_at(ser["none"], r["gg_scale"])
            if not r["esc_count"] or not n or n["status"] != "completed":
                continue
            b = run_at(ser["esc+cs"], r["gg_scale"])
            both = b is not None and b["status"] == "completed"
            out.append((v["label"], r["gg_scale"], r["mean_lap_time_s"] - n["mean_lap_time_s"],
                        b["mean_lap_time_s"] - n["mean_lap_time_s"] if both else None,
                        int(r["esc_count"]), int(b["esc_count"]) if both else 0,
                        limit_cycling(v)))
    return out


def d_premise_text(prem):
    """What ESC costs wherever (d)'s premise holds (d_premise_runs): the lap-time pattern of the
    paper (Δ(ESC) in 0.05-0.40 s, ESC + CS less, ESC acting in both) counted at every such GG,
    a diagnostic beside the criterion, which judges one GG."""
    if not prem:
        return ""
    lo, hi = CLAIM_D_COST
    d = sorted(x[2] for x in prem)
    inside = sum(1 for x in d if lo <= x <= hi)
    pattern = [x for x in prem if lo <= x[2] <= hi and x[3] is not None
               and 0 <= x[3] < x[2] and x[5] > 0]
    nv = len({x[0] for x in prem})
    cyc = [x for x in prem if x[6]]
    return (f" Wherever ESC only acts in a lap `none` completes at the same GG ({len(prem)} "
            f"run{'s' * (len(prem) != 1)} in {nv} variant{'s' * (nv != 1)}, any GG of the axis), "
            "Δ(ESC) is "
            f"{d[0]:+.3f} to {d[-1]:+.3f} s (median {d[len(d) // 2]:+.3f}), in 0.05–0.40 s in "
            f"{inside}, below 0 in {sum(1 for x in d if x < 0)}; the paper's pattern (Δ(ESC) "
            "in 0.05–0.40 s and 0 ≤ Δ(ESC + CS) < Δ(ESC), ESC acting in both) appears at "
            f"{len(pattern)} of them" + (" (" + "; ".join(
                f"{x[0]} at GG {g(x[1])}: {x[2]:+.3f}/{x[3]:+.3f} s, ESC {x[4]}×/{x[5]}×"
                for x in pattern[:4]) + ")" if pattern else "") + "." + (
                f" {len(cyc)} of the {len(prem)} runs ({sum(1 for x in pattern if x[6])} of "
                f"the pattern's) are of variants whose motion controller limit-cycles "
                f"(`none`'s steering above 1.6 Hz ≥ {STEER_LIMIT_CYCLE_DEG}° RMS): ESC's "
                "activations there follow the oscillation, not an excursion `none` recovers "
                "from." if cyc else ""))


def cliff_mechanism(cols, everywhere):
    """What makes the limit a cliff, from the knife-edge numbers of each column: how long the
    car takes from rear saturation to the loss, against the brake response, and whether ESC's
    pressure reached a wheel in that time."""
    parts = []
    for c in cols:
        s2 = c[2].get("study2_lateral")
        ke = s2 and s2.get("knife_edge")
        if not ke:
            continue
        lost = {n: x for n, x in ke["results"].items() if x and x["spun"] and x["saturated"]}
        if not lost:
            continue
        w = [x["window_s"] for x in lost.values()]
        esc = [n for n in ("esc", "esc+cs") if n in lost]
        arr = [n for n in esc if lost[n]["t_delivered"] is not None and
               lost[n]["t_delivered"] < lost[n]["t20"]]
        parts.append(f"{col_title(c)} (GG {g(ke['gg'])}): {min(w):.2f}–{max(w):.2f} s from rear "
                     f"saturation to the loss in {len(lost)} configuration(s), brake response "
                     f"{ke['t_act'] * 1000:.0f} ms; ESC's pressure reached a wheel before the "
                     f"loss in {len(arr)} of {len(esc)} lost ESC runs")
    if not parts:
        return []
    return ["Mechanism (knife-edge traces below): once the rear axle passes its peak slip angle "
            "at the abort GG, the car is lost within a few tenths of a second — " +
            "; ".join(parts) + "." + (" No series has an intermediate regime in which "
                                     "interventions slow the car without losing it."
                                     if everywhere else ""), ""]


def knife_edge_section(cols, root):
    """Part 3: the traced first lap at the GG where `none` first aborts (study 2), per
    column, from knife_edge.json written by study2_lateral.py."""
    out = []
    for c in cols:
        s2 = c[2].get("study2_lateral")
        ke = s2 and s2.get("knife_edge")
        if not ke:
            continue
        import knife_edge
        res = knife_edge.with_statuses(s2)
        lines = [knife_edge.describe(n, s2["configs"].get(n, n), res.get(n), CORNERS,
                                     (res.get(n) or {}).get("status")) for n in s2["configs"]]
        lines.append(knife_edge.verdict_line(res, ACT_SHORT.get(column_of(c)["actuators"])))
        out += [f"### {col_title(c)}: GG {g(ke['gg'])}, rear μy {ke['mu']}", ""]
        out += [f"- {x}" for x in lines] + [""]
    if out:
        out = ["## The mechanism at the knife edge (study 2)", "",
               "At the first GG where `none` aborts (main rear μy), the whole run of each "
               "configuration traced (`scw sweep --trace-dir`; `experiments/knife_edge.py`). "
               "The loss = |β| = 20°, or the run's abort when that comes first (lateral error, "
               "off track); rear saturation t_sat = the time from which the rear axle's mean "
               "slip angle stays beyond the rear tyre's peak slip angle (Magic Formula, nominal "
               "load) until the loss; ESC's brake moment arrives when a wheel's applied pressure "
               "first exceeds both its value when ESC switched on and the motion controller's "
               "request by 10 bar; the bound is the constant yaw moment that removes the largest "
               "yaw-rate excess Δr in the time left after the brake actuator's response: "
               "M ≥ Iz · Δr / (t_loss − t_sat − t_act).", ""] + out
    return out


def claims_map_section(root):
    out = []
    for cm in claims_maps(root):
        title = "## Claims map: what decides each claim (issue 25 part 2)" \
            if cm["dir"] == "claims_map" else \
            f"## Claims map with the {cm['set_label']} set"
        out += [title, "", cm.get("text", ""), "", f"Wall time {cm['wall_time_s'] / 60:.1f} min, "
                f"CPU {cm.get('cpu_time_s', 0) / 60:.1f} min; sweeps: "
                f"{len(cm.get('commands', []))}"
                + (f", of which {len(cm['reused'])} read from an earlier run of the same commands "
                   "(`--reuse`; their cost is not in these times: experiments/README.md)"
                   if cm.get("reused") else "") + ".", ""]
        out += figs([os.path.join(cm["dir"], x) for x in cm.get("figures", [])]) + [""]
        out += cm.get("table", []) + [""]
    return out


def sensitivity(s, labels, pert_label, claims, metric, study1=False, prefix=""):
    sens = s.get("sensitivity", {})
    if not sens:
        return []
    out = ["### Sensitivity (unscored)", ""]
    for tag, v in sens.items():
        out += [f"**{v['label']}** — wall time {v['wall_time_s'] / 60:.1f} min. Command: "
                f"`{rel(v['command'])}`", ""]
        out += figs(prefixed(v["figures"], prefix)) + [""]
        out += series_table(v["runs"], labels, pert_label, study1) + [""]
        for label, fn, *extra in claims:
            if extra and not any(n.startswith(f"{extra[0]}_") for ser in v["runs"].values()
                                 for n in ser):
                continue  # this variant did not run that controller
            ok, res = evaluate(fn, v["runs"], *extra)
            failed = [f"{p}: " + "; ".join(f"{name} ({text})" for name, iok, text in items
                                           if iok is False)
                      for p, (o, items) in res.items() if not o]
            out.append(f"- claim {label} under this variant: {verdict(ok, scored=False)}" +
                       (f" — failed: {' | '.join(failed)}" if failed else ""))
        first = next(iter(v["runs"]))
        out += ["", f"Per GG ({pert_label} {first}): mean lap or abort · metric · ESC/CS/ABS/TC",
                ""] + detail_table(v["runs"][first], labels, metric, study1) + [""]
    return out


def publish(report_path, dest):
    """Copies the report and the figures it links into dest, keeping their paths relative to
    the report (so the links work unchanged); figures no longer linked are removed."""
    os.makedirs(dest, exist_ok=True)
    with open(report_path) as f:
        text = f.read()
    linked = set(re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text))
    for rel_path in linked:
        src = os.path.join(os.path.dirname(report_path), rel_path)
        dst = os.path.join(dest, rel_path)
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        shutil.copyfile(src, dst)
    for root, _, files in os.walk(dest):
        for name in files:
            rel_path = os.path.relpath(os.path.join(root, name), dest)
            if name.endswith(".png") and rel_path not in linked:
                os.remove(os.path.join(root, name))
    with open(os.path.join(dest, "report.md"), "w") as f:
        f.write(text)
    print(f"published {dest}/report.md")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
