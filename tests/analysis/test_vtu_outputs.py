"""The committed VTU outputs read back by an independent reader (meshio), with the
point and cell counts summary.json states (files ParaView opens)."""
import glob
import json
import os
import unittest

import meshio

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RESULTS = os.path.join(ROOT, "results", "paper")


class VtuOutputs(unittest.TestCase):
    def test_every_result_surface_reads_back(self):
        files = sorted(glob.glob(os.path.join(RESULTS, "*", "*", "surface.vtu")))
        self.assertGreaterEqual(len(files), 16)
        for f in files:
            # The mesh summary each run.json records (the liver's mesh folders are not committed).
            with open(os.path.join(os.path.dirname(f), "run.json")) as s:
                summary = json.load(s)["mesh"]
            m = meshio.read(f)
            self.assertEqual(m.points.shape, (summary["surface_vertices"], 3), f)
            self.assertEqual(m.cells[0].type, "triangle", f)
            self.assertEqual(len(m.cells[0].data), summary["surface_triangles"], f)
            self.assertEqual(m.point_data["displacement"].shape, (summary["surface_vertices"], 3), f)

    def test_mesh_volumes_read_back(self):
        mesh_dirs = sorted(glob.glob(os.path.join(RESULTS, "*", "mesh")))
        self.assertGreaterEqual(len(mesh_dirs), 2)  # the cube's, committed
        for mesh_dir in mesh_dirs:
            with open(os.path.join(mesh_dir, "summary.json")) as s:
                summary = json.load(s)
            coarse = meshio.read(os.path.join(mesh_dir, "coarse_volume.vtu"))
            self.assertEqual(len(coarse.points), summary["coarse_nodes"])
            self.assertEqual(coarse.cells[0].type, "tetra")
            self.assertEqual(len(coarse.cells[0].data), summary["coarse_tets"])
            fine = meshio.read(os.path.join(mesh_dir, "fine_volume.vtu"))
            self.assertEqual(len(fine.points), summary["fine_nodes"])
            self.assertEqual(len(fine.cells[0].data), summary["fine_tets"])


if __name__ == "__main__":
    unittest.main()
