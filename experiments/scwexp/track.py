"""Places on the track: the corners of a scenario's track (`scw track info`) and an arc length
named the way the report names it (T1, hairpin, braking into, exit of, straight)."""

import math
import subprocess

from scwexp.paths import ROOT


# Named places of Yas Marina North (the spec's names; corners from `scw track info`).
CORNER_NAMES = {1: "T1", 5: "hairpin", 7: "chicane", 8: "chicane"}


def track_corners(scw, sets=()):
    """Corners (number, from, to) of the scenario's track, parsed from `scw track info`."""
    track = next((s.split("=", 1)[1] for s in sets if s.startswith("track=")), None)
    cmd = [scw, "track", "info"] + (["--track", track] if track else [])
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT).stdout
    corners = []
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 6 and f[0].isdigit() and f[1] in ("left", "right"):
            corners.append({"n": int(f[0]), "dir": f[1], "from": float(f[2]),
                            "to": float(f[3]), "r_min": float(f[4])})
    return corners


def place(s, corners):
    """'braking into T1', 'corner 3', 'exit of corner 3', 'straight' for arc length s [m]."""
    if s is None or (isinstance(s, float) and math.isnan(s)) or not corners:
        return "–"
    best, dist = None, 1e9
    for c in corners:
        d = 0.0 if c["from"] <= s <= c["to"] else min(abs(s - c["from"]), abs(s - c["to"]))
        if d < dist:
            best, dist = c, d
    name = CORNER_NAMES.get(best["n"], f"corner {best['n']}")
    if dist == 0.0:
        return name
    if s < best["from"] and dist <= 150:
        return f"braking into {name}"
    if s > best["to"] and dist <= 120:
        return f"exit of {name}"
    return "straight"
