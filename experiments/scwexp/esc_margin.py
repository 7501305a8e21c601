"""Claim (d)'s premise, the pieces experiments/esc_margin.py runs (its docstring says what and
why): the GG where (d) is judged, the band around `none`'s first abort (bisection levels, the
scan grid), the probe sets and configurations (ESC's sideslip-error thresholds scaled, the rear
tyre's falloff), a run's row and the table of the report."""

import argparse
import math
import os
import re
import sys

import scwexp
from scwexp import claims
from scwexp.studies import STUDY2_BASE_SETS, STUDY2_CONFIGS


S2 = STUDY2_BASE_SETS  # study 2's scenario overrides
CONFIGS = ("none", "esc", "cs", "esc+cs")
TERMS = scwexp.ESC_TERMS
RESOLUTION = 0.001  # GG: how finely `none`'s first abort is bisected (--resolution)
SCAN_STEP = 0.0025  # GG: the grid across `none`'s first abort (--scan-step)
PROBE = "0.5,0.3"  # factors on ESC's sideslip-error thresholds (--threshold-probe)
FALLOFF_PROBE = "0,1.5"  # the rear tyre's loss beyond its peak, beside 1 (--falloff-probe)
BETA_ERROR_KEYS = ("beta_error_threshold_activate", "beta_error_threshold_deactivate")
DEFAULT_SET = os.path.join(scwexp.ROOT, "params", "stability", "default.yaml")
CONFIG_OVERRIDES = {n: o for n, o, *_ in STUDY2_CONFIGS}  # the study's own switches


def none_bounds(series):
    """(`none`'s last completed GG, its first abort) in the study's runs, or None."""
    return scwexp.series_bounds(
        [dict(r, gg_scale=float(r["gg_scale"])) for r in series["none"].get("runs") or []])


def scan_grid(series, step):
    """GGs strictly between `none`'s last completed GG and its first abort (the study's runs),
    `step` apart (rounded to 1e-6), or [] without such a pair or with step 0."""
    bounds = none_bounds(series)
    if not bounds or not step:
        return []
    lo, hi = bounds
    n = int(math.floor((hi - lo) / step + 1e-9))
    return [round(lo + k * step, 6) for k in range(1, n + 1) if lo + k * step < hi - 1e-9]


def bisection_levels(lo, hi, resolution):
    """Rounds of bisection that bring the interval [lo, hi] down to `resolution` or below."""
    if not resolution or hi - lo <= resolution:
        return 0
    return math.ceil(math.log2((hi - lo) / resolution) - 1e-9)


def row_of(name, col, cfg, tag, gg, first_abort_fine, r):
    """One row of the summary from one row of a sweep's table."""
    return {"column": name, "set_label": col["set_label"], "actuators": col["actuators"],
            "config": cfg, "at": tag, "gg": gg, "status": r["status"],
            "first_abort_fine": first_abort_fine, "max_esc_margin": r.get("max_esc_margin"),
            **{k: r.get(k) for k in TERMS},
            **{k: r.get(k) for k in scwexp.ACTIVATION_KEYS},
            "max_abs_sideslip_deg": r.get("max_abs_sideslip_deg"),
            "mean_lap_time_s": r.get("mean_lap_time_s")}


def scaled_beta_error_set(src, factor, dst):
    """Writes the stability file `src` to `dst` with ESC's sideslip-error thresholds (activate,
    per speed, and deactivate) multiplied by `factor`: the threshold probe's set. A diagnostic,
    never a set for the car; exits naming the file and key when a key is not there once."""
    with open(src) as f:
        text = f.read()

    def scale(m):
        nums = re.sub(r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?",
                      lambda x: f"{float(x.group(0)) * factor:.6g}", m.group(2))
        return m.group(1) + nums
    for key in BETA_ERROR_KEYS:
        text, n = re.subn(rf"^(\s*{key}:\s*)(\S.*)$", scale, text, flags=re.M)
        if n != 1:
            sys.exit(f"error: {src}: ESC.{key}: expected once, found {n} times")
    with open(dst, "w") as f:
        f.write(f"# {os.path.basename(src)} with ESC's sideslip-error thresholds x{factor:g} "
                "(experiments/esc_margin.py threshold probe; not a set for the car)\n" + text)


