"""The limit as a probability (issue 48 item 2, experiments/statistical_criteria.md): study 2's
four configurations (and study 3's controllers without and with SC) over n sensor-noise seeds per GG, summarised as P(loss | GG) with Wilson 95 %
intervals, the GG where it crosses 10 % and 50 % (with intervals), the activations beside every
number, and claims (b) and (e) in their statistical form. Pure functions over sweep rows (dicts with config,
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
    """(completed runs in which `key` > 0, completed runs) at one GG; `key` may be a tuple of
    activation columns (acted: any of them > 0)."""
    keys = (key,) if isinstance(key, str) else tuple(key)
    done = [r for r in rows if r["config"] == config and abs(_f(r["gg_scale"]) - gg) < 1e-9
            and r["status"] == "completed"]
    return sum(1 for r in done if any(_f(r.get(k)) > 0 for k in keys)), len(done)


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
                  # The Wilson upper bound already reaches q at the grid's first GG (0 of 10 lost
                  # still allows 28 %): the crossing's low end is at or below the grid.
                  "low_open": {str(q): bool(cv) and cv[0][5] >= q for q in LEVELS},
                  "statuses": statuses(rows, c),
                  "seeds": min((p[1] for p in cv), default=0)}
    return out


def _at_or_above(cv, gg):
    """The first grid GG at or above `gg` (None past the grid)."""
    return next((p[0] for p in cv if p[0] >= gg - 1e-9), None)


def gain_claim(rows, summary, base, subsystem_of, gap=GAP_B, premise=True):
    """A claim of the form "c raises the limit over `base`" (statistical_criteria.md (b), (e)):
    for each configuration c of subsystem_of ({config: activation column or tuple of them}),
    GG_50(c) >= GG_50(base) + gap at the point estimates, with confidence when the intervals are
    separated by the gap; P5: at the grid GG at or above GG_50(base) the subsystem acted in >= 50 %
    of c's completed runs; `premise` (e.g. the base's losses mostly sideslip) and >= MIN_SEEDS
    seeds everywhere are required too. Returns {config: {...}, "evaluable": ...}."""
    ref = summary[base]
    est_n, lo_n, hi_n = ref["limits"]["0.5"]
    out = {"evaluable": all(summary[c]["seeds"] >= MIN_SEEDS for c in [base, *subsystem_of])}
    for c, key in subsystem_of.items():
        s = summary[c]
        est, lo, hi = s["limits"]["0.5"]
        at = _at_or_above(ref["curve"], est_n) if est_n is not None else None
        acted, done = activations(rows, c, at, key) if at is not None else (0, 0)
        p5 = done > 0 and acted >= 0.5 * done
        point = est_n is not None and (est is None or est >= est_n + gap - 1e-9)
        # A crossing of c's Wilson upper bound beyond the grid (lo None) lies above any hi_n.
        conf = hi_n is not None and (lo is None or hi_n + gap <= lo + 1e-9)
        ok = point and p5 and premise and out["evaluable"]
        out[c] = {"gg50": (est, lo, hi), "base_gg50": (est_n, lo_n, hi_n), "p5_gg": at,
                  "acted": acted, "completed": done, "holds": bool(ok),
                  "with_confidence": bool(ok and conf)}
    return out


def claim_b(rows, summary, subsystem_of):
    """Claim (b) over seeds: ESC, CS and ESC + CS each raise GG_50 over `none` by 0.05, `none`'s
    losses mostly `sideslip` (>= 50 %)."""
    none = summary["none"]
    lost = sum(none["statuses"].values())
    premise = lost > 0 and none["statuses"].get("sideslip", 0) >= 0.5 * lost
    out = gain_claim(rows, summary, "none", subsystem_of, GAP_B, premise)
    out["premise_sideslip"] = premise
    return out


GAP_E = 0.05  # claim (e): GG_50(with SC) >= GG_50(without) + 0.05, per controller


def claim_e(rows, summary, controller):
    """Claim (e) over seeds for one motion controller: with ESC + CS (config <ctrl>_sc) GG_50 at
    least 0.05 above without (<ctrl>_off), ESC or CS acting at GG_50(without)."""
    return gain_claim(rows, summary, f"{controller}_off",
                      {f"{controller}_sc": ("esc_count", "cs_count")}, GAP_E)


def fmt_limit(lim, low_open=False):
    """"1.07 [1.05, 1.10]": the crossing and its interval; "≤" where the low end is at or below
    the grid's first GG, "> grid" where a curve never crosses within the grid."""
    est, lo, hi = lim
    if est is None:
        return "> grid"
    a = "> grid" if lo is None else ("≤ " if low_open else "") + f"{lo:.2f}"
    b = "> grid" if hi is None else f"{hi:.2f}"
    return f"{est:.2f} [{a}, {b}]"
