"""The knife-edge section (study 2): the traced lap at `none`'s first abort, per column."""

from scwexp.claims import CORNERS, g
from scwexp.report.common import ACT_SHORT, col_title
from scwexp.results import column_of


def knife_edge_section(cols, root):
    """Part 3: the traced first lap at the GG where `none` first aborts (study 2), per
    column, from knife_edge.json written by study2_lateral.py."""
    out = []
    for c in cols:
        s2 = c[2].get("study2_lateral")
        ke = s2 and s2.get("knife_edge")
        if not ke:
            continue
        from scwexp import knife_edge
        res = knife_edge.with_statuses(s2)
        lines = [knife_edge.describe(n, s2["configs"].get(n, n), res.get(n), CORNERS,
                                     (res.get(n) or {}).get("status")) for n in s2["configs"]]
        lines.append(knife_edge.verdict_line(res, ACT_SHORT.get(column_of(c)["actuators"])))
        out += [f"### {col_title(c)}: GG {g(ke['gg'])}, rear μy {ke['mu']}", ""]
        out += [f"- {x}" for x in lines] + [""]
    if out:
        out = ["## The mechanism at the knife edge (study 2)", "",
               "At the first GG where `none` aborts (main rear μy), the whole run of each "
               "configuration traced (`scw sweep --trace-dir`; `experiments/knife_edge.py`). "
               "The loss = |β| = 20°, or the run's abort when that comes first (lateral error, "
               "off track); rear saturation t_sat = the time from which the rear axle's mean "
               "slip angle stays beyond the rear tyre's peak slip angle (Magic Formula, nominal "
               "load) until the loss; ESC's brake moment arrives when a wheel's applied pressure "
               "first exceeds both its value when ESC switched on and the motion controller's "
               "request by 10 bar; the bound is the constant yaw moment that removes the largest "
               "yaw-rate excess Δr in the time left after the brake actuator's response: "
               "M ≥ Iz · Δr / (t_loss − t_sat − t_act).", ""] + out
    return out
