#!/usr/bin/env python3
"""The mechanism at the knife edge (issue 25 part 3): when ESC and CS act, and what they deliver,
between the rear axle's final saturation and |β| = 20° in study 2 at `none`'s first-abort GG.
The definitions (t20, t_sat, t_act, the yaw-moment bound) are in scwexp.knife_edge's docstring.

The analysis is scwexp.knife_edge (study2_lateral.py runs it after its traces); this command
re-analyses a finished study 2 from the traces it kept:

    python3 experiments/knife_edge.py --reanalyse STUDY2_DIR ...

A configuration that completes at `none`'s first-abort GG is read where `none` lost the car:
the same lap, `none`'s window from rear saturation to the loss, 30 m either side
(CATCH_MARGIN_M): when ESC and CS first acted, for how long, and what they delivered.
"""

import sys

import debpython  # noqa: F401  (first: Debian's numpy/matplotlib, else a re-run with them)
from scwexp.knife_edge import reanalyse  # noqa: E402

if __name__ == "__main__":
    # python3 experiments/knife_edge.py --reanalyse STUDY2_DIR ...
    if len(sys.argv) < 3 or sys.argv[1] != "--reanalyse":
        sys.exit("usage: knife_edge.py --reanalyse STUDY2_DIR ...")
    for d in sys.argv[2:]:
        print(f"{d}: " + ("reanalysed" if reanalyse(d) else "no knife-edge results"))
