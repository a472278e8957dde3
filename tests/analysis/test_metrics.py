"""Metrics on hand-made fields, and the table script on a small fixture."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import metrics  # noqa: E402
import results_index  # noqa: E402
import table1  # noqa: E402
import table2  # noqa: E402
import table3  # noqa: E402
import time_vs_accuracy  # noqa: E402


class Metrics(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(3)
        self.rest = rng.uniform(-1, 1, (50, 3))
        self.u = rng.normal(size=(50, 3))

    def test_identical_fields(self):
        m = metrics.compare(self.u, self.u, self.rest, self.rest[0])
        self.assertAlmostEqual(m["corr_uz"], 1.0, places=12)
        self.assertEqual(m["rel_l2"], 0.0)
        self.assertEqual(m["max_error"], 0.0)
        self.assertAlmostEqual(m["load_ratio"], 1.0, places=12)

    def test_scaled_field_correlates_but_l2_and_ratio_show_scale(self):
        m = metrics.compare(0.5 * self.u, self.u, self.rest, self.rest[3])
        self.assertAlmostEqual(m["corr_uz"], 1.0, places=12)
        self.assertAlmostEqual(m["corr_mag"], 1.0, places=12)
        self.assertAlmostEqual(m["rel_l2"], 0.5, places=12)
        self.assertAlmostEqual(m["load_ratio"], 0.5, places=12)

    def test_hand_computed_correlation(self):
        # x = (1, 2, 3), y = (1, 3, 2): r = 0.5 (cov 0.5 / (1 * 1)).
        self.assertAlmostEqual(metrics.pearson([1, 2, 3], [1, 3, 2]), 0.5, places=15)
        self.assertTrue(np.isnan(metrics.pearson([1, 1, 1], [1, 2, 3])))

    def test_bad_csv_header(self):
        with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
            f.write("a,b\n1,2\n")
        with self.assertRaisesRegex(ValueError, "bad header"):
            metrics.read_displacements(f.name)
        os.unlink(f.name)


def read(path):
    with open(path) as f:
        return f.read()


def write_case(root, scenario, case, rest, u, median, model=None):
    d = os.path.join(root, scenario, case)
    os.makedirs(d)
    with open(os.path.join(d, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(rest, u)):
            f.write(f"{i},{p[0]},{p[1]},{p[2]},{q[0]},{q[1]},{q[2]}\n")
    build = {"cpu_model": "test cpu", "hardware_threads": 2, "build_type": "Release", "compiler": "g++",
             "git_commit": "abc"}
    run = {"scenario_resolved": {"load": {"point": [0, 0, 1]}}, "build": build, "model": model or case,
           "parameters": {"iterations": 10}, "parameters_given": {"iterations": 10}, "reached_steady_state": True}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"setup_ms": 1.0, "step": {"median_ms": median, "p95_ms": 2 * median}}, f)


def write_fixture(exp, extra_cases=(), name_of=lambda kind, lc: f"{kind}-{lc}"):
    """A paper-like results tree: four scenarios in the paper's roles (cube_pull ...),
    named name_of(kind, load case), the paper's cases plus `extra_cases`."""
    rest = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]], float)
    ref = np.array([[0, 0, 4], [0, 0, 1], [0, 0, 2], [0, 0, 0]], float)
    cases = ["fem-direct", "fem-iterative", "pbd", "hybrid", *extra_cases]
    index = {"name": "paper", "reference": "fem-direct", "scenarios": []}
    for kind in ["cube", "liver"]:
        for lc in ["pull", "push"]:
            s = name_of(kind, lc)
            index["scenarios"].append({"name": s, "role": f"{kind}_{lc}", "cases": cases})
            write_case(exp, s, "fem-direct", rest, ref, 3.0, "fem")
            write_case(exp, s, "fem-iterative", rest, ref, 100.0, "fem")
            write_case(exp, s, "hybrid", rest, 0.5 * ref, 4.0)
            # PBD: u_z = (1, 3, 2, 0) -> hand-computed r against (4, 1, 2, 0).
            write_case(exp, s, "pbd", rest, np.array([[0, 0, 1], [0, 0, 3], [0, 0, 2], [0, 0, 0]], float), 2.0)
            for extra in extra_cases:
                write_case(exp, s, extra, rest, 0.25 * ref + 0.01, 0.5, "some-new-model")
    with open(os.path.join(exp, "experiment.json"), "w") as f:
        json.dump(index, f)


class TableScripts(unittest.TestCase):
    def test_tables_from_fixture(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp)
            out = os.path.join(tmp, "tables")
            table1.make(exp, out)
            table2.make(exp, out)
            rows = read(os.path.join(out, "table1.csv")).splitlines()
            self.assertEqual(rows[0], "models,pull (measured),pull (paper),push (measured),push (paper)")
            self.assertEqual(rows[1], "hybrid vs fem-direct,1.000,0.975,1.000,0.972")
            r = np.corrcoef([1, 3, 2, 0], [4, 1, 2, 0])[0, 1]
            self.assertEqual(rows[2], f"pbd vs fem-direct,{r:.3f},0.852,{r:.3f},0.863")
            self.assertEqual(rows[3], "fem-iterative vs fem-direct,1.000,,1.000,")
            t2 = read(os.path.join(out, "table2.csv")).splitlines()
            self.assertTrue(t2[1].startswith("hybrid,4.00,8.00,3.8,4.00,8.00,3.7"), t2[1])
            self.assertTrue(t2[3].startswith("fem-direct,3.00,6.00,108.2"), t2[3])
            self.assertIn("test cpu", read(os.path.join(out, "table2.md")))

    def test_a_killed_runs_staging_folders_are_not_cases(self):
        # A run killed between its last write and the rename leaves <case>.tmp<pid>
        # (run.json and all); one killed during the swap, <case>.old<pid>
        # (meshing/staged_folder.h). Neither is a case of the experiment.
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp)
            rest = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]], float)
            write_case(exp, "cube-pull", "pbd.tmp4242", rest, rest, 1.0, "pbd")
            write_case(exp, "cube-pull", "hybrid.old77", rest, rest, 1.0, "hybrid")
            e = results_index.Experiment(exp)
            self.assertEqual(list(e.scenarios["cube-pull"]), ["fem-direct", "fem-iterative", "pbd", "hybrid"])
            self.assertTrue(results_index.is_case_folder(os.path.join(exp, "cube-pull", "pbd")))
            self.assertFalse(results_index.is_case_folder(os.path.join(exp, "cube-pull", "pbd.tmp4242")))

    def test_no_reference_declared_is_a_clear_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp)
            index_path = os.path.join(exp, "experiment.json")
            with open(index_path) as f:
                index = json.load(f)
            del index["reference"]
            with open(index_path, "w") as f:
                json.dump(index, f)
            with self.assertRaisesRegex(ValueError, "no reference case declared"):
                table1.make(exp, os.path.join(tmp, "tables"))


