"""scwexp.analysis (the former experiments/loss_stats.py) on synthetic data: Wilson's interval
against values computed by hand, the loss curve, the crossings and their interval."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "experiments"))
from scwexp import analysis as loss_stats  # noqa: E402


def close(a, b, tol=1e-4):
    return abs(a - b) <= tol


def main():
    # 0 of 10: [0, 0.2775]; 5 of 10: [0.2366, 0.7634]; 10 of 10: [0.7225, 1] (z = 1.96).
    lo, hi = loss_stats.wilson(0, 10)
    assert lo == 0.0 and close(hi, 0.27753), hi
    lo, hi = loss_stats.wilson(5, 10)
    assert close(lo, 0.23659) and close(hi, 0.76341), (lo, hi)
    lo, hi = loss_stats.wilson(10, 10)
    assert close(lo, 0.72247) and close(hi, 1.0), (lo, hi)
    assert loss_stats.wilson(0, 0) == (0.0, 1.0)
    # none or all lost: the bounds are exactly 0 and 1 for any n
    assert all(loss_stats.wilson(0, n)[0] == 0.0 and loss_stats.wilson(n, n)[1] == 1.0
               for n in range(1, 40)), [loss_stats.wilson(0, n) for n in range(1, 4)]
    # A limit between GG 1.1 (2 of 10 lost) and 1.15 (8 of 10).
    runs = [(1.05, False)] * 10 + [(1.1, i < 2) for i in range(10)] + \
        [(1.15, i < 8) for i in range(10)] + [(1.2, True)] * 10
    curve = loss_stats.loss_curve(runs)
    assert [c[0] for c in curve] == [1.05, 1.1, 1.15, 1.2]
    assert [c[2] for c in curve] == [0, 2, 8, 10]
    est, low, high = loss_stats.limit(curve, 0.5)
    assert close(est, 1.125), est  # halfway between 0.2 and 0.8
    assert low is not None and high is not None and low <= est <= high, (low, est, high)
    est10, _, _ = loss_stats.limit(curve, 0.1)
    assert close(est10, 1.05 + 0.05 * 0.1 / 0.2), est10
    # Never lost: no crossing, an open interval.
    assert loss_stats.limit(loss_stats.loss_curve([(1.0, False)] * 10), 0.5)[0] is None
    assert loss_stats.separated((1.0, 1.1), (1.2, 1.3), 0.05)
    assert not loss_stats.separated((1.0, 1.18), (1.2, 1.3), 0.05)
    assert not loss_stats.separated((1.0, None), (1.2, 1.3))
    print("loss_stats: ok")


if __name__ == "__main__":
    main()
