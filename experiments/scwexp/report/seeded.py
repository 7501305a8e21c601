"""The limit as a probability in the report (issue 48 item 2): each column's seeded studies
(experiments/seeded_limit.py: columns/<column>/study2_seeded/ and study3_seeded/summary.json)
as rows of the verdict table (claims (b) and (e) in their statistical form) and an appendix with
the crossings, the claims' verdicts with their activation counts, and a link to each column's
full P(loss | GG) table and figure."""

import json
import os

from scwexp import seeded
from scwexp.report.common import col_title

STUDIES = ("study2_seeded", "study3_seeded")
LABELS = {"none": "none", "esc": "ESC", "cs": "CS", "esc+cs": "ESC + CS"}


def read(col, study="study2_seeded"):
    """A column's seeded summary of `study`, or None."""
    path = os.path.join(col[1], study, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def claims_of(s):
    """{claim key: verdicts} of a seeded summary (the first layout kept claim (b) alone)."""
    return s.get("claims") or ({"b": s["claim_b"]} if "claim_b" in s else {})


def _configs(v):
    return [c for c, r in v.items() if isinstance(r, dict)]


def _cell(s, key):
    """One verdict cell: symbol and min over the claim's configurations of GG_50 − base's."""
    v = claims_of(s).get(key)
    if v is None:
        return "–"
    rs = [v[c] for c in _configs(v)]
    base = rs[0]["base_gg50"][0] if rs else None
    top = max(p[0] for c in s["summary"].values() for p in c["curve"])
    gains = [((top if r["gg50"][0] is None else r["gg50"][0]) - base, r["gg50"][0] is None)
             for r in rs] if base is not None else []
    sym = ("?" if not v["evaluable"] else "✓✓" if all(r["with_confidence"] for r in rs)
           else "✓" if all(r["holds"] for r in rs) else "✗")
    if not gains:
        return f"{sym} –"
    g, open_ = min(gains)
    return f"{sym} " + ("≥ " if open_ else "") + f"{g:+.2f}"


def verdict_row(cols):
    """The verdict table's rows for the claims over seeds; [] when no column has a seeded run."""
    out = []
    for study in STUDIES:
        found = [read(c, study) for c in cols]
        if not any(found):
            continue
        first = next(s for s in found if s)
        for key in claims_of(first):
            name = f"({key[0]})" + (f" `{key.split(':', 1)[1]}`" if ":" in key else "")
            out.append(f"| {name} over {first['seeds']} seeds: GG_50 | "
                       + " | ".join("–" if s is None else _cell(s, key) for s in found) + " |")
    return out


def legend():
    return ("Over seeds: ✓✓ holds with 95 % confidence, ✓ at the point estimates, ✗ not, ? fewer "
            "than 10 seeds; the number: the smallest GG_50 gain over the claim's base "
            "([seeded](appendix/seeded.md)).")


def _column_lines(c, s, root, study):
    d = os.path.relpath(os.path.join(c[1], study), root)
    labels = s.get("configs") or LABELS
    out = [f"## {col_title(c)}, study {study[5]}", "",
           f"{s['seeds']} seeds; wall {s['wall_time_s'] / 60:.1f} min.", "",
           "| config | GG_10 | GG_50 | abort statuses |", "| --- | --- | --- | --- |"]
    for k, sm in s["summary"].items():
        st = ", ".join(f"{a} {n}" for a, n in sorted(sm["statuses"].items())) or "-"
        lo = sm.get("low_open", {})
        out.append(f"| {labels.get(k, k)} | {seeded.fmt_limit(sm['limits']['0.1'], lo.get('0.1'))} | "
                   f"{seeded.fmt_limit(sm['limits']['0.5'], lo.get('0.5'))} | {st} |")
    out += ["", "| claim | config | holds | acted / completed at the base's GG_50 |",
            "| --- | --- | --- | --- |"]
    for key, v in claims_of(s).items():
        for cfg in _configs(v):
            r = v[cfg]
            verdict = "✓✓" if r["with_confidence"] else "✓" if r["holds"] else "✗"
            out.append(f"| ({key}) | {labels.get(cfg, cfg)} | {verdict} | "
                       f"{r['acted']} / {r['completed']} |")
    out += ["", f"Every GG: [{d}/seeded.md]({d}/seeded.md).", "",
            f"![P(loss) per GG, {col_title(c)}, study {study[5]}]({d}/seeded.png)", ""]
    return out


def appendix(cols, root):
    """The appendix's lines (links relative to the results root)."""
    out = ["# Studies 2 and 3 over sensor-noise seeds: the limit as a probability", "",
           "P(loss | GG) from n runs per configuration and GG that differ only in the "
           "sensor-noise seed (experiments/seeded_limit.py; criteria written before the first "
           "seeded run: experiments/statistical_criteria.md). GG_q: where P(loss) crosses q, "
           "[crossing of the Wilson upper bound, of the lower bound], each interpolated linearly "
           "between grid points as the criteria state: where P(loss) jumps from 0 of n to n of n "
           "within one step, the limit is sharp across seeds and lies anywhere in that step; the "
           "interval then measures the seeds, not the grid. Activations: runs in which the "
           "subsystem acted among the completed runs at the base's GG_50.", ""]
    found = False
    for c in cols:
        for study in STUDIES:
            s = read(c, study)
            if s is not None:
                found = True
                out += _column_lines(c, s, root, study)
    if not found:
        out += ["No column has a seeded run yet (experiments/seeded_limit.py).", ""]
    return out
