#!/usr/bin/env python3
"""experiments/compare.py without real scw runs (issue 50, findings 6 and 12): a stand-in scw
(SCW_BIN) that writes `scw evaluate`'s table where the real program would, i.e. relative paths
resolved in the folder scw runs in; and the two charts drawn from synthetic rows.

    python3 test/experiments/compare_test.py EXPERIMENTS_DIR WORK_DIR
"""

import csv
import os
import shutil
import subprocess
import sys
import unittest

EXP, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
del sys.argv[1:]
sys.path.insert(0, EXP)
try:
    import matplotlib  # noqa: F401
    import numpy  # noqa: F401
except ImportError:
    print("skipped: no numpy/matplotlib")
    sys.exit(77)
import compare  # noqa: E402
import matplotlib.image  # noqa: E402

# A stand-in for `scw evaluate PARAMS... --csv PATH [--scenarios SET]`: PATH is opened relative to
# the folder it runs in, as the real program does; it refuses (exit 1, as scw's "cannot write")
# a PATH outside WORK, so a regression cannot write into the source tree.
FAKE_SCW = r'''#!/usr/bin/env python3
import csv, os, sys
work = os.environ["COMPARE_TEST_WORK"]
args = sys.argv[1:]
assert args[0] == "evaluate", args
out = args[args.index("--csv") + 1]
target = os.path.abspath(out)
if not target.startswith(work + os.sep) or not os.path.isdir(os.path.dirname(target)):
    sys.exit("error: cannot write %s/%s (run in %s)" % (os.path.basename(os.path.dirname(out)),
                                                        os.path.basename(out), os.getcwd()))
params, k = [], 1
while not args[k].startswith("--"):
    params.append(args[k])
    k += 1
tracks = "--scenarios" in args and "extra_tracks" in args[args.index("--scenarios") + 1]
with open(target, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["group", "scenario", "set", "status", "progress", "mean_lap_time_s",
                "max_abs_sideslip_deg", "esc_count", "cs_count"])
    for k, p in enumerate(params):
        name = os.path.basename(p)
        if tracks:
            w.writerow(["training", "short_nominal_gg1.1", name, "completed", 1, 20.0 + 0.1 * k,
                        2.0, 0, 0])
        else:
            w.writerow(["training", "clean", name, "completed", 1, 70.0 + 0.2 * k, 3.0, 0, 0])
            w.writerow(["held_out", "oversteer", name, "sideslip" if k else "completed",
                        0.43 if k else 1, "nan" if k else 71.0, 12.0, 3, 1])
'''


def row(group, scenario, label, lap, status="completed", progress=1.0, beta=3.0):
    return {"group": group, "scenario": scenario, "set": label, "status": status,
            "progress": str(progress), "mean_lap_time_s": str(lap),
            "max_abs_sideslip_deg": str(beta), "esc_count": "0", "cs_count": "0"}


def many_rows():
    """28 scenarios like the built-in set plus two tracks: lap times 66-120 s, a 20 s track;
    set B 0.1-0.4 s slower or faster, one of its runs aborted."""
    rows = []
    for i in range(28):
        lap = 66.0 + (54.0 if i % 9 == 4 else 0.0) + 0.3 * i
        key = f"s{i}"
        rows.append(row("training", key, "A.yaml", lap))
        if i == 5:
            rows.append(row("training", key, "B.yaml", "nan", "sideslip", 0.43, 14.0))
        else:
            rows.append(row("training", key, "B.yaml", lap + (0.1, -0.4, 0.25)[i % 3]))
    rows.append(row("extra_tracks", "short", "A.yaml", 20.0))
    rows.append(row("extra_tracks", "short", "B.yaml", 20.3))
    return rows


