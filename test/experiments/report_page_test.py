#!/usr/bin/env python3
"""The report's shape (issue 48 item 1). Standard library: scwexp.report.markdown on synthetic
lines (a cell over 200 characters and a row over 400 move to notes, prose is wrapped, no word is
lost, links are re-rooted). With matplotlib (else exit 77 after those): experiments/report.py
on a tiny real results tree (data/report_tiny.tar.gz), then the verdict table and the links of
figures A, B and C within report.md's first 60 lines, the figures written, no table cell over
200 characters and no line over 400 in report.md and every appendix, every relative link of
them resolving, the same in a --publish copy; and the same tree without its claims map and
esc_margin run, or without study 2, still gives three figures, the page saying what is missing.

    python3 test/experiments/report_page_test.py EXPERIMENTS_DIR WORK_DIR

The tree: one-lap studies 1-3 of the shipped set with both actuator models (studies 2-3 at
GG 1.0,1.1, study 1 at 1.3,1.5; --no-sensitivity), esc_margin.py --laps 1 --resolution 0.02
--scan-step 0.025 --threshold-probe 0.5 --falloff-probe 0, claims_map.py --quick --gg 1.0,1.1
--laps 1; regenerate it with those commands into one results folder, then keep its
summary.json files and the columns' sweep*.csv (with their .cmd): `tar czf
report_tiny.tar.gz $(find . -name summary.json -o -path './columns/*/sweep*.csv*')`.
"""

import glob
import os
import shutil
import subprocess
import sys
import tarfile
import unittest

EXP, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
del sys.argv[1:]
sys.path.insert(0, EXP)
from scwexp.report import markdown as M  # noqa: E402  (standard library only)

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "report_tiny.tar.gz")
PAGE = 60


class Markdown(unittest.TestCase):
    def test_long_cells_and_rows_move_to_notes_without_losing_a_word(self):
        long = "word " * 60
        rows = ["| a | b | c |", "|---|---|---|", f"| x | {long.strip()} | y |",
                "| " + " | ".join(["z" * 150] * 3) + " |"]
        out = M.fit(rows + ["", "prose " * 100])
        text = "\n".join(out)
        self.assertEqual(M.problems(text), [])
        self.assertIn("| x | note 1 | y |", out)
        self.assertIn("note 2", out[3])
        self.assertEqual(text.count("word"), 60)
        self.assertEqual(text.count("z" * 150), 3)
        self.assertEqual(text.count("prose"), 100)
        self.assertTrue(all(len(x) <= M.WRAP for x in out if x.startswith("prose")))

    def test_problems_names_a_long_line_and_a_long_cell(self):
        bad = M.problems("x" * 401 + "\n| " + "y" * 201 + " |\n", "r.md")
        self.assertEqual(len(bad), 2)
        self.assertIn("r.md:1: line of 401", bad[0])
        self.assertIn("r.md:2: table cell of 201", bad[1])

    def test_relink_prefixes_relative_targets_only(self):
        out = M.relink(["![f](a/b.png) [x](c.md) [u](https://e.org) [h](#top)"], "../")
        self.assertEqual(out, ["![f](../a/b.png) [x](../c.md) [u](https://e.org) [h](#top)"])


def python_with_matplotlib():
    for cand in (sys.executable, "/usr/bin/python3"):
        if cand and os.access(cand, os.X_OK) and subprocess.run(
                [cand, "-c", "import matplotlib, numpy"], capture_output=True).returncode == 0:
            return cand
    return None


REPORT_FIGURES = ("page", "overlay")   # folders of the figures report.py draws itself


def stub_study_figures(root):
    """An empty file for each image the pages link outside REPORT_FIGURES: the studies'
    figures, which the tiny tree does not hold (the studies draw them, not the report); the
    report's own figures must exist already."""
    for p in [os.path.join(root, "report.md")] + glob.glob(os.path.join(root, "appendix",
                                                                        "*.md")):
        with open(p, encoding="utf-8") as f:
            text = f.read()
        for image, target in M.links(text):
            path = os.path.normpath(os.path.join(os.path.dirname(p), target))
            rel = os.path.relpath(path, root)
            if image and not rel.startswith(REPORT_FIGURES) and not rel.startswith(".."):
                os.makedirs(os.path.dirname(path), exist_ok=True)
                open(path, "a").close()


def build(results, *args):
    py = python_with_matplotlib()
    env = dict(os.environ, SCW_PY_REEXEC="1")
    cmd = [py, os.path.join(EXP, "report.py"), "--results", results]
    for extra in ([], list(args)) if args else ([],):
        r = subprocess.run(cmd + extra, capture_output=True, text=True, env=env)
        if r.returncode != 0:
            raise AssertionError(f"report.py failed:\n{r.stdout}\n{r.stderr}")
        stub_study_figures(results)
    with open(os.path.join(results, "report.md"), encoding="utf-8") as f:
        return f.read()


