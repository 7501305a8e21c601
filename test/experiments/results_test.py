#!/usr/bin/env python3
"""scwexp.results.load on synthetic study folders (issue 48 item 4): a summary.json and its sweep
tables, plain and gzip-compressed, read into typed records; P(loss | GG) from them; and every bad
input refused with a message naming the file, the row or key, and the rule (NaN where a number is
required, a missing column or key, text in a number's place). Standard library only, no scw.

    python3 test/experiments/results_test.py WORK_DIR
"""

import gzip
import json
import math
import os
import shutil
import sys
import unittest

WORK = sys.argv[1] if len(sys.argv) > 1 else "/tmp/results_test"
del sys.argv[1:]
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "experiments"))
from scwexp import results  # noqa: E402

HEADER = "config,gg_scale,grip.rear_mu_y,status,mean_lap_time_s,esc_count,max_abs_sideslip_deg"


def run(gg, status="completed", lap=71.5, esc=0, **kw):
    r = {"gg_scale": gg, "refined": 0, "status": status,
         "mean_lap_time_s": lap if status == "completed" else math.nan, "esc_count": esc,
         "max_esc_margin": 0.4}
    r.update(kw)
    return r


def series(runs):
    done = [r for r in runs if r["status"] == "completed"]
    lost = [r for r in runs if r["status"] != "completed"]
    return {"values": [r["gg_scale"] for r in runs], "runs": runs,
            "max_stable": done[-1]["gg_scale"] if done else None,
            "first_abort": lost[0]["gg_scale"] if lost else None,
            "first_abort_status": lost[0]["status"] if lost else None,
            "min_lap_value": 1.0, "min_lap_time_s": 71.5}


def summary():
    none = [run(1.0), run(1.05, "sideslip")]
    esc = [run(1.0), run(1.05, esc=2), run(1.075, refined=1, esc=4), run(1.1, "lateral_error")]
    return {"study": "study2_lateral", "column": {"set_label": "shipped", "actuators": "vehicle"},
            "perturbation": {"key": "grip.rear_mu_y", "label": "rear μy",
                             "values": ["0.78", "0.8"], "main": "0.8"},
            "runs": {"0.78": {"none": series(none), "esc": series(esc)},
                     "0.8": {"none": series([run(1.0), run(1.05), run(1.1, "off_track")]),
                             "esc": series([dict(r) for r in esc])}}}


def write_study(d, s=None, table=None, gz=False, refine=None):
    if os.path.exists(d):
        shutil.rmtree(d)
    os.makedirs(d)
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump(summary() if s is None else s, f)
    rows = table if table is not None else [
        HEADER, "none,1.0,0.8,completed,71.5,0,3.2", "none,1.05,0.8,sideslip,nan,0,20.4",
        "esc,1.0,0.8,completed,71.6,1,3.1", "esc,1.05,0.8,completed,71.7,3,4.0"]
    text = "\n".join(rows) + "\n"
    if gz:
        with gzip.open(os.path.join(d, "sweep.csv.gz"), "wt") as f:
            f.write(text)
    else:
        with open(os.path.join(d, "sweep.csv"), "w") as f:
            f.write(text)
    if refine:
        with open(os.path.join(d, "sweep_refine1.csv"), "w") as f:
            f.write("config,laps,status,mean_lap_time_s\n" + "\n".join(refine[0]) + "\n")
        with open(os.path.join(d, "sweep_refine1.csv.cmd"), "w") as f:
            f.write("\n".join(refine[1]))
    return d


