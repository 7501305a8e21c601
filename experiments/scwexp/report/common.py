"""What every section of the report shares: verdict words, relative commands and figure links,
column titles, the study metrics of the detail tables."""

import os

from scwexp.claims import steer_hf
from scwexp.paths import ROOT
from scwexp.results import column_of


def verdict(ok, scored=True):
    if ok is None:
        return "**not evaluable**"
    if scored:
        return "**reproduced**" if ok else "**NOT reproduced**"
    return "holds" if ok else "does not hold"


def slip_metric(r):
    return f"slip {r['max_slip_front_pct']:.1f}/{r['max_slip_rear_pct']:.1f} %"


def beta_metric(r):
    return f"β {r['max_abs_sideslip_deg']:.1f}°"


SENS_NAMES = {"brake40ms": "40 ms brake", "old_defaults": "old defaults",
              "no_esc_cs": "ESC + CS off", "esc_hold": "throttle held during ESC"}


def rel(cmd):
    """A command line with the repository root left out of its paths."""
    return cmd.replace(ROOT + "/", "")


def figs(paths):
    return [f"![{os.path.splitext(os.path.basename(p))[0]}]({p})" for p in paths]


def timing(s):
    cpu = s.get("cpu_time_s")
    return (f"wall time {s['wall_time_s'] / 60:.1f} min"
            + (f" (CPU {cpu / 60:.1f} min over 2 cores)" if cpu else ""))


ACT_NAMES = {"vehicle": "real car (vehicle file's actuators)",
             "paper_sim": "paper's simulator (`plant.actuators=paper_sim`)",
             "paper_sim_v1": "paper's simulator as its IV-2024 code "
                             "(`plant.actuators=paper_sim_v1`)"}
ACT_SHORT = {"vehicle": "real car", "paper_sim": "paper's sim", "paper_sim_v1": "paper's sim v1"}


PLANT_SHORT = {"ocd": "OCD"}  # a plant other than scw's is named in the column's title


def col_title(col):
    info = column_of(col)
    plant = PLANT_SHORT.get(info.get("plant", "scw"), "")
    return (f"{info['set_label']} set, {ACT_SHORT.get(info['actuators'], info['actuators'])}"
            + (f", {plant}" if plant else ""))


def prefixed(paths, prefix):
    return [os.path.join(prefix, p) if prefix else p for p in paths]


def steer_hf_text(v):
    x = steer_hf(v)
    return "–" if x is None else f"steering above 1.6 Hz {x:.2f}° RMS"


def from_column(v):
    """(actuator model of the scored column a claims-map variant is nearest to, its changes
    from that column): the paper's simulator's column for a variant that runs its actuators
    (claims_map.nearest_column), else the real-car column (the vehicle file)."""
    if "column_actuators" in v:
        return v["column_actuators"], v.get("column_changes")
    return "vehicle", v.get("changes")
