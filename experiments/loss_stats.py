"""The limit as a probability (experiments/statistical_criteria.md): P(loss | GG) from runs that
differ only in the sensor-noise seed, its 95 % Wilson interval, and the GG where it crosses a
level, with an interval. Pure functions over plain numbers; no scw runs."""

import math

Z95 = 1.959963984540054


def wilson(k, n, z=Z95):
    """(low, high) of the Wilson score interval for k losses in n runs; (0, 1) for n = 0."""
    if n <= 0:
        return 0.0, 1.0
    p = k / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n)
    return max(0.0, centre - half), min(1.0, centre + half)


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
