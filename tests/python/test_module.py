"""The Python module tissuebench (python/, docs/python.md) against the tissuebench program.

Each exposed function, its error paths (a bad file, an unknown model, case or
parameter, a step after a failed one) and a Run's fields against what `tissuebench
run` writes for the same case (small_cube.json beside this file): the same surface,
probes and reactions, digit for digit. Registered in CTest by python/CMakeLists.txt,
which sets PYTHONPATH to the built module and TB_CLI to the program.

Run by hand: PYTHONPATH=build/python TB_CLI=build/experiments/tissuebench \
  /usr/bin/python3 -m unittest discover -s tests/python -v
"""
import tissuebench  # first: it pins OpenBLAS's kernels as the program does, before numpy loads OpenBLAS

import csv
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SMALL = os.path.join(HERE, "small_cube.json")
CLI = os.environ.get("TB_CLI", os.path.join(HERE, "..", "..", "build", "experiments", "tissuebench"))


# The program's answers to the commands started together by setUpModule (each waits
# seconds at start-up, mostly idle: one after another they took most of this file's time).
_started = {}


def start(*args):
    """Starts `tissuebench args` in the background; cli(*args) then waits for it."""
    _started[args] = subprocess.Popen([CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def cli(*args):
    """(exit status, stdout, stderr) of the tissuebench program."""
    p = _started.pop(args, None) or subprocess.Popen([CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                                      text=True)
    out, err = p.communicate(timeout=600)
    return p.returncode, out, err


def cli_error_line(*args):
    """The program's error for `args`: its last stderr line, without "tissuebench: "."""
    status, _, err = cli(*args)
    assert status != 0, err
    line = err.strip().splitlines()[-1]
    assert line.startswith("tissuebench: "), line
    return line[len("tissuebench: "):]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def small():
    with open(SMALL) as f:
        return json.load(f)


# Files with one error each (written by setUpModule into FILES).
FILES = tempfile.mkdtemp(prefix="tissuebench_python_files_")
BAD = os.path.join(FILES, "bad.json")
ABSENT = os.path.join(FILES, "absent.json")
FANCY = os.path.join(FILES, "fancy.json")
BOGUS = os.path.join(FILES, "bogus.json")
BOGUS_OVERRIDE = ("run", SMALL, "--index-only", "--out", FILES, "--set", "models.fem-direct.parameters.bogus=1")


def setUpModule():
    with open(BAD, "w") as f:
        f.write('{"name": ')
    fancy, bogus = small(), small()
    fancy["models"][1]["model"] = "fancy"
    bogus["models"][0]["parameters"] = {"bogus": 1}
    for path, j in ((FANCY, fancy), (BOGUS, bogus)):
        with open(path, "w") as f:
            json.dump(j, f)
    for args in (("models",), ("resolve", SMALL), ("resolve", BAD), ("resolve", ABSENT), ("resolve", FANCY),
                 ("resolve", BOGUS), BOGUS_OVERRIDE):
        start(*args)


def tearDownModule():
    for p in _started.values():
        p.kill()
        p.wait()
    shutil.rmtree(FILES, ignore_errors=True)


class Folder(unittest.TestCase):
    """A temporary folder per test class, removed after it; the mesh cache inside it."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="tissuebench_python_")
        cls.cache = os.path.join(cls.tmp, "mesh-cache")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def write(self, name, scenario):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            json.dump(scenario, f)
        return path

    def small(self):
        return small()


class Models(unittest.TestCase):
    def test_the_registry_is_what_the_program_lists(self):
        models = tissuebench.models()
        status, out, _ = cli("models")
        self.assertEqual(status, 0)
        headers = [line for line in out.splitlines() if not line.startswith(" ")]
        self.assertEqual(len(models), len(headers))
        for m, header in zip(models, headers):
            self.assertEqual(header, f"{m['name']} ({'dynamic' if m['dynamic'] else 'static'}): {m['description']}")
        params = [line for line in out.splitlines() if line.startswith("  ") and " = " in line.split(":")[0]]
        self.assertEqual(sum(len(m["parameters"]) for m in models), len(params))
        fem = next(m for m in models if m["name"] == "fem")
        self.assertFalse(fem["dynamic"])
        self.assertIn("point_force", fem["loads"])
        self.assertIn("grasp", fem["tools"])
        for p in fem["parameters"]:
            self.assertIn(p["type"], ("number", "integer", "choice"))
            if p["type"] == "choice":
                self.assertIn(p["default"], p["choices"])
            else:
                self.assertLessEqual(p["min"], p["default"])
                self.assertLessEqual(p["default"], p["max"])
        self.assertTrue(any(p["type"] == "integer" and isinstance(p["default"], int)
                            for m in models for p in m["parameters"]))
        pbd = next(m for m in models if m["name"] == "pbd")
        self.assertIsNone(pbd["probes"])  # no volume: "none (no volume)"


class Load(unittest.TestCase):
    def test_a_scenario_resolves_as_the_program_resolves_it(self):
        e = tissuebench.load(SMALL)
        status, out, _ = cli("resolve", SMALL)
        self.assertEqual(status, 0)
        resolved = json.loads(out)
        self.assertEqual(e.name, "small")
        self.assertEqual([s.name for s in e.scenarios], ["small"])
        s = e.scenarios[0]
        self.assertEqual(s.to_json(), resolved["scenarios_resolved"][0])
        index = dict(resolved)
        del index["scenarios_resolved"]
        self.assertEqual(e.to_json(), index)
        self.assertEqual(s.role, "")
        self.assertEqual(s.case_names, ["fem-direct", "pbd"])
        self.assertEqual([c["model"] for c in s.cases], ["fem", "pbd"])
        self.assertEqual(s.cases[0]["parameters"], resolved["scenarios_resolved"][0]["models"][0]["parameters"])
        self.assertEqual(e.scenario("small").name, "small")
        self.assertEqual(s.not_run, [])

    def test_overrides_are_the_programs_set(self):
        for overrides in ({"frames.static": 2}, [["frames.static", 2]]):
            s = tissuebench.load(SMALL, overrides=overrides).scenarios[0]
            self.assertEqual(s.to_json()["frames"]["static"], 2)
        self.assertEqual(tissuebench.load(SMALL).scenarios[0].to_json()["frames"]["static"], 4)

    def test_a_bad_file_is_the_programs_one_line_error(self):
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(BAD)
        self.assertEqual(str(caught.exception), cli_error_line("resolve", BAD))
        self.assertIn("bad.json", str(caught.exception))
        self.assertNotIn("\n", str(caught.exception))
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(ABSENT)
        self.assertEqual(str(caught.exception), cli_error_line("resolve", ABSENT))

    def test_an_unknown_model_names_the_file_and_key(self):
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(FANCY)
        self.assertIn("models[1].model: unknown model 'fancy'", str(caught.exception))
        self.assertEqual(str(caught.exception), cli_error_line("resolve", FANCY))

    def test_an_unknown_parameter_in_a_file_or_an_override(self):
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(BOGUS)
        self.assertIn("bogus", str(caught.exception))
        self.assertEqual(str(caught.exception), cli_error_line("resolve", BOGUS))
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(SMALL, overrides={"models.fem-direct.parameters.bogus": 1})
        self.assertIn("bogus", str(caught.exception))
        self.assertEqual(str(caught.exception), cli_error_line(*BOGUS_OVERRIDE))

    def test_malformed_overrides_and_unknown_scenarios_are_errors(self):
        for overrides in (5, [["frames.static"]], [[1, 2]], {"frames.static": object()}):
            with self.assertRaises(tissuebench.Error) as caught:
                tissuebench.load(SMALL, overrides=overrides)
            self.assertIn("overrides", str(caught.exception))
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.load(SMALL).scenario("nowhere")
        self.assertEqual(str(caught.exception),
                         "experiment 'small' has no scenario named 'nowhere' (its scenarios: small)")


class RunAgainstTheProgram(Folder):
    """Each case of small_cube.json run by the program and by tissuebench.Run."""

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.out = os.path.join(cls.tmp, "runs")
        status, _, err = cli("run", SMALL, "--out", cls.out, "--mesh-cache", cls.cache, "--quiet")
        assert status == 0, err
        cls.scenario = tissuebench.load(SMALL).scenarios[0]

    def case_dir(self, case):
        return os.path.join(self.out, "small", "small", case)

    def check_case(self, case):
        run = tissuebench.Run(self.scenario, case, mesh_cache=self.cache)
        self.assertEqual((run.scenario, run.case, run.frames), ("small", case, 0))
        self.assertFalse(run.finished)
        np.testing.assert_array_equal(run.displacement, np.zeros_like(run.rest_positions))
        run.step()
        self.assertEqual(run.frames, 1)
        frames = run.run()
        self.assertTrue(run.finished)
        with open(os.path.join(self.case_dir(case), "run.json")) as f:
            written = json.load(f)
        with open(os.path.join(self.case_dir(case), "timings.json")) as f:
            timings = json.load(f)
        self.assertEqual(frames, written["frames"])
        self.assertEqual(run.steady_frame, written["steady_frame"] if run.dynamic else -1)
        self.assertEqual(len(run.step_ms), len(timings["step_ms_per_frame"]))
        self.assertTrue(np.all(run.step_ms > 0))

        # The surface: every vertex, rest position and displacement, as surface.csv's 17 digits.
        rows = read_csv(os.path.join(self.case_dir(case), "surface.csv"))
        self.assertEqual(len(rows), run.displacement.shape[0])
        rest = np.array([[float(r[k]) for k in ("x", "y", "z")] for r in rows])
        u = np.array([[float(r[k]) for k in ("ux", "uy", "uz")] for r in rows])
        np.testing.assert_array_equal(run.rest_positions, rest)
        np.testing.assert_array_equal(run.displacement, u)
        top = read_csv(os.path.join(self.case_dir(case), "top_surface.csv"))
        vertices = [int(r["vertex"]) for r in top]
        np.testing.assert_array_equal(run.displacement[vertices],
                                      np.array([[float(r[k]) for k in ("ux", "uy", "uz")] for r in top]))
        self.assertEqual(run.faces.shape[1], 3)
        self.assertEqual(run.faces.max() + 1, run.rest_positions.shape[0])

        # Reactions of the last frame (reactions.csv: every frame) and probes.
        self.assertEqual(run.reaction_names, ["tools[0]", "support"])
        reactions = [r for r in read_csv(os.path.join(self.case_dir(case), "reactions.csv"))
                     if int(r["frame"]) == frames - 1]
        np.testing.assert_array_equal(run.reactions,
                                      np.array([[float(r[k]) for k in ("fx", "fy", "fz")] for r in reactions]))
        probes_csv = os.path.join(self.case_dir(case), "probes.csv")
        if os.path.exists(probes_csv):
            probes = read_csv(probes_csv)
            np.testing.assert_array_equal(run.probes,
                                          np.array([[float(r[k]) for k in ("ux", "uy", "uz")] for r in probes]))
            np.testing.assert_array_equal(run.probe_points, [[0, 0, 0.05]])
        else:
            self.assertIsNone(run.probes)
        self.assertIsInstance(run.report(), dict)
        return run

    def test_the_static_fem_is_the_programs_digit_for_digit(self):
        run = self.check_case("fem-direct")
        self.assertFalse(run.dynamic)
        self.assertEqual(run.frames, 4)
        self.assertIsNotNone(run.probes)

    def test_the_dynamic_pbd_is_the_programs_digit_for_digit(self):
        run = self.check_case("pbd")
        self.assertTrue(run.dynamic)
        self.assertIsNone(run.probes)  # pbd has no volume

    def test_read_results_is_the_programs_folder_as_data_frames(self):
        r = tissuebench.read_results(os.path.join(self.out, "small"))
        self.assertEqual((r.name, r.reference), ("small", "fem-direct"))
        self.assertEqual(list(r.cases["case"]), ["fem-direct", "pbd"])
        for case in ("fem-direct", "pbd"):
            row = r.cases[r.cases["case"] == case].iloc[0]
            with open(os.path.join(self.case_dir(case), "run.json")) as f:
                written = json.load(f)
            with open(os.path.join(self.case_dir(case), "timings.json")) as f:
                timings = json.load(f)
            self.assertEqual((row["model"], row["frames"], row["steady_frame"]),
                             (written["model"], written["frames"], written["steady_frame"]))
            self.assertEqual(row["step_median_ms"], timings["step"]["median_ms"])
            self.assertIsNone(row["error"])
            series = r.frames[r.frames["case"] == case]
            self.assertEqual(list(series["frame"]), list(range(written["frames"])))
            self.assertEqual(list(series["step_ms"]), timings["step_ms_per_frame"])
        # pbd against the reference on the top surface, as metrics.compare computes it.
        self.assertEqual(list(r.metrics["case"]), ["pbd"])
        u = {c: np.array([[float(row[k]) for k in ("ux", "uy", "uz")]
                          for row in read_csv(os.path.join(self.case_dir(c), "top_surface.csv"))])
             for c in ("fem-direct", "pbd")}
        self.assertAlmostEqual(r.metrics["rel_l2"].iloc[0],
                               np.linalg.norm(u["pbd"] - u["fem-direct"]) / np.linalg.norm(u["fem-direct"]), 12)
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.read_results(os.path.join(self.tmp, "nowhere"))
        self.assertIn("nowhere: no such results folder", str(caught.exception))

    def test_a_step_after_the_last_frame_is_an_error(self):
        run = tissuebench.Run(self.scenario, "fem-direct", mesh_cache=self.cache)
        self.assertEqual(run.run(), 4)
        self.assertEqual(run.run(), 4)  # nothing left: no error
        with self.assertRaises(tissuebench.Error) as caught:
            run.step()
        self.assertEqual(str(caught.exception),
                         "small/fem-direct: no frame left after 4 frames (the frame budget of 4 frames)")

    def test_an_unknown_case_names_the_file_and_the_cases(self):
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.Run(self.scenario, "nope", mesh_cache=self.cache)
        self.assertEqual(str(caught.exception),
                         f"{SMALL}: scenario 'small' has no case 'nope' (its cases: fem-direct, pbd)")

    def test_a_failed_frame_is_the_programs_error_and_every_later_step_too(self):
        overrides = {"load.force": [0, 0, 1e9]}  # a static solution far beyond the divergence bound
        scenario = tissuebench.load(SMALL, overrides=overrides).scenarios[0]
        run = tissuebench.Run(scenario, "fem-direct", mesh_cache=self.cache)
        with self.assertRaises(tissuebench.Error) as caught:
            run.step()
        message = str(caught.exception)
        self.assertTrue(message.startswith("small/fem-direct failed: the static solution at frame 0"), message)
        self.assertEqual(run.error, message[len("small/fem-direct failed: "):])
        status, _, err = cli("run", SMALL, "--out", os.path.join(self.tmp, "diverged"), "--mesh-cache", self.cache,
                             "--quiet", "--model", "fem-direct", "--set", "load.force=[0,0,1e9]")
        self.assertEqual(status, 1)
        self.assertIn("tissuebench: " + message, err.splitlines(), err)
        cases = tissuebench.read_results(os.path.join(self.tmp, "diverged", "small")).cases
        self.assertEqual(list(cases["case"]), ["fem-direct"])
        self.assertEqual(cases["error"].iloc[0], message[len("small/fem-direct failed: "):])
        for again in (run.step, run.run):
            with self.assertRaises(tissuebench.Error) as caught:
                again()
            self.assertIn("small/fem-direct failed at frame 0, before this step: the static solution",
                          str(caught.exception))

    def test_a_case_that_cannot_be_placed_on_its_mesh_is_the_programs_error(self):
        j = self.small()
        j["tools"][0]["point"] = [0, 0, 5]  # far above the cube: the grasp holds no vertex
        path = self.write("no_grasp.json", j)
        with self.assertRaises(tissuebench.Error) as caught:
            tissuebench.Run(tissuebench.load(path).scenarios[0], "fem-direct", mesh_cache=self.cache)
        message = str(caught.exception)
        self.assertTrue(message.startswith("small/fem-direct failed: "), message)
        self.assertIn("tools[0]", message)
        status, _, err = cli("run", path, "--out", os.path.join(self.tmp, "no-grasp"), "--mesh-cache", self.cache,
                             "--quiet", "--model", "fem-direct")
        self.assertEqual(status, 1)
        self.assertIn("tissuebench: " + message, err.splitlines(), err)

    def test_a_run_stepped_in_a_thread_can_be_watched_between_frames(self):
        # frames and finished stay readable while another thread steps; the model's arrays
        # are refused until the frame is done (they would race with it), never torn.
        run = tissuebench.Run(self.scenario, "pbd", mesh_cache=self.cache)
        worker = threading.Thread(target=run.run)
        worker.start()
        seen, refused = [], 0
        while worker.is_alive():
            seen.append(run.frames)
            try:
                self.assertEqual(run.displacement.shape, run.rest_positions.shape)
            except tissuebench.Error as e:
                self.assertEqual(str(e), "small/pbd: stepping in another thread; read its results between steps")
                refused += 1
        worker.join()
        self.assertEqual(seen, sorted(seen))
        self.assertTrue(run.finished)
        self.assertEqual(run.frames, len(run.step_ms))

    def test_the_gil_is_released_while_cpp_builds_sets_up_and_steps(self):
        # Built without the cache (TetGen, the FEM's factorisation) in a thread: the main
        # thread keeps running Python meanwhile, with no pause near the build's length.
        done, built = threading.Event(), {}

        def build():
            try:
                start = time.perf_counter()
                built["run"] = tissuebench.Run(self.scenario, "fem-direct", mesh_cache="")
                built["run"].run()
                built["seconds"] = time.perf_counter() - start
            finally:
                done.set()

        worker = threading.Thread(target=build)
        worker.start()
        last = time.perf_counter()
        longest_pause = 0.0
        while not done.is_set():
            now = time.perf_counter()
            longest_pause, last = max(longest_pause, now - last), now
        worker.join()
        self.assertLess(longest_pause, 0.5 * built["seconds"], (longest_pause, built["seconds"]))
        self.assertEqual(built["run"].frames, 4)


if __name__ == "__main__":
    unittest.main()
