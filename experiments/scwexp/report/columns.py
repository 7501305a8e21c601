"""Each column's details: studies 1-3 with their claims, series, traces and unscored sensitivity
runs."""

from scwexp.claims import (CLAIM_CONFIGS, CORNERS, acts, claim_a, claim_b, claim_c, claim_d,
                           claim_e, claim_f, evaluate, g, where)
from scwexp.report.common import (SENS_NAMES, beta_metric, col_title, figs, prefixed, rel,
                                  slip_metric, timing, verdict)
from scwexp.report.findings import diagnosis, mechanism
from scwexp.report.verdicts import claim_block, detail_table, series_table
from scwexp.results import STUDIES


def sens_verdicts(s, fn, *extra):
    """'40 ms brake: holds; ...' for the sensitivity runs of a study that have the series."""
    parts = []
    for tag, v in s.get("sensitivity", {}).items():
        if extra and not any(n.startswith(f"{extra[0]}_") for ser in v["runs"].values()
                             for n in ser):
            continue
        ok, _ = evaluate(fn, v["runs"], *extra)
        parts.append(f"{SENS_NAMES.get(tag, tag)}: {verdict(ok, scored=False)}")
    return "; ".join(parts)


def column_sections(col, prefix):
    """The detailed sections of one column (as the single-column report had them)."""
    name, _, ss = col
    s1, s2, s3 = (ss.get(st) for st in STUDIES)
    title = col_title(col)
    sections = [f"## Details: {title}", ""]
    if s1:
        sections += _study1_section(s1, title, prefix)
    if s2:
        sections += _study2_section(s2, title, prefix)
    if s3:
        sections += _study3_section(s3, title, prefix)
    return sections


def _study1_section(s1, title, prefix):
    """Study 1's details in a column: claim (a), its series, diagnoses and sensitivity."""
    lab = s1["configs"]
    pl = s1["perturbation"]["label"]
    ok, n, m, blk = claim_block("a", s1["runs"], pl, claim_a)
    sec = [f"### {title} — study 1, longitudinal: slip control on / off "
           f"({s1['controller']}, nominal grip, sensor noise)", "",
           f"{timing(s1)}; main sweep {s1['wall_time_main_s'] / 60:.1f} min. Command: "
           f"`{rel(s1['command'])}`", ""]
    sec += figs(prefixed(s1["figures"], prefix)) + [""]
    sec += series_table(s1["runs"], lab, pl, study1=True) + [""]
    sec += diagnosis(s1, lab, pl)
    sec += [f"#### Claim (a), {title}", ""] + blk + [""]
    if not ok:
        sec += mechanism(s1, ["sc_on", "sc_off"], lab)
    first = next(iter(s1["runs"]))
    sec += [f"Per GG, seed {first}: mean lap or abort · max front/rear slip · ESC/CS/ABS/TC",
            ""] + detail_table(s1["runs"][first], lab, slip_metric, study1=True) + [""]
    sec += sensitivity(s1, lab, pl, [("(a)", claim_a)], slip_metric, study1=True,
                       prefix=prefix)
    return sec


