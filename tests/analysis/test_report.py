"""analysis/report/build.py: the static report built from the committed results (every
page there, every link resolving, every figure holding traces, the same inputs giving
the same pages), and a missing input failing in one line that names it. The pages in a
real browser: tests/browser/test_report_browser.py (CTest report_browser).

Run by CTest (analysis_tests), or alone:
  /usr/bin/python3 -m unittest discover -s tests/analysis -p "test_report.py"
"""
import html.parser
import json
import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(ROOT, "analysis", "report"), os.path.join(ROOT, "analysis")]
import build  # noqa: E402
import sources  # noqa: E402
import truthcube  # noqa: E402
from results_index import ResultsError  # noqa: E402

RESULTS = os.path.join(ROOT, "results")


class Page(html.parser.HTMLParser):
    """A page's links (href and src), figure placeholders and figures' JSON."""

    def __init__(self, path):
        super().__init__()
        self.links, self.divs, self.figures, self._figure = [], set(), {}, None
        with open(path, encoding="utf-8") as f:
            self.feed(f.read())

    def handle_starttag(self, name, attrs):
        a = dict(attrs)
        self.links += [a[k] for k in ("href", "src") if k in a]
        if name == "div" and "id" in a:
            self.divs.add(a["id"])
        if name == "script" and "data-figure" in a:
            self._figure = a["data-figure"]

    def handle_data(self, data):
        if self._figure:
            self.figures[self._figure] = json.loads(data)

    def handle_endtag(self, name):
        if name == "script":
            self._figure = None


class CommittedReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = tempfile.mkdtemp(prefix="report-")
        cls.pages = build.make(RESULTS, cls.out)
        cls.roles = list(dict.fromkeys(r["role"] for r in sources.read_dicts(
            os.path.join(RESULTS, "tables", "suite_scores.csv"))))
        cls.parsed = {name: Page(os.path.join(cls.out, name)) for name in cls.pages}

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_every_page_is_there(self):
        expected = {"index.html", "truth_cube.html", "paper.html", "scaling.html"} | {f"{r}.html" for r in self.roles}
        self.assertEqual(set(self.pages), expected)
        with open(os.path.join(self.out, "plotly.js"), encoding="utf-8") as f:
            self.assertIn("plotly.js v", f.read(200))

    def test_every_link_resolves(self):
        for name, page in self.parsed.items():
            for target in page.links:
                self.assertFalse(target.startswith(("http:", "https:", "//")), f"{name}: {target} is not offline")
                self.assertTrue(os.path.isfile(os.path.join(self.out, target.split("#")[0])), f"{name}: {target}")
            for other in self.pages:  # the navigation links every page
                self.assertIn(other, page.links, name)

    def test_every_figure_holds_traces_and_has_its_place(self):
        for name, page in self.parsed.items():
            for div_id, fig in page.figures.items():
                self.assertIn(div_id, page.divs, name)
                self.assertGreater(len(fig["data"]), 0, f"{name}: {div_id}")
        self.assertEqual(self.parsed["index.html"].figures, {})  # the verdict is a table
        for name in ("truth_cube.html", "paper.html", "scaling.html") + tuple(f"{r}.html" for r in self.roles):
            self.assertTrue(self.parsed[name].figures, name)

    def test_the_pareto_plot_draws_the_budgets_and_the_bands(self):
        fig = self.parsed["cube_pull_disc.html"].figures["cube_pull_disc-pareto"]
        self.assertEqual(fig["layout"]["xaxis"]["type"], "log")
        self.assertEqual(fig["layout"]["yaxis"]["type"], "log")
        self.assertEqual(sorted(s["x0"] for s in fig["layout"]["shapes"]), [0.1, 1.0, 16.0])
        names = [t["name"] for t in fig["data"]]
        self.assertTrue(any(n.startswith("reference's own error") for n in names), names)
        self.assertTrue(any(n.startswith("law-to-law gap") for n in names), names)
        hovers = [h for t in fig["data"] for h in t.get("hovertext", [])]
        self.assertTrue(any("<b>pd</b>" in h and "iterations = 10" in h for h in hovers))

    def test_every_pareto_plot_holds_its_cases_not_only_the_bands(self):
        for role in self.roles:
            fig = self.parsed[f"{role}.html"].figures[f"{role}-pareto"]
            cases = [h for t in fig["data"] for h in t.get("hovertext", []) if h.startswith("<b>")]
            self.assertGreater(len(cases), 1, role)

    def test_a_scenario_without_coordinates_has_no_3d_view(self):
        for role in self.roles:
            figures = self.parsed[f"{role}.html"].figures
            if role.startswith("liver"):
                self.assertNotIn(f"{role}-surface-3d", figures)
                with open(os.path.join(self.out, f"{role}.html"), encoding="utf-8") as f:
                    self.assertIn("No 3D view", f.read())
            else:
                self.assertIn(f"{role}-surface-3d", figures)
                self.assertGreaterEqual(len(figures[f"{role}-surface-3d"]["data"]), 2, role)  # the reference, a winner

    def test_each_page_says_once_where_it_was_measured(self):
        for name in self.pages:
            with open(os.path.join(self.out, name), encoding="utf-8") as f:
                text = f.read()
            self.assertEqual(text.count("Where these numbers were measured"), 1, name)
            self.assertIn("Measured", text.split("Where these numbers were measured")[1], name)

    def test_the_same_inputs_give_the_same_pages(self):
        again = tempfile.mkdtemp(prefix="report-again-")
        try:
            self.assertEqual(build.make(RESULTS, again), self.pages)
            for name in self.pages:
                with open(os.path.join(self.out, name), "rb") as a, open(os.path.join(again, name), "rb") as b:
                    self.assertEqual(a.read(), b.read(), name)
        finally:
            shutil.rmtree(again, ignore_errors=True)


