#!/usr/bin/env python3
"""The layers of docs/architecture.md, checked on every #include of the project's code.

Headers are included by file name (their folders are on the include path), so a
name must be unique in the tree; this test resolves each include to its file and
fails when a lower layer includes a higher one:

  python/                      the Python module's bindings: may include experiments/ and below
  experiments/                 may include models/ and meshing/
  models/ (root files)         the Model interface and registry: numerics, meshing, model folders
  models/<model>/              a registered model: models/ root, numerics, meshing, its own folder
  models/numerics/<area>/      numerics, meshing, and models/parameters.h only
  meshing/                     meshing only

Usage: test_layering.py <source dir>
"""
import os
import re
import sys
import unittest

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)
CODE_DIRS = ("meshing", "models", "experiments", "python")
# The one models/ root header numerics may use: parameter declarations (name,
# default, range, description) that every layer above resolves.
NUMERICS_MAY_USE_FROM_ROOT = {"models/parameters.h"}


def layer(path):
    """('meshing' | 'numerics' | 'model' | 'models_root' | 'experiments' | 'python', folder)."""
    parts = path.split("/")
    if parts[0] == "python":
        return "python", "python"
    if parts[0] == "meshing":
        return "meshing", "meshing"
    if parts[0] == "experiments":
        return "experiments", "experiments"
    if parts[1] == "numerics":
        return "numerics", "/".join(parts[:3])
    if len(parts) == 2:
        return "models_root", "models"
    return "model", "/".join(parts[:2])


def allowed(src, dst):
    (ls, fs), (ld, fd) = layer(src), layer(dst)
    if ld == "python" or ls == "python":  # the top layer: it includes every other, none includes it
        return ls == "python"
    if ls == "meshing":
        return ld == "meshing"
    if ls == "numerics":
        return ld in ("meshing", "numerics") or dst in NUMERICS_MAY_USE_FROM_ROOT
    if ls == "model":
        return ld in ("meshing", "numerics", "models_root") or fd == fs
    if ls == "models_root":
        return ld in ("meshing", "numerics", "models_root", "model")
    return ld != "experiments" or fd == "experiments"  # experiments: everything below


def project_files(root):
    out = []
    for top in CODE_DIRS:
        for dirpath, _, names in os.walk(os.path.join(root, top)):
            for n in names:
                if n.endswith((".h", ".cc", ".cpp")):
                    out.append(os.path.relpath(os.path.join(dirpath, n), root).replace(os.sep, "/"))
    return sorted(out)


def check(root):
    """(duplicate header names, [(file, included file, why)])."""
    files = project_files(root)
    by_name = {}
    for f in files:
        if f.endswith(".h"):
            by_name.setdefault(os.path.basename(f), []).append(f)
    duplicates = {n: p for n, p in by_name.items() if len(p) > 1}
    violations = []
    for f in files:
        with open(os.path.join(root, f), encoding="utf-8") as fh:
            text = fh.read()
        for inc in INCLUDE.findall(text):
            same_folder = os.path.normpath(os.path.join(os.path.dirname(f), inc)).replace(os.sep, "/")
            if same_folder in files:
                target = same_folder
            else:
                candidates = [p for p in files if p.endswith("/" + inc) or p == inc]
                candidates = candidates or by_name.get(os.path.basename(inc), [])
                if len(candidates) != 1:
                    continue  # generated (compile_flags.h) or a system header in quotes
                target = candidates[0]
            if not allowed(f, target):
                violations.append((f, target, f"{layer(f)[0]} may not include {layer(target)[0]}"))
    return duplicates, violations


class LayeringTest(unittest.TestCase):
    root = None

    def test_header_names_are_unique(self):
        duplicates, _ = check(self.root)
        self.assertEqual(duplicates, {}, "headers are included by file name: these names are ambiguous")

    def test_no_layer_includes_a_higher_one(self):
        _, violations = check(self.root)
        self.assertEqual(violations, [], "\n".join(f"{a} includes {b}: {why}" for a, b, why in violations))

    def test_the_rule_catches_an_upward_include(self):
        # The check itself can fail: numerics including the Model interface or a
        # model folder, and meshing including numerics, are refused.
        self.assertFalse(allowed("models/numerics/pbd/pbd_solver.h", "models/model.h"))
        self.assertFalse(allowed("models/numerics/pbd/pbd_solver.h", "models/hybrid/hybrid_model.h"))
        self.assertFalse(allowed("meshing/shapes.h", "models/numerics/pbd/constraints.h"))
        self.assertFalse(allowed("models/hybrid/hybrid_model.cc", "models/fem/fem_model.h"))
        self.assertFalse(allowed("models/model.h", "experiments/scenario.h"))
        self.assertFalse(allowed("experiments/runner.cc", "python/python_bindings.h"))
        self.assertTrue(allowed("python/run_binding.cc", "experiments/case_run.h"))
        self.assertTrue(allowed("models/hybrid/hybrid_model.cc", "models/numerics/pbd/pbd_solver.h"))
        self.assertTrue(allowed("models/numerics/pbd/pbd_solver.h", "models/parameters.h"))


if __name__ == "__main__":
    LayeringTest.root = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../..")
    unittest.main(verbosity=2)
