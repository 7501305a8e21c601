"""scwexp.seeded on synthetic sweep rows: the loss curve per configuration, the activation counts
at a GG, and claim (b)'s statistical form (experiments/statistical_criteria.md) holding, holding
only at the point estimates, failing when the subsystem never acted, and not evaluable on too few
seeds; claim (e) for one controller."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "experiments"))
from scwexp import seeded  # noqa: E402


def rows_for(config, losses_by_gg, n=10, acted=True, status="sideslip"):
    """n runs per GG, the first `losses` of them lost; every completed run acted (or none did)."""
    out = []
    for gg, losses in losses_by_gg.items():
        for seed in range(1, n + 1):
            lost = seed <= losses
            out.append({"config": config, "gg_scale": str(gg), "seed": str(seed),
                        "status": status if lost else "completed",
                        "mean_lap_time_s": "nan" if lost else "80.0",
                        "esc_count": "3" if acted and not lost else "0",
                        "cs_count": "5" if acted and not lost else "0"})
    return out


def study(none, others, n=10, acted=True):
    rows = rows_for("none", none, n, acted=False)
    for c in ("esc", "cs", "esc+cs"):
        rows += rows_for(c, others, n, acted)
    names = ["none", "esc", "cs", "esc+cs"]
    summary = seeded.summarise(rows, names)
    return rows, summary, seeded.claim_b(rows, summary, {"esc": "esc_count", "cs": "cs_count",
                                                         "esc+cs": "esc_count"})


def main():
    # none is lost from 1.1 on, the others only from 1.4: far apart, intervals separated.
    none = {1.0: 0, 1.05: 0, 1.1: 10, 1.15: 10, 1.2: 10, 1.25: 10, 1.3: 10, 1.35: 10, 1.4: 10}
    far = {1.0: 0, 1.05: 0, 1.1: 0, 1.15: 0, 1.2: 0, 1.25: 0, 1.3: 0, 1.35: 0, 1.4: 10}
    rows, summary, v = study(none, far)
    assert summary["none"]["curve"][2] == (1.1, 10, 10, 1.0, summary["none"]["curve"][2][4], 1.0)
    assert abs(summary["none"]["limits"]["0.5"][0] - 1.075) < 1e-9, summary["none"]["limits"]
    assert summary["none"]["statuses"] == {"sideslip": 70}
    assert seeded.activations(rows, "esc", 1.1, "esc_count") == (10, 10)
    assert v["premise_sideslip"] and v["evaluable"]
    for c in ("esc", "cs", "esc+cs"):
        assert v[c]["holds"] and v[c]["with_confidence"], (c, v[c])
        assert v[c]["p5_gg"] == 1.1 and v[c]["acted"] == 10, v[c]

    # One step apart with a gradual edge: the point estimates differ by 0.05, the intervals overlap.
    none = {1.0: 0, 1.05: 2, 1.1: 6, 1.15: 9, 1.2: 10}
    near = {1.0: 0, 1.05: 0, 1.1: 2, 1.15: 6, 1.2: 9}
    _, _, v = study(none, near)
    assert v["esc"]["holds"] and not v["esc"]["with_confidence"], v["esc"]

    # The same gain, but the subsystems never acted: P5 fails, the claim does not hold.
    _, _, v = study({1.0: 0, 1.1: 10, 1.4: 10}, {1.0: 0, 1.1: 0, 1.4: 10}, acted=False)
    assert not v["esc"]["holds"] and v["esc"]["acted"] == 0, v["esc"]

    # Five seeds: not evaluable, never "holds".
    _, _, v = study(none, far, n=5)
    assert not v["evaluable"] and not v["esc"]["holds"], v

    # A configuration never lost within the grid: its crossing is beyond the grid.
    _, summary, _ = study(none, {1.0: 0, 1.1: 0})
    assert summary["esc"]["limits"]["0.5"][0] is None
    assert seeded.fmt_limit(summary["esc"]["limits"]["0.5"]) == "> grid"
    assert seeded.fmt_limit((1.075, 1.05, None)) in ("1.07 [1.05, > grid]", "1.08 [1.05, > grid]")
    # 0 of 10 lost at the grid's first GG still allows 28 %: GG_10's low end is at or below it.
    assert summary["none"]["low_open"]["0.1"] and not summary["none"]["low_open"]["0.5"]
    assert seeded.fmt_limit((1.02, 1.0, 1.05), True) == "1.02 [≤ 1.00, 1.05]"
    # Claim (e) for one controller: with SC lost two steps later, ESC or CS acting.
    rows = rows_for("pmpc_off", {1.0: 0, 1.1: 10, 1.2: 10}, acted=False)
    rows += rows_for("pmpc_sc", {1.0: 0, 1.1: 0, 1.2: 10})
    for r in rows:   # CS alone acts in the runs with SC: either subsystem is enough
        r["esc_count"] = "0"
    summary = seeded.summarise(rows, ["pmpc_off", "pmpc_sc"])
    e = seeded.claim_e(rows, summary, "pmpc")
    assert e["pmpc_sc"]["holds"] and e["pmpc_sc"]["acted"] == 10, e
    assert "premise_sideslip" not in e
    print("seeded_test: ok")


if __name__ == "__main__":
    main()
