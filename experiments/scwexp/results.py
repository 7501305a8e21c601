"""Results of the studies: the sweep tables scw writes and the summaries the studies keep
(summary.json), read and written as plain dicts by the scripts, and loaded as typed records for
re-analysis without a rerun (`load`, `load_columns`).

    import scwexp.results as R
    s = R.load("experiments/reference-results/columns/shipped__vehicle/study2_lateral")
    print(s.loss_curve("none"))      # [(gg, n, lost, p, low, high)]: P(loss | GG), Wilson 95 %

Standard library only.
"""

import csv
import dataclasses
import glob
import gzip
import json
import math
import os
from typing import Any, Mapping, Optional

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
              "end_s_m", "max_esc_margin", "max_esc_beta_error_ratio", "steer_hf_rms_deg")
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
                info.get("plant", "scw") != "scw", info["actuators"] != "vehicle",
                info["actuators"])
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
    parts = name.split("__")
    for s in ss.values():
        if s and s.get("column"):
            info = dict(s["column"])
            # a summary written before the plant was recorded: the folder name says it
            info.setdefault("plant", parts[2] if len(parts) > 2 else "scw")
            return info
    return {"set_label": parts[0], "actuators": parts[1] if len(parts) > 1 else "vehicle",
            "plant": parts[2] if len(parts) > 2 else "scw", "stability": "?"}


# ---------------------------------------------------------------------------------------------
# Typed records and their loader: a study's folder (summary.json and its sweep tables) read
# without running anything, every rule checked with the file, the row or key and the rule named.

class ResultsError(ValueError):
    """Bad input to `load`: the message names the file, the row or key, and the rule."""


@dataclasses.dataclass(frozen=True)
class Run:
    """One scored run of a series (RUN_FIELDS of its sweep row, as kept in summary.json).
    mean_lap_time_s is NaN for a run that did not complete; a field the summary lacks (an older
    layout) is None."""
    gg_scale: float
    status: str
    refined: bool
    mean_lap_time_s: float
    values: Mapping[str, Any]   # every field of the run, as stored

    @property
    def lost(self):
        """The run ended in an abort (any status but `completed`)."""
        return self.status != "completed"

    def get(self, key, default=None):
        return self.values.get(key, default)


@dataclasses.dataclass(frozen=True)
class Series:
    """One configuration at one perturbation value, in GG order, up to its first abort."""
    config: str
    perturbation: str
    runs: tuple
    max_stable: Optional[float]
    first_abort: Optional[float]
    first_abort_status: Optional[str]
    min_lap_value: Optional[float]
    min_lap_time_s: Optional[float]


@dataclasses.dataclass(frozen=True)
class SweepRow:
    """One row of a sweep table (`scw sweep -o`): numbers as float (NaN where scw wrote nan),
    text as str. gg_scale is None in a table that varies it through the configurations (the
    bisection sweeps: `r<i>:...,gg_scale=G`) when no recorded command names it."""
    source: str
    line: int
    config: str
    status: str
    gg_scale: Optional[float]
    mean_lap_time_s: float
    values: Mapping[str, Any]

    @property
    def lost(self):
        return self.status != "completed"


@dataclasses.dataclass(frozen=True)
class Study:
    """A study's results: its summary (raw, and its series as records) and its sweep tables."""
    path: str
    name: str
    column: Mapping[str, Any]
    perturbation: Mapping[str, Any]
    series: Mapping[tuple, Series]    # (perturbation value, config) -> Series
    sweeps: Mapping[str, tuple]       # table file name -> (SweepRow, ...)
    summary: Mapping[str, Any]

    def configs(self):
        return sorted({c for _, c in self.series})

    def loss_curve(self, config, perturbation=None):
        """P(loss | GG) of one configuration: [(gg, n, lost, p, low, high)] with Wilson's 95 %
        interval (analysis.loss_curve), over every run of its series (at one perturbation value
        when given, else all of them)."""
        from scwexp import analysis
        pairs = [(r.gg_scale, r.lost) for (pv, c), s in sorted(self.series.items())
                 if c == config and (perturbation is None or pv == str(perturbation))
                 for r in s.runs]
        if not pairs:
            raise KeyError(f"{self.path}: no runs of configuration {config!r}")
        return analysis.loss_curve(pairs)

    def sweep_loss_curve(self, config, table=None, **where):
        """P(loss | GG) from the sweep tables' rows instead of the summary's series: every row of
        `config` that has a GG (of `table` only, when given) and whose columns equal `where`
        (e.g. **{"grip.rear_mu_y": 0.8}). A table without --stop-at-first-abort (seeded runs
        over the whole grid) holds the runs above a series' first abort too."""
        from scwexp import analysis
        pairs = [(r.gg_scale, r.lost) for name, rows in sorted(self.sweeps.items())
                 if table in (None, name) for r in rows
                 if r.config == config and r.gg_scale is not None
                 and all(r.values.get(k) == v for k, v in where.items())]
        if not pairs:
            raise KeyError(f"{self.path}: no sweep rows of configuration {config!r} with {where}")
        return analysis.loss_curve(pairs)


