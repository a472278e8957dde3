"""The reference-convergence analysis: matching vertices by rest
coordinates, and the tables on a small hand-made study."""
import json
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import reference_convergence as rc  # noqa: E402


def write_case(folder, rest, u, dofs, extra_stats=None):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "top_surface.csv"), "w") as f:
        f.write("vertex,x,y,z,ux,uy,uz\n")
        for i, (p, d) in enumerate(zip(rest, u)):
            f.write(",".join(repr(float(v)) for v in [i, *p, *d]) + "\n")
    stats = {"dofs": dofs, "cells": dofs // 2, "cg_iterations_last_step": 10, "newton_iterations_last_step": 4,
             "load_increments_last_step": 2, "increment_halvings_last_step": 0,
             "seconds": {"mesh": 1, "dofs": 0.1, "assembly": 1, "preconditioner": 1, "solve_last_step": 2}}
    stats.update(extra_stats or {})
    with open(os.path.join(folder, "run.json"), "w") as f:
        json.dump({"model_report": stats, "build": {"cpu_model": "test CPU"}}, f)
    with open(os.path.join(folder, "timings.json"), "w") as f:
        json.dump({"setup_ms": 1000, "step": {"median_ms": 2000}, "processes": {"peak_rss_mib_max": 1024,
                                                                                "peak_rss_mib_sum": 2048}}, f)


def grid(n):
    """The top face at refinement n: (2^n 4 + 1)^2 points, level 0's first."""
    coarse = [(x, y) for x in np.linspace(-0.05, 0.05, 5) for y in np.linspace(-0.05, 0.05, 5)]
    fine = [(x, y) for x in np.linspace(-0.05, 0.05, 4 * 2 ** n + 1) for y in np.linspace(-0.05, 0.05, 4 * 2 ** n + 1)]
    pts = coarse + [p for p in fine if not any(np.allclose(p, q, atol=1e-15) for q in coarse)]
    return np.array([[x, y, 0.1] for x, y in pts])


def field(rest, scale):
    r = np.linalg.norm(rest - rc.LOAD_POINT, axis=1)
    return np.stack([0 * r, 0 * r, scale / (1 + 100 * r)], axis=1)


class MatchVertices(unittest.TestCase):
    def test_matches_equal_coordinates_in_any_order_and_refuses_strangers(self):
        ref = grid(1)
        perm = np.random.default_rng(1).permutation(len(ref))
        idx = rc.match_vertices(ref[perm][:7], ref)
        np.testing.assert_array_equal(idx, perm[:7])
        # Round-off below the tolerance still matches; a vertex elsewhere does not.
        np.testing.assert_array_equal(rc.match_vertices(ref[:3] + 3e-13, ref), [0, 1, 2])
        with self.assertRaisesRegex(ValueError, "no reference vertex"):
            rc.match_vertices(np.array([[0.0123, 0.0, 0.1]]), ref)

    def test_scenario_names(self):
        self.assertEqual(rc.parse_scenario("ref-L2-push-disc-0.1N"), (2, "push", "disc", 0.1))
        self.assertEqual(rc.parse_scenario("ref-L0-pull-point"), (0, "pull", "point", 1.0))
        self.assertIsNone(rc.parse_scenario("cube-pull"))


class Tables(unittest.TestCase):
    def test_a_small_study(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "study")
            for level in range(3):
                rest = grid(level)
                for load in ("point", "disc"):
                    base = os.path.join(root, "np1", "reference_convergence", f"ref-L{level}-pull-{load}")
                    # Level L: the field 1 + 2^-L times the finest's (level 2).
                    write_case(os.path.join(base, "fem-p1"), rest, field(rest, 1 + 2.0 ** -level - 0.25), 100 * 8 ** level)
                    write_case(os.path.join(base, "neo-p1"), rest, field(rest, 1.1), 100 * 8 ** level)
                write_case(os.path.join(root, "np2", "reference_convergence", f"ref-L{level}-pull-disc", "fem-p1"),
                           grid(level), field(grid(level), 1 + 2.0 ** -level - 0.25), 100 * 8 ** level)
            # The paper's cube results, found by role (their names are not the paper's).
            paper = os.path.join(tmp, "paper")
            index = {"name": "paper", "reference": "fem-direct", "scenarios": []}
            for d in ("pull", "push"):
                write_case(os.path.join(paper, f"box-{d}s", "hybrid"), grid(0), field(grid(0), 0.5), 0)
                index["scenarios"].append({"name": f"box-{d}s", "role": f"cube_{d}", "cases": ["hybrid"]})
            with open(os.path.join(paper, "experiment.json"), "w") as f:
                json.dump(index, f)
            with open(os.path.join(root, "failures.txt"), "w") as f:
                f.write("ref-L2-pull-point neo-p1 np1: neo-Hookean: Newton failed\n")
            os.remove(os.path.join(root, "np1", "reference_convergence", "ref-L2-pull-point", "neo-p1", "run.json"))
            out = os.path.join(tmp, "out")
            study = rc.Study(root)
            conv, cost, neo, t1 = rc.write_tables(study, paper, out)
            p1_point = [r for r in conv if r["load"] == "point" and r["order"] == "P1"]
            self.assertEqual([r["level"] for r in p1_point], [0, 1, 2])
            # u_L = (1 + 2^-L - 0.25) / 1.0 u_2: change 2^-L - 0.25 relative.
            self.assertAlmostEqual(p1_point[0]["change"], 0.75, places=12)
            self.assertAlmostEqual(p1_point[1]["change"], 0.25, places=12)
            self.assertEqual(p1_point[2]["change"], 0.0)
            self.assertAlmostEqual(p1_point[0]["uz_load_mm"], 1750.0, places=9)
            self.assertEqual(len(cost), 9)  # 3 levels x (point at np 1, disc at np 1 and 2)
            np2 = [r for r in cost if r["np"] == 2]
            self.assertTrue(all(r["np_diff"] == 0 for r in np2))
            failed = [r for r in neo if "failed" in r]
            self.assertEqual(len(failed), 1)
            self.assertIn("Newton failed", failed[0]["failed"])
            # Linear (1.75) against neo-Hookean (1.1): divided by the neo-Hookean field, as the docs say.
            l0_disc = next(r for r in neo if r["level"] == 0 and r["load"] == "disc")
            self.assertAlmostEqual(l0_disc["difference"], 0.65 / 1.1, places=12)
            hybrid_l0 = [r for r in t1 if r["model"] == "hybrid" and r["reference"] == "P1 L0" and r["direction"] == "pull"]
            self.assertAlmostEqual(hybrid_l0[0]["rel_l2"], 1 - 0.5 / 1.75, places=12)
            for name in ("reference_convergence", "reference_convergence_cost", "reference_convergence_neo_hookean",
                         "reference_convergence_table1"):
                self.assertTrue(os.path.isfile(os.path.join(out, "tables", name + ".md")), name)


if __name__ == "__main__":
    unittest.main()
