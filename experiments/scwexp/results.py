"""Results of the studies: the sweep tables scw writes and the summaries the studies keep
(summary.json), read and written as plain dicts; the columns of a results tree. Standard library
only."""

import csv
import json
import math
import os

from scwexp import paths
from scwexp.paths import results_dir


# The paper's series stop at the first abort; these statuses mean "the car lost it".
SPIN_STATUSES = ("sideslip", "wheel_spin")


def to_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path):
    """Rows as dicts; numeric-looking fields converted to float."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in list(r.items()):
            f = to_float(v)
            if not math.isnan(f) or v in ("nan", "NaN"):
                r[k] = f
    return rows


def series(rows, config, key="gg_scale"):
    """The rows of one configuration sorted by `key`."""
    out = [r for r in rows if r["config"] == config]
    return sorted(out, key=lambda r: r[key])


def analyse_series(rows, key="gg_scale"):
    """Key numbers of one series (one configuration over increasing `key`), as the paper reads
    its figures: the largest value completed before the first abort, the first abort (value and
    reason) and the value with the minimum mean lap time among the completed runs."""
    completed = [r for r in rows if r["status"] == "completed"]
    aborted = [r for r in rows if r["status"] != "completed"]
    res = {
        "values": [r[key] for r in rows],
        "max_stable": completed[-1][key] if completed else None,
        "first_abort": aborted[0][key] if aborted else None,
        "first_abort_status": aborted[0]["status"] if aborted else None,
        "min_lap_value": None,
        "min_lap_time_s": None,
    }
    if completed:
        best = min(completed, key=lambda r: r["mean_lap_time_s"])
        res["min_lap_value"] = best[key]
        res["min_lap_time_s"] = best["mean_lap_time_s"]
    return res


def row_at(rows, config, value, key="gg_scale"):
    for r in rows:
        if r["config"] == config and abs(r[key] - value) < 1e-9:
            return r
    return None


def write_json(path, obj):
    """Writes obj to path as JSON through a temporary file: a reader sees the old or the new
    file, never half of one."""
    with open(path + ".tmp", "w") as f:
        json.dump(obj, f, indent=2)
    os.replace(path + ".tmp", path)
    return path


def write_summary(study, summary):
    return write_json(os.path.join(results_dir(study), "summary.json"), summary)


def read_summary(study):
    path = os.path.join(paths.RESULTS, study, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def fmt(x, digits=2):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    return f"{x:.{digits}f}"


# Columns of a sweep row kept per run in summary.json (the report is computed from these).
RUN_FIELDS = ("gg_scale", "refined", "status", "progress", "laps_completed", "mean_lap_time_s",
              "max_abs_sideslip_deg", "max_slip_front_pct", "max_slip_rear_pct",
              "max_abs_lateral_error_m", "max_speed_mps", "esc_count", "cs_count", "abs_count",
              "tc_count", "esc_time_s", "cs_time_s", "abs_time_s", "tc_time_s", "end_lap",
              "end_s_m", "max_esc_margin", "steer_hf_rms_deg")
ACTIVATION_KEYS = ("esc_count", "cs_count", "abs_count", "tc_count")
# The terms of ESC's activation condition (sweep columns): |β|/B_a, |e_β,f|/Eβ_a, |e_ψ,f|/Eψ_a,
# each at its largest while the oversteer signs held, and their short names.
ESC_TERMS = ("max_esc_beta_ratio", "max_esc_beta_error_ratio", "max_esc_yaw_rate_error_ratio")
ESC_TERM_NAMES = ("β", "e_β", "e_ψ")


def esc_terms_text(row):
    """The three terms of a run's ESC margin, e.g. "β 2.41 · e_β 0.37 · e_ψ 3.51" ("" if the
    table has none)."""
    vals = [to_float(row.get(k)) for k in ESC_TERMS]
    if any(v != v for v in vals):
        return ""
    return " · ".join(f"{n} {v:.2f}" for n, v in zip(ESC_TERM_NAMES, vals))


def esc_binding_terms(row):
    """The names of the terms that stayed below 1 in a run: each alone kept ESC off."""
    vals = [to_float(row.get(k)) for k in ESC_TERMS]
    return [n for n, v in zip(ESC_TERM_NAMES, vals) if v == v and v < 1.0]


# Abort statuses of study 1 that are the paper's test end (a tyre locks or spins); every other
# abort there is a safety stop (sideslip, lateral error, off track, timeout).
SLIP_STATUSES = ("wheel_lock", "wheel_spin")


def pack_series(rows, key="gg_scale"):
    """analyse_series of one series plus its runs (RUN_FIELDS of each row, in GG order)."""
    rows = sorted(rows, key=lambda r: r[key])
    a = analyse_series(rows, key)
    a["runs"] = [{k: r.get(k) for k in RUN_FIELDS} for r in rows]
    if a["first_abort"] is not None:
        ab = next(r for r in rows if r["status"] != "completed")
        a["first_abort_s_m"] = ab.get("end_s_m")
        a["first_abort_lap"] = ab.get("end_lap")
    return a


def perturbed_series(rows, configs, pert_key, pert_values):
    """{str(pert value): {config: pack_series}} of a sweep varied over gg_scale and pert_key."""
    out = {}
    for v in pert_values:
        sel = [r for r in rows if abs(float(r[pert_key]) - float(v)) < 1e-9]
        out[str(v)] = {c: pack_series([r for r in sel if r["config"] == c]) for c in configs}
    return out


STUDIES = ("study1_longitudinal", "study2_lateral", "study3_motion")


def find_columns(root):
    """[(name, dir, {study: summary})]: experiments/results/columns/<set>__<actuators>/ as
    run_all.sh writes them (shipped set first, vehicle before paper_sim), else the single
    column of studies run directly into experiments/results/."""
    cols = []
    cdir = os.path.join(root, "columns")
    names = sorted(os.listdir(cdir)) if os.path.isdir(cdir) else []
    for n in names:
        d = os.path.join(cdir, n)
        ss = {st: read_summary_in(d, st) for st in STUDIES}
        if any(ss.values()):
            cols.append((n, d, ss))
    if not cols:
        ss = {st: read_summary_in(root, st) for st in STUDIES}
        if any(ss.values()):
            cols.append(("shipped__vehicle", root, ss))

    def order(c):
        info = column_of(c)
        return (info["set_label"] != "shipped", info["set_label"],
                info["actuators"] != "vehicle", info["actuators"])
    return sorted(cols, key=order)


def read_summary_in(d, study):
    path = os.path.join(d, study, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        s = json.load(f)
    if study in STUDIES and "runs" not in s:
        return None  # an older layout (before issue 14) is ignored
    return s


def column_of(col):
    """{set_label, actuators, stability, ...} of a column (from its summaries)."""
    name, _, ss = col
    for s in ss.values():
        if s and s.get("column"):
            return s["column"]
    label, _, act = name.partition("__")
    return {"set_label": label, "actuators": act or "vehicle", "stability": "?"}

