#!/usr/bin/env python3
"""Builds experiments/results/report.md from the studies' summary.json files: the figures, the
key numbers per configuration and, for each qualitative claim of the paper (§V-A), whether our
run reproduces it, with the numbers. A claim that is not reproduced is reported as such.

    python3 experiments/report.py     (after the studies; each study also calls it)
"""

import os
import sys

import scwexp


def series_table(summary, value_name="GG"):
    lines = [f"| configuration | max stable {value_name} | first abort (reason) | "
             f"min mean lap [s] at {value_name} |", "|---|---|---|---|"]
    for name, a in summary["series"].items():
        abort = (f"{a['first_abort']:g} ({a['first_abort_status']})"
                 if a["first_abort"] is not None else "none in range")
        stable = f"{a['max_stable']:g}" if a["max_stable"] is not None else "–"
        best = (f"{a['min_lap_time_s']:.3f} at {a['min_lap_value']:g}"
                if a["min_lap_value"] is not None else "–")
        lines.append(f"| {a.get('label', name)} (`{name}`) | {stable} | {abort} | {best} |")
    return "\n".join(lines)


def verdict(ok):
    if ok is None:
        return "**not evaluable**"
    return "**reproduced**" if ok else "**NOT reproduced**"


def stable(a):
    """Max stable GG; a series without any completed run counts as below every value."""
    return a["max_stable"] if a["max_stable"] is not None else -1.0


def claim_a(s1):
    on, off = s1["series"].get("sc_on"), s1["series"].get("sc_off")
    if not on or not off:
        return None, "study 1 missing a configuration"
    ok = stable(on) > stable(off)
    text = (f"max stable GG with slip control {on['max_stable']} (first abort at "
            f"{on['first_abort']}: {on['first_abort_status']}), without {off['max_stable']} "
            f"(first abort at {off['first_abort']}: {off['first_abort_status']}); minimum mean "
            f"lap {scwexp.fmt(on['min_lap_time_s'], 3)} s with vs "
            f"{scwexp.fmt(off['min_lap_time_s'], 3)} s without.")
    if on["first_abort"] is None:
        text += " (The slip-control series did not abort within the GG range: widen --gg.)"
    return ok, text


def claim_b(s2):
    ser = s2["series"]
    if "none" not in ser or len(ser) < 2:
        return None, "study 2 missing configurations"
    none = ser["none"]
    others = {k: v for k, v in ser.items() if k != "none"}
    lowest = all(stable(none) < stable(v) for v in others.values())
    spins = none["first_abort_status"] in scwexp.SPIN_STATUSES
    text = (f"`none` is stable up to GG {none['max_stable']} and aborts at "
            f"{none['first_abort']} ({none['first_abort_status']}); " +
            ", ".join(f"`{k}` up to {v['max_stable']} (abort at {v['first_abort']}: "
                      f"{v['first_abort_status']})" for k, v in others.items()) + ".")
    tr = s2.get("trace_runs", {})
    if tr:
        text += (f" First lap at GG {s2.get('trace_gg')}: " +
                 ", ".join(f"`{k}` {v['status']} (progress {v['progress']:.2f}, max |β| "
                           f"{v['max_abs_sideslip_deg']:.1f}°)" for k, v in tr.items()) + ".")
    if not lowest:
        text += (" The configuration without lateral stability control does not have the "
                 "strictly lowest stable scaling.")
    return lowest and spins, text


def claim_c(s2):
    parts, oks = [], []
    for name in ("esc", "esc+cs", "none", "cs"):
        a = s2["series"].get(name)
        if not a:
            continue
        if a["min_lap_value"] is None:
            parts.append(f"`{name}`: no completed run")
            if name in ("esc", "esc+cs"):
                oks.append(False)
            continue
        below = a["min_lap_value"] < a["max_stable"]
        parts.append(f"`{name}`: min lap at GG {a['min_lap_value']:g}, max stable "
                     f"{a['max_stable']:g} ({'below' if below else 'coincide'})")
        if name in ("esc", "esc+cs"):
            oks.append(below)
    if not oks:
        return None, "study 2 lacks the ESC configurations"
    return all(oks), "; ".join(parts) + ". (Paper: below for ESC and ESC + CS, coincide for " \
        "none and CS only.)"


def claim_d(s2):
    at = s2.get("gg1.3", {})
    need = ("none", "esc", "esc+cs")
    if any(at.get(k) is None for k in need):
        missing = [k for k in need if at.get(k) is None]
        return None, (f"GG 1.3 was not reported for {', '.join(missing)} (the series stopped "
                      f"earlier or 1.3 is not on the GG grid)")
    bad = [k for k in need if at[k]["status"] != "completed"]
    if bad:
        return None, ("at GG 1.3 " + ", ".join(f"`{k}` {at[k]['status']}" for k in bad) +
                      ": no lap-time comparison possible")
    t0 = at["none"]["mean_lap_time_s"]
    acts = ", ".join(f"`{k}` ESC {int(at[k].get('esc_count', 0))}×, CS {int(at[k].get('cs_count', 0))}×"
                     for k in need)
    d_esc = at["esc"]["mean_lap_time_s"] - t0
    d_both = at["esc+cs"]["mean_lap_time_s"] - t0
    text = (f"mean lap at GG 1.3: none {t0:.3f} s, ESC only {t0 + d_esc:.3f} s (Δ {d_esc:+.3f} s), "
            f"ESC + CS {t0 + d_both:.3f} s (Δ {d_both:+.3f} s); activations per run: {acts}. "
            f"Paper: Δ 0.15 s vs 0.05 s.")
    if abs(d_esc) < 1e-3 and abs(d_both) < 1e-3:
        text += " Neither ESC nor CS makes a measurable difference at this scaling."
        return None, text
    return d_both < d_esc, text


