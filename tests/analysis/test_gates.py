"""The gate checker (analysis/gates.py) on a hand-made results tree: gates that
hold pass, gates that do not fail, and identical-file gates see a changed byte."""
import io
import json
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gates  # noqa: E402
from test_metrics import write_fixture  # noqa: E402


def write_gates(path, gate_list):
    with open(path, "w") as f:
        json.dump({"gates": gate_list}, f)


class Gates(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.exp = os.path.join(self.tmp.name, "first")
        self.again = os.path.join(self.tmp.name, "second")
        write_fixture(self.exp)
        write_fixture(self.again)
        self.file = os.path.join(self.tmp.name, "gates.json")

    def tearDown(self):
        self.tmp.cleanup()

    def check(self, gate_list, repeat=None):
        write_gates(self.file, gate_list)
        out = io.StringIO()
        return gates.check(self.exp, self.file, repeat, out), out.getvalue()

    def test_holding_and_failing_thresholds(self):
        # hybrid is 0.5 x the reference: r = 1, relative L2 = 0.5.
        ok, text = self.check([{"role": "cube_pull", "case": "hybrid", "metric": "rel_l2", "at_most": 0.51}])
        self.assertTrue(ok, text)
        self.assertIn("measured          0.5", text)
        ok, text = self.check([{"role": "cube_pull", "case": "hybrid", "metric": "rel_l2", "at_most": 0.49}])
        self.assertFalse(ok, text)
        self.assertIn("FAIL", text)
        ok, _ = self.check([{"role": "cube_pull", "case": "hybrid", "metric": "corr_uz", "at_least": 1.01}])
        self.assertFalse(ok)

    def test_below_case(self):
        ok, _ = self.check([{"role": "cube_pull", "case": "hybrid", "metric": "rel_l2", "below_case": "pbd"}])
        self.assertTrue(ok)
        ok, _ = self.check([{"role": "cube_pull", "case": "pbd", "metric": "rel_l2", "below_case": "hybrid"}])
        self.assertFalse(ok)

    def test_identical_files(self):
        gate = [{"role": "cube_push", "case": "pbd", "identical": ["top_surface.csv"]}]
        ok, _ = self.check(gate, self.again)
        self.assertTrue(ok)
        with open(os.path.join(self.again, "cube-push", "pbd", "top_surface.csv"), "a") as f:
            f.write(" ")
        ok, text = self.check(gate, self.again)
        self.assertFalse(ok)
        self.assertIn("differ: top_surface.csv", text)
        with self.assertRaisesRegex(ValueError, "needs --repeat"):
            self.check(gate)


if __name__ == "__main__":
    unittest.main()
