"""Metrics on hand-made fields, and the table script on a small fixture (issue 7)."""
import json
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import metrics  # noqa: E402
import tables  # noqa: E402


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


def write_case(root, scenario, case, rest, u, median):
    d = os.path.join(root, scenario, case)
    os.makedirs(d)
    with open(os.path.join(d, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(rest, u)):
            f.write(f"{i},{p[0]},{p[1]},{p[2]},{q[0]},{q[1]},{q[2]}\n")
    build = {"cpu_model": "test cpu", "hardware_threads": 2, "build_type": "Release", "compiler": "g++",
             "git_commit": "abc"}
    run = {"scenario_as_read": {"load": {"point": [0, 0, 1]}}, "build": build, "parameters": {"iterations": 10},
           "reached_steady_state": True}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"setup_ms": 1.0, "step": {"median_ms": median, "p95_ms": 2 * median}}, f)


class TableScript(unittest.TestCase):
    def test_tables_from_fixture(self):
        rest = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]], float)
        ref = np.array([[0, 0, 4], [0, 0, 1], [0, 0, 2], [0, 0, 0]], float)
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "paper")
            for kind in ["cube", "liver"]:
                for case in ["pull", "push"]:
                    s = f"{kind}-{case}"
                    write_case(exp, s, "fem-direct", rest, ref, 3.0)
                    write_case(exp, s, "fem-iterative", rest, ref, 100.0)
                    write_case(exp, s, "hybrid", rest, 0.5 * ref, 4.0)
                    # PBD: u_z = (1, 3, 2, 0) -> hand-computed r against (4, 1, 2, 0).
                    write_case(exp, s, "pbd", rest, np.array([[0, 0, 1], [0, 0, 3], [0, 0, 2], [0, 0, 0]], float), 2.0)
            out = os.path.join(tmp, "tables")
            tables.make_tables(exp, out)
            rows = open(os.path.join(out, "table1.csv")).read().splitlines()
            self.assertEqual(rows[0], "models,pull (measured),pull (paper),push (measured),push (paper)")
            self.assertEqual(rows[1], "hybrid vs FEM,1.000,0.975,1.000,0.972")
            r = np.corrcoef([1, 3, 2, 0], [4, 1, 2, 0])[0, 1]
            self.assertEqual(rows[2], f"PBD vs FEM,{r:.3f},0.852,{r:.3f},0.863")
            t2 = open(os.path.join(out, "table2.csv")).read().splitlines()
            self.assertTrue(t2[1].startswith("hybrid,4.00,8.00,3.8,4.00,8.00,3.7"), t2[1])
            self.assertIn("test cpu", open(os.path.join(out, "table2.md")).read())


if __name__ == "__main__":
    unittest.main()
