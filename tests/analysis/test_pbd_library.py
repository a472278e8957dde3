"""The PositionBasedDynamics-library comparison's analysis on a hand-made results tree."""
import csv
import json
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import pbd_library  # noqa: E402

BUILD = {"cpu_model": "test cpu", "hardware_threads": 2, "build_type": "Release", "compiler": "g++", "git_commit": "x"}


def dump(path, obj):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(obj, f)


def write_size(root, vertices, tb_median, lib_median):
    """cube-<vertices>: tissuebench's four pbd cases and the library at 1 and 2 threads; the
    loaded vertex is vertex 1 at (0, 0, 0.1)."""
    d = os.path.join(root, f"cube-{vertices}")
    for precision in ("double", "single"):
        for threads in (1, 2):
            case = os.path.join(d, f"pbd-{precision}-t{threads}")
            median = tb_median[(precision, threads)]
            dump(os.path.join(case, "run.json"), {
                "model": "pbd", "parameters": {"threads": threads, "precision": precision, "iterations": 10},
                "model_report": {"instruction_set": "avx"}, "build": BUILD, "frames": 300,
                "max_displacement_m": 0.02,
                "mesh": {"surface_vertices": vertices, "surface_triangles": 2 * vertices - 4}})
            dump(os.path.join(case, "timings.json"), {
                "step_after_ramp": {"median_ms": median, "p95_ms": 1.5 * median, "min_ms": 0.5 * median, "count": 250},
                "solver_iterations_per_frame": [10] * 300})
    dump(os.path.join(d, "tissuebench_loaded_vertex.json"),
         {f"pbd-{p}-t{t}": {"vertex": 1, "position": [0, 0, 0.1], "displacement_m": [0, 0, 0.02]}
          for p in ("double", "single") for t in (1, 2)})
    for threads in (1, 2):
        dump(os.path.join(d, f"library-t{threads}.json"), {
            "omp_max_threads": threads, "vertices": vertices, "triangles": 2 * vertices - 4, "frames": 300,
            "ramp_frames": 50, "frame_ms": [100.0] * 50 + [lib_median[threads]] * 249 + [0.5 * lib_median[threads]],
            "load_vertex": 1, "load_vertex_position": [0, 0, 0.1], "load_vertex_displacement_m": [0, 0, 0.015],
            "max_displacement_m": 0.015, "fixed_vertices": 10, "force_N": [0, 0, 1.0],
            "edges": 3 * vertices - 6, "interior_edges": 3 * vertices - 6,
            "distance_constraints": 3 * vertices - 6, "dihedral_constraints": 3 * vertices - 6,
            "constraint_groups": 27, "iterations": 10,
            "frame_after_ramp": {"median_ms": lib_median[threads], "p95_ms": 2 * lib_median[threads], "count": 250},
            "library_timers_after_ramp_mean_ms": {"simulation step": 2.0, "position constraints projection": 1.9}})
    with open(os.path.join(d, "machine_load.csv"), "w") as f:
        f.write("case,load_before,load_after\ntissuebench,1.0,1.5\nlibrary-t1,2.0,2.5\nlibrary-t2,3.0,2.0\n")


class PbdLibrary(unittest.TestCase):
    def test_tables_from_results(self):
        with tempfile.TemporaryDirectory() as tmp:
            root = os.path.join(tmp, "pbd_library")
            tb = {("double", 1): 1.0, ("double", 2): 0.8, ("single", 1): 0.5, ("single", 2): 0.4}
            write_size(root, 1000, tb, {1: 6.0, 2: 4.0})
            write_size(root, 10000, {k: 10 * v for k, v in tb.items()}, {1: 80.0, 2: 40.0})
            dump(os.path.join(root, "library_build.json"), {
                "source": "/x/PositionBasedDynamics", "version": "2.2.2", "commit": "d0894bdb0190c5f2",
                "build_type": "Release", "cxx_flags": "-O3 -DNDEBUG -march=native -fopenmp", "compiler": "g++",
                "eigen": "/usr/include/eigen3 (3.4.0)"})
            pbd_library.make(root, tmp)
            with open(os.path.join(tmp, "tables", "pbd_library.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual([(int(r["vertices"]), int(r["threads"])) for r in rows],
                             [(1000, 1), (1000, 2), (10000, 1), (10000, 2)])
            self.assertAlmostEqual(float(rows[0]["ratio_double"]), 6.0)
            self.assertAlmostEqual(float(rows[0]["ratio_single"]), 12.0)
            self.assertAlmostEqual(float(rows[3]["ratio_double"]), 5.0)
            self.assertEqual(rows[1]["load_library"], "3.0")  # the larger of before and after
            with open(os.path.join(tmp, "tables", "pbd_library.md")) as f:
                md = f.read()
            self.assertIn("load-average column", md.splitlines()[2])
            self.assertIn("| 10000 | 1 | 80.000 | 160.000 | 10.000 | 15.000 | 5.000 | 7.500 | 8.00 | 16.00 | 8.00 | 2.5 / 1.5 |", md)
            self.assertIn("| 1000 | 2994 / 2994 | 2994 / 2994 | 27 | 10 / 10 |", md)
            self.assertIn("15.00 / 20.00", md)


if __name__ == "__main__":
    unittest.main()
