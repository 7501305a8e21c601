"""The report's first page (issue 48 item 1): at most PAGE_LINES lines that answer "does
stability control do what the paper says, and under which conditions": the verdict table
(claims x columns, one symbol and one number per cell), one sentence per claim (where it holds,
what blocks it), the three figures and the links to the appendices."""

import os

from scwexp.claims import CRITERIA
from scwexp.report import page_data as D
from scwexp.report import seeded as S
from scwexp.report.common import ACT_SHORT, col_title, from_column
from scwexp.results import column_of

PAGE_LINES = 60
SYMBOL = {True: "✓", False: "✗", None: "?"}
SHORT = {"a": "slip control: higher GG, faster, gradual slip",
         "b": "without lateral SC the car spins first",
         "c": "with ESC the best lap lies below the limit",
         "d": "at GG 1.3 ESC costs 0.05–0.40 s, ESC + CS less",
         "e": "SC raises the controller's limit",
         "f": "best lap below the limit with SC only"}
UNIT = {"a": "GG", "b": "GG", "c": "GG", "d": "s", "e": "GG", "f": "GG"}
NUMBER = {"a": "max stable GG, SC on − off", "b": "first abort, min(ESC, CS, ESC + CS) − none",
          "c": "ESC + CS, max stable − best-lap GG",
          "d": "Δ lap, ESC − none [s] at GG 1.3 or the highest GG all four complete",
          "e": "max stable GG, with SC − without", "f": "with SC, max stable − best-lap GG"}


def _cell(res, key):
    if res is None:
        return "–"
    m = res["margin"]
    num = "–" if m is None else (f"{m:+.3f}" if UNIT[key] == "s" else f"{m:+.2f}")
    return f"{SYMBOL[res['ok']]} {num}"


def verdict_rows(cols):
    """The verdict table's lines and {(claim, controller or None): {column: result}}."""
    titles = [col_title(c) for c in cols]
    out = ["| claim | " + " | ".join(titles) + " |", "|---|" + "---|" * len(cols)]
    res = {}
    keys = [(k, None) for k in "abcd"] + [(k, x) for k in "ef"
                                          for x in D.study3_controllers(cols)]
    for k, ctrl in keys:
        rs = {c[0]: D.claim_result(k, c, ctrl) for c in cols}
        res[(k, ctrl)] = rs
        name = f"({k}) {SHORT[k]}" + (f", `{ctrl}` (unscored)" if ctrl else "")
        out.append(f"| {name} | " + " | ".join(_cell(rs[c[0]], k) for c in cols) + " |")
    return out, res


def _names(items, most=3):
    items = list(items)
    if len(items) <= most:
        return "; ".join(items)
    return "; ".join(items[:most]) + f" and {len(items) - most} more"


def claim_sentence(key, ctrl, rs, cols, maps):
    """One sentence: where the claim holds (columns, then claims-map variants that are not
    limit-cycling) and what blocks it elsewhere (its criterion item failing most often)."""
    by = {c[0]: c for c in cols}
    yes = [col_title(by[n]) for n, r in rs.items() if r and r["ok"]]
    no = [n for n, r in rs.items() if r and not r["ok"]]
    lead = f"**({key})**" + (f" `{ctrl}`" if ctrl else "")
    if not any(rs.values()):
        return f"- {lead}: not evaluable: no column has its study."
    text = f"- {lead} holds in {_names(yes) if yes else 'no scored column'}"
    if no:
        count = {}
        for n in no:
            for item in rs[n]["failed"]:
                count[item] = count.get(item, 0) + 1
        if count:
            item, c = max(count.items(), key=lambda x: x[1])
            text += (f"; {'elsewhere it' if yes else 'it'} fails on “{item}” ({c} of {len(no)} "
                     f"column{'s' * (len(no) != 1)})")
    if key in "abcd" and maps:
        vs = [(cm, v) for cm in maps for v in cm.get("variants", [])]
        # the fewest changes from the nearest scored column first
        held = sorted(((cm, v) for cm, v in vs if v["claims"].get(key, {}).get("ok")
                       and not D.limit_cycling(v)),
                      key=lambda p: len(from_column(p[1])[1] or [None, None]))
        ok = [f"{v['label']} ({cm['set_label']} set)" for cm, v in held]
        text += (f"; the claims maps find it in {len(ok)} of {len(vs)} variants (limit-cycling "
                 "ones aside)"
                 + (f" ({_names(ok, 2)})" if ok else ""))
    return text + "."


def gain_line(cols):
    """One line: the first-abort gain of ESC and of ESC + CS over `none` (study 2, main
    perturbation) per actuator model, as a range over the sets."""
    by = {}
    for c in cols:
        s = c[2].get("study2_lateral")
        if s:
            _, ser = D.main_series(s)
            by.setdefault(column_of(c)["actuators"], []).append(
                [(D.gain(ser, k), D.open_ended(ser, k)) for k in ("esc", "esc+cs")])

    def rng(xs):
        xs = [x for x in xs if x[0] is not None]
        if not xs:
            return "–"
        lo, hi = min(xs), max(xs)
        t = [("≥ " if o else "") + f"{v:+.2f}" for v, o in (lo, hi)]
        return t[0] if t[0] == t[1] else f"{t[0]} to {t[1]}"
    parts = [f"{ACT_SHORT.get(a, a)}: ESC {rng(x[0] for x in v)}, ESC + CS {rng(x[1] for x in v)}"
             for a, v in by.items()]
    return ["- **The gain** over `none` in first-abort GG (study 2, main perturbation, over the "
            "sets; ≥: never lost in its range): " + "; ".join(parts) + "."] if parts else []


