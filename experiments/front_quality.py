"""How close a `scw tune --front` is to converged: its hypervolume against that of a front from a
much larger budget, on the same reference point (issue 47).

    python3 experiments/front_quality.py FRONT_DIR REFERENCE_DIR [REFERENCE_DIR ...]

Each folder holds a front.csv (scw tune --front N --out-dir DIR; the reference e.g. with
--max-evals four times larger). Both fronts are read as points (largest clean-lap loss [s/lap],
stability cost) on the training scenarios, both minimised; the common reference point is
(1.1 x the largest loss of either front, the base set's training stability). Several reference
folders pool their points. Prints the front's hypervolume, the reference's and that of the best
front known (the non-dominated points of the reference and the front together: a front can beat a
larger budget's search, and is then measured against what both found); exit 0 when the front
reaches at least 95 % of the best known, 1 when it does not, 2 for unreadable input.
"""

import csv
import math
import os
import sys


def hypervolume(points, reference):
    """The area dominated by `points` (x, y), both minimised, within the box up to `reference`."""
    rx, ry = reference
    area, best_y = 0.0, ry
    for x, y in sorted(points):
        if not (x < rx) or not (y < best_y):
            continue
        area += (rx - x) * (best_y - y)
        best_y = y
    return area


def read_front(folder):
    """(points, base stability) of a front.csv; ValueError when it is unusable."""
    path = os.path.join(folder, "front.csv")
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    need = ("training_lap_loss_s", "training_stability", "base_training_stability")
    if not rows or any(k not in rows[0] for k in need):
        raise ValueError("%s: not a front.csv (needs the columns %s)" % (path, ", ".join(need)))
    points = []
    for r in rows:
        x, y = float(r["training_lap_loss_s"]), float(r["training_stability"])
        if math.isfinite(x) and math.isfinite(y):
            points.append((x, y))
    return points, float(rows[0]["base_training_stability"])


def quality(front, reference):
    """(hv_front, hv_reference, ratio, reference point) for two (points, base) pairs."""
    (a, base_a), (b, base_b) = front, reference
    losses = [x for x, _ in a + b] or [0.0]
    ref = (max(1.1 * max(losses), 0.01), max(base_a, base_b))
    hv_a, hv_b = hypervolume(a, ref), hypervolume(b, ref)
    return hv_a, hv_b, (hv_a / hv_b if hv_b > 0 else math.nan), ref


def pooled(fronts):
    """(points, base) of several fronts read together."""
    return [p for pts, _ in fronts for p in pts], max(b for _, b in fronts)


def main(argv):
    if len(argv) < 3:
        sys.stderr.write("usage: front_quality.py FRONT_DIR REFERENCE_DIR [REFERENCE_DIR ...]\n")
        return 2
    try:
        front = read_front(argv[1])
        reference = pooled([read_front(d) for d in argv[2:]])
    except (OSError, ValueError, KeyError) as e:
        sys.stderr.write("front_quality: %s\n" % e)
        return 2
    hv_a, hv_b, _, ref = quality(front, reference)
    best = hypervolume(front[0] + reference[0], ref)
    ratio = hv_a / best if best > 0 else math.nan
    print("reference point: loss %.3f s/lap, stability %.3f" % ref)
    print("hypervolume: front %.3f, reference %.3f, best known %.3f; front / best known %.3f "
          "(%s 0.95)" % (hv_a, hv_b, best, ratio, ">=" if ratio >= 0.95 else "<"))
    return 0 if ratio >= 0.95 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