class ScenariosByRole(unittest.TestCase):
    """The analysis finds the paper's scenarios by their role in experiment.json, never
    by their names, and a partial or role-less experiment is a one-line error."""

    def test_scenarios_are_found_by_role_whatever_their_names(self):
        with tempfile.TemporaryDirectory() as tmp:
            plain, renamed = os.path.join(tmp, "plain", "paper"), os.path.join(tmp, "renamed", "paper")
            write_fixture(plain)
            # Names that say nothing, and in another order than the roles: push before pull.
            write_fixture(renamed, name_of=lambda kind, lc: {"pull": "zz", "push": "aa"}[lc] + f"-{len(kind)}")
            for module in (table1, table2, table3):
                module.make(plain, os.path.join(tmp, "plain", "tables"))
                module.make(renamed, os.path.join(tmp, "renamed", "tables"))
            for name in ("table1", "table1_metrics", "table2", "table3", "table3_metrics"):
                self.assertEqual(read(os.path.join(tmp, "plain", "tables", name + ".csv")),
                                 read(os.path.join(tmp, "renamed", "tables", name + ".csv")), name)
            exp = results_index.Experiment(renamed)
            self.assertEqual(exp.scenario_name("cube_push"), "aa-4")
            self.assertEqual(list(exp.by_role("liver_pull")), ["fem-direct", "fem-iterative", "pbd", "hybrid"])

    def run_script(self, script, exp_dir, out):
        return subprocess.run([sys.executable, os.path.join(ROOT, "analysis", script), exp_dir, out],
                              capture_output=True, text=True)

    def test_a_partial_experiment_is_a_one_line_error_naming_the_role_and_folder(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp)
            shutil.rmtree(os.path.join(exp, "cube-push"))  # only cube-pull (and the liver) ran
            for script in ("table1.py", "table2.py", "time_vs_accuracy.py", "figure4.py", "reproduce.py"):
                r = self.run_script(script, exp, os.path.join(tmp, "out"))
                self.assertEqual(r.returncode, 2, script + ": " + r.stderr)
                self.assertNotIn("Traceback", r.stderr, script)
                self.assertEqual(len(r.stderr.strip().splitlines()), 1, script + ": " + r.stderr)
                self.assertIn(f"{exp}: no results for role 'cube_push' (scenario 'cube-push')", r.stderr, script)
            with self.assertRaisesRegex(results_index.ResultsError, "no results for role 'cube_push'"):
                table1.make(exp, os.path.join(tmp, "tables"))

    def test_an_experiment_without_roles_says_so(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp)
            index_path = os.path.join(exp, "experiment.json")
            with open(index_path) as f:
                index = json.load(f)
            for s in index["scenarios"]:
                del s["role"]
            with open(index_path, "w") as f:
                json.dump(index, f)
            r = self.run_script("table3.py", exp, os.path.join(tmp, "out"))
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertNotIn("Traceback", r.stderr)
            self.assertIn("experiment.json gives no scenario the role 'liver_pull' (roles: none;", r.stderr)


class AnalysisReadsTheModelListFromResults(unittest.TestCase):
    """A case the analysis code never names flows into tables 1-3 and the
    time-vs-accuracy figure."""

    def test_extra_case_appears_everywhere(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            write_fixture(exp, extra_cases=["my-variant"])
            out = os.path.join(tmp, "tables")
            self.assertIn("my-variant", table1.make(exp, out))
            self.assertIn("my-variant", table2.make(exp, out))
            self.assertIn("my-variant", table3.make(exp, out))
            t1 = read(os.path.join(out, "table1.csv"))
            self.assertIn("my-variant vs fem-direct,1.000,,1.000,", t1)
            t1m = read(os.path.join(out, "table1_metrics.csv"))
            self.assertIn("my-variant,relative L2 error", t1m)
            t2 = read(os.path.join(out, "table2.csv"))
            self.assertIn("my-variant,0.50,1.00,,0.50,1.00,,1", t2)
            self.assertIn("| my-variant | some-new-model | iterations 10 |", read(os.path.join(out, "table2.md")))
            self.assertIn("my-variant", read(os.path.join(out, "table3_metrics.csv")))
            figures = os.path.join(tmp, "figures")
            os.makedirs(figures)
            self.assertIn("my-variant", time_vs_accuracy.make(exp, figures))
            self.assertTrue(os.path.getsize(os.path.join(figures, "time_vs_accuracy.png")) > 0)


if __name__ == "__main__":
    unittest.main()