def numbers(text, ok, error):
    """Comma-separated numbers each satisfying `ok`, or [] for an empty text; an
    argparse.ArgumentTypeError `error.format(x)` names the first that does not."""
    out = []
    for x in (t.strip() for t in text.split(",") if t.strip()):
        try:
            v = float(x)
        except ValueError:
            v = float("nan")
        if not ok(v):
            raise argparse.ArgumentTypeError(error.format(repr(x)))
        out.append(v)
    return out


def falloffs(text):
    """--falloff-probe: comma-separated scales of the rear tyre's loss beyond its peak (>= 0,
    not 1: the vehicle file's is always run), or [] for an empty text."""
    return numbers(text, lambda v: v >= 0 and v != 1,
                   "--falloff-probe: {} is not a number >= 0 other than 1 (1 is always run)")


def falloff_configs(lo, hi, values):
    """The falloff probe's named configurations: `none` at its last completed GG (lo) and at its
    first abort (hi), with the vehicle file's loss beyond the peak (1) and each of `values`;
    the names carry the scale in hundredths (none.fo150_last)."""
    out = []
    for f in [1.0] + list(values):
        for at, g in (("last", lo), ("abort", hi)):
            out.append(f"none.fo{round(f * 100)}_{at}:{CONFIG_OVERRIDES['none']},gg_scale={g},"
                       f"plant.rear_tire_falloff={f:g}")
    return out


def factors(text):
    """--threshold-probe: comma-separated positive factors, or [] for an empty text."""
    return numbers(text, lambda v: v > 0, "--threshold-probe: {} is not a positive number")


def judged_gg(series):
    """The GG claim (d) is judged at (claims.claim_d_gg), None without all four configurations."""
    if any(k not in series for k in CONFIGS):
        return None
    return claims.claim_d_gg(series)


def stability_path(column):
    """The stability file of a column (its `stability` text starts with the path)."""
    text = (column.get("stability") or "").split(" ")[0]
    return text if text and text != "params/stability/default.yaml" else None


def text_of(rows):
    """The report's table: per column, `none` and ESC at the judged GG, at `none`'s abort and at
    the last GG `none` completes with its abort bisected finer (when run)."""
    def cell(r):
        if r is None:
            return "–"
        m = scwexp.to_float(r["max_esc_margin"])
        if m != m:
            return f"{r['status']}"
        terms = scwexp.esc_terms_text(r)
        return (f"{r['status']} · margin {m:.2f}" + (f" ({terms})" if terms else "")
                + f" · ESC {int(scwexp.to_float(r['esc_count']))}×")
    cols = []
    for r in rows:
        if r["column"] not in cols:
            cols.append(r["column"])
    fine = any(r["at"] == "finest" for r in rows)
    head = ("| column | (d) judged at GG | `none` there | ESC only there | `none`'s first abort "
            "GG | `none` there | ESC only there |")
    rule = "|---|---|---|---|---|---|---|"
    if fine:
        head += " last GG `none` completes (finer) | `none` there | ESC only there |"
        rule += "---|---|---|"
    lines = [head, rule]
    for c in cols:
        rs = {(r["config"], r["at"]): r for r in rows if r["column"] == c}
        any_r = next(r for r in rows if r["column"] == c)

        def gg(at):
            return next((r["gg"] for r in rows if r["column"] == c and r["at"] == at), None)
        line = (f"| {any_r['set_label']}, {any_r['actuators']} | {scwexp.fmt(gg('judged'), 3)} | "
                f"{cell(rs.get(('none', 'judged')))} | {cell(rs.get(('esc', 'judged')))} | "
                f"{scwexp.fmt(gg('none_abort'), 3)} | {cell(rs.get(('none', 'none_abort')))} | "
                f"{cell(rs.get(('esc', 'none_abort')))} |")
        if fine:
            fa = any_r.get("first_abort_fine")
            g = gg("finest")
            line += (f" {scwexp.fmt(g, 4)}" + (f" (lost at {fa:.4f})" if fa is not None else "")
                     + f" | {cell(rs.get(('none', 'finest')))} | "
                     f"{cell(rs.get(('esc', 'finest')))} |")
        lines.append(line)
    return lines
