"""analysis/suite_reference_convergence.py on a small results tree whose fields follow
u_k = u* + C h_k^p exactly: the observed order, the extrapolated errors, the finest run's
choice, the tables and the declared errors the leaderboard reads."""
import json
import math
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import leaderboard  # noqa: E402
import suite_reference_convergence as src  # noqa: E402

# The level-0 observed vertices (the top centre among them); each finer level adds one.
REST0 = np.array([[0, 0, 0.1], [0.05, 0, 0.1], [0, 0.05, 0.1], [0.05, 0.05, 0.1]])
U_STAR = np.array([[0, 0, 0.030], [0, 0, 0.020], [0, 0, 0.020], [0, 0, 0.010]])
SHAPE = np.array([[0, 0, -0.008], [0, 0, -0.004], [0, 0, -0.004], [0, 0, -0.002]])


def write_case(root, role, level, order, u, dofs, nu=0.45, wall=1.5):
    scenario = f"sref-{role.replace('_', '-')}-L{level}-p{order}"
    d = os.path.join(root, "suite_reference_convergence", scenario, f"neo-p{order}")
    os.makedirs(d)
    extra = np.array([[0.01 * (k + 1), 0.02, 0.1] for k in range(level)]).reshape(-1, 3)
    rest = np.vstack([REST0[::-1], extra])  # reordered, and a vertex more per level
    disp = np.vstack([u[::-1], np.full((level, 3), 0.001)])
    with open(os.path.join(d, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, q) in enumerate(zip(rest, disp)):
            f.write(f"{i},{p[0]!r},{p[1]!r},{p[2]!r},{q[0]!r},{q[1]!r},{q[2]!r}\n")
    run = {"model": "fem_distributed", "model_report": {"dofs": dofs, "newton_iterations_last_step": 7},
           "scenario_resolved": {"material": {"poisson_ratio": nu}}, "mesh": {"fine_nodes": dofs // 3},
           "build": {"peak_memory_mib": 100.0}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump({"setup_ms": 500.0, "step": {"median_ms": 1000.0},
                   "processes": {"ranks": 1, "peak_rss_mib_max": 100.0}}, f)
    path = os.path.join(root, "cases.csv")
    if not os.path.isfile(path):
        with open(path, "w") as f:
            f.write("scenario,case,ranks,wall_s,load_before,load_after,status\n")
    with open(path, "a") as f:
        f.write(f"{scenario},neo-p{order},1,{wall},1.0,2.0,ok\n")


class SuiteReferenceConvergence(unittest.TestCase):
    def test_richardson_observes_the_order_and_extrapolates(self):
        q = [5 + 3 * 0.5 ** (2 * k) for k in range(3)]  # p = 2, r = 2 (dofs x 8)
        errors, p, how = src.richardson(q, [1000, 8000, 64000], 1)
        self.assertAlmostEqual(p, 2.0)
        self.assertIn("observed", how)
        np.testing.assert_allclose(errors, [3, 0.75, 0.1875], rtol=1e-12)
        errors, p, how = src.richardson(q[:2], [1000, 8000], 2)  # two levels: P2's assumed order 3
        self.assertEqual(p, 3.0)
        np.testing.assert_allclose(errors[1], 2.25 / 7, rtol=1e-12)
        erratic = [1.0, 2.0, 3.0]  # changes that do not shrink: assumed p
        _, p, how = src.richardson(erratic, [1000, 8000, 64000], 1)
        self.assertEqual(p, 2.0)
        self.assertIn("not trusted", how)
        self.assertTrue(math.isnan(src.richardson([1.0], [10], 1)[0][0]))

    def test_tables_and_declared_errors(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "results")
            os.makedirs(root)
            for level in range(3):  # P1, h halved per level (dofs x 8): u_k = u* + SHAPE h_k^2
                write_case(root, "cube_pull_disc", level, 1, U_STAR + SHAPE * 0.25 ** level, 1000 * 8 ** level)
            write_case(root, "cube_pull_disc", 0, 2, U_STAR + SHAPE * 0.01, 7000)  # a lower level than P1's finest
            with open(os.path.join(root, "cases.csv"), "a") as f:  # a case that ran and left nothing
                f.write("sref-cube-pull-disc-L1-p2,neo-p2,2,600.5,3.0,2.5,timeout\n")
            errors_path = os.path.join(tmp, "errors.json")
            decl = src.make(root, tmp, None, errors_path)["cube_pull_disc"]
            rel = np.linalg.norm(SHAPE) / np.linalg.norm(U_STAR)
            # The finest is the highest level (P1 L2), not P2 on level 0.
            self.assertEqual((decl["converged"]["order"], decl["converged"]["level"]), (1, 2))
            # P1 L0's error: Richardson's (exact here) exceeds its change against the finest.
            self.assertAlmostEqual(decl["field_error"], rel, places=12)
            self.assertAlmostEqual(decl["converged"]["field_error"], rel / 16, places=12)
            self.assertAlmostEqual(decl["qoi"]["load_uz_mm"]["value"], 22.0)
            self.assertAlmostEqual(decl["qoi"]["load_uz_mm"]["error"], 8.0, places=9)
            with open(os.path.join(tmp, "tables", "suite_reference_convergence.md")) as f:
                md = f.read()
            self.assertIn("observed p = 2.00 (three levels)", md)
            self.assertIn("load-point u_z (mm) 22 ± 8", md)
            self.assertIn("- cube_pull_disc level 1 P2 (case neo-p2): stopped at TIMEOUT after 600 s (2 rank(s), load average 3.0 / 2.5)", md)
            with open(os.path.join(tmp, "tables", "suite_reference_cost.md")) as f:
                self.assertIn("| cube_pull_disc | 2 | P1 | 64000 | 1 | 7 | 0.5 | 1.0 | 1.5 | 0.10 | 1.0 / 2.0 |", f.read())
            # The leaderboard's reader takes the file as written.
            entry = leaderboard.read_reference_errors(errors_path)["cube_pull_disc"]
            self.assertEqual(leaderboard.reference_error_text(entry), f"{rel:.3g} (vs Richardson's limit of P1 L0-2)")

    def test_the_declared_error_is_the_largest_change_against_any_larger_run(self):
        # As the liver: P1 level 1 the finest (level first), P2 level 0 farther from the reference.
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "results")
            os.makedirs(root)
            write_case(root, "liver_grasp_gravity", 0, 1, U_STAR * 0.9, 1000)
            write_case(root, "liver_grasp_gravity", 1, 1, U_STAR * 0.95, 8000)
            write_case(root, "liver_grasp_gravity", 0, 2, U_STAR * 1.2, 7000)
            errors_path = os.path.join(tmp, "e.json")
            decl = src.make(root, tmp, None, errors_path)["liver_grasp_gravity"]
            self.assertEqual((decl["converged"]["order"], decl["converged"]["level"]), (1, 1))
            self.assertAlmostEqual(decl["field_error"], 0.3 / 1.2, places=12)  # |0.9 - 1.2| / 1.2
            self.assertEqual(decl["field_error_against"], "P2 L0")
            self.assertIn("change against P1 L1 0.0526", decl["field_error_how"])  # 0.05 / 0.95
            entry = leaderboard.read_reference_errors(errors_path)["liver_grasp_gravity"]
            self.assertEqual(leaderboard.reference_error_text(entry), "0.25 (vs P2 L0)")

    def test_a_nearly_incompressible_scenario_takes_p2_as_finest(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "results")
            os.makedirs(root)
            write_case(root, "cube_push_disc", 0, 1, U_STAR * 0.5, 1000, nu=0.499)
            write_case(root, "cube_push_disc", 1, 1, U_STAR * 0.8, 8000, nu=0.499)
            write_case(root, "cube_push_disc", 0, 2, U_STAR, 7000, nu=0.499)
            decl = src.make(root, tmp, None, os.path.join(tmp, "e.json"))["cube_push_disc"]
            self.assertEqual((decl["converged"]["order"], decl["converged"]["level"]), (2, 0))
            self.assertIsNone(decl["converged"]["field_error"])  # one P2 level: no estimate
            self.assertAlmostEqual(decl["field_error"], 0.5)  # the change against P2 L0 exceeds Richardson's 0.44

    def test_without_the_suite_s_level_0_it_is_a_one_line_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "results")
            os.makedirs(root)
            write_case(root, "torus_grasp", 1, 1, U_STAR, 8000)
            with self.assertRaisesRegex(src.ResultsError, "no level-0 P1 run"):
                src.make(root, tmp, None, os.path.join(tmp, "e.json"))


if __name__ == "__main__":
    unittest.main()
