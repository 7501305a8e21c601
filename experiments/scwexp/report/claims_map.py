"""The claims maps' section: one map per parameter set, what decides each claim."""

import os

from scwexp.report.common import figs
from scwexp.results import read_summary_in


def claims_maps(root):
    """Every claims map under `root`: the shipped set's (claims_map/) first, then one per other
    set (claims_map_<set>/), each with its folder name under "dir"."""
    names = sorted(d for d in os.listdir(root) if d.startswith("claims_map")) \
        if os.path.isdir(root) else []
    names.sort(key=lambda d: d != "claims_map")
    maps = []
    for d in names:
        cm = read_summary_in(root, d)
        if cm:
            maps.append(dict(cm, dir=d, set_label=cm.get("set_label", "shipped")))
    return maps


def claims_map_section(root):
    out = []
    for cm in claims_maps(root):
        out += claims_map_lines(cm)
    return out


def claims_map_lines(cm):
    """One claims map: what it found, its time, figures and table."""
    title = "# Claims map: what decides each claim (issue 25 part 2)" \
        if cm["dir"] == "claims_map" else f"# Claims map with the {cm['set_label']} set"
    out = [title, "", cm.get("text", ""), "", f"Wall time {cm['wall_time_s'] / 60:.1f} min, "
           f"CPU {cm.get('cpu_time_s', 0) / 60:.1f} min; sweeps: "
           f"{len(cm.get('commands', []))}"
           + (f", of which {len(cm['reused'])} read from an earlier run of the same commands "
              "(`--reuse`; their cost is not in these times: experiments/README.md)"
              if cm.get("reused") else "") + ".", ""]
    out += figs([os.path.join(cm["dir"], x) for x in cm.get("figures", [])]) + [""]
    out += cm.get("table", []) + [""]
    return out