def _study2_section(s2, title, prefix):
    """Study 2's details in a column: claims (b)-(d), series, time series, sensitivity."""
    lab = s2["configs"]
    pl = s2["perturbation"]["label"]
    sec = [f"### {title} — study 2, lateral: none / ESC / CS / ESC + CS "
           f"({s2['controller']}, rear μy reduced in the car only)", "",
           f"{timing(s2)}; main sweep {s2['wall_time_main_s'] / 60:.1f} min. Command: "
           f"`{rel(s2['command'])}`", ""]
    sec += figs(prefixed(s2["figures"][:1], prefix)) + [""]
    sec += series_table(s2["runs"], lab, pl) + [""]
    sec += diagnosis(s2, lab, pl)
    for k, fn in (("b", claim_b), ("c", claim_c), ("d", claim_d)):
        ok, n, m, blk = claim_block(k, s2["runs"], pl, fn)
        sec += [f"#### Claim ({k}), {title}", ""] + blk + [""]
        if not ok:
            sec += mechanism(s2, CLAIM_CONFIGS[k], lab)
    main_p = s2["perturbation"].get("main", next(iter(s2["runs"])))
    sec += [f"Per GG, rear μy {main_p}: mean lap or abort · max |β| · ESC/CS/ABS/TC", ""]
    sec += detail_table(s2["runs"][main_p], lab, beta_metric) + [""]
    tr = s2.get("trace_runs", {})
    if tr:
        sec += [f"First lap at GG {g(s2['trace_gg'])}, rear μy {main_p} (the paper's "
                "time-series figure): " + "; ".join(
                    f"{lab.get(k, k)}: {r['status']}"
                    + (f" at {where(r, CORNERS)}" if r["status"] != "completed" else "")
                    + f", max |β| {r['max_abs_sideslip_deg']:.1f}°, activations {acts(r)}"
                    for k, r in tr.items()), ""]
    sec += figs(prefixed(s2["figures"][1:], prefix)) + [""]
    xt = s2.get("trace_at_none_abort")
    if xt:
        sec += [f"The run at GG {g(xt['gg'])}, where `none` first aborts (rear μy "
                f"{main_p}): " + "; ".join(
                    f"{lab.get(k, k)}: {r['status']}"
                    + (f" at {where(r, CORNERS)}" if r["status"] != "completed" else "")
                    + f", max |β| {r['max_abs_sideslip_deg']:.1f}°, activations "
                    f"{acts(r)}" for k, r in xt["runs"].items()), ""]
        sec += figs(prefixed([xt["figure"]], prefix)) + [""]
    sec += sensitivity(s2, lab, pl, [("(b)", claim_b), ("(c)", claim_c), ("(d)", claim_d)],
                       beta_metric, prefix=prefix)
    return sec


def _study3_section(s3, title, prefix):
    """Study 3's details in a column: claims (e) and (f) per controller, sensitivity."""
    lab = s3["configs"]
    pl = s3["perturbation"]["label"]
    walls = ", ".join(f"{c} {w / 60:.1f} min" for c, w in
                      s3.get("wall_time_per_controller_s", {}).items())
    sec = [f"### {title} — study 3, motion controllers without / with ESC + CS", "",
           f"{timing(s3)}; main sweeps: {walls}.", ""]
    for ctrl, why in s3.get("skipped", {}).items():
        sec.append(f"- skipped `{ctrl}`: {why}")
    sec += [""] + figs(prefixed(s3["figures"], prefix)) + [""]
    sec += series_table(s3["runs"], lab, pl) + [""]
    done = [c for c in s3["controllers"] if c not in s3.get("skipped", {})]
    for k, fn in (("e", claim_e), ("f", claim_f)):
        sec += [f"#### Claim ({k}) (not scored), {title}", ""]
        for ctrl in done:
            ok, n, m, blk = claim_block(k, s3["runs"], pl, fn, ctrl, scored=False)
            sec += [f"`{ctrl}`:", ""] + blk + [""]
    sec += ["Commands: " + "; ".join(f"`{rel(c)}`" for c in s3["commands"]), ""]
    sec += sensitivity(s3, lab, pl, [(f"({k}) `{c}`", fn, c) for c in done
                                     for k, fn in (("e", claim_e), ("f", claim_f))],
                       beta_metric, prefix=prefix)
    return sec


def sensitivity(s, labels, pert_label, claims, metric, study1=False, prefix=""):
    sens = s.get("sensitivity", {})
    if not sens:
        return []
    out = ["### Sensitivity (unscored)", ""]
    for tag, v in sens.items():
        out += [f"**{v['label']}** — wall time {v['wall_time_s'] / 60:.1f} min. Command: "
                f"`{rel(v['command'])}`", ""]
        out += figs(prefixed(v["figures"], prefix)) + [""]
        out += series_table(v["runs"], labels, pert_label, study1) + [""]
        for label, fn, *extra in claims:
            if extra and not any(n.startswith(f"{extra[0]}_") for ser in v["runs"].values()
                                 for n in ser):
                continue  # this variant did not run that controller
            ok, res = evaluate(fn, v["runs"], *extra)
            failed = [f"{p}: " + "; ".join(f"{name} ({text})" for name, iok, text in items
                                           if iok is False)
                      for p, (o, items) in res.items() if not o]
            out.append(f"- claim {label} under this variant: {verdict(ok, scored=False)}" +
                       (f" — failed: {' | '.join(failed)}" if failed else ""))
        first = next(iter(v["runs"]))
        out += ["", f"Per GG ({pert_label} {first}): mean lap or abort · metric · ESC/CS/ABS/TC",
                ""] + detail_table(v["runs"][first], labels, metric, study1) + [""]
    return out
