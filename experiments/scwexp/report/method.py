"""The report's method sections: what had to change to run the studies as the paper did, the GG
axis, the actuator models, the time per column and the parameter sets with their provenance."""

import os

from scwexp import sweeps
from scwexp.paths import ROOT
from scwexp.report.common import col_title
from scwexp.results import column_of
from scwexp.sweeps import GG_AXIS


CHANGES = """\
## What had to change to run the studies as the paper did

The car's shipped stability parameters (`params/stability/default.yaml`) are used unchanged in
every run. Everything below was fixed before any claim was evaluated
(design note: `../shared/spec/closed-loop-fidelity.md` §8–9):

1. **Plant recalibrated against public EAV data** (`docs/plant-calibration.md`): tyre friction
   μx ≈ μy ≈ 1.5 at nominal load (the shipped file had μx ≈ 1.0 against μy ≈ 1.4), positive
   understeer gradient at all speeds, brake actuator 150 ms total response (116 ms dead time +
   32 ms lag + rate limit; the paper's "about 150 ms"), LSD; full-limit lap 61.3 s.
2. **The planner and the MPCs use the plant's own combined g-g-v envelope** (drive and brake
   exponents fitted per speed inside the quasi-steady double-track envelope) instead of one
   exponent between pure limits, which asked a rear-driven car for drive it could not deliver at
   corner exits (`docs/plant-calibration.md`, "The planner's envelope").
3. **GG mapping**: `limit_fraction` 0.7, so GG 1.43 is 100 % of the limits and the studied range
   crosses them.
4. **Scenario as the paper**: studies 1 and 2 with the point-mass MPC (`pmpc`; ~1.5 s per lap,
   sweeps in worker processes); the rear-grip reduction only in the simulated car
   (`plan_with_nominal_grip=true`); study 1 ends a series only when a tyre begins to lock or spin
   (slip < −50 % or > +30 % for ≥ 0.1 s: `abort.lock_slip_pct=50`, `abort.spin_slip_pct=30`,
   `abort.slip_time=0.1`, all existing keys); there the lateral-error abort is lifted
   (`abort.max_lateral_error=100`, the largest allowed) and |β| > 20°, leaving the track or the
   time-out end a run as a *safety stop*, reported apart from lock and spin;
   3 perturbations per study, a claim holding in ≥ 2 of 3.
5. Not changed: the car's stability parameters, the ESC's yaw reference (the MPCs publish their
   planned a_y; pure pursuit the car node's feedback curvature × v², `motion.esc_target`).
6. **Two actuator models, both scored** (issue 25): the vehicle file's actuators (the real car)
   and the paper's simulator's (`plant.actuators=paper_sim`); every parameter set is run with
   both, side by side.
"""

def method_section(cols):
    info = [column_of(c) for c in cols]
    sets = []
    for x in info:
        if (x["set_label"], x.get("stability")) not in sets:
            sets.append((x["set_label"], x.get("stability")))
    out = ["## Method: GG axis, actuator models, parameter sets", "",
           f"- **GG axis (issue 25 part 6), fixed before any run, the same for every "
           f"configuration, set and actuator model:** {GG_AXIS} (start 1.0 = 70 % of the "
           "combined limits, step 0.05); each series stops at its first abort, which is then "
           f"resolved by {info[0].get('refine_levels', sweeps.REFINE_LEVELS) if info else 1} "
           "round(s) of bisection between the last completed GG and the abort (0.025). A "
           "bisected run belongs to its series like any other; the claims' thresholds (0.05 "
           "GG, 0.05 s, …) are those written before the numbers. Where P5 asks what a "
           "configuration did at another series' bisected first abort, the configuration is "
           "run at that GG too (a probe run), unless it aborted below it.",
           "- **Actuator models**: each study is scored twice, with the vehicle file's actuators "
           "(*real car*: brake 116 ms dead time + 32 ms lag + 1800 bar/s, steering 30 ms + 30 ms) "
           "and with `plant.actuators=paper_sim` (*paper's simulator*: Open-Car-Dynamics' "
           "published actuation, no brake-pressure dynamics, steering 60 ms dead time + 60 ms "
           "PT1 at 0.5 rad/s; `docs/plant-calibration.md`), passed as `--set` to every sweep. "
           "The claims maps add the same simulator as its IV-2024 code had it "
           "(`plant.actuators=paper_sim_v1`: brakes 10 ms + PT1 30 ms, steering 50 ms + PT1 "
           "50 ms at 1.0 rad/s), the other published reading of the paper's simulator, and "
           "two readings the paper leaves open: the study-2 rear grip reduction on the whole "
           "tyre curve (`plant.grip_scaling=curve`, as the simulator's friction input multiplies "
           "the tyre force; the vehicle file scales the friction coefficient only) and the "
           "PMPC's commanded instead of planned lateral acceleration as the ESC's target "
           "(`motion.pmpc.esc_target=commanded`).",
           "- **Time per column** (wall, and the CPU time of scw and its workers, which "
           "depends much less on what else the machine runs): " + "; ".join(
               f"{col_title(c)} {sum(x['wall_time_s'] for x in c[2].values() if x) / 60:.1f} "
               f"min wall, {sum(x.get('cpu_time_s') or 0 for x in c[2].values() if x) / 60:.1f}"
               " min CPU" for c in cols) + ".",
           "- **Parameter sets**: " + "; ".join(f"`{lab}` = `{stab}`" for lab, stab in sets) +
           ". The car's shipped set is never changed."]
    for lab, stab in sets:
        # a params file's provenance: <file>.command.txt beside it (how it was made)
        path = os.path.join(ROOT, os.path.splitext(stab or "")[0] + ".command.txt")
        if lab != "shipped" and os.path.exists(path):
            with open(path) as f:
                out.append(f"- **How `{lab}` was made** (`{os.path.relpath(path, ROOT)}`"
                           "): " + " ".join(f.read().split()))
    out.append("")
    return out
