"""The flags the project's libraries are really compiled with (compile_commands.json)
are the ones it chooses and records in run.json: the build type's
optimisation level last, none of deal.II's flags outside the deal.II translation
unit, and the recorded strings equal to what the compiler was given.

Run by CTest with the build folder as argument.
"""
import glob
import json
import os
import re
import shlex
import subprocess
import sys
import unittest

BUILD = os.environ.get("TB_BUILD_DIR", "build")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Flags that only deal.II's configuration brings (DEAL_II_CXX_FLAGS and definitions).
DEAL_II_ONLY = ["-funroll-all-loops", "-D_FORTIFY_SOURCE=2", "-DBOOST_NO_AUTO_PTR", "-fopenmp", "-pedantic"]


def deal_ii_units():
    """The deal.II translation units, as models/CMakeLists.txt lists them (TB_DEAL_II_SOURCES)."""
    with open(os.path.join(ROOT, "models", "CMakeLists.txt")) as f:
        listed = re.search(r"set\(TB_DEAL_II_SOURCES([^)]*)\)", f.read()).group(1).split()
    return ["models/" + u for u in listed]


DEAL_II_UNITS = deal_ii_units()


def pbd_kernel_sources():
    """The sources with the lane-math options, as models/CMakeLists.txt gives them
    (TB_PBD_KERNEL_SOURCES): the scalar wrappers of the kernels and every PBD
    constraint kind (models/numerics/pbd/<name>_kind.cc), whose kernels are
    compiled for every instruction set in its own file."""
    kinds = sorted(glob.glob(os.path.join(ROOT, "models", "numerics", "pbd", "*_kind.cc")))
    return {"models/numerics/pbd/constraints.cc"} | {os.path.relpath(k, ROOT).replace(os.sep, "/") for k in kinds}


PBD_KERNEL_SOURCES = pbd_kernel_sources()


def code_generation_flags(args):
    """The flags that decide code generation: -O*, -f*, -m*, -g*, -std, in order."""
    return [a for a in args if a.startswith(("-O", "-f", "-m", "-g", "-std"))]


def commands():
    with open(os.path.join(BUILD, "compile_commands.json")) as f:
        for entry in json.load(f):
            rel = os.path.relpath(entry["file"], ROOT)
            yield rel, shlex.split(entry["command"])


def recorded_flags():
    out = subprocess.run([os.path.join(BUILD, "experiments", "tissuebench"), "build-info"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)["compiler_flags"]


class CompileFlags(unittest.TestCase):
    def test_last_optimisation_flag_is_the_build_types_and_no_deal_ii_flag_leaks(self):
        checked = 0
        for rel, args in commands():
            if not rel.startswith(("models/", "meshing/", "experiments/")):
                continue
            levels = [a for a in args if a.startswith("-O")]
            self.assertEqual(levels[-1], "-O3", f"{rel}: optimisation flags {levels}")
            if rel in DEAL_II_UNITS:
                continue
            checked += 1
            self.assertIn("-O3", levels, rel)
            self.assertEqual(levels.count("-O2"), 0, f"{rel}: {levels}")
            leaked = [a for a in args if a in DEAL_II_ONLY]
            self.assertEqual(leaked, [], f"{rel}: deal.II flags {leaked}")
        self.assertGreater(checked, 20)

    def test_run_json_records_what_compiled_each_library(self):
        recorded = recorded_flags()
        groups = {"tb_models": lambda rel: rel.startswith("models/") and rel not in DEAL_II_UNITS and
                  rel not in PBD_KERNEL_SOURCES,
                  "tb_models PBD kernel sources": lambda rel: rel in PBD_KERNEL_SOURCES,
                  "tb_fem_assembly (deal.II)": lambda rel: rel in DEAL_II_UNITS,
                  "tb_meshing": lambda rel: rel.startswith("meshing/"),
                  "tb_experiments": lambda rel: rel.startswith("experiments/") and "benchmarks" not in rel and
                  not rel.endswith("tissuebench_main.cc")}
        for group, member in groups.items():
            expected = code_generation_flags(shlex.split(recorded[group]))
            sources = [(rel, args) for rel, args in commands() if member(rel)]
            self.assertTrue(sources, group)
            if group == "tb_models PBD kernel sources":  # the kinds found, and each one compiled
                self.assertGreaterEqual(len(PBD_KERNEL_SOURCES), 3, PBD_KERNEL_SOURCES)
                self.assertEqual({rel for rel, _ in sources}, PBD_KERNEL_SOURCES)
            for rel, args in sources:
                # The standard flag CMake adds from CMAKE_CXX_STANDARD is not a flag the project writes.
                actual = [a for a in code_generation_flags(args) if not a.startswith("-std")]
                self.assertEqual(actual, [a for a in expected if not a.startswith("-std")],
                                 f"{rel} ({group}): compiled with {actual}, run.json records {expected}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        BUILD = sys.argv.pop(1)
    unittest.main()