def interventions(a, keys):
    """'ESC in 0 of 7 completed runs, ...' for the completed runs of a series."""
    done = [i for i, st in enumerate(a["status"]) if st == "completed"]
    parts = []
    for k in keys:
        if k in a:
            n = sum(1 for i in done if a[k][i] > 0)
            parts.append(f"{k.split('_')[0].upper()} active in {n} of {len(done)}")
    return ", ".join(parts) + " completed runs"


def observations(s1, s2, s3):
    out = []
    if s1:
        for name, a in s1["series"].items():
            if "abs_count" in a:
                out.append(f"- Study 1 `{name}`: " +
                           interventions(a, ("abs_count", "tc_count", "esc_count", "cs_count")) +
                           ".")
    for s, tag in ((s2, "Study 2"), (s3, "Study 3")):
        if s:
            for name, a in s["series"].items():
                if "esc_count" in a:
                    out.append(f"- {tag} `{name}`: " +
                               interventions(a, ("esc_count", "cs_count")) + ".")
    if out:
        out.insert(0, "How often each subsystem acted before the first abort (a subsystem that "
                      "never acts cannot change the outcome; where ESC stays inactive until the "
                      "spin, its activation thresholds are the first thing to look at):")
        out.insert(1, "")
    return out


def main(argv=None):
    s1 = scwexp.read_summary("study1_longitudinal")
    s2 = scwexp.read_summary("study2_lateral")
    s3 = scwexp.read_summary("study3_motion")
    cmp_ = scwexp.read_summary("compare")
    out = ["# Simulation studies: reproduction report", "",
           "Generated by `experiments/report.py` from `experiments/results/*/summary.json` "
           "(re-run a study or `experiments/run_all.sh` to refresh). Setup: built-in Yas Marina "
           "North, EAV24-class plant, pure pursuit unless stated, velocity reference = plant "
           "g-g-v limits × limit_fraction 0.6 × GG, runs of 3 laps, each series reported up to "
           "its first abort (paper §IV).", ""]

    out += ["## Claims of the paper", "", "| claim | result | numbers |", "|---|---|---|"]
    rows = []
    if s1:
        ok, text = claim_a(s1)
        rows.append(("(a) slip control allows a higher scaling without wheel lock or spin", ok,
                     text))
    if s2:
        for label, fn in (("(b) without lateral stability control the car spins first", claim_b),
                          ("(c) with ESC the scaling of minimum lap time lies below the maximum "
                           "stable scaling", claim_c),
                          ("(d) at GG 1.3 the lap-time cost of ESC + CS versus none is smaller "
                           "than that of ESC only", claim_d)):
            ok, text = fn(s2)
            rows.append((label, ok, text))
    for label, ok, text in rows:
        out.append(f"| {label} | {verdict(ok)} | {text} |")
    if not rows:
        out.append("| – | – | no study results yet |")
    out.append("")

    obs = observations(s1, s2, s3)
    if obs:
        out += ["## Observations", ""] + obs + [""]
    if s1:
        out += ["## Study 1 — longitudinal (slip control on/off)", "",
                f"Wall time {s1['wall_time_s']:.0f} s. Command: `{s1['command']}`", "",
                series_table(s1), ""]
        out += [f"![study 1]({f})" for f in s1["figures"]] + [""]
    if s2:
        out += ["## Study 2 — lateral (none / ESC / CS / ESC + CS, rear μy −20 %)", "",
                f"Wall time {s2['wall_time_s']:.0f} s. Command: `{s2['command']}`", "",
                series_table(s2), ""]
        out += [f"![study 2]({f})" for f in s2["figures"]] + [""]
    if s3:
        out += ["## Study 3 — motion controllers without / with ESC + CS (rear μy −20 %)", "",
                f"Wall time {s3['wall_time_s']:.0f} s. Controllers: "
                f"{', '.join(s3['controllers'])}.", ""]
        for ctrl, why in s3.get("skipped", {}).items():
            out.append(f"- skipped `{ctrl}`: {why}")
        out += ["", series_table(s3), ""]
        for ctrl in s3["controllers"]:
            off, sc = s3["series"].get(f"{ctrl}_off"), s3["series"].get(f"{ctrl}_sc")
            if off and sc:
                higher = stable(sc) > stable(off)
                verb = "raises" if higher else "does not raise"
                out.append(f"- `{ctrl}`: stability control {verb} the max stable GG "
                           f"({off['max_stable']} → {sc['max_stable']}); min lap "
                           f"{scwexp.fmt(off['min_lap_time_s'], 3)} s → "
                           f"{scwexp.fmt(sc['min_lap_time_s'], 3)} s.")
        out += [""] + [f"![study 3]({f})" for f in s3["figures"]] + [""]
    if cmp_:
        out += ["## Comparison of parameter sets", "", f"Wall time {cmp_['wall_time_s']:.0f} s. "
                f"Sets: {', '.join(cmp_['labels'])}. Table: `{cmp_['markdown']}`.", ""]
        out += [f"![compare]({f})" for f in cmp_["figures"]] + [""]
    path = os.path.join(scwexp.RESULTS, "report.md")
    os.makedirs(scwexp.RESULTS, exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(path + ".tmp", path)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