def figures(cols, maps, esc_margin, root):
    """Draws figures A, B and C under root/page/ and returns their markdown (image and caption
    lines)."""
    from scwexp import page_plots as P
    os.makedirs(os.path.join(root, "page"), exist_ok=True)
    out = []
    col = D.paper_like(cols)
    a = D.figure_a_data(col) if col is not None else None
    path = P.figure_a(a, D.PAPER_POINTS, D.LIMIT_FRACTION, os.path.join(root, "page", "a.png"),
                      f"A. Study 2, {col_title(col)}, {a['perturbation']}" if a else
                      "A. Study 2: not run")
    out += [f"![A: study 2 as the paper drew it]({os.path.relpath(path, root)})", ""]
    if a is None:
        out += ["**A.** Missing: no column has study 2, so the paper's figure cannot be drawn.",
                ""]
    else:
        paper_sim = column_of(col)["actuators"] == "paper_sim"
        out += [f"**A.** Study 2 of {col_title(col)} ("
                + ("most like the paper: its simulator's actuators" if paper_sim
                   else "no column has the paper's simulator's actuators") + f"), "
                f"{a['perturbation']}; top: {a['caption']}; ×: lost; bottom: mean lap time; ★ "
                "the paper's Δ at GG 1.3, grey band: its `none` lost before 1.4; top axis: % of "
                "the plant's limits.", ""]
    b = D.figure_b_data(cols, esc_margin)
    path = P.figure_b(b, {c[0]: col_title(c) for c in cols}, D.LIMIT_FRACTION,
                      os.path.join(root, "page", "b.png"), "B. `none`'s ESC margin against GG")
    out += [f"![B: none's ESC margin]({os.path.relpath(path, root)})", "",
            "**B.** Missing: no study-2 run of `none` with its ESC margin in this results tree."
            if not any(b.values()) else
            "**B.** Study 2, `none` (no lateral SC), main rear μy, "
            + ("with esc_margin.py's finer runs" if esc_margin and esc_margin.get("rows") else
               "the study's GG axis only (esc_margin.py not run)") + ": "
            "the closest approach to ESC's activation condition (> 1: it held); × = lost. "
            "Where `none` completes below 1, ESC cannot act, so it cannot cost time (claim (d)).",
            ""]
    rows, missing = D.figure_c_data(maps, cols)
    path = P.figure_c(rows, missing, os.path.join(root, "page", "c.png"),
                      "C. Gain over `none` in first-abort GG, every claims-map variant")
    n, cyc, good = D.gains_summary(rows)
    out += [f"![C: gain of ESC and ESC + CS over none]({os.path.relpath(path, root)})", "",
            f"**C.** First-abort GG of ESC and ESC + CS minus `none`'s, scored columns (bold) "
            f"and {n} claims-map variants ({cyc} limit-cycling, grey); ESC + CS gains a full "
            f"step in {len(good)}" + (f" ({_names([r[0] for r in good], 2)})" if good else "")
            + "." + (" Missing: " + "; ".join(missing) + "." if missing else ""), ""]
    return out


def run_line(run):
    """The header's line on how the tree was made (results/run_all.json), or []."""
    if not run:
        return []
    wall = (f"{run['wall_s'] / 60:.1f} min wall summed over {run['pieces']} pieces of a resumed run"
            if run.get("resumed") else f"{run['wall_s'] / 60:.1f} min wall")
    return [f"Made by `experiments/run_all.sh{' --quick' if run.get('mode') == 'quick' else ''}` "
            f"at commit {run.get('commit', '?')}: {wall}, "
            f"{run['cpu_s'] / 60:.1f} CPU-min (2 cores).", ""]


def page(cols, maps, esc_margin, root, appendix_links, laps, run=None):
    """The first page's lines (at most PAGE_LINES once fitted)."""
    vt, res = verdict_rows(cols)
    seeded_rows = S.verdict_row(cols)
    s2 = next((c[2]["study2_lateral"] for c in cols if c[2].get("study2_lateral")), None)
    pert = (f", study 2 at {s2['perturbation']['label']} "
            + "/".join(s2["perturbation"].get("values", [])) if s2 else "")
    out = ["# Does stability control do what the paper says?", "",
           f"Yas Marina North, the EAV24/25 plant, {laps} per run{pert}; GG 1.0 = 70 %, "
           "GG 1.43 = 100 % of the plant's combined limits. A claim holds "
           "in a column if its criterion (written before the numbers, "
           "[method](appendix/method.md)) holds in 2 of 3 perturbations.", ""] + run_line(run) + [
           "## Verdict", ""] + vt + seeded_rows + [
           "", "✓ holds, ✗ does not, – not run; the number (main perturbation): "
           + "; ".join(f"({k}) {NUMBER[k]}" for k in "abcd")
           + "; (e)/(f) as (b)/(c) per controller."
           + (" " + S.legend() if seeded_rows else ""), "", "## Where each claim holds",
           ""]
    for (k, ctrl), rs in res.items():
        out.append(claim_sentence(k, ctrl, rs, cols, maps))
    out += gain_line(cols)
    out += ["", "## Figures", ""] + figures(cols, maps, esc_margin, root)
    out += ["## Appendices", ""] + appendix_links
    return out


def criteria_lines():
    """The claims' criteria as a list (for the method appendix)."""
    return [f"- **({k}) {CRITERIA[k][0]}.** Criterion: {CRITERIA[k][1]}" for k in "abcdef"]

