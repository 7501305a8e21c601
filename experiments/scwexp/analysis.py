"""Analysis of the studies' results, pure functions over plain numbers and series (no scw
runs, no files): the limit as a probability (experiments/statistical_criteria.md: P(loss | GG)
from runs that differ only in the sensor-noise seed, its 95 % Wilson interval, the GG where it
crosses a level, with an interval), the margin of a series, and `none`'s ESC margin at its edge
and claim (d)'s premise over a claims map."""

import math

from scwexp.claims import EPS, STEP, best_run, done_runs, limit_cycling, run_at

Z95 = 1.959963984540054


def wilson(k, n, z=Z95):
    """(low, high) of the Wilson score interval for k losses in n runs; (0, 1) for n = 0."""
    if n <= 0:
        return 0.0, 1.0
    p = k / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n)
    # k = 0 and k = n have the exact bounds 0 and 1 (the formula leaves rounding noise there)
    return (0.0 if k == 0 else max(0.0, centre - half),
            1.0 if k == n else min(1.0, centre + half))


def loss_curve(runs):
    """[(gg, n, k, p, low, high)] sorted by GG, from runs given as (gg, lost) pairs."""
    by_gg = {}
    for gg, lost in runs:
        n, k = by_gg.get(gg, (0, 0))
        by_gg[gg] = (n + 1, k + (1 if lost else 0))
    out = []
    for gg in sorted(by_gg):
        n, k = by_gg[gg]
        lo, hi = wilson(k, n)
        out.append((gg, n, k, k / n, lo, hi))
    return out


def crossing(points, level):
    """The smallest x where y reaches `level`, linearly interpolated from the point before it;
    None when y never reaches it. `points` are (x, y) sorted by x."""
    prev = None
    for x, y in points:
        if y >= level:
            if prev is None or prev[1] >= level:
                return x
            x0, y0 = prev
            return x0 + (level - y0) * (x - x0) / (y - y0)
        prev = (x, y)
    return None


def limit(curve, level):
    """(estimate, low, high) of the GG where P(loss) crosses `level`: the crossing of p̂, and of
    the Wilson upper bound (the low end) and lower bound (the high end); None where a curve never
    crosses within the grid."""
    est = crossing([(c[0], c[3]) for c in curve], level)
    low = crossing([(c[0], c[5]) for c in curve], level)
    high = crossing([(c[0], c[4]) for c in curve], level)
    return est, low, high


def separated(a, b, gap=0.0):
    """Whether interval a lies at least `gap` below interval b (None ends: open, never separated
    on that side)."""
    return a[1] is not None and b[0] is not None and a[1] + gap <= b[0]


# ---------------------------------------------------------------------------------------------
# The margin of every series (claim (c) as a quantity) and claim (d)'s premise over a map

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
