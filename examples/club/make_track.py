#!/usr/bin/env python3
"""Writes examples/club/club.csv: the centre line of a made-up club circuit.

The lap is a list of straights and constant-radius corners joined by clothoids (curvature
changing linearly over `ramp` metres), integrated at a fine step and sampled every 5 m. Two
straights are solved for so that the loop closes exactly. Regenerate:

    python3 examples/club/make_track.py > examples/club/club.csv
"""
import bisect
import math
import sys

WIDTH = 12.0  # [m] track width, split evenly left and right of the centre line
SAMPLE = 5.0  # [m] spacing of the written points
RAMP = 25.0  # [m] clothoid length into and out of every corner

# (kind, value): straight length [m], or corner (radius [m], turn [deg], left > 0).
# Anticlockwise; s = 0 is the start of the main straight.
LAYOUT = [
    ("straight", 330.0),            # main straight
    ("corner", (22.0, 165.0)),      # 1: hairpin, left
    ("straight", None),             # back straight (solved)
    ("corner", (70.0, -55.0)),      # 2: right kink into the infield
    ("straight", 90.0),
    ("corner", (40.0, 115.0)),      # 3: medium left
    ("straight", None),             # second straight (solved)
    ("corner", (28.0, 95.0)),       # 4: slow left after the longest braking zone
    ("straight", 110.0),
    ("corner", (120.0, 40.0)),      # 5: fast left sweeper onto the main straight
    ("straight", 60.0),
]


def curvature_profile(layout):
    """(length, k_start, k_end) pieces of the lap."""
    pieces = []
    for kind, value in layout:
        if kind == "straight":
            pieces.append([value, 0.0, 0.0])
        else:
            radius, turn_deg = value
            k = math.copysign(1.0 / radius, turn_deg)
            turn = math.radians(abs(turn_deg))
            arc = turn * radius - RAMP  # each clothoid turns by RAMP * |k| / 2
            if arc <= 0:
                raise SystemExit(f"corner R {radius} turn {turn_deg}: too short for the ramps")
            pieces += [[RAMP, 0.0, k], [arc, k, k], [RAMP, k, 0.0]]
    return pieces


def integrate(pieces, step=0.05):
    """Points of the centre line and the heading at the start of every piece."""
    x = y = psi = 0.0
    xs, ys, starts = [0.0], [0.0], []
    for length, k0, k1 in pieces:
        starts.append(psi)
        n = max(1, int(round(length / step)))
        h = length / n
        for i in range(n):
            ka = k0 + (k1 - k0) * (i + 0.5) / n
            psi_mid = psi + 0.5 * ka * h
            x += h * math.cos(psi_mid)
            y += h * math.sin(psi_mid)
            psi += ka * h
            xs.append(x)
            ys.append(y)
    return xs, ys, starts


def main():
    layout = [list(item) for item in LAYOUT]
    unknown = [i for i, (kind, value) in enumerate(layout) if value is None]
    for i in unknown:
        layout[i][1] = 0.0
    pieces = curvature_profile(layout)
    # Index of each solved straight among the pieces.
    piece_of = []
    p = 0
    for i, (kind, _) in enumerate(layout):
        if i in unknown:
            piece_of.append(p)
        p += 1 if kind == "straight" else 3
    xs, ys, starts = integrate(pieces)
    # The end point moves by L (cos psi, sin psi) with the length L of each solved straight:
    # solve the 2 x 2 system that brings it back to the start.
    (c0, s0), (c1, s1) = [(math.cos(starts[q]), math.sin(starts[q])) for q in piece_of]
    det = c0 * s1 - c1 * s0
    lengths = [(-xs[-1] * s1 + ys[-1] * c1) / det, (-c0 * ys[-1] + s0 * xs[-1]) / det]
    if min(lengths) < 20.0:
        raise SystemExit(f"the layout does not close with straights of positive length: {lengths}")
    for q, length in zip(piece_of, lengths):
        pieces[q][0] = float(length)
    xs, ys, _ = integrate(pieces)
    total = sum(piece[0] for piece in pieces)
    s = [0.0]
    for i in range(1, len(xs)):
        s.append(s[-1] + math.hypot(xs[i] - xs[i - 1], ys[i] - ys[i - 1]))
    count = int(round(total / SAMPLE))
    out = sys.stdout
    out.write("# x_m,y_m,w_tr_right_m,w_tr_left_m\n")
    out.write(f"# Club circuit (examples/club): {total:.1f} m, anticlockwise, {WIDTH:g} m wide, "
              f"5 corners; made by make_track.py\n")
    for i in range(count):
        si = total * i / count
        j = min(max(bisect.bisect_right(s, si) - 1, 0), len(s) - 2)
        w = (si - s[j]) / (s[j + 1] - s[j])
        x = xs[j] + w * (xs[j + 1] - xs[j])
        y = ys[j] + w * (ys[j + 1] - ys[j])
        out.write(f"{x:.3f},{y:.3f},{WIDTH / 2:g},{WIDTH / 2:g}\n")


if __name__ == "__main__":
    main()
