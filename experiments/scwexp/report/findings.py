"""Findings computed from all scored runs of a column (its appendix), the diagnosis of each
first abort, and the mechanism behind a failing claim."""

from scwexp.claims import CORNERS, active_count, done_runs, g
from scwexp.track import place
from scwexp.results import ACTIVATION_KEYS


def diagnosis(s, labels, pert_label):
    d = s.get("diagnosis") or {}
    if not d:
        return []
    out = [f"How each first abort happened ({pert_label} {s.get('diagnosis_perturbation')}; "
           "the aborted run re-run with `scw simulate --trace`, the same scenario):", ""]
    for name, x in d.items():
        out.append(f"- {labels.get(name, name)}, GG {g(x['gg'])}, `{x['status']}` "
                   f"({place(x['s_m'], CORNERS)}): {x['text']}.")
    return out + [""]


def mechanism(s, names, labels):
    """Why a claim fails, from the data: how often each subsystem acted in the completed runs
    of the configurations that decide it (all perturbations) and how their first aborts
    happened (the traced re-runs)."""
    out = []
    parts = []
    for n in names:
        d = [r for ser in s["runs"].values() if n in ser for r in done_runs(ser[n])]
        if d:
            parts.append(f"{labels.get(n, n)}: " + ", ".join(
                f"{k.split('_')[0].upper()} {active_count(d, k)}"
                for k in ACTIVATION_KEYS) + f" of {len(d)}")
    if parts:
        out.append("- Completed runs in which each subsystem acted (all perturbations): " +
                   "; ".join(parts) + ".")
    diag = s.get("diagnosis") or {}
    for n in names:
        x = diag.get(n)
        if not x:
            continue
        lead = ", ".join(f"{k.upper()} {x['t_s'] - t:.2f} s"
                         for k, t in x["active_since"].items() if t is not None)
        txt = (f"- {labels.get(n, n)}, first abort GG {g(x['gg'])} "
               f"({s['perturbation']['label']} {s.get('diagnosis_perturbation')}): "
               f"`{x['status']}` at s = {x['s_m']:.0f} m ({place(x['s_m'], CORNERS)}), "
               f"lap {x['lap']}, {x['v_mps']:.0f} m/s; subsystems last switched on (s before "
               f"the abort): {lead or 'none'}; max |β| {x['max_beta_deg']:.1f}°, max |lateral error| "
               f"{x['max_lat_err_m']:.1f} m in the last 2 s")
        if abs(x["wheel_slip_pct"]) >= 50:
            src = "with ESC active" if x["esc_at_peak"] else "ESC not active"
            txt += (f"; {x['wheel']} {'locked' if x['wheel_slip_pct'] < 0 else 'spun'} "
                    f"(slip {x['wheel_slip_pct']:.0f} %) after a commanded "
                    f"{x['wheel_p_peak_bar']:.0f} bar on that wheel ({src}; the motion "
                    f"controller requested {x['wheel_p_req_at_peak_bar']:.0f} bar)")
        out.append(txt + ".")
    if out:
        out.insert(0, "Why (from the data):")
        out.insert(1, "")
        out.append("")
    return out


def findings(s1, s2, s3):
    """Facts over all scored series: how far the GG got, where and why the series ended, how
    often ESC acted before the first abort, what the traced aborts show."""
    from collections import Counter
    series, esc_runs = [], []
    for s, esc_on in ((s1, lambda n: True), (s2, lambda n: "esc" in n),
                      (s3, lambda n: n.endswith("_sc"))):
        if not s:
            continue
        for p, ser in s["runs"].items():
            for n, a in ser.items():
                series.append((s["study"], p, n, a))
                if esc_on(n):
                    esc_runs += done_runs(a)
    if not series:
        return []
    lf = 0.7
    st = [a["max_stable"] for *_, a in series if a["max_stable"] is not None]
    places = Counter(place(a.get("first_abort_s_m"), CORNERS) for *_, a in series
                     if a["first_abort"] is not None)
    statuses = Counter(a["first_abort_status"] for *_, a in series if a["first_abort"])
    out = ["## Findings (computed from all runs of the three studies, sensitivity runs excluded)",
           ""]
    if st:
        out.append(f"- Max stable GG over the {len(series)} series of the studies: {min(st):.2f}–"
                   f"{max(st):.2f}, i.e. {100 * lf * min(st):.0f}–{100 * lf * max(st):.0f} % of "
                   "the combined limits (GG 1.43 = 100 %); "
                   f"{sum(1 for *_, a in series if a['max_stable'] is None)} series did not "
                   "complete GG 1.0.")
    out.append("- First aborts by reason: " + ", ".join(f"{k} {v}" for k, v in
                                                       statuses.most_common()) +
               "; by place: " + ", ".join(f"{k} {v}" for k, v in places.most_common()) + ".")
    if esc_runs:
        n = active_count(esc_runs, "esc_count")
        out.append(f"- ESC acted in {n} of {len(esc_runs)} completed runs with ESC enabled "
                   "(studies 1–3)" + (": its interventions happen almost only in the runs that "
                                      "abort." if n < 0.25 * len(esc_runs) else "."))
    diags = [x for s in (s1, s2) if s for x in (s.get("diagnosis") or {}).values()]
    locks = [x for x in diags if x["wheel_slip_pct"] <= -50 and x["esc_at_peak"]]
    leads = [x["t_s"] - x["active_since"]["esc"] for x in diags
             if x["active_since"].get("esc") is not None]
    if diags:
        txt = (f"- Of the {len(diags)} traced first aborts (studies 1–2), {len(locks)} end with a "
               "wheel locked after an ESC brake command the motion controller did not request")
        if locks:
            txt += (f" ({min(x['wheel_p_peak_bar'] for x in locks):.0f}–"
                    f"{max(x['wheel_p_peak_bar'] for x in locks):.0f} bar)")
        if leads:
            txt += (f"; where ESC acted, it switched on {min(leads):.2f}–{max(leads):.2f} s before "
                    "the abort (brake response 150 ms)")
        out.append(txt + ".")
    return out + [""]

