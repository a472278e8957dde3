"""The thread speed-up analysis on a hand-made Google Benchmark JSON."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import thread_speedup  # noqa: E402

SCRIPT = os.path.join(ROOT, "analysis", "thread_speedup.py")


def run(name, vertices, rep, ms):
    return {"name": name, "run_name": name, "run_type": "iteration", "repetition_index": rep,
            "real_time": ms, "time_unit": "ms", "surface_vertices": vertices}


def aggregate(name, ms):
    return {"name": name + "_median", "run_name": name, "run_type": "aggregate", "aggregate_name": "median",
            "real_time": ms, "time_unit": "ms", "surface_vertices": 9602}


def pbd(threads):
    return f"BM_PbdFrameScaling/divisions:40/threads:{threads}/single:1/domains:2/real_time"


def hybrid(threads):
    return f"BM_HybridFrameScaling/divisions:129/coarse:150/threads:{threads}/single:0/domains:2/real_time"


class ThreadSpeedupTest(unittest.TestCase):
    def write(self, d, benchmarks):
        path = os.path.join(d, "thread_speedup.json")
        with open(path, "w") as f:
            json.dump({"context": {"date": "today", "num_cpus": 2, "tissuebench_cpu_model": "test cpu",
                                   "tissuebench_build_type": "Release", "load_avg": [0.5]},
                       "benchmarks": benchmarks}, f)
        return path

    def table(self, d):
        with open(os.path.join(d, "tables", "thread_speedup.csv")) as f:
            return list(csv.DictReader(f))

    def test_speedup_is_the_ratio_of_the_medians_and_of_the_minima(self):
        # pbd 10k: one thread 2.0, 2.2, 2.4 ms; two threads 1.0, 1.5, 1.2 ms (repetitions 0, 1, 2)
        benchmarks = [run(pbd(1), 9602, k, ms) for k, ms in enumerate([2.0, 2.2, 2.4])]
        benchmarks += [run(pbd(2), 9602, k, ms) for k, ms in enumerate([1.0, 1.5, 1.2])]
        # hybrid 100k, double: 30 ms on one thread, 20 on two (1.5x, below the target)
        benchmarks += [run(hybrid(t), 99848, k, 30.0 if t == 1 else 20.0) for t in (1, 2) for k in range(3)]
        benchmarks += [aggregate(pbd(1), 100.0)]  # aggregates are not repetitions
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([sys.executable, SCRIPT, self.write(d, benchmarks), d], check=True, capture_output=True)
            rows = {(r["series"], r["surface vertices"]): r for r in self.table(d)}
        p = rows[("pbd, single, 2 domains", "9602")]
        self.assertEqual(p["repetitions"], "3")
        self.assertEqual(p["1 thread median ms"], "2.200")
        self.assertEqual(p["1 thread min ms"], "2.000")
        self.assertEqual(p["2 threads median ms"], "1.200")
        self.assertEqual(p["2 threads min ms"], "1.000")
        self.assertEqual(p["speed-up (medians)"], "1.83")  # 2.2 / 1.2
        self.assertEqual(p["speed-up (minima)"], "2.00")  # 2.0 / 1.0
        self.assertEqual(p["medians >= 1.7x"], "yes")
        h = rows[("hybrid, coarse 150, double, 2 domains", "99848")]
        self.assertEqual(h["speed-up (medians)"], "1.50")
        self.assertEqual(h["medians >= 1.7x"], "no")
        self.assertEqual(h["1 thread cv"], "0.000")

    def test_a_case_without_its_other_thread_count_is_left_out(self):
        benchmarks = [run(pbd(1), 9602, 0, 2.0)]
        with tempfile.TemporaryDirectory() as d:
            r = subprocess.run([sys.executable, SCRIPT, self.write(d, benchmarks), d], capture_output=True, text=True)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("no frame-scaling benchmark with both 1 and 2 threads", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "tables", "thread_speedup.csv")))

    def test_an_unreadable_file_is_named(self):
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "broken.json")
            with open(bad, "w") as f:
                f.write("{not json")
            r = subprocess.run([sys.executable, SCRIPT, bad, d], capture_output=True, text=True)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn(bad, r.stderr)

    def test_other_time_units_are_refused(self):
        b = run(pbd(1), 9602, 0, 2.0)
        b["time_unit"] = "us"
        with self.assertRaises(ValueError):
            thread_speedup.repetitions([b])

    def test_nonlinear_steppers_use_the_median_frame_and_fit_the_cost_slope(self):
        def frame(solver, tets, threads, rep, p50, mean=99.0):
            name = f"BM_NonlinearStepperFrame/xpbd:{solver}/refine:1/threads:{threads}/work:1/zorder:1/real_time"
            b = run(name, 0, rep, mean)  # the loop's mean is not what is read
            b.update({"p50_ms": p50, "tets": tets})
            return b
        # vbd: 1 ms per 10 000 tets on one thread, 0.55 on two (slope 1); xpbd on one size only
        benchmarks = [frame(0, n, t, k, n / 1e4 * (1.0 if t == 1 else 0.55)) for n in (10000, 20000, 40000)
                      for t in (1, 2) for k in range(3)]
        benchmarks += [frame(1, 10000, t, 0, 2.0 / t) for t in (1, 2)]
        benchmarks += [run(pbd(t), 9602, 0, 2.0 / t) for t in (1, 2)]  # the frame-scaling table too
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([sys.executable, SCRIPT, self.write(d, benchmarks), d], check=True, capture_output=True)
            with open(os.path.join(d, "tables", "nonlinear_thread_speedup.csv")) as f:
                rows = {(r["series"], r["tets"]): r for r in csv.DictReader(f)}
            with open(os.path.join(d, "tables", "nonlinear_cost_slope.csv")) as f:
                slopes = list(csv.DictReader(f))
            self.assertEqual(len(self.table(d)), 1)  # pbd's row, in its own table
        v = rows[("vbd, 1 sweep", "20000")]
        self.assertEqual(v["1 thread median ms"], "2.000")
        self.assertEqual(v["2 threads median ms"], "1.100")
        self.assertEqual(v["speed-up (medians)"], "1.82")
        self.assertEqual(rows[("xpbd, 1 sub-step of 1 ms", "10000")]["speed-up (medians)"], "2.00")
        self.assertEqual(len(slopes), 1)  # xpbd has one size: no slope
        self.assertEqual(slopes[0]["series"], "vbd, 1 sweep")
        self.assertEqual(slopes[0]["slope, 1 thread"], "1.00")
        self.assertEqual(slopes[0]["slope, 2 threads"], "1.00")
        self.assertEqual(slopes[0]["both <= 1.1"], "yes")

    def test_a_nonlinear_benchmark_without_its_median_frame_is_refused_by_name(self):
        b = run("BM_NonlinearStepperFrame/xpbd:0/refine:1/threads:1/work:1/zorder:1/real_time", 0, 0, 2.0)
        b["tets"] = 17821
        with tempfile.TemporaryDirectory() as d:
            path = self.write(d, [b])
            r = subprocess.run([sys.executable, SCRIPT, path, d], capture_output=True, text=True)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn(path, r.stderr)
            self.assertIn("no p50_ms counter", r.stderr)


if __name__ == "__main__":
    unittest.main()
