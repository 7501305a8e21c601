"""The sets overlaid: one figure per study and actuator model."""

import os

from scwexp.report.common import ACT_NAMES
from scwexp.results import STUDIES, column_of


# ---------------------------------------------------------------------------------------------
# Figures overlaying the parameter sets (one figure per study and actuator model)

SET_STYLES = ["-", "--", ":", "-."]
CONFIG_COLORS = {"sc_on": "tab:blue", "sc_off": "tab:red", "none": "tab:gray", "esc": "tab:red",
                 "cs": "tab:blue", "esc+cs": "tab:purple", "pure_pursuit_off": "tab:blue",
                 "pure_pursuit_sc": "tab:cyan", "pmpc_off": "tab:orange", "pmpc_sc": "tab:brown",
                 "nmpc_off": "tab:green", "nmpc_sc": "tab:olive"}


def overlay_figures(cols, root):
    from scwexp import plots
    out = []
    acts_ = []
    for c in cols:
        a = column_of(c)["actuators"]
        if a not in acts_:
            acts_.append(a)
    top = {"study1_longitudinal": ([("max_slip_front_pct", None, ", front")],
                                   "max front slip [%]", None),
           "study2_lateral": ([("max_abs_sideslip_deg", None, "")], "max |β| [deg]", 20.0),
           "study3_motion": ([("max_abs_sideslip_deg", None, "")], "max |β| [deg]", 20.0)}
    os.makedirs(os.path.join(root, "overlay"), exist_ok=True)
    for st in STUDIES:
        for act in acts_:
            mine = [c for c in cols if column_of(c)["actuators"] == act and c[2].get(st)]
            if not mine:
                continue
            perts = list(mine[0][2][st]["runs"])
            panels, lines = [], []
            for p in perts:
                merged = {}
                for c in mine:
                    lab = column_of(c)["set_label"]
                    for n, a in c[2][st]["runs"].get(p, {}).items():
                        merged[f"{lab}:{n}"] = a
                panels.append((f"{mine[0][2][st]['perturbation']['label']} {p}", merged))
            for i, c in enumerate(mine):
                lab = column_of(c)["set_label"]
                for n, label in c[2][st]["configs"].items():
                    lines.append((f"{lab}:{n}", f"{label} ({lab})", CONFIG_COLORS.get(n, "k"),
                                  SET_STYLES[i % len(SET_STYLES)]))
            path = os.path.join(root, "overlay", f"{st}_{act}.png")
            plots.plot_grid(panels, lines, top[st][0], top[st][1], path,
                                f"{st.replace('_', ' ')}, {ACT_NAMES.get(act, act)}: sets "
                                "overlaid (" + ", ".join(
                                    f"{column_of(c)['set_label']} {SET_STYLES[i % 4]}"
                                    for i, c in enumerate(mine)) + ")", hline=top[st][2])
            out.append(os.path.relpath(path, root))
    return out
