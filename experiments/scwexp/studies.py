"""The paper's three simulation studies as the drivers run them (experiments/study1_longitudinal.py,
study2_lateral.py, study3_motion.py; their docstrings say why): each study's results folder, motion
controller, scenario overrides, perturbation and configurations (name, overrides, label, colour or
line style). One definition, read by the drivers and by esc_margin.py."""

# study1_longitudinal
STUDY1 = "study1_longitudinal"
STUDY1_CONTROLLER = "pmpc"
STUDY1_BASE_SETS = ["abort.lock_slip_pct=50", "abort.spin_slip_pct=30", "abort.slip_time=0.1",
                    "abort.max_lateral_error=100", "sensor_noise=true"]
STUDY1_PERT = ("seed", [1, 2, 3])
STUDY1_CONFIGS = [
    ("sc_on", "subsystems.abs=true,subsystems.tc=true", "slip control on", "tab:blue"),
    ("sc_off", "subsystems.abs=false,subsystems.tc=false", "slip control off", "tab:red"),
]
STUDY1_TOP = [("max_slip_front_pct", "-", ", front"), ("max_slip_rear_pct", "--", ", rear")]

# study2_lateral
STUDY2 = "study2_lateral"
STUDY2_CONTROLLER = "pmpc"
STUDY2_BASE_SETS = ["plan_with_nominal_grip=true", "abort.lock_slip_pct=100"]
STUDY2_PERT = ("grip.rear_mu_y", ["0.78", "0.8", "0.82"])
STUDY2_MAIN_PERT = "0.8"
STUDY2_CONFIGS = [
    ("none", "subsystems.esc=false,subsystems.cs=false", "no lateral SC", "tab:gray"),
    ("esc", "subsystems.esc=true,subsystems.cs=false", "ESC only", "tab:red"),
    ("cs", "subsystems.esc=false,subsystems.cs=true", "CS only", "tab:blue"),
    ("esc+cs", "subsystems.esc=true,subsystems.cs=true", "ESC + CS", "tab:purple"),
]
STUDY2_TOP = [("max_abs_sideslip_deg", None, "")]

# study3_motion
STUDY3 = "study3_motion"
STUDY3_BASE_SETS = ["plan_with_nominal_grip=true", "abort.lock_slip_pct=100"]
STUDY3_PERT = ("grip.rear_mu_y", ["0.78", "0.8", "0.82"])
STUDY3_MAIN_PERT = "0.8"
STUDY3_CONTROLLERS = ["pure_pursuit", "pmpc", "nmpc"]
STUDY3_VARIANTS = [("off", "subsystems.esc=false,subsystems.cs=false", "without SC", "-"),
                   ("sc", "subsystems.esc=true,subsystems.cs=true", "with ESC + CS", "--")]
STUDY3_COLORS = {"pure_pursuit": "tab:blue", "pmpc": "tab:orange", "nmpc": "tab:green"}
STUDY3_SENSITIVITY_CONTROLLERS = ["pure_pursuit", "pmpc"]
