"""Where each claim reproduces: the scored columns, else what the claims maps show flips it or
keeps it from holding, with claim (d)'s premise over the maps."""

import math

from scwexp import paths
from scwexp.analysis import d_premise_runs, none_edge_margins
from scwexp.claims import (CLAIM_D_COST, EPS, STEER_LIMIT_CYCLE_DEG, STEP, abort_gg, cycling_label,
                           g, limit_cycling, run_at, status_text)
from scwexp.report.claims_map import claims_maps
from scwexp.report.common import col_title, from_column, rel, steer_hf_text
from scwexp.report.esc_margin import esc_margin_section
from scwexp.results import column_of


def goal_section(results, cols):
    """Each of (a)-(d): reproduced where (with its credited subsystem acting, P5 being part of
    every criterion), else what the claims maps (one per parameter set) show flips it."""
    maps = claims_maps(paths.ROOT_RESULTS)
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
                line += _flipped(k, flips, cols, results)
            elif maps:
                line += _closest(k, maps)
            for cm in maps:
                blockers = map_blockers(cm, k)
                if blockers:
                    line += (f" {cm['set_label'].capitalize()} set's map:" if len(maps) > 1
                             else "") + blockers
        out.append(line)
    return out + [""] + esc_margin_section()


def _flipped(k, flips, cols, results):
    """Where claim k holds in the claims maps (flips: [(map, variant)], not limit-cycling): the
    variants, the single modelling choice that flips it (if one), and the run that shows it."""
    text = ""
    # the fewest changes from the nearest scored column first
    flips.sort(key=lambda p: len(from_column(p[1])[1] or [None, None]))
    cm, v = flips[0]
    text += (" The claims maps (one perturbation, everything else as the vehicle "
             "file) find it holding with: " +
             "; ".join(f"{x['label']} ({m['set_label']} set)"
                       for m, x in flips[:8]) + ".")
    act, ch = from_column(v)
    near = [c for c in cols if column_of(c)["set_label"] == cm["set_label"]
            and column_of(c)["actuators"] == act]
    if ch is not None and len(ch) == 1 and near:
        text += (f" **The single modelling choice that flips it: {ch[0]}**, one "
                 f"change from the scored column {col_title(near[0])} ("
                 + ("the vehicle file's actuators" if act == "vehicle" else
                    "the paper's simulator's actuators") + "), where it "
                 + ("holds too." if results.get((k, near[0][0])) else "fails."))
    text += (f" The run that shows it, {v['label']}, {cm['set_label']} set: " +
             "; ".join(f"{n} ({'yes' if o else 'no'}: {t})"
                       for n, o, t in v["claims"][k]["items"]) +
             (f" (sweep: `{rel(v['command'])}`)" if v.get("command") else "") +
             ".")
    if v.get("family") == "GG resolution":
        # the same runs with the first abort bisected, as the scored columns have it
        fine = next((x for x in cm.get("variants", [])
                     if x["label"].startswith("vehicle file (")), None)
        if fine:
            text += (" The same runs with the first abort bisected (the scored "
                     "columns' axis) give: " + "; ".join(
                         f"{n} ({'yes' if o else 'no'}: {t})"
                         for n, o, t in fine["claims"][k]["items"] if o is False)
                     + ". The claim then rests on the resolution: it holds at the "
                     "axis step and not once the abort is resolved to half a step.")
    return text


def _closest(k, maps):
    """No map variant makes claim k hold: the closest one (largest margin, then the fewest
    failing criterion items) among the variants whose motion controller does not limit-cycle."""
    text = ""
    vs = [(cm, x) for cm in maps for x in cm.get("variants", [])
          if not math.isnan(x["claims"][k].get("margin", math.nan))
          and not limit_cycling(x)]
    # closest: the largest margin, then the fewest failing criterion items
    best = max(vs, key=lambda p: (p[1]["claims"][k]["margin"],
                                  -len(p[1]["claims"][k]["failed"]))) if vs else None
    text += (f" No variant of the claims map{'s' if len(maps) > 1 else ''} ("
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
    return text


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
