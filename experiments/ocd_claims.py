#!/usr/bin/env python3
"""The claims of studies 1 and 2 on Open-Car-Dynamics beside scw's plant (issue 49 item 5,
docs/ocd-plant.md): reads study columns run with `--set plant.model=ocd` and judges them with the
report's unchanged criteria (scwexp.claims), next to the same column on scw's plant.

    python3 experiments/study2_lateral.py --set plant.model=ocd --set plant.actuators=paper_sim \\
        --results experiments/results/ocd_columns/shipped__paper_sim --label shipped \\
        --no-report --no-sensitivity
    python3 experiments/ocd_claims.py [--ocd DIR ...] [--scw DIR ...]

    python3 experiments/study2_lateral.py --set plant.actuators=paper_sim \
        --results experiments/results/scw_columns/shipped__paper_sim --label shipped \
        --no-report --no-sensitivity

Study 1 likewise (study1_longitudinal.py with the same options). --ocd: column folders holding
study1_longitudinal/ and study2_lateral/ summaries on OCD (default: every folder under
experiments/results/ocd_columns/); --scw: the same columns on scw's plant, run with the same
binary (default: experiments/results/scw_columns/<same name>, or for run_all.sh's columns
<name>__ocd the folder <name> beside it). Writes claims.md into --out (default
experiments/results/ocd_columns/) and prints it. After `PLANTS="scw ocd" experiments/run_all.sh`:

    python3 experiments/ocd_claims.py --ocd experiments/results/columns/*__ocd \
        --out experiments/results/ocd         (the page the report links)
"""

import argparse
import json
import os

import scwexp  # the standard library only here: no numpy or matplotlib needed

from scwexp import claims as C  # noqa: E402  (the claims' criteria, unchanged)

CLAIMS = (("study1_longitudinal", "a", C.claim_a),
          ("study2_lateral", "b", C.claim_b),
          ("study2_lateral", "c", C.claim_c),
          ("study2_lateral", "d", C.claim_d))


def read_summary(column, study):
    path = os.path.join(column, study, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def judge(fn, runs):
    """(verdict, perturbations where it holds, perturbations): the report's rule, a claim holds
    if it holds in at least two of three perturbations (all of fewer)."""
    res = [fn(ser)[0] for ser in runs.values()]
    known = [ok for ok in res if ok is not None]
    n_ok = sum(1 for ok in known if ok)
    need = 2 if len(res) >= 3 else len(res)
    ok = None if not known else n_ok >= need
    return ok, n_ok, len(res)


def verdict(ok):
    return "not evaluable" if ok is None else ("**reproduced**" if ok else "**NOT reproduced**")


def first_aborts(summary):
    """{configuration: first abort GG} at the study's main perturbation, and that perturbation."""
    main = summary["perturbation"].get("main", next(iter(summary["runs"])))
    ser = summary["runs"][main]
    return {c: C.abort_gg(a) for c, a in ser.items()}, main


def activations(summary):
    """"config ESC/CS/ABS/TC" summed over each configuration's completed runs at the study's main
    perturbation: which subsystem acted in the runs that decide the claims."""
    main = summary["perturbation"].get("main", next(iter(summary["runs"])))
    out = []
    for c, a in summary["runs"][main].items():
        tot = [sum(int(r.get(k) or 0) for r in C.done_runs(a)) for k in scwexp.ACTIVATION_KEYS]
        out.append(f"{c} {'/'.join(str(t) for t in tot)}")
    return ", ".join(out)


OCD_SUFFIX = "__ocd"


def column_name(ocd_dir):
    """The column's name: its folder's, without run_all.sh's "__ocd" suffix."""
    name = os.path.basename(os.path.normpath(ocd_dir))
    return name[:-len(OCD_SUFFIX)] if name.endswith(OCD_SUFFIX) else name


def scw_column(ocd_dir):
    """The same column on scw's plant: run_all.sh's <name> beside <name>__ocd, else
    experiments/results/scw_columns/<name>."""
    ocd_dir = os.path.normpath(ocd_dir)
    if os.path.basename(ocd_dir).endswith(OCD_SUFFIX):
        return ocd_dir[:-len(OCD_SUFFIX)]
    return os.path.join(scwexp.RESULTS, "scw_columns", os.path.basename(ocd_dir))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    base = os.path.join(scwexp.RESULTS, "ocd_columns")
    ap.add_argument("--ocd", nargs="*")
    ap.add_argument("--scw", nargs="*")
    ap.add_argument("--out", default=base, help="folder for claims.md (default: %(default)s)")
    args = ap.parse_args(argv)
    ocd = args.ocd or sorted(os.path.join(base, d) for d in os.listdir(base)
                             if os.path.isdir(os.path.join(base, d)))
    scw = args.scw or [scw_column(d) for d in ocd]
    if len(scw) != len(ocd):
        ap.error(f"--scw names {len(scw)} columns for the {len(ocd)} of --ocd")
    lines = ["| column | plant | (a) | (b) | (c) | (d) | first aborts (main perturbation) | "
             "ESC/CS/ABS/TC in the completed runs |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for o, s in zip(ocd, scw):
        for plant, d in (("scw", s), ("ocd", o)):
            cells, aborts, acts = [], [], []
            for study, key, fn in CLAIMS:
                summ = read_summary(d, study)
                if summ is None:
                    cells.append("not run")
                    continue
                ok, n, m = judge(fn, summ["runs"])
                cells.append(f"{verdict(ok)} ({n} of {m})")
                if key in ("a", "b"):
                    fa, main_p = first_aborts(summ)
                    aborts.append(f"study {study[5]}, {summ['perturbation']['label']} {main_p}: "
                                  + ", ".join(f"{c} {C.g(v)}" for c, v in fa.items()))
                    acts.append(f"study {study[5]}: " + activations(summ))
            lines.append(f"| {column_name(o)} | {plant} | " + " | ".join(cells) + " | "
                         + "; ".join(aborts) + " | " + "; ".join(acts) + " |")
    text = "\n".join(lines) + "\n"
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "claims.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
