"""The scaling analysis on a hand-made results tree."""
import csv
import json
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import scaling  # noqa: E402

BUILD = {"cpu_model": "test cpu", "hardware_threads": 2, "build_type": "Release", "compiler": "g++", "git_commit": "x"}


def write_case(root, scenario, case, model, vertices, threads, median, phases, domains=None):
    d = os.path.join(root, scenario, case)
    os.makedirs(d)
    parameters = {"threads": threads, "precision": "double"}
    if domains:
        parameters["domains"] = domains
    run = {"model": model, "parameters": parameters,
           "model_report": {"instruction_set": "avx"}, "build": BUILD,
           "mesh": {"surface_vertices": vertices, "coarse_nodes": 150, "fine_tets": 10 * vertices,
                    "build_seconds": vertices / 1e4, "process_peak_memory_mib_after_build": 100.0,
                    "read_from_cache": False}}
    timings = {"step_after_ramp": {"median_ms": median, "p95_ms": 1.2 * median, "count": 250},
               "phases_after_ramp": {k: {"median_ms": v} for k, v in phases.items()}}
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(run, f)
    with open(os.path.join(d, "timings.json"), "w") as f:
        json.dump(timings, f)


class Scaling(unittest.TestCase):
    def test_slope_of_power_laws(self):
        self.assertAlmostEqual(scaling.fitted_slope([(1e3, 2.0), (1e4, 20.0), (1e5, 200.0)]), 1.0, places=12)
        self.assertAlmostEqual(scaling.fitted_slope([(10, 1.0), (100, 100.0)]), 2.0, places=12)
        self.assertIsNone(scaling.fitted_slope([(10, 1.0)]))

    def test_tables_and_figure_from_results(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "scaling")
            for v in (1000, 10000, 100000):
                write_case(root, f"cube-{v}-coarse150", "pbd", "pbd", v, 1, v * 1e-3, {"projection": v * 0.9e-3})
                write_case(root, f"cube-{v}-coarse150", "pbd-t2", "pbd", v, 2, v * 0.6e-3, {"projection": v * 0.5e-3})
                write_case(root, f"cube-{v}-coarse150", "pbd-d2", "pbd", v, 1, v * 0.8e-3, {}, domains=2)
                write_case(root, f"cube-{v}-coarse150", "pbd-d2-t2", "pbd", v, 2, v * 0.4e-3, {}, domains=2)
            scaling.make(root, tmp)
            with open(os.path.join(tmp, "tables", "scaling.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), 12)
            one = [r for r in rows if r["series"] == "pbd, double, 1 thread"]
            two = [r for r in rows if r["series"] == "pbd, double, 2 threads"]
            self.assertEqual([int(r["surface vertices"]) for r in one], [1000, 10000, 100000])
            self.assertEqual(one[0]["slope (all sizes)"], "1.000")
            self.assertEqual(two[2]["2 threads speed-up"], "1.67")
            self.assertEqual(two[2]["projection ms"], "50.000")
            # With domains: its own series, the speed-up against one thread with the same domains.
            two_domains = [r for r in rows if r["series"] == "pbd, double, 2 domains, 2 threads"]
            self.assertEqual(two_domains[2]["2 threads speed-up"], "2.00")
            self.assertTrue(os.path.isfile(os.path.join(tmp, "figures", "scaling.png")))
            with open(os.path.join(tmp, "tables", "scaling_mesh.csv")) as f:
                mesh = list(csv.DictReader(f))
            self.assertEqual([m["build s"] for m in mesh], ["0.1", "1.0", "10.0"])


if __name__ == "__main__":
    unittest.main()