class RelativeOut(unittest.TestCase):
    """Finding 6: --out cmp (relative) from another folder writes there, not in the repo."""

    def test_relative_out_from_another_folder(self):
        run = os.path.join(WORK, "relative_out")
        shutil.rmtree(run, ignore_errors=True)
        os.makedirs(run)
        fake = os.path.join(WORK, "fake_scw")
        with open(fake, "w") as f:
            f.write(FAKE_SCW)
        os.chmod(fake, 0o755)
        for name in ("A.yaml", "B.yaml"):
            with open(os.path.join(run, name), "w") as f:
                f.write("{}\n")
        with open(os.path.join(run, "short.csv"), "w") as f:
            f.write("x_m,y_m,w_tr_right_m,w_tr_left_m\n")
        env = dict(os.environ, SCW_BIN=fake, COMPARE_TEST_WORK=WORK)
        proc = subprocess.run([sys.executable, os.path.join(EXP, "compare.py"), "A.yaml",
                               "B.yaml", "--out", "cmp", "--no-default-tracks", "--track",
                               "short.csv"], cwd=run, env=env, capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)
        for name in ("evaluate_sets.csv", "evaluate_tracks.csv", "comparison.md",
                     "comparison.csv", "compare_lap_time.png", "compare_sideslip.png"):
            self.assertTrue(os.path.isfile(os.path.join(run, "cmp", name)), name)
        with open(os.path.join(run, "cmp", "comparison.csv")) as f:
            got = list(csv.DictReader(f))
        self.assertEqual(len(got), 6)
        self.assertIn("**sideslip** at 43 %", open(os.path.join(run, "cmp",
                                                                "comparison.md")).read())


class LapTimeChart(unittest.TestCase):
    """Finding 12: a readable size, differences visible, aborted runs marked, no bar cut off."""

    def test_two_sets_show_differences(self):
        path = os.path.join(WORK, "lap_two.png")
        info = compare.lap_time_plot(many_rows(), ["A.yaml", "B.yaml"], path)
        w, h = info["size_px"]
        self.assertLessEqual(w, 1200)
        img = matplotlib.image.imread(path)
        self.assertEqual((img.shape[1], img.shape[0]), (w, h))
        self.assertLess(h, 2400)
        # The differences themselves, in seconds, on an axis that starts near them.
        self.assertAlmostEqual(info["values"][("training/s0", "B.yaml")], 0.1, places=9)
        self.assertAlmostEqual(info["values"][("training/s1", "B.yaml")], -0.4, places=9)
        self.assertAlmostEqual(info["values"][("extra_tracks/short", "B.yaml")], 0.3, places=9)
        lo, hi = info["xlim"]
        self.assertLessEqual(lo, -0.4)
        self.assertGreaterEqual(hi, 0.3)
        self.assertGreater(0.1 / (hi - lo), 0.05, "a 0.1 s difference is under 5 % of the axis")
        # The aborted run: no value, but marked (and the title says how).
        self.assertNotIn(("training/s5", "B.yaml"), info["values"])
        self.assertIn(("training/s5", "B.yaml"), info["aborted"])
        self.assertIn("×", info["title"])
        self.assertNotIn("hatched", info["title"])

    def test_one_set_from_zero(self):
        path = os.path.join(WORK, "lap_one.png")
        rows = [r for r in many_rows() if r["set"] == "A.yaml"]
        info = compare.lap_time_plot(rows, ["A.yaml"], path)
        lo, hi = info["xlim"]
        self.assertEqual(lo, 0.0)  # a 20 s lap's bar is whole beside a 120 s one
        self.assertEqual(info["values"][("extra_tracks/short", "A.yaml")], 20.0)
        self.assertGreater(hi, max(info["values"].values()))

    def test_first_set_aborted(self):
        rows = [row("training", "x", "A.yaml", "nan", "wheel_lock", 0.2),
                row("training", "x", "B.yaml", 70.0)]
        info = compare.lap_time_plot(rows, ["A.yaml", "B.yaml"],
                                     os.path.join(WORK, "lap_base_aborted.png"))
        self.assertEqual(info["values"], {})
        self.assertEqual(len(info["aborted"]), 1)


class SideslipChart(unittest.TestCase):
    def test_aborted_hatched_with_value(self):
        info = compare.sideslip_plot(many_rows(), ["A.yaml", "B.yaml"],
                                     os.path.join(WORK, "beta.png"))
        self.assertLessEqual(info["size_px"][0], 1200)
        self.assertEqual(info["values"][("training/s5", "B.yaml")], 14.0)
        self.assertIn(("training/s5", "B.yaml"), info["aborted"])
        self.assertGreater(info["xlim"][1], 14.0)


if __name__ == "__main__":
    os.makedirs(WORK, exist_ok=True)
    unittest.main(verbosity=2)
