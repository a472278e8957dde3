"""The committed results hold no third-party geometry (README "Data"): a case whose
mesh was read from a data: file keeps displacements by vertex index, with no rest
coordinates, no surface or volume files and no mesh folder. Checked on the files
git tracks (every file, outside a git checkout)."""
import csv
import json
import os
import subprocess
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GEOMETRY_FILES = (".vtu", ".pvd", ".obj", ".msh", ".stl", ".off", ".ply", ".ele", ".node")


def committed_files():
    """Paths (relative to the repository) of the files under results/ git tracks."""
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "results"], capture_output=True, text=True, check=True)
        return out.stdout.split()
    except (OSError, subprocess.CalledProcessError):
        return [os.path.relpath(os.path.join(d, f), ROOT)
                for d, _, fs in os.walk(os.path.join(ROOT, "results")) for f in fs]


def data_references(run):
    """The data: files a run's mesh was read from."""
    scenario = run.get("scenario_resolved") or run.get("scenario_as_read") or {}
    mesh = scenario.get("mesh", {})
    return [mesh[k] for k in ("surface", "coarse") if str(mesh.get(k, "")).startswith("data:")]


class ThirdPartyGeometry(unittest.TestCase):
    def test_cases_on_data_meshes_commit_displacements_alone(self):
        files = committed_files()
        by_folder = {}
        for f in files:
            by_folder.setdefault(os.path.dirname(f), []).append(os.path.basename(f))
        cases = 0
        for folder, names in by_folder.items():
            if "run.json" not in names:
                continue
            with open(os.path.join(ROOT, folder, "run.json")) as f:
                run = json.load(f)
            if not data_references(run):
                continue
            cases += 1
            self.assertIs(run.get("observed_coordinates"), False, folder)
            for name in names:
                self.assertFalse(name.endswith(GEOMETRY_FILES), f"{folder}/{name}")
            for name in ("top_surface.csv", "surface.csv"):
                if name in names:
                    with open(os.path.join(ROOT, folder, name), newline="") as f:
                        header = next(csv.reader(f))
                    self.assertEqual(header, ["vertex", "ux", "uy", "uz"], f"{folder}/{name}")
            # Nor the mesh folder beside the case (its scenario's).
            scenario_dir = os.path.dirname(folder)
            self.assertFalse([f for f in files if f.startswith(scenario_dir + "/mesh/")], scenario_dir)
        # The liver's cases are committed (paper, suite, 10k, reference levels): the check ran.
        self.assertGreaterEqual(cases, 50)

    def test_the_geometry_files_committed_are_the_projects_own(self):
        # Every committed mesh or surface file sits in a scenario folder whose runs used
        # no data: file (the cube, the generated shapes).
        files = committed_files()
        for f in files:
            if not f.endswith(GEOMETRY_FILES):
                continue
            scenario_dir = os.path.dirname(os.path.dirname(f))  # <scenario>/<case or mesh>/<file>
            runs = [g for g in files if g.startswith(scenario_dir + "/") and g.endswith("/run.json")]
            for r in runs:
                with open(os.path.join(ROOT, r)) as fh:
                    self.assertEqual(data_references(json.load(fh)), [], f"{f} beside {r}")


if __name__ == "__main__":
    unittest.main()