def unpack(name, drop=()):
    d = os.path.join(WORK, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with tarfile.open(DATA) as t:
        t.extractall(d)
    for x in drop:
        shutil.rmtree(os.path.join(d, x))
    return d


class Report(unittest.TestCase):
    def check_tree(self, root):
        """Every .md of the report under root: the shape, and every relative link resolving."""
        pages = [os.path.join(root, "report.md")] + sorted(
            glob.glob(os.path.join(root, "appendix", "*.md")))
        self.assertGreater(len(pages), 3)
        for p in pages:
            with open(p, encoding="utf-8") as f:
                text = f.read()
            self.assertEqual(M.problems(text, p), [])
            for _, target in M.links(text):
                path = os.path.normpath(os.path.join(os.path.dirname(p), target))
                self.assertTrue(os.path.exists(path), f"{p}: link {target} does not resolve")
        return pages

    def test_first_page_then_appendices(self):
        root = unpack("full")
        # Another page kept in the published folder (as maneuvers.md is): its figure stays, a
        # figure no page links goes.
        published = os.path.join(WORK, "published")
        shutil.rmtree(published, ignore_errors=True)
        os.makedirs(os.path.join(published, "other"))
        with open(os.path.join(published, "other.md"), "w") as f:
            f.write("![kept](other/kept.png)\n")
        for name in ("other/kept.png", "stale.png"):
            with open(os.path.join(published, name), "wb") as f:
                f.write(b"png")
        os.makedirs(os.path.join(root, "ocd"), exist_ok=True)
        with open(os.path.join(root, "ocd", "crossval.md"), "w") as f:
            f.write("| test | metric | scw | ocd |\n")
        text = build(os.path.join(root), "--publish", published)
        self.assertIn("[scw's plant against Open-Car-Dynamics](ocd/crossval.md)",
                      "\n".join(text.splitlines()[:PAGE]))
        self.assertTrue(os.path.exists(os.path.join(published, "other", "kept.png")))
        self.assertFalse(os.path.exists(os.path.join(published, "stale.png")))
        head = text.splitlines()[:PAGE]
        self.assertIn("## Verdict", head)
        self.assertIn("## Appendices", head)   # the whole answer within the page
        table = [x for x in head if x.startswith("| (")]
        self.assertGreaterEqual(len(table), 4)
        for row in table:
            cells = M._cells(row)[1:]
            self.assertEqual(len(cells), 2)   # two columns in the tiny tree
            for c in cells:   # one symbol and one number (or – when not run)
                self.assertRegex(c, r"^(– *|[✓✗?] ([+-]\d+\.\d+|–))$")
        for fig in ("page/a.png", "page/b.png", "page/c.png"):
            self.assertTrue(any(f"]({fig})" in x for x in head), f"{fig} not in the first page")
            self.assertTrue(os.path.exists(os.path.join(root, fig)))
        self.assertTrue(any("appendix/column_shipped__vehicle.md" in x for x in text.splitlines()))
        pages = self.check_tree(root)
        names = {os.path.basename(p) for p in pages}
        self.assertTrue({"column_shipped__vehicle.md", "column_shipped__paper_sim.md",
                         "claims_map.md", "method.md"} <= names)
        self.check_tree(os.path.join(WORK, "published"))
        # The data behind the copy: every study's summary and its sweep tables, compressed, which
        # the loader reads back without running scw.
        pub = os.path.join(WORK, "published", "columns", "shipped__vehicle", "study2_lateral")
        self.assertTrue(os.path.exists(os.path.join(pub, "summary.json")))
        self.assertTrue(glob.glob(os.path.join(pub, "sweep*.csv.gz")), os.listdir(pub))
        self.assertFalse(glob.glob(os.path.join(pub, "sweep*.csv")))
        from scwexp import results as R
        study = R.load(pub)
        self.assertTrue(study.sweeps)
        self.assertTrue(study.sweep_loss_curve("none"))

    def test_missing_inputs_are_said_not_invented(self):
        root = unpack("bare", drop=("claims_map", "esc_margin"))
        text = build(root)
        head = "\n".join(text.splitlines()[:PAGE])
        for fig in ("page/a.png", "page/b.png", "page/c.png"):
            self.assertIn(f"]({fig})", head)
        self.assertIn("Missing: no claims map in this results tree", head)
        self.assertNotIn("claims_map.md", text)
        self.check_tree(root)

    def test_without_study_2_figure_a_says_so(self):
        root = unpack("no_study2", drop=[f"columns/shipped__{a}/study2_lateral"
                                         for a in ("vehicle", "paper_sim")])
        head = "\n".join(build(root).splitlines()[:PAGE])
        for fig in ("page/a.png", "page/b.png", "page/c.png"):
            self.assertIn(f"]({fig})", head)
            self.assertTrue(os.path.exists(os.path.join(root, fig)))
        self.assertIn("**A.** Missing: no column has study 2", head)
        self.check_tree(root)


if __name__ == "__main__":
    ok = unittest.main(argv=["markdown"], defaultTest="Markdown", exit=False).result
    if not ok.wasSuccessful():
        sys.exit(1)
    if python_with_matplotlib() is None:
        print("skipped: the report itself (no python3 with numpy and matplotlib)")
        sys.exit(77)
    ok = unittest.main(argv=["report"], defaultTest="Report", exit=False).result
    sys.exit(0 if ok.wasSuccessful() else 1)
