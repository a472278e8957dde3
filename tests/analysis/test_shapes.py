"""analysis/shapes.py on a small fixture: metrics against fem-direct, failed cases listed."""
import json
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import shapes  # noqa: E402


def write_case(root, scenario, case, shape, resolution, rest, u, median, steady=True):
    d = os.path.join(root, scenario, case)
    os.makedirs(d)
    with open(os.path.join(d, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(rest, u)):
            f.write(f"{i},{p[0]},{p[1]},{p[2]},{q[0]},{q[1]},{q[2]}\n")
    run = {"scenario_resolved": {"mesh": {"type": "shape", "shape": shape, "resolution": resolution},
                                "load": {"point": [0, 0, 1]}},
           "mesh": {"surface_vertices": len(rest)}, "reached_steady_state": steady,
           "build": {"cpu_model": "test cpu", "build_type": "Release", "compiler": "g++", "git_commit": "abc"}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"setup_ms": 1.0, "step": {"median_ms": median, "p95_ms": 2 * median}}, f)


def read(path):
    with open(path) as f:
        return f.read()


class ShapesScript(unittest.TestCase):
    def test_table_and_figure_from_fixture(self):
        rest = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 0], [1, 1, 0]], float)
        ref = np.array([[0, 0, 4], [0, 0, 1], [0, 0, 2], [0, 0, 0]], float)
        pbd = np.array([[0, 0, 1], [0, 0, 3], [0, 0, 2], [0, 0, 0]], float)
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "shapes")
            for scenario, shape in [("s-sphere", "sphere"), ("s-torus", "torus")]:
                write_case(exp, scenario, "fem-direct", shape, 15, rest, ref, 0.5)
                write_case(exp, scenario, "pbd", shape, 15, rest, pbd, 1.0, steady=False)
            write_case(exp, "s-sphere", "hybrid", "sphere", 15, rest, 0.5 * ref, 2.0)  # the torus's hybrid failed
            with open(os.path.join(exp, "s-torus", "hybrid.failed.json"), "w") as f:
                json.dump({"case": "hybrid", "error": "boom"}, f)
            cases = ["fem-direct", "pbd", "hybrid"]
            with open(os.path.join(exp, "experiment.json"), "w") as f:
                json.dump({"name": "shapes", "reference": "fem-direct",
                           "scenarios": [{"name": "s-sphere", "cases": cases}, {"name": "s-torus", "cases": cases}]}, f)
            shapes.make(exp, tmp)
            rows = read(os.path.join(tmp, "tables", "shapes.csv")).splitlines()
            self.assertEqual(rows[0], "shape,resolution,surface vertices,model,r(u_z),relative L2,"
                                      "|u| ratio at load,median ms,p95 ms")
            self.assertEqual(rows[1], "sphere,15,4,fem-direct,1.000,0.000,1.000,0.50,1.00")
            r = np.corrcoef([1, 3, 2, 0], [4, 1, 2, 0])[0, 1]
            l2 = np.linalg.norm(pbd - ref) / np.linalg.norm(ref)
            self.assertEqual(rows[2], f"sphere,15,4,pbd,{r:.3f} (not steady),{l2:.3f} (not steady),"
                                      "0.250 (not steady),1.00,2.00")
            self.assertEqual(rows[3], "sphere,15,4,hybrid,1.000,0.500,0.500,2.00,4.00")
            self.assertEqual(rows[6], "torus,15,4,hybrid" + ",no result" * 5)
            self.assertIn("test cpu", read(os.path.join(tmp, "tables", "shapes.md")))
            self.assertIn("s-torus/hybrid: boom", read(os.path.join(tmp, "tables", "shapes.md")))
            self.assertGreater(os.path.getsize(os.path.join(tmp, "figures", "shapes.png")), 1000)

    def test_different_observed_vertices_are_an_error(self):
        rest = np.array([[0, 0, 1], [1, 0, 1]], float)
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "shapes")
            write_case(exp, "s", "fem-direct", "sphere", 15, rest, rest, 0.5)
            write_case(exp, "s", "pbd", "sphere", 15, rest + 1, rest, 0.5)
            with open(os.path.join(exp, "experiment.json"), "w") as f:
                json.dump({"name": "shapes", "reference": "fem-direct"}, f)
            with self.assertRaisesRegex(ValueError, "observed vertices differ"):
                shapes.make(exp, tmp)


if __name__ == "__main__":
    unittest.main()