def _number(value, where, required=True, finite=True):
    """value as a float; ResultsError naming `where` when it is missing (required), not a
    number, or NaN/infinite where a finite number is required."""
    if value is None or value == "":
        if required:
            raise ResultsError(f"{where}: missing; a number is required")
        return None
    if isinstance(value, bool):
        raise ResultsError(f"{where}: {value!r} is not a number")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ResultsError(f"{where}: {value!r} is not a number") from None
    if finite and not math.isfinite(x):
        raise ResultsError(f"{where}: {value!r} where a finite number is required")
    return x


def _run(d, where):
    if not isinstance(d, dict):
        raise ResultsError(f"{where}: expected an object with the run's fields")
    status = d.get("status")
    if not isinstance(status, str) or not status:
        raise ResultsError(f"{where}.status: missing or not text; a run's status is required")
    gg = _number(d.get("gg_scale"), f"{where}.gg_scale")
    lap = _number(d.get("mean_lap_time_s"), f"{where}.mean_lap_time_s",
                  required=status == "completed", finite=status == "completed")
    return Run(gg, status, bool(d.get("refined") or 0), math.nan if lap is None else lap,
               dict(d))


def _series(d, config, pv, where):
    if not isinstance(d, dict) or not isinstance(d.get("runs"), list):
        raise ResultsError(f"{where}: expected a series with a list of runs")
    runs = tuple(_run(r, f"{where}.runs[{i}]") for i, r in enumerate(d["runs"]))
    if any(b.gg_scale < a.gg_scale for a, b in zip(runs, runs[1:])):
        raise ResultsError(f"{where}.runs: not in GG order; a series' runs are sorted by GG")

    def opt(key):
        return _number(d.get(key), f"{where}.{key}", required=False)
    return Series(config, pv, runs, opt("max_stable"), opt("first_abort"),
                  d.get("first_abort_status"), opt("min_lap_value"), opt("min_lap_time_s"))


def _open_text(path):
    if path.endswith(".gz"):
        return gzip.open(path, "rt", newline="", encoding="utf-8")
    return open(path, newline="", encoding="utf-8")


def _recorded_gg(path):
    """{config: gg_scale} from the command recorded beside a sweep table (`<table>.cmd`,
    reuse_or_run), for the tables that vary GG through named configurations."""
    side = (path[:-3] if path.endswith(".gz") else path) + ".cmd"
    if not os.path.exists(side):
        return {}
    with open(side, encoding="utf-8") as f:
        words = f.read().split("\n")
    out = {}
    for w, nxt in zip(words, words[1:]):
        if w == "--config" and ":" in nxt:
            name, ov = nxt.split(":", 1)
            kv = dict(x.split("=", 1) for x in ov.split(",") if "=" in x)
            if "gg_scale" in kv:
                out[name] = to_float(kv["gg_scale"])
    return out


