"""analysis/steady_state.py on a small fixture: steady frames, the last change against
the tolerance, inverted triangles counted, metrics against the reference, failed cases."""
import json
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import steady_state  # noqa: E402

REST = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
TRIANGLES = [[0, 1, 2], [1, 3, 2]]


def write_csv(path, u):
    with open(path, "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(REST, u)):
            f.write(f"{i},{p[0]},{p[1]},{p[2]},{q[0]},{q[1]},{q[2]}\n")


def write_case(root, point, case, u, steady, frames, change):
    d = os.path.join(root, point, case)
    os.makedirs(d)
    write_csv(os.path.join(d, "top_surface.csv"), u)
    write_csv(os.path.join(d, "surface.csv"), u)
    run = {"scenario_resolved": {"load": {"point": [0, 0, 0]}, "frames": {"steady_tolerance": 1e-5}},
           "reached_steady_state": steady, "steady_frame": frames - 1 if steady else -1, "frames": frames,
           "last_frame_change_m": change, "max_displacement_m": float(np.linalg.norm(u, axis=1).max()),
           "parameters": {}, "build": {"cpu_model": "test cpu", "build_type": "Release", "compiler": "g++",
                                       "git_commit": "abc"}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"step": {"median_ms": 9.0}, "step_after_ramp": {"median_ms": 2.0}}, f)


def write_mesh(root, point):
    d = os.path.join(root, point, "mesh")
    os.makedirs(d)
    with open(os.path.join(d, "fine_surface.obj"), "w") as f:
        f.writelines(f"v {p[0]} {p[1]} {p[2]}\n" for p in REST)
        f.writelines(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n" for t in TRIANGLES)


class SteadyStateScript(unittest.TestCase):
    def test_tables_from_fixture(self):
        ref = np.array([[0, 0, 1], [0, 0, 2], [0, 0, 3], [0, 0, 4]], float)
        folded = np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0], [-1.5, -1.5, 0]], float)  # vertex 3 across edge 1-2
        with tempfile.TemporaryDirectory() as tmp:
            exp = os.path.join(tmp, "study")
            points = []
            for n, u, steady in [(1, folded, False), (3, 0.5 * ref, True)]:
                name = f"pull__substeps={n}"
                write_mesh(exp, name)
                write_case(exp, name, "fem-direct", ref, True, 50, 0.0)
                write_case(exp, name, "pbd", u, steady, 120 if steady else 5000, 1e-6 if steady else 2e-3)
                points.append({"name": name, "cases": ["fem-direct", "pbd", "hybrid"],
                               "sweep": {"base": "pull", "values": {"substeps": n}}})
            with open(os.path.join(exp, "pull__substeps=1", "hybrid.failed.json"), "w") as f:
                json.dump({"case": "hybrid", "error": "diverged"}, f)
            with open(os.path.join(exp, "experiment.json"), "w") as f:
                json.dump({"name": "study", "reference": "fem-direct", "scenarios": points}, f)
            steady, total = steady_state.make(exp, tmp)
            self.assertEqual((steady, total), (1, 4))
            with open(os.path.join(tmp, "tables", "study.csv")) as f:
                rows = f.read().splitlines()
            self.assertEqual(rows[0], "scenario,case,substeps,steady at frame,last change / max |u|,r(u_z),"
                                      "relative L2,|u| ratio at load,inverted triangles,median ms")
            self.assertTrue(rows[1].startswith("pull,pbd,1,no (5000),"), rows[1])
            self.assertTrue(rows[1].endswith(",1,2.00"), rows[1])  # one triangle turned over
            self.assertEqual(rows[2], "pull,hybrid,1,no result" + "," * 7)
            self.assertEqual(rows[3], f"pull,pbd,3,119,{1e-6 / 2:.1e},1.000,0.500,0.500,0,2.00")
            with open(os.path.join(tmp, "tables", "study_summary.csv")) as f:
                summary = f.read().splitlines()
            self.assertEqual(summary[0], "case,substeps,pull steady at,pull rel. L2,pull inverted")
            self.assertEqual(summary[3], "pbd,3,119,0.500,0")


if __name__ == "__main__":
    unittest.main()
