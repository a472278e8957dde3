"""The committed results hold no third-party geometry (README "Data"): a case whose
mesh was read from a data: file keeps displacements by vertex index, with no rest
coordinates, no surface or volume files and no mesh folder. Checked on the files
git tracks (every file, outside a git checkout)."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import results_index  # noqa: E402

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


class CoordinateFreeCases(unittest.TestCase):
    """The analysis of a case whose CSVs give no coordinates: the load's vertex from
    run.json, the rest surface from the run's mesh folder, else a one-line error."""

    def write_case(self, root, name, u):
        folder = os.path.join(root, "scenario", name)
        os.makedirs(folder)
        with open(os.path.join(folder, "top_surface.csv"), "w") as f:
            f.write("vertex,ux,uy,uz\n")
            for v, row in zip((0, 2), u):
                f.write(f"{v},{row[0]},{row[1]},{row[2]}\n")
        run = {"observed_vertex_nearest_load": 2, "scenario_resolved": {"load": {"point": [0, 0, 1]}}}
        return {"folder": folder, "run": run}

    def test_metrics_rest_and_the_missing_mesh_folder(self):
        with tempfile.TemporaryDirectory() as root:
            ref = self.write_case(root, "ref", [(0, 0, 1), (0, 0, 2)])
            case = self.write_case(root, "case", [(0, 0, 1), (0, 0, 1)])
            m = results_index.case_metrics(case, ref)
            self.assertAlmostEqual(m["load_ratio"], 0.5)  # vertex 2, the second row
            with self.assertRaisesRegex(results_index.ResultsError, "no coordinates .* no .*fine_surface.vtu"):
                results_index.observed_rest(case)
            os.makedirs(os.path.join(root, "scenario", "mesh"))
            points = "0 0 0  1 0 0  0 1 1  0 0 3"
            with open(os.path.join(root, "scenario", "mesh", "fine_surface.vtu"), "w") as f:
                f.write('<VTKFile><Piece><Points><DataArray Name="Points" NumberOfComponents="3">' + points +
                        '</DataArray></Points><Cells><DataArray Name="connectivity">0 1 2</DataArray>'
                        '<DataArray Name="offsets">3</DataArray></Cells></Piece></VTKFile>')
            np.testing.assert_array_equal(results_index.observed_rest(case), [[0, 0, 0], [0, 1, 1]])


if __name__ == "__main__":
    unittest.main()
