#!/usr/bin/env python3
"""Study 2's claims (b)-(d) on Open-Car-Dynamics beside scw's plant (issue 49 item 5,
docs/ocd-plant.md): reads study-2 columns run with `--set plant.model=ocd` and judges them with
the report's unchanged criteria (experiments/report.py), next to the same column on scw's plant.

    python3 experiments/study2_lateral.py --set plant.model=ocd --set plant.actuators=paper_sim \\
        --results experiments/results/ocd_columns/shipped__paper_sim --label shipped \\
        --no-report --no-sensitivity
    python3 experiments/ocd_claims.py [--ocd DIR ...] [--scw DIR ...]

    python3 experiments/study2_lateral.py --set plant.actuators=paper_sim \
        --results experiments/results/scw_columns/shipped__paper_sim --label shipped \
        --no-report --no-sensitivity

--ocd: column folders holding study2_lateral/summary.json on OCD (default: every folder under
experiments/results/ocd_columns/); --scw: the same columns on scw's plant, run with the same
binary (default: experiments/results/scw_columns/<same name>). Writes
experiments/results/ocd_columns/claims.md and prints it.
"""

import argparse
import os

import scwexp  # first: picks Debian's numpy/matplotlib, Agg backend
import report  # noqa: E402  (the claims' criteria, unchanged)

CLAIMS = (("b", report.claim_b), ("c", report.claim_c), ("d", report.claim_d))


def judge(summary):
    pl = summary["perturbation"]["label"]
    out = {}
    for key, fn in CLAIMS:
        ok, n, m, _ = report.claim_block(key, summary["runs"], pl, fn)
        out[key] = (ok, n, m)
    return out


def first_aborts(summary):
    main = summary["perturbation"].get("main", next(iter(summary["runs"])))
    ser = summary["runs"][main]
    return {c: report.abort_gg(a) for c, a in ser.items()}, main


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    base = os.path.join(scwexp.RESULTS, "ocd_columns")
    ap.add_argument("--ocd", nargs="*")
    ap.add_argument("--scw", nargs="*")
    args = ap.parse_args(argv)
    ocd = args.ocd or sorted(os.path.join(base, d) for d in os.listdir(base)
                             if os.path.isdir(os.path.join(base, d, "study2_lateral")))
    ref = os.path.join(scwexp.RESULTS, "scw_columns")
    scw = args.scw or [os.path.join(ref, os.path.basename(d)) for d in ocd]
    lines = ["| column | plant | claim (b) | claim (c) | claim (d) | first abort GG (main "
             "perturbation): none / ESC / CS / ESC + CS |", "| --- | --- | --- | --- | --- | --- |"]
    for o, s in zip(ocd, scw):
        for plant, d in (("scw", s), ("ocd", o)):
            summ = report.read_summary_in(d, "study2_lateral")
            if summ is None:
                lines.append(f"| {os.path.basename(d)} | {plant} | no study2_lateral/summary.json "
                             "| | | |")
                continue
            v = judge(summ)
            fa, main_p = first_aborts(summ)
            cells = [f"{report.verdict(ok)} ({n} of {m})" for ok, n, m in v.values()]
            aborts = " / ".join(report.g(fa.get(c)) if fa.get(c) is not None else "none"
                                for c in ("none", "esc", "cs", "esc+cs"))
            lines.append(f"| {os.path.basename(o)} | {plant} | " + " | ".join(cells)
                         + f" | {aborts} (rear μy {main_p}) |")
    text = "\n".join(lines) + "\n"
    os.makedirs(base, exist_ok=True)
    with open(os.path.join(base, "claims.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