def read_sweep(path):
    """The rows of one sweep table (CSV, or CSV compressed with gzip: `.csv.gz`) as SweepRows.
    Rules: the columns config, status and mean_lap_time_s are present; gg_scale, where the table
    has it, is a finite number in every row; mean_lap_time_s is a finite number in every
    completed row (NaN, as scw writes it, only in an aborted one)."""
    name = os.path.basename(path)
    with _open_text(path) as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames or []
        for col in ("config", "status", "mean_lap_time_s"):
            if col not in header:
                raise ResultsError(f"{path}: no column {col!r}; a sweep table has config, "
                                   "status and mean_lap_time_s")
        recorded = {} if "gg_scale" in header else _recorded_gg(path)
        rows = []
        for i, r in enumerate(reader, start=2):
            if None in r or any(v is None for v in r.values()):
                raise ResultsError(f"{path}: row {i}: {len(header)} columns expected")
            where = f"{path}: row {i} (config {r['config']})"
            if not r["status"]:
                raise ResultsError(f"{where}: empty status; every run has one")
            vals = {k: (to_float(v) if not math.isnan(to_float(v)) or v in ("nan", "NaN")
                        else v) for k, v in r.items()}
            gg = _number(r["gg_scale"], f"{where}: column gg_scale") if "gg_scale" in r \
                else recorded.get(r["config"])
            done = r["status"] == "completed"
            lap = _number(r["mean_lap_time_s"], f"{where}: column mean_lap_time_s",
                          required=done, finite=done)
            rows.append(SweepRow(name, i, r["config"], r["status"], gg,
                                 math.nan if lap is None else lap, vals))
    return tuple(rows)


def _summary(path):
    try:
        with open(path, encoding="utf-8") as f:
            s = json.load(f)
    except json.JSONDecodeError as e:
        raise ResultsError(f"{path}: not JSON ({e})") from None
    if not isinstance(s, dict):
        raise ResultsError(f"{path}: expected a JSON object")
    return s


def _sweep_files(d):
    """The sweep tables of a study folder: sweep*.csv, else sweep*.csv.gz of the same name."""
    plain = sorted(glob.glob(os.path.join(d, "sweep*.csv")))
    packed = [p for p in sorted(glob.glob(os.path.join(d, "sweep*.csv.gz")))
              if p[:-3] not in plain]
    return sorted(plain + packed)


def load(path):
    """A study's results as a Study: `path` is the study's folder (or its summary.json) holding
    summary.json and its sweep tables (sweep*.csv, each possibly gzip-compressed as .csv.gz).
    Studies 1-3 need `runs` ({perturbation value: {config: series}}); every series' runs need a
    status and a finite gg_scale, and a finite mean_lap_time_s when completed. Raises
    ResultsError naming the file, the row or key, and the rule broken."""
    d = os.path.dirname(path) if os.path.basename(path) == "summary.json" else path
    spath = os.path.join(d, "summary.json")
    if not os.path.isdir(d):
        raise ResultsError(f"{d}: no such folder")
    if not os.path.exists(spath):
        raise ResultsError(f"{spath}: missing; a study's folder holds its summary.json")
    s = _summary(spath)
    name = s.get("study") or os.path.basename(os.path.normpath(d))
    runs = s.get("runs")
    if name in STUDIES and not isinstance(runs, dict):
        raise ResultsError(f"{spath}: key 'runs' missing or not an object; studies 1-3 keep "
                           "{perturbation value: {config: series}}")
    series = {}
    for pv, by_cfg in (runs or {}).items():
        if not isinstance(by_cfg, dict):
            raise ResultsError(f"{spath}: runs[{pv!r}]: expected {{config: series}}")
        for cfg, a in by_cfg.items():
            series[(pv, cfg)] = _series(a, cfg, pv, f"{spath}: runs[{pv!r}][{cfg!r}]")
    sweeps = {os.path.basename(p): read_sweep(p) for p in _sweep_files(d)}
    return Study(d, name, s.get("column") or {}, s.get("perturbation") or {}, series, sweeps, s)


def load_columns(root):
    """{column name: {study: Study}} of every column under root/columns/ (run_all.sh's layout,
    e.g. experiments/reference-results), each study that has a summary.json."""
    out = {}
    cdir = os.path.join(root, "columns")
    if not os.path.isdir(cdir):
        raise ResultsError(f"{cdir}: no such folder; expected one folder per column")
    for n in sorted(os.listdir(cdir)):
        studies = {st: load(os.path.join(cdir, n, st)) for st in sorted(os.listdir(
            os.path.join(cdir, n))) if os.path.exists(os.path.join(cdir, n, st, "summary.json"))}
        if studies:
            out[n] = studies
    return out