def results_without(missing):
    """A temporary results tree of links to the committed one without `missing` (a file one
    folder down, e.g. "tables/leaderboard.csv"); returns (its folder, the missing path)."""
    tmp = tempfile.mkdtemp(prefix="report-results-")
    folder, name = os.path.split(missing)
    for entry in os.listdir(RESULTS):
        if entry != folder:
            os.symlink(os.path.join(RESULTS, entry), os.path.join(tmp, entry))
    os.makedirs(os.path.join(tmp, folder))
    for f in os.listdir(os.path.join(RESULTS, folder)):
        if f != name:
            os.symlink(os.path.join(RESULTS, folder, f), os.path.join(tmp, folder, f))
    return tmp, os.path.join(tmp, missing)


class MissingInputs(unittest.TestCase):
    def assert_one_line_naming(self, missing, named=None):
        """Building without `missing` raises one line starting with `named` (default: the
        missing file's path) and writes nothing."""
        tmp, path = results_without(missing)
        try:
            out = os.path.join(tmp, "report")
            with self.assertRaises(ResultsError) as caught:
                build.make(tmp, out)
            message = str(caught.exception)
            self.assertTrue(message.startswith(os.path.join(tmp, named or missing) + ": missing"), message)
            self.assertNotIn("\n", message)
            self.assertFalse(os.path.exists(out))
        finally:
            shutil.rmtree(tmp)

    def test_a_scenario_whose_cases_have_no_error_is_an_error_not_an_empty_plot(self):
        tmp, path = results_without("tables/suite_scores.csv")
        try:
            with open(os.path.join(RESULTS, "tables", "suite_scores.csv"), newline="") as f:
                rows = list(csv.reader(f))
            column = rows[0].index("rel L2 vs reference")
            for r in rows[1:]:
                if r[0] == "cube_pull_disc":
                    r[column] = "n/a"
            with open(path, "w", newline="") as f:
                csv.writer(f, lineterminator="\n").writerows(rows)
            with self.assertRaisesRegex(ResultsError, "^cube_pull_disc: no ranked case has a finite"):
                build.make(tmp, os.path.join(tmp, "report"))
        finally:
            shutil.rmtree(tmp)

    def test_a_missing_table_is_one_line_naming_it(self):
        for missing in ("tables/leaderboard.csv", "tables/law_sensitivity.csv", "tables/scaling.csv",
                        "tables/table2.csv", "tables/truth_cube.csv"):
            with self.subTest(missing):
                self.assert_one_line_naming(missing)

    def test_a_missing_machine_note_or_figure_is_one_line_naming_it(self):
        self.assert_one_line_naming("tables/suite_scores.md")
        self.assert_one_line_naming("figures/figure5_liver.png", "figures/figure5*.png")

    def test_the_command_prints_the_one_line_and_exits_2(self):
        tmp, path = results_without("tables/leaderboard_converged.csv")
        try:
            run = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "report", "build.py"),
                                  "--results", tmp, "--out", os.path.join(tmp, "report")],
                                 capture_output=True, text=True)
            self.assertEqual(run.returncode, 2)
            self.assertEqual(run.stderr.strip().splitlines(), [f"report: {path}: missing "
                                                              "(a committed table: regenerate it with the script "
                                                              "named in its .md)"])
        finally:
            shutil.rmtree(tmp)

    def test_without_the_bead_table_the_truth_cube_page_says_so(self):
        empty = tempfile.mkdtemp(prefix="report-data-")
        try:
            body, _ = truthcube.body(sources.Suite(RESULTS), empty)
            self.assertIn("The measured bead table is not in the data directory", body)
            self.assertIn(os.path.join(empty, "data", "truthcube", "uniaxial_positions.csv"), body)
            self.assertNotIn("truth-cube-beads-3d", body)
        finally:
            shutil.rmtree(empty)


class MachineNotes(unittest.TestCase):
    def test_the_sentence_and_its_busy_machine_sentence(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "t.md")
            with open(path, "w") as f:
                f.write("| a |\n|---|\n| 1 |\n\nWhat it is. Measured on CPU X (2 hardware threads), g++ 12.2.0, "
                        "commit abc; one thread. On a busy machine (load 5.9): c (load 5.9).\n\n### Next\n"
                        "Measured 2026-01-01T00:00:00 on Y, load average 0.30, 0.83 at the start.\n")
            self.assertEqual(sources.machine_notes(path), [
                "Measured on CPU X (2 hardware threads), g++ 12.2.0, commit abc; one thread. "
                "On a busy machine (load 5.9): c (load 5.9).",
                "Measured 2026-01-01T00:00:00 on Y, load average 0.30, 0.83 at the start."])


if __name__ == "__main__":
    unittest.main()
