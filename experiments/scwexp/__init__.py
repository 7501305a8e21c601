"""The experiments' library (issue 48 item 5): find and run `scw`, read and write its results,
judge the paper's claims, analyse and plot; the drivers (experiments/<study>.py) and the report
(experiments/report.py, scwexp.report) build on it, never the other way round.

    paths     where the scw binary and the results are (RESULTS, ROOT_RESULTS, find_scw)
    runner    running scw: commands, sweeps reused by their recorded command, the track's corners
    sweeps    a study's sweep: the GG axis, each series' first abort bisected, probe runs
    results   sweep tables and summaries as dicts; typed records and their loader (`load`)
    claims    the paper's claims (a)-(f) as pure functions over series
    studies   the three studies' definitions (configurations, overrides, perturbations)
    claims_map  the claims map's families, edited vehicle files, variants and verdicts
    esc_margin  claim (d)'s premise: judged GG, the band at `none`'s loss, probes, table
    analysis  statistics: P(loss | GG) with Wilson intervals, margins, claim (d)'s premise
    diagnose  an aborted run re-run with a trace and described
    track     the track's corners (`scw track info`) and places on it (T1, braking into ...)
    knife_edge  the mechanism at the knife edge from traces
    plots     the studies' figures; trace_plot: one or more traces over distance or time
    study     what every study driver shares: its options, its column, its end

`import scwexp` keeps the flat names the scripts use (scwexp.run, scwexp.read_csv, ...). Only
plots and trace_plot need numpy and matplotlib (Debian's python3-numpy and python3-matplotlib;
they select the non-interactive Agg backend); everything else, the loader included, is the
Python standard library. The drivers import `debpython` first: without numpy and matplotlib
they re-run themselves with Debian's /usr/bin/python3.
"""

from scwexp import paths, sweeps
from scwexp.diagnose import diagnose_abort, diagnose_series
from scwexp.paths import (BINARY_CANDIDATES, HERE, ROOT, find_scw, results_dir,
                          set_results)
from scwexp.results import (ACTIVATION_KEYS, ESC_TERM_NAMES, ESC_TERMS,
                            RUN_FIELDS, SLIP_STATUSES, SPIN_STATUSES, analyse_series,
                            esc_binding_terms, esc_terms_text, fmt, pack_series,
                            perturbed_series, read_csv, read_summary, row_at, series, to_float,
                            write_json, write_summary)
from scwexp.runner import (REUSED, Timer, brake_40ms_vehicle, list_controllers,
                           mpc_sweep_cmd, reuse_or_run, run, sweep_cmd, threads_arg)
from scwexp.study import (add_common_args, apply_common_args, column_info,
                          finish_study, update_report)
from scwexp.sweeps import (GG_AXIS, GG_STEP, cut_at_first_abort,
                           refine_first_aborts, series_bounds, study_sweep)
from scwexp.track import CORNER_NAMES, place, track_corners

# The flat names of the scripts (the module scwexp.py they used before the package); also
# scwexp.mark_aborts (matplotlib, on first use) and the live settings below.
__all__ = ["ACTIVATION_KEYS", "BINARY_CANDIDATES", "CORNER_NAMES", "ESC_TERMS", "ESC_TERM_NAMES",
           "GG_AXIS", "GG_STEP", "HERE", "REUSED", "ROOT", "RUN_FIELDS", "SLIP_STATUSES",
           "SPIN_STATUSES", "Timer", "add_common_args", "analyse_series", "apply_common_args",
           "brake_40ms_vehicle", "column_info", "cut_at_first_abort", "diagnose_abort",
           "diagnose_series", "esc_binding_terms", "esc_terms_text", "find_scw", "finish_study",
           "fmt", "list_controllers", "mpc_sweep_cmd", "pack_series",
           "perturbed_series", "place", "read_csv", "read_summary", "refine_first_aborts",
           "results_dir", "reuse_or_run", "row_at", "run", "series", "series_bounds", "set_results",
           "study_sweep", "sweep_cmd", "threads_arg", "to_float", "track_corners", "update_report",
           "write_json", "write_summary"]

# Settings that change while a script runs (--results, --refine) live in their module; these
# names read them there.
_LIVE = {"RESULTS": paths, "ROOT_RESULTS": paths, "REFINE_LEVELS": sweeps}


def __getattr__(name):
    if name in _LIVE:
        return getattr(_LIVE[name], name)
    if name == "mark_aborts":  # a figure helper: matplotlib only when asked for
        from scwexp.plots import mark_aborts
        return mark_aborts
    raise AttributeError(f"module 'scwexp' has no attribute {name!r}")
