"""Where things are: the experiments folder and the repository, the results folder (RESULTS,
moved by --results; ROOT_RESULTS, where the report reads), and the scw binary ($SCW_BIN, a build
folder, PATH)."""

import os
import shutil
import sys


HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")
ROOT_RESULTS = RESULTS

# Where the scw binary is looked for when SCW_BIN is not set (first existing wins).
BINARY_CANDIDATES = [
    "build/release/tuning/scw",
    "build/ci/tuning/scw",
    "build/exp/tuning/scw",
    "build/dev/tuning/scw",
    "build/lead-full/tuning/scw",
]


def find_scw():
    """The scw binary: $SCW_BIN, else the first of BINARY_CANDIDATES, else `scw` on PATH."""
    env = os.environ.get("SCW_BIN")
    if env:
        if not (os.path.isfile(env) and os.access(env, os.X_OK)):
            sys.exit(f"error: SCW_BIN={env} is not an executable file")
        return env
    for rel in BINARY_CANDIDATES:
        path = os.path.join(ROOT, rel)
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    path = shutil.which("scw")
    if path:
        return path
    sys.exit("error: scw not found; build it (cmake --build build/release --target scw) or set "
             "SCW_BIN=/path/to/scw")


def set_results(path):
    """Writes the studies' outputs under `path` instead of experiments/results (run_all.sh
    gives every parameter set and actuator model a directory of its own)."""
    global RESULTS
    RESULTS = os.path.abspath(path)
    os.makedirs(RESULTS, exist_ok=True)
    return RESULTS


def results_dir(study):
    path = os.path.join(RESULTS, study)
    os.makedirs(path, exist_ok=True)
    return path
