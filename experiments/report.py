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
"""

import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
from scwexp.report import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
