#!/usr/bin/env python3
"""The mechanism at the knife edge (issue 25 part 3): from the traced first lap of each study-2
configuration at the GG where `none` first aborts, the time from the start of the rear axle's
final saturation to |β| = 20°, when ESC and CS first act and what they deliver, against a simple
bound of the yaw moment that would be needed in that time.

Definitions (stated in the report):
- t20: the first time |β| ≥ 20°, or the abort when the run ends otherwise (lateral error, off
  track: the car was lost before |β| reached 20°), or the end of a completed run;
- t_sat: the first rear saturation of the final divergence: the time from which the rear
  axle's mean |slip angle| stays at or beyond the rear tyre's peak slip angle (Magic Formula,
  nominal load) until t20;
- ESC's brake moment arrives when, with ESC active, a wheel's applied pressure first exceeds
  both its value when ESC switched on and the motion controller's request by 10 bar;
- the actuator's response t_act: the brake's dead time + lag (the vehicle file's, or ~0 for
  paper_sim), the time before a brake command can build a yaw moment;
- the bound: M_needed = Iz · Δr_max / (t20 − t_sat − t_act), with Δr_max the largest yaw-rate
  excess |r − r_ref| in [t_sat, t20]: the constant moment that removes that excess in the time
  left once the brakes respond; infinite when no time is left.

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
