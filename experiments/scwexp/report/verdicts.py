"""The claim tables: each claim per perturbation item by item, the series tables, the per-GG
detail tables, and the side-by-side verdict table (claims x columns)."""

from scwexp.claims import (CORNERS, EPS, abort_gg, abort_text, active_count, acts, best_run,
                           claim_a, claim_b, claim_c, claim_d, claim_e, claim_f, done_runs,
                           evaluate, g, needed, run_at, status_text, t3)
from scwexp.report.common import col_title, verdict
from scwexp.results import ACTIVATION_KEYS


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
            tot = "/".join(str(int(sum(r[k] or 0 for r in d))) for k in ACTIVATION_KEYS)
            act = " / ".join(str(active_count(d, k)) for k in ACTIVATION_KEYS)
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


def verdict_by_claim(cols):
    """The side-by-side verdicts as one table per claim, a row per column (verdict, n of m,
    the deciding numbers): narrow enough for any number of columns."""
    out = []
    for key, st in (("a", "study1_longitudinal"), ("b", "study2_lateral"),
                    ("c", "study2_lateral"), ("d", "study2_lateral")):
        out += [f"**({key})**", "", "| column | verdict | the deciding numbers |",
                "|---|---|---|"]
        for c in cols:
            s = c[2].get(st)
            if not s:
                out.append(f"| {col_title(c)} | – | not run |")
                continue
            ok, n, m, txt = claim_cell(key, s)
            out.append(f"| {col_title(c)} | {verdict(ok)} ({n} of {m}) | {txt} |")
        out.append("")
    return out
