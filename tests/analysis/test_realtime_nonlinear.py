"""analysis/realtime_nonlinear.py on a small fixture: each case scored against the
Newton case of its own law (xpbd_neo's implied law included) and against the
reference, steady-state flags, per-frame times."""
import csv
import json
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import realtime_nonlinear  # noqa: E402

REST = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1]], float)


def write_case(root, case, model, params, u, dynamic, frames=50, steady=None):
    d = os.path.join(root, "pull", case)
    os.makedirs(d)
    with open(os.path.join(d, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(REST, u)):
            f.write(f"{i},{p[0]},{p[1]},{p[2]},{q[0]},{q[1]},{q[2]}\n")
    run = {"model": model, "parameters": params, "dynamic": dynamic, "frames": frames,
           "reached_steady_state": steady, "last_frame_change_m": 1e-12, "max_displacement_m": 1.0,
           "scenario_resolved": {"load": {"point": [0, 0, 1]}},
           "build": {"cpu_model": "test cpu", "hardware_threads": 2, "build_type": "Release", "compiler": "g++",
                     "git_commit": "abc"}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"step": {"median_ms": 9.0, "p95_ms": 10.0, "count": frames}, "setup_ms": 5.0,
                   "step_after_ramp": {"median_ms": 2.0, "p95_ms": 3.0, "count": frames - 1}}, f)


class RealtimeNonlinearScript(unittest.TestCase):
    def test_each_case_against_its_own_law(self):
        neo = np.array([[0, 0, 4], [0, 0, 2], [0, 0, 2]], float)
        xlaw = 1.1 * neo
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "rt")
            write_case(exp, "newton-neo", "fem", {"solver": "newton", "material_law": "neo_hookean"}, neo, False)
            write_case(exp, "newton-x", "fem", {"solver": "newton", "material_law": "xpbd_neo_hookean"}, xlaw, False)
            write_case(exp, "linear", "fem", {"solver": "direct", "material_law": "neo_hookean"}, 0.8 * neo, False)
            write_case(exp, "vbd", "vbd", {"material_law": "neo_hookean", "time_step": 0.01}, 0.99 * neo, True,
                       300, True)
            write_case(exp, "xpbd", "xpbd_neo", {"time_step": 0.001}, 0.98 * xlaw, True, 3000, False)
            with open(os.path.join(exp, "experiment.json"), "w") as f:
                json.dump({"name": "realtime_nonlinear", "reference": "newton-neo",
                           "scenarios": [{"name": "pull", "role": "cube_pull",
                                          "cases": ["newton-neo", "newton-x", "linear", "vbd", "xpbd"]}]}, f)
            realtime_nonlinear.make(exp, tmp, None)
            with open(os.path.join(tmp, "tables", "realtime_nonlinear.csv")) as f:
                rows = list(csv.reader(f))
            by_case = {r[1]: r for r in rows[1:]}
            self.assertEqual(by_case["newton-x"][2:5], ["xpbd_neo_hookean", "0", "0.1"])
            self.assertEqual(by_case["linear"][2:5], ["linear", "", "0.2"])  # fem direct is linear whatever it is given
            self.assertEqual(by_case["vbd"][2:7], ["neo_hookean", "0.01", "0.01", "300 (3.00)", "yes"])
            self.assertEqual(by_case["xpbd"][2:7], ["xpbd_neo_hookean", "0.02", "0.078", "3000 (3.00)", "no"])
            self.assertEqual(by_case["vbd"][8:10], ["2.000", "3.000"])  # after the ramp
            self.assertEqual(by_case["newton-neo"][8], "9.000")  # static: every frame
            self.assertTrue(os.path.isfile(os.path.join(tmp, "figures", "realtime_nonlinear.png")))

    def test_missing_reference_is_one_line(self):
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "rt")
            write_case(exp, "vbd", "vbd", {}, REST, True, 10, True)
            with open(os.path.join(exp, "experiment.json"), "w") as f:
                json.dump({"name": "realtime_nonlinear", "reference": "newton-neo",
                           "scenarios": [{"name": "pull", "role": "cube_pull", "cases": ["vbd"]}]}, f)
            with self.assertRaises(realtime_nonlinear.ResultsError) as e:
                realtime_nonlinear.make(exp, tmp, None)
            self.assertIn("newton-neo", str(e.exception))


if __name__ == "__main__":
    unittest.main()
