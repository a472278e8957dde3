"""analysis/robustness_table.py on hand-made reports of scripts/fuzz_libfuzzer."""
import json
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import robustness_table  # noqa: E402


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


class RobustnessTable(unittest.TestCase):
    def test_counts_of_both_drivers_and_libfuzzers_artifacts(self):
        with tempfile.TemporaryDirectory() as work:
            mutator = {"obj": {"inputs": 5004, "findings": 0, "distinct_messages": 2, "slowest_ms": 12.34,
                               "messages": {"a.obj: line # bad": 3, "a.obj: empty": 1}}}
            write(os.path.join(work, "reports", "mutator_obj.json"), json.dumps(mutator))
            libfuzzer = {"inputs": 99, "distinct_messages": 4, "slowest_ms": 1500.0,
                         "messages": {"a.obj: empty": 7, "a.obj: face # out of range": 2,
                                      "a.obj: line #: expected a number, found '...'x'...'": 1,
                                      "a.obj: line #: expected a number, found '...'": 1}}
            write(os.path.join(work, "reports", "libfuzzer_obj.json"), json.dumps(libfuzzer))
            write(os.path.join(work, "libfuzzer", "obj", "log.txt"),
                  "Done 100 runs in 60 second(s)\nstat::number_of_executed_units: 100\nstat::peak_rss_mb: 80\n")
            write(os.path.join(work, "libfuzzer", "obj", "artifacts", "slow-unit-abc"), "x")
            write(os.path.join(work, "libfuzzer", "obj", "artifacts", "timeout-def"), "x")
            out = os.path.join(work, "table.md")
            rows = robustness_table.make(work, out, ["obj", "gmsh"], 5000, 60)
            obj, gmsh = rows
            self.assertEqual(obj["mutator_inputs"], 5004)
            self.assertEqual(obj["libfuzzer_inputs"], 100)  # libFuzzer's count of executed units
            self.assertEqual(obj["messages_union"], 5)
            self.assertEqual(obj["messages_before_quote"], 4)  # the two 'expected a number' are one
            self.assertEqual((obj["crashes"], obj["hangs"], obj["slow_units"]), (0, 1, 1))
            self.assertIsNone(gmsh["mutator_inputs"])  # no report: said so, not zero
            with open(out) as f:
                text = f.read()
            self.assertIn("| obj | Wavefront OBJ | 5004 | 100 | 0 | 1 | 0 | 2 / 4 / 5 | 4 | 12.3 / 1500.0 | 1 |", text)
            self.assertIn("| gmsh | Gmsh .msh v1 and v2 | (no report) | (no report) |", text)


if __name__ == "__main__":
    unittest.main()
