"""The numbers of the report's first page: each claim's verdict and margin per column, the
column most like the paper's setup, and the data of its three figures (A: study 2 of that
column as the paper drew it; B: `none`'s ESC margin per column; C: ESC's and ESC + CS's gain
over `none` in every claims-map variant). Standard library only; reads summaries and sweep
tables, runs nothing."""

import glob
import math
import os

from scwexp.claims import (EPS, abort_gg, best_run, claim_a, claim_b, claim_c, claim_d,
                           claim_d_gg, claim_e, claim_f, evaluate, limit_cycling, run_at, stable)
from scwexp.claims_map import DEFAULT_FAMILIES
from scwexp.results import column_of, read_sweep, to_float

# The sideslip of figure A, in the order tried: the sideslip error over ESC's activation
# threshold (taken while ESC's oversteer signs hold, so not at the low-speed hairpin), else the
# plain max |β| of an older table.
SIDESLIP_KEYS = (
    ("max_esc_beta_error_ratio", "max sideslip error |e_β,f| / Eβ_a [-]",
     "the largest sideslip error |e_β,f| (β against ESC's reference) over its threshold "
     "Eβ_a, while ESC's oversteer signs hold, not at the low-speed hairpin"),
    ("max_abs_sideslip_deg", "max |β| [deg]",
     "max |β| over the run, which the low-speed hairpin sets (the sweep tables with the "
     "sideslip error are not in this results tree)"))
LIMIT_FRACTION = 0.7   # GG 1.0 = 70 % of the plant's combined limits (method, "GG mapping")
# The paper's study-2 statements (§V): at GG 1.3 ESC costs 0.15 s and ESC + CS 0.05 s against
# `none`; `none` is lost before GG 1.4.
PAPER_POINTS = {"gg": 1.3, "esc": 0.15, "esc+cs": 0.05, "none_lost_before": 1.4}


def main_series(s):
    """(perturbation value, {config: series}) of a study's main perturbation."""
    p = s["perturbation"].get("main", next(iter(s["runs"])))
    return p, s["runs"][p]


def _margin(key, ser, ctrl=None):
    """The one number of a claim in a column (main perturbation): the quantity its criterion
    thresholds (MARGIN_NAMES of the claims map), None where it cannot be computed."""
    try:
        if key == "a":
            return stable(ser["sc_on"]) - stable(ser["sc_off"])
        if key == "b":
            na = abort_gg(ser["none"])
            return min(abort_gg(ser[k]) for k in ("esc", "cs", "esc+cs")) - na
        if key == "c":
            a = ser["esc+cs"]
            b = best_run(a)
            return a["max_stable"] - b["gg_scale"] if b and a["max_stable"] is not None \
                else None
        if key == "d":
            at = claim_d_gg(ser)
            r = {k: run_at(ser[k], at) for k in ("none", "esc")} if at is not None else None
            return r and r["esc"]["mean_lap_time_s"] - r["none"]["mean_lap_time_s"]
        off, sc = ser[f"{ctrl}_off"], ser[f"{ctrl}_sc"]
        if key == "e":
            return stable(sc) - stable(off)
        b = best_run(sc)
        return sc["max_stable"] - b["gg_scale"] if b and sc["max_stable"] is not None else None
    except (KeyError, TypeError):
        return None


CLAIM_FN = {"a": claim_a, "b": claim_b, "c": claim_c, "d": claim_d, "e": claim_e, "f": claim_f}
CLAIM_STUDY = {"a": "study1_longitudinal", "b": "study2_lateral", "c": "study2_lateral",
               "d": "study2_lateral", "e": "study3_motion", "f": "study3_motion"}


def claim_result(key, col, ctrl=None):
    """{ok, margin, failed} of one claim in one column: the verdict over the perturbations
    (≥ 2 of 3), the margin and the failing criterion items of the main perturbation; None when
    the column lacks the study (or the controller)."""
    s = col[2].get(CLAIM_STUDY[key])
    if not s:
        return None
    extra = (ctrl,) if ctrl else ()
    if ctrl and (ctrl not in s.get("controllers", []) or ctrl in s.get("skipped", {})):
        return None
    ok, res = evaluate(CLAIM_FN[key], s["runs"], *extra)
    p, ser = main_series(s)
    failed = [n for n, o, _ in res[p][1] if o is False]
    return {"ok": ok, "margin": _margin(key, ser, ctrl), "failed": failed,
            "n_ok": sum(1 for o, _ in res.values() if o), "n": len(res)}


def study3_controllers(cols):
    out = []
    for c in cols:
        s3 = c[2].get("study3_motion")
        for x in (s3 or {}).get("controllers", []):
            if x not in out and x not in s3.get("skipped", {}):
                out.append(x)
    return out


def paper_like(cols):
    """The column most like the paper's setup among those with study 2: the paper's simulator's
    actuators first, on the paper's own simulator (Open-Car-Dynamics) before scw's plant, then a
    set trained with them (its label names paper_sim), then the shipped set; None without
    study 2."""
    have = [c for c in cols if c[2].get("study2_lateral")]
    if not have:
        return None

    def score(c):
        info = column_of(c)
        return (info["actuators"] == "paper_sim", info.get("plant", "scw") == "ocd",
                "paper_sim" in info["set_label"], info["set_label"] == "shipped")
    return max(have, key=score)