class Load(unittest.TestCase):
    def test_typed_records_from_a_study_folder(self):
        d = write_study(os.path.join(WORK, "ok"))
        s = results.load(d)
        self.assertEqual(s.name, "study2_lateral")
        self.assertEqual(s.column["actuators"], "vehicle")
        self.assertEqual(s.configs(), ["esc", "none"])
        esc = s.series[("0.8", "esc")]
        self.assertIsInstance(esc, results.Series)
        self.assertEqual([r.gg_scale for r in esc.runs], [1.0, 1.05, 1.075, 1.1])
        self.assertTrue(esc.runs[2].refined)
        self.assertTrue(math.isnan(esc.runs[3].mean_lap_time_s))
        self.assertTrue(esc.runs[3].lost)
        self.assertEqual(esc.runs[1].get("esc_count"), 2)
        self.assertEqual(esc.first_abort, 1.1)
        rows = s.sweeps["sweep.csv"]
        self.assertEqual(len(rows), 4)
        self.assertIsInstance(rows[0], results.SweepRow)
        self.assertEqual((rows[1].config, rows[1].status, rows[1].gg_scale), ("none", "sideslip",
                                                                              1.05))
        self.assertTrue(math.isnan(rows[1].mean_lap_time_s))
        self.assertEqual(rows[2].values["esc_count"], 1.0)
        self.assertEqual(rows[3].line, 5)
        # the same folder given as its summary.json
        self.assertEqual(results.load(os.path.join(d, "summary.json")).series, s.series)

    def test_loss_curve_with_wilson_intervals(self):
        s = results.load(write_study(os.path.join(WORK, "curve")))
        curve = s.loss_curve("none")
        # none: 1.0 completed twice; 1.05 lost once (0.78) and completed once (0.8); 1.1 lost
        self.assertEqual([c[:4] for c in curve], [(1.0, 2, 0, 0.0), (1.05, 2, 1, 0.5),
                                                  (1.1, 1, 1, 1.0)])
        lo, hi = curve[1][4:]
        self.assertTrue(0.0 < lo < 0.5 < hi < 1.0)
        self.assertEqual([c[0] for c in s.loss_curve("none", perturbation="0.78")], [1.0, 1.05])
        with self.assertRaises(KeyError):
            s.loss_curve("cs")
        # from the sweep table's rows, filtered by a column
        self.assertEqual([c[:4] for c in s.sweep_loss_curve("none")], [(1.0, 1, 0, 0.0),
                                                                       (1.05, 1, 1, 1.0)])
        self.assertEqual(s.sweep_loss_curve("esc", **{"grip.rear_mu_y": 0.8})[1][:3], (1.05, 1, 0))
        with self.assertRaises(KeyError):
            s.sweep_loss_curve("esc", **{"grip.rear_mu_y": 0.78})

    def test_gzip_tables_and_gg_from_the_recorded_command(self):
        d = write_study(os.path.join(WORK, "gz"), gz=True,
                        refine=(["r0,1,completed,71.6", "r1,1,sideslip,nan"],
                                ["sweep", "--config", "r0:subsystems.esc=true,gg_scale=1.075",
                                 "--config", "r1:subsystems.esc=false,gg_scale=1.025"]))
        s = results.load(d)
        self.assertEqual(sorted(s.sweeps), ["sweep.csv.gz", "sweep_refine1.csv"])
        self.assertEqual(len(s.sweeps["sweep.csv.gz"]), 4)
        self.assertEqual([r.gg_scale for r in s.sweeps["sweep_refine1.csv"]], [1.075, 1.025])
        # a table beside its compressed copy is read once
        with gzip.open(os.path.join(d, "sweep.csv.gz"), "rt") as f, \
                open(os.path.join(d, "sweep.csv"), "w") as g:
            g.write(f.read())
        self.assertEqual(sorted(results.load(d).sweeps), ["sweep.csv", "sweep_refine1.csv"])

    def test_every_column_of_a_results_tree(self):
        root = os.path.join(WORK, "tree")
        for col in ("shipped__vehicle", "shipped__paper_sim"):
            write_study(os.path.join(root, "columns", col, "study2_lateral"))
        cols = results.load_columns(root)
        self.assertEqual(sorted(cols), ["shipped__paper_sim", "shipped__vehicle"])
        self.assertEqual(list(cols["shipped__vehicle"]), ["study2_lateral"])

    def test_a_column_on_open_car_dynamics(self):
        # run_all.sh PLANTS="scw ocd": <set>__<actuators>__ocd, after scw's columns of its set,
        # named in the report's titles; a summary that records no plant is read as scw's.
        root = os.path.join(WORK, "plants")
        for col in ("shipped__paper_sim__ocd", "shipped__paper_sim", "shipped__vehicle"):
            s = summary()
            del s["column"]  # the folder's name says which column it is
            write_study(os.path.join(root, "columns", col, "study2_lateral"), s)
        names = [c[0] for c in results.find_columns(root)]
        self.assertEqual(names, ["shipped__vehicle", "shipped__paper_sim",
                                 "shipped__paper_sim__ocd"])
        from scwexp.report.common import col_title
        titles = {c[0]: col_title(c) for c in results.find_columns(root)}
        self.assertTrue(titles["shipped__paper_sim__ocd"].endswith(", OCD"), titles)
        self.assertFalse(titles["shipped__paper_sim"].endswith("OCD"), titles)
        self.assertEqual(results.column_of(("x__paper_sim__ocd", "", {}))["plant"], "ocd")
        self.assertEqual(results.column_of(("x__vehicle", "", {}))["plant"], "scw")


