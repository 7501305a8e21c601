"""Claim (c) as a quantity: the margin of every series (GG from the best lap to the last stable GG,
and what running past the best lap costs), and what makes the limit a cliff."""

from scwexp.analysis import margin_of
from scwexp.claims import EPS, g, run_at, t3
from scwexp.report.common import col_title
from scwexp.results import STUDIES


def margin_table(cols):
    out = ["| column | study | perturbation | configuration | best lap (GG) | max stable | first "
           "abort | margin GG (steps of 0.05) | lap at max stable − best | ESC activations "
           "above the best | Δ lap vs `none` at `none`'s max stable |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    zero, total = 0, 0
    for col in cols:
        for st in STUDIES:
            s = col[2].get(st)
            if not s:
                continue
            for p, ser in s["runs"].items():
                for n, a in ser.items():
                    m = margin_of(a)
                    if m is None:
                        continue
                    total += 1
                    zero += m["margin_gg"] < EPS
                    dn = "–"
                    if st == "study2_lateral" and n != "none" and "none" in ser:
                        ns = ser["none"]["max_stable"]
                        r0, r1 = run_at(ser["none"], ns), run_at(a, ns)
                        if ns is not None and r1 and r1["status"] == "completed":
                            dn = (f"{r1['mean_lap_time_s'] - r0['mean_lap_time_s']:+.3f} s at "
                                  f"{g(ns)} (ESC {int(r1['esc_count'] or 0)})")
                    out.append(
                        f"| {col_title(col)} | {st.split('_')[0]} | {p} | {n} | "
                        f"{t3(m['lap_best'])} ({g(m['best'])}) | {g(m['stable'])} | "
                        f"{g(m['abort'])} {m['abort_status'] or ''} | {m['margin_gg']:.3f} "
                        f"({m['margin_steps']:.1f}) | {m['cost_s']:+.3f} s | "
                        f"{'/'.join(map(str, m['esc_above'])) or '–'} | {dn} |")
    return out, zero, total


def cliff_mechanism(cols, everywhere):
    """What makes the limit a cliff, from the knife-edge numbers of each column: how long the
    car takes from rear saturation to the loss, against the brake response, and whether ESC's
    pressure reached a wheel in that time."""
    parts = []
    for c in cols:
        s2 = c[2].get("study2_lateral")
        ke = s2 and s2.get("knife_edge")
        if not ke:
            continue
        lost = {n: x for n, x in ke["results"].items() if x and x["spun"] and x["saturated"]}
        if not lost:
            continue
        w = [x["window_s"] for x in lost.values()]
        esc = [n for n in ("esc", "esc+cs") if n in lost]
        arr = [n for n in esc if lost[n]["t_delivered"] is not None and
               lost[n]["t_delivered"] < lost[n]["t20"]]
        parts.append(f"{col_title(c)} (GG {g(ke['gg'])}): {min(w):.2f}–{max(w):.2f} s from rear "
                     f"saturation to the loss in {len(lost)} configuration(s), brake response "
                     f"{ke['t_act'] * 1000:.0f} ms; ESC's pressure reached a wheel before the "
                     f"loss in {len(arr)} of {len(esc)} lost ESC runs")
    if not parts:
        return []
    return ["Mechanism (knife-edge traces below): once the rear axle passes its peak slip angle "
            "at the abort GG, the car is lost within a few tenths of a second — " +
            "; ".join(parts) + "." + (" No series has an intermediate regime in which "
                                     "interventions slow the car without losing it."
                                     if everywhere else ""), ""]
