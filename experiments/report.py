#!/usr/bin/env python3
"""Builds experiments/results/report.md from the studies' summary.json files: one page first
(at most 60 lines: the verdict of each claim per parameter set and actuator model, one sentence
per claim on where it holds and what blocks it, figures A-C under page/), then the appendices
under appendix/: the method and the claims' criteria (written before the numbers), every claim
side by side with where it reproduces and claim (d)'s premise, one file per column (findings,
margins, knife edge, studies 1-3 in detail) and one per claims map. No table cell over 200
characters, no line over 400.

    python3 experiments/report.py                      (after the studies; each study runs it)
    python3 experiments/report.py --results DIR        (the studies under DIR, the report there)
    python3 experiments/report.py --publish experiments/reference-results
        (also copies report.md, appendix/ and the figures they link there, same relative paths)

The report itself is the package scwexp.report, one module per section; this file is its only
entry point and the only file that imports it.
"""Builds experiments/results/report.md from the studies' summary.json files: what was changed
to run the studies as the paper did, the explicit pass criterion of each claim of the paper
(written before the numbers), the verdict per perturbation and overall (a claim holds if it holds
in at least two of three perturbations), the mechanism seen in the data where a claim fails, the
figures with the subsystem activation counts beside them, and the unscored sensitivity runs.

    python3 experiments/report.py                      (after the studies; each study runs it)
    python3 experiments/report.py --publish experiments/reference-results
        (also copies report.md and the figures it links there, same relative paths)

The report itself is the package scwexp.report, one module per section; this file is its only
entry point and the only file that imports it.

The sections: the changes made to run the studies as the paper did, the method (GG axis,
actuator models, sets), every claim per set and actuator model side by side with activation
counts, where each claim reproduces (or which claims-map variant flips it) with claim (d)'s
premise (esc_margin.py), the sets overlaid in one figure per study and actuator model, the
margin of every series (claim (c) as a quantity), the knife-edge account, the claims maps, then
per column the details: criteria before the numbers, verdicts per perturbation, the mechanism of
each failure, figures with activation counts, sensitivity runs.
"""

import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
from scwexp.report import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