class Refuses(unittest.TestCase):
    def fails(self, name, expect, **kw):
        d = write_study(os.path.join(WORK, "bad", name), **kw)
        with self.assertRaises(results.ResultsError) as e:
            results.load(d)
        for part in expect:
            self.assertIn(part, str(e.exception))
        return str(e.exception)

    def test_nan_where_a_number_is_required(self):
        self.fails("nan_gg", ["sweep.csv: row 3 (config none): column gg_scale",
                              "'nan' where a finite number is required"],
                   table=[HEADER, "none,1.0,0.8,completed,71.5,0,3.2",
                          "none,nan,0.8,sideslip,nan,0,20.4"])
        self.fails("nan_lap", ["sweep.csv: row 2 (config esc): column mean_lap_time_s",
                               "'nan' where a finite number is required"],
                   table=[HEADER, "esc,1.0,0.8,completed,nan,0,3.2"])
        s = summary()
        s["runs"]["0.8"]["esc"]["runs"][1]["gg_scale"] = math.nan
        self.fails("nan_json", ["summary.json: runs['0.8']['esc'].runs[1].gg_scale",
                                "nan where a finite number is required"], s=s)
        s = summary()
        s["runs"]["0.8"]["none"]["runs"][0]["mean_lap_time_s"] = None
        self.fails("missing_lap", ["runs['0.8']['none'].runs[0].mean_lap_time_s: missing; a "
                                   "number is required"], s=s)

    def test_missing_column_or_key(self):
        self.fails("no_status", ["sweep.csv: no column 'status'"],
                   table=["config,gg_scale,mean_lap_time_s", "none,1.0,71.5"])
        self.fails("short_row", ["sweep.csv: row 2: 7 columns expected"],
                   table=[HEADER, "none,1.0,0.8,completed"])
        s = summary()
        del s["runs"]
        self.fails("no_runs", ["summary.json: key 'runs' missing or not an object"], s=s)
        s = summary()
        del s["runs"]["0.78"]["esc"]["runs"][0]["status"]
        self.fails("no_status_key", ["runs['0.78']['esc'].runs[0].status: missing"], s=s)
        d = os.path.join(WORK, "bad", "empty")
        os.makedirs(d, exist_ok=True)
        with self.assertRaises(results.ResultsError) as e:
            results.load(d)
        self.assertIn("summary.json: missing", str(e.exception))

    def test_text_in_a_numbers_place_and_order(self):
        self.fails("text_gg", ["row 2 (config none): column gg_scale: 'high' is not a number"],
                   table=[HEADER, "none,high,0.8,completed,71.5,0,3.2"])
        s = summary()
        runs = s["runs"]["0.8"]["esc"]["runs"]
        runs[0], runs[1] = runs[1], runs[0]
        self.fails("order", ["runs['0.8']['esc'].runs: not in GG order"], s=s)
        d = write_study(os.path.join(WORK, "bad", "json"))
        with open(os.path.join(d, "summary.json"), "w") as f:
            f.write("{not json")
        with self.assertRaises(results.ResultsError) as e:
            results.load(d)
        self.assertIn("summary.json: not JSON", str(e.exception))


if __name__ == "__main__":
    os.makedirs(WORK, exist_ok=True)
    unittest.main(verbosity=1)
