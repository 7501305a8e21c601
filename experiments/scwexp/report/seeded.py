"""The limit as a probability in the report (issue 48 item 2): each column's seeded study 2
(experiments/seeded_limit.py: columns/<column>/study2_seeded/summary.json) as one row of the
verdict table (claim (b) in its statistical form) and an appendix with the crossings, claim (b)
and a link to each column's full P(loss | GG) table and figure."""

import json
import os

from scwexp import seeded
from scwexp.report.common import col_title

STUDY = "study2_seeded"
LABELS = {"none": "none", "esc": "ESC", "cs": "CS", "esc+cs": "ESC + CS"}


def read(col):
    """A column's seeded summary, or None."""
    path = os.path.join(col[1], STUDY, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def _gain(s):
    """min over ESC, CS, ESC + CS of GG_50(c) − GG_50(none), and whether one is open (beyond the
    grid: at least that much)."""
    n = s["summary"]["none"]["limits"]["0.5"][0]
    if n is None:
        return None, False
    top = max(p[0] for p in s["summary"]["none"]["curve"])
    vals = [(s["summary"][c]["limits"]["0.5"][0], s["summary"][c]["limits"]["0.5"][0] is None)
            for c in ("esc", "cs", "esc+cs")]
    g = min((top if v is None else v) - n for v, _ in vals)
    return g, any(o for _, o in vals)


def verdict_row(cols):
    """The verdict table's row for claim (b) over seeds; [] when no column has the seeded run."""
    found = [read(c) for c in cols]
    if not any(found):
        return []
    cells = []
    for s in found:
        if s is None:
            cells.append("–")
            continue
        v = s["claim_b"]
        ok = all(v[c]["holds"] for c in ("esc", "cs", "esc+cs"))
        conf = all(v[c]["with_confidence"] for c in ("esc", "cs", "esc+cs"))
        g, open_ = _gain(s)
        sym = "?" if not v["evaluable"] else ("✓✓" if conf else "✓" if ok else "✗")
        cells.append(f"{sym} " + ("–" if g is None else ("≥ " if open_ else "") + f"{g:+.2f}"))
    return [f"| (b) over {found[[x is not None for x in found].index(True)]['seeds']} seeds: "
            "GG_50 | " + " | ".join(cells) + " |"]


def legend():
    return ("(b) over seeds: ✓✓ holds with 95 % confidence, ✓ at the point estimates, ✗ not, ? "
            "fewer than 10 seeds; the number: min over ESC, CS, ESC + CS of GG_50 − none's "
            "([seeded](appendix/seeded.md)).")


def appendix(cols, root):
    """The appendix's lines (links relative to the results root)."""
    out = ["# Study 2 over sensor-noise seeds: the limit as a probability", "",
           "P(loss | GG) from n runs per configuration and GG that differ only in the "
           "sensor-noise seed (experiments/seeded_limit.py; criteria written before the first "
           "seeded run: experiments/statistical_criteria.md). GG_q: where P(loss) crosses q, "
           "[crossing of the Wilson upper bound, of the lower bound]. Activations: runs in "
           "which the subsystem acted among the completed runs at `none`'s GG_50.", ""]
    any_ = False
    for c in cols:
        s = read(c)
        if s is None:
            continue
        any_ = True
        d = os.path.relpath(os.path.join(c[1], STUDY), root)
        v = s["claim_b"]
        out += [f"## {col_title(c)}", "",
                f"{s['seeds']} seeds; wall {s['wall_time_s'] / 60:.1f} min; none's losses "
                f"mostly sideslip: {'yes' if v['premise_sideslip'] else 'no'}.", "",
                "| config | GG_10 | GG_50 | (b) | acted / completed at none's GG_50 |",
                "| --- | --- | --- | --- | --- |"]
        for k, lab in LABELS.items():
            sm = s["summary"][k]
            b = v.get(k)
            verdict = "–" if b is None else ("✓✓" if b["with_confidence"] else "✓" if b["holds"]
                                              else "✗")
            acted = "–" if b is None else f"{b['acted']} / {b['completed']}"
            out.append(f"| {lab} | {seeded.fmt_limit(sm['limits']['0.1'])} | "
                       f"{seeded.fmt_limit(sm['limits']['0.5'])} | {verdict} | {acted} |")
        out += ["", f"Every GG: [{d}/seeded.md]({d}/seeded.md).", "",
                f"![P(loss) per GG, {col_title(c)}]({d}/seeded.png)", ""]
    if not any_:
        out += ["No column has the seeded run yet (experiments/seeded_limit.py).", ""]
    return out
