"""Claim (d)'s premise from experiments/esc_margin.py: how close ESC's activation condition comes
where `none` completes, the finer bisection and grid across `none`'s loss, the threshold and
falloff probes."""

from scwexp.claims import CLAIM_D_COST, acts, claim_d, g
from scwexp.results import (ACTIVATION_KEYS, ESC_TERMS, ESC_TERM_NAMES, esc_binding_terms,
                            esc_terms_text, fmt, read_summary, to_float)


def esc_margin_section():
    """Claim (d) needs ESC to act where `none` also completes: how close ESC's activation
    condition came in those runs (experiments/esc_margin.py), if it was run."""
    s = read_summary("esc_margin")
    if not s or not s.get("rows"):
        return []
    rows = s["rows"]

    def margins(cfg, at, completed):
        return [to_float(r["max_esc_margin"]) for r in rows
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
             and to_float(r["max_esc_margin"]) >= 1.0]
    esc_there = {(r["set_label"], r["actuators"]): int(to_float(r["esc_count"]))
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
            d = to_float(x["mean_lap_time_s"]) - to_float(base["mean_lap_time_s"])
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
                     + (f"{to_float(base['mean_lap_time_s']):.3f} s"
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
            and r["status"] == "completed" and esc_terms_text(r)]
    if not kept:
        return []
    counts = {}
    for r in kept:
        for n in esc_binding_terms(r):
            counts[n] = counts.get(n, 0) + 1
    peaks = {n: [to_float(r[k]) for r in kept]
             for n, k in zip(ESC_TERM_NAMES, ESC_TERMS)}
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
    m = [to_float(r["max_esc_margin"]) for r in none]
    gaps = sorted({round(r["first_abort_fine"] - r["gg"], 6) for r in none
                   if r.get("first_abort_fine") is not None})
    acts = [int(to_float(r["esc_count"])) for r in esc if r["status"] == "completed"]
    lap = {r["column"]: to_float(r["mean_lap_time_s"]) for r in none}
    deltas = [to_float(r["mean_lap_time_s"]) - lap[r["column"]] for r in esc
              if r["status"] == "completed" and r["column"] in lap]
    lo, hi = CLAIM_D_COST
    opens = [r["column"] for r in esc if r["status"] == "completed" and r["column"] in lap
             and int(to_float(r["esc_count"])) > 0
             and lo <= to_float(r["mean_lap_time_s"]) - lap[r["column"]] <= hi]
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
            if e and e["status"] == "completed" and to_float(e["esc_count"]) > 0:
                deltas.append((g, to_float(e["mean_lap_time_s"])
                               - to_float(none[g]["mean_lap_time_s"])))
        inside = [d for _, d in deltas if lo <= d <= hi]
        all_d += [d for _, d in deltas]
        n_acts += len(deltas)
        n_ok += len(done)
        if not mono:
            nonmono.append(c)
        r0 = rs[0]
        below = ", ".join(f"{g:.4f}" for g in lost if not mono and g < max(done))
        lines.append(
            f"| {r0['set_label']}, {r0['actuators']} | {fmt(ggs[0], 4)}–"
            f"{fmt(ggs[-1], 4)} ({len(ggs)}) | {len(done)} of {len(ggs)} | "
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
                run = {k: to_float(r.get(k)) for k in
                       ("mean_lap_time_s",) + ACTIVATION_KEYS}
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