def _sweep_index(study_dir):
    """{(gg, max |β|, status): sweep row values} over a study folder's sweep tables: a
    summary's run is found again in its table by those three (the same numbers, as written)."""
    idx = {}
    for path in sorted(glob.glob(os.path.join(study_dir, "sweep*.csv"))):
        try:
            rows = read_sweep(path)
        except (ValueError, OSError):
            continue
        for r in rows:
            if r.gg_scale is None:
                continue
            key = (round(r.gg_scale, 6), to_float(r.values.get("max_abs_sideslip_deg")),
                   r.status)
            idx[key] = r.values
    return idx


def figure_a_data(col):
    """Study 2 of `col` at its main perturbation: per configuration [(gg, sideslip, lap or
    None, lost)], the sideslip key used and its description, and the perturbation."""
    s = col[2]["study2_lateral"]
    p, ser = main_series(s)
    idx = _sweep_index(os.path.join(col[1], "study2_lateral"))
    found = {k for k, *_ in SIDESLIP_KEYS if any(k in v for v in idx.values())
             or any(r.get(k) is not None for a in ser.values() for r in a["runs"])}
    key, what, caption = next((x for x in SIDESLIP_KEYS if x[0] in found), SIDESLIP_KEYS[-1])
    out = {}
    for name, a in ser.items():
        pts = []
        for r in a["runs"]:
            row = r if r.get(key) is not None else idx.get(
                (round(r["gg_scale"], 6), to_float(r.get("max_abs_sideslip_deg")), r["status"]),
                r)
            y = to_float(row.get(key))
            lap = r["mean_lap_time_s"] if r["status"] == "completed" else None
            pts.append((r["gg_scale"], y, lap, r["status"] != "completed"))
        out[name] = pts
    return {"series": out, "key": key, "what": what, "caption": caption,
            "labels": s.get("configs", {}),
            "perturbation": f"{s['perturbation']['label']} {p}"}


def figure_b_data(cols, esc_margin):
    """`none`'s ESC margin per column: [(gg, max_esc_margin, lost)] from study 2's main
    perturbation, with esc_margin.py's runs of `none` at rear μy 0.80 (finer GGs) merged in."""
    out = {}
    extra = (esc_margin or {}).get("rows", [])
    for c in cols:
        s = c[2].get("study2_lateral")
        if not s:
            continue
        _, ser = main_series(s)
        pts = {}
        for r in (ser.get("none") or {}).get("runs", []):
            m = to_float(r.get("max_esc_margin"))
            if not math.isnan(m):
                pts[round(r["gg_scale"], 6)] = (r["gg_scale"], m, r["status"] != "completed")
        for r in extra:
            if r.get("column") == c[0] and r.get("config") == "none" \
                    and r.get("factor") is None and r.get("falloff") in (None, 1.0):
                m = to_float(r.get("max_esc_margin"))
                if not math.isnan(m):
                    pts.setdefault(round(r["gg"], 6), (r["gg"], m, r["status"] != "completed"))
        out[c[0]] = sorted(pts.values())
    return out


def open_ended(ser, name):
    """True when `name`'s series never aborted in its range: its gain is then a lower bound
    (claims.abort_gg counts it one step above its last run)."""
    return bool(ser.get(name)) and ser[name].get("first_abort") is None


def gain(ser, name):
    """First-abort GG of `name` minus `none`'s in one perturbation's series (None without
    them); a lower bound where open_ended(ser, name)."""
    try:
        return abort_gg(ser[name]) - abort_gg(ser["none"])
    except (KeyError, TypeError):
        return None


def figure_c_data(maps, cols):
    """Rows [(label, gain ESC, gain ESC + CS, limit-cycling, is a scored column, ESC's gain a
    lower bound, ESC + CS's a lower bound)]: the scored
    columns' study 2 (main perturbation) first, then every variant of every claims map; the
    gain is the first-abort GG over `none`'s. Also what is missing: the default families
    absent from each map."""
    rows = []
    for c in cols:
        s = c[2].get("study2_lateral")
        if s:
            _, ser = main_series(s)
            info = column_of(c)
            rows.append((f"scored: {info['set_label']}, {info['actuators']}",
                         gain(ser, "esc"), gain(ser, "esc+cs"), False, True,
                         open_ended(ser, "esc"), open_ended(ser, "esc+cs")))
    missing = []
    fams = {f[1] for f in DEFAULT_FAMILIES}
    for cm in maps:
        vs = cm.get("variants", [])
        for v in vs:
            rows.append((f"{cm['set_label']}: {v['label']}", gain(v["series"], "esc"),
                         gain(v["series"], "esc+cs"), limit_cycling(v), False,
                         open_ended(v["series"], "esc"), open_ended(v["series"], "esc+cs")))
        have = {v.get("family") for v in vs}
        gone = sorted(fams - have)
        if gone:
            missing.append(f"{cm['set_label']} set's map lacks {len(gone)} of the "
                           f"{len(fams)} default families")
    if not maps:
        missing.append("no claims map in this results tree (experiments/claims_map.py)")
    return rows, missing


def gains_summary(rows):
    """(n variants, n limit-cycling, [(label, esc, both)] of the non-cycling variants where
    ESC + CS gains ≥ one step)."""
    vs = [r for r in rows if not r[4]]
    good = [r for r in vs if not r[3] and r[2] is not None and r[2] >= 0.05 - EPS]
    return len(vs), sum(1 for r in vs if r[3]), good
