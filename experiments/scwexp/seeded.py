"""The limit as a probability (issue 48 item 2, experiments/statistical_criteria.md): study 2's
four configurations over n sensor-noise seeds per GG, summarised as P(loss | GG) with Wilson 95 %
intervals, the GG where it crosses 10 % and 50 % (with intervals), the activations beside every
number, and claim (b)'s statistical form. Pure functions over sweep rows (dicts with config,
gg_scale, seed, status, esc_count, cs_count, ...); no scw runs, no files."""

import math
import statistics

from scwexp import analysis

LEVELS = (0.10, 0.50)
MIN_SEEDS = 10  # a claim needs at least this many seeds at every GG it uses
GAP_B = 0.05    # claim (b): GG_50(c) >= GG_50(none) + 0.05


def _f(x):
    try:
        v = float(x)
    except (TypeError, ValueError):
        return math.nan
    return v


def curve(rows, config):
    """analysis.loss_curve of one configuration's rows."""
    return analysis.loss_curve([(_f(r["gg_scale"]), r["status"] != "completed")
                                for r in rows if r["config"] == config])


def activations(rows, config, gg, key):
    """(runs where `key` > 0, completed runs) at one GG, over the completed runs."""
    done = [r for r in rows if r["config"] == config and abs(_f(r["gg_scale"]) - gg) < 1e-9
            and r["status"] == "completed"]
    return sum(1 for r in done if _f(r.get(key)) > 0), len(done)


def statuses(rows, config):
    """{abort status: count} over a configuration's lost runs."""
    out = {}
    for r in rows:
        if r["config"] == config and r["status"] != "completed":
            out[r["status"]] = out.get(r["status"], 0) + 1
    return out


def median_lap(rows, config, gg):
    laps = [_f(r["mean_lap_time_s"]) for r in rows if r["config"] == config
            and abs(_f(r["gg_scale"]) - gg) < 1e-9 and r["status"] == "completed"]
    return statistics.median(laps) if laps else None


def summarise(rows, configs):
    """{config: {"curve", "limits": {level: (est, low, high)}, "statuses", "seeds"}}."""
    out = {}
    for c in configs:
        cv = curve(rows, c)
        out[c] = {"curve": cv,
                  "limits": {str(q): analysis.limit(cv, q) for q in LEVELS},
                  "statuses": statuses(rows, c),
                  "seeds": min((p[1] for p in cv), default=0)}
    return out


def _at_or_above(cv, gg):
    """The first grid GG at or above `gg` (None past the grid)."""
    return next((p[0] for p in cv if p[0] >= gg - 1e-9), None)


def claim_b(rows, summary, subsystem_of):
    """Claim (b) in its statistical form: for each configuration c but `none`,
    GG_50(c) >= GG_50(none) + 0.05 (point estimates), with confidence when the intervals are
    separated by the gap; >= 50 % of none's losses are `sideslip`; P5: at the grid GG at or above
    GG_50(none) the subsystem acted in >= 50 % of c's completed runs. subsystem_of: {config:
    activation column, e.g. "esc_count"}. Returns {config: {...}, "premise": ...}."""
    none = summary["none"]
    est_n, lo_n, hi_n = none["limits"]["0.5"]
    lost = sum(none["statuses"].values())
    premise = lost > 0 and none["statuses"].get("sideslip", 0) >= 0.5 * lost
    out = {"premise_sideslip": premise,
           "evaluable": all(s["seeds"] >= MIN_SEEDS for s in summary.values())}
    for c, key in subsystem_of.items():
        s = summary[c]
        est, lo, hi = s["limits"]["0.5"]
        at = _at_or_above(none["curve"], est_n) if est_n is not None else None
        acted, done = activations(rows, c, at, key) if at is not None else (0, 0)
        p5 = done > 0 and acted >= 0.5 * done
        point = est_n is not None and (est is None or est >= est_n + GAP_B - 1e-9)
        # A crossing of c's Wilson upper bound beyond the grid (lo None) lies above any hi_n.
        conf = hi_n is not None and (lo is None or hi_n + GAP_B <= lo + 1e-9)
        out[c] = {"gg50": (est, lo, hi), "p5_gg": at, "acted": acted, "completed": done,
                  "holds": bool(point and p5 and premise and out["evaluable"]),
                  "with_confidence": bool(point and conf and p5 and premise and out["evaluable"])}
    return out


def fmt_limit(lim):
    est, lo, hi = lim
    if est is None:
        return "> grid"
    a = "> grid" if lo is None else f"{lo:.2f}"
    b = "> grid" if hi is None else f"{hi:.2f}"
    return f"{est:.2f} [{a}, {b}]"
