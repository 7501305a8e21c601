"""experiments/ocd_claims.py's pure parts on synthetic summaries: the two-of-three rule of the
report and the activation counts beside the verdicts (summed over each configuration's completed
runs at the main perturbation; an aborted run's activations are not counted), and the columns
it pairs in run_all.sh's layout."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "experiments"))
import ocd_claims as O  # noqa: E402


def main():
    s = {"perturbation": {"main": "0.8"},
         "runs": {"0.8": {"none": {"runs": [{"status": "completed"}]},
                          "esc": {"runs": [{"status": "completed", "esc_count": 2, "cs_count": 1},
                                           {"status": "completed", "esc_count": 3},
                                           {"status": "sideslip", "esc_count": 5}]}}}}
    assert O.activations(s) == "none 0/0/0/0, esc 5/1/0/0", O.activations(s)
    holds = {"a": (True, []), "b": (True, []), "c": (False, [])}
    assert O.judge(lambda ser: holds[ser], {"1": "a", "2": "b", "3": "c"}) == (True, 2, 3)
    assert O.judge(lambda ser: holds[ser], {"1": "a", "2": "c", "3": "c"}) == (False, 1, 3)
    assert O.judge(lambda ser: (None, []), {"1": "a"}) == (None, 0, 1)
    # run_all.sh's layout: <name>__ocd beside <name>; other folders keep their name.
    assert O.column_name("/r/columns/shipped__paper_sim__ocd/") == "shipped__paper_sim"
    assert O.scw_column("/r/columns/shipped__paper_sim__ocd") == "/r/columns/shipped__paper_sim"
    assert O.column_name("/r/ocd_columns/shipped__paper_sim") == "shipped__paper_sim"
    assert O.scw_column("/r/ocd_columns/shipped__paper_sim").endswith(
        os.path.join("scw_columns", "shipped__paper_sim"))
    print("ocd_claims_test: ok")


if __name__ == "__main__":
    main()
