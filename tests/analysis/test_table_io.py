"""The notes every table carries (analysis/table_io.py)."""
import os
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import table_io  # noqa: E402


def case(commit, cpu="Xeon"):
    return {"run": {"build": {"cpu_model": cpu, "hardware_threads": 2, "build_type": "Release",
                              "compiler": "g++ 12.2.0", "git_commit": commit}}}


class MachineNote(unittest.TestCase):
    def test_one_commit_is_named_once(self):
        note = table_io.machine_note({"a": case("abc"), "b": case("abc")})
        self.assertEqual(note, "Measured on Xeon (2 hardware threads), Release build, g++ 12.2.0, commit abc; "
                               "one thread.")

    def test_every_commit_is_named_with_its_case_count(self):
        note = table_io.machine_note({"a": case("abc"), "b": case("def"), "c": case("abc")})
        self.assertIn("commits abc (2 cases), def (1 case)", note)

    def test_every_machine_is_named_with_its_case_count(self):
        note = table_io.machine_note({"a": case("abc", "Xeon"), "b": case("abc", "EPYC")})
        self.assertTrue(note.startswith("Measured on machines EPYC (2 hardware threads), Release build, g++ 12.2.0 "
                                        "(1 case), Xeon"), note)
        self.assertIn("commit abc;", note)

    def test_a_case_run_on_a_busy_machine_is_named_with_its_load(self):
        busy, quiet, old = case("abc"), case("abc"), case("abc")
        busy["timings"] = {"load_average_1min": {"at_setup": 1.2, "at_last_frame": 4.6}}
        quiet["timings"] = {"load_average_1min": {"at_setup": 0.4, "at_last_frame": 1.9}}
        note = table_io.machine_note({"busy": busy, "quiet": quiet, "old": old})
        self.assertTrue(note.endswith("its times inflated by the other work): busy (load 4.6)."), note)

    def test_a_two_thread_case_alone_on_two_hardware_threads_is_not_busy(self):
        alone, crowded = case("abc"), case("abc")
        alone["timings"] = {"load_average_1min": {"at_setup": 1.0, "at_last_frame": 2.0098}}
        crowded["timings"] = {"load_average_1min": {"at_setup": 2.0, "at_last_frame": 2.6}}
        self.assertEqual(table_io.busy_cases({"alone": alone, "crowded": crowded}), {"crowded": 2.6})
        at, above = case("abc"), case("abc")
        at["timings"] = {"load_average_1min": {"at_setup": 2.2}}
        above["timings"] = {"load_average_1min": {"at_setup": 2.21}}
        self.assertEqual(table_io.busy_cases({"at": at, "above": above}), {"above": 2.21})

    def test_a_group_all_of_whose_cases_were_busy_is_named_once(self):
        cases = {}
        for name, load in [("a/x", 3.5), ("a/y", 7.25), ("b/x", 5.0), ("b/y", 0.5)]:
            cases[name] = case("abc")
            cases[name]["timings"] = {"load_average_1min": {"at_setup": load, "at_last_frame": load}}
        note = table_io.machine_note(cases)
        self.assertIn("other work): a (all 2 cases, load 3.5-7.2), b/x (load 5.0).", note)


if __name__ == "__main__":
    unittest.main()
