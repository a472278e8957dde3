"""analysis/rim_strain.py: the principal stretches of a surface triangle against
closed-form deformations (a rotation, a stretch in a tilted plane, a shear), and the
bands of a small surface around a held vertex."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import rim_strain  # noqa: E402

# Two triangles in a plane tilted out of xy, so the in-plane frame is not the axes.
TILT = np.array([[1, 0, 0], [0, np.cos(0.4), np.sin(0.4)], [0, -np.sin(0.4), np.cos(0.4)]])
REST = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float) @ TILT.T
TRIANGLES = np.array([[0, 1, 2], [1, 3, 2]])


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


class PrincipalStretches(unittest.TestCase):
    def stretches(self, deformation):
        return rim_strain.principal_stretches(REST, REST @ deformation.T, TRIANGLES)

    def test_a_rotation_stretches_nothing(self):
        np.testing.assert_allclose(self.stretches(rotation([1, 2, 3], 0.7)), 1, atol=1e-14)

    def test_a_stretch_along_the_plane_is_found_whatever_the_tilt(self):
        # 1.5 along the plane's first axis, 0.6 along its second, then rotated.
        in_plane = TILT @ np.diag([1.5, 0.6, 1.0]) @ TILT.T
        s = self.stretches(rotation([0, 1, 1], 1.1) @ in_plane)
        np.testing.assert_allclose(s, [[1.5, 0.6], [1.5, 0.6]], rtol=1e-13)

    def test_a_simple_shear_gives_its_closed_form_stretches(self):
        gamma = 0.8  # stretches sqrt(1 + g^2/4) +- g/2
        shear = TILT @ np.array([[1, gamma, 0], [0, 1, 0], [0, 0, 1]]) @ TILT.T
        expected = np.sqrt(1 + gamma**2 / 4) + np.array([gamma / 2, -gamma / 2])
        np.testing.assert_allclose(self.stretches(shear), [expected, expected], rtol=1e-13)


def write_vtu(path, points, displacement, triangles):
    def block(name, values, kind="Float64", components=None):
        c = f' NumberOfComponents="{components}"' if components else ""
        text = " ".join(repr(float(v)) if kind == "Float64" else str(int(v)) for v in np.ravel(values))
        return f'<DataArray type="{kind}" Name="{name}"{c} format="ascii">{text}</DataArray>\n'

    with open(path, "w") as f:
        f.write('<VTKFile type="UnstructuredGrid"><UnstructuredGrid>'
                f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(triangles)}">\n<PointData>\n')
        f.write(block("displacement", displacement, components=3) + "</PointData>\n<Points>\n")
        f.write(block("Points", points, components=3) + "</Points>\n<Cells>\n")
        f.write(block("connectivity", triangles, "Int32"))
        f.write(block("offsets", 3 * np.arange(1, len(triangles) + 1), "Int32"))
        f.write(block("types", np.full(len(triangles), 5), "UInt8") + "</Cells>\n</Piece></UnstructuredGrid></VTKFile>\n")


class Bands(unittest.TestCase):
    def test_the_rim_and_the_free_bands_are_reported_apart(self):
        # A strip of squares along x (1 mm), vertex 0 held and lifted; the rim's
        # triangles hold it, the others are banded by distance from it.
        n = 8
        points = np.array([[1e-3 * i, 1e-3 * j, 0] for i in range(n) for j in range(2)])
        triangles = np.array([t for i in range(n - 1) for t in ([2 * i, 2 * i + 2, 2 * i + 1],
                                                               [2 * i + 2, 2 * i + 3, 2 * i + 1])])
        lift = np.array([0, 0, 1e-4])
        displacement = np.zeros_like(points)
        displacement[0] = lift
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "surface.vtu")
            write_vtu(path, points + displacement, displacement, triangles)  # its points deformed
            out = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "rim_strain.py"),
                                  "--displacement", *map(str, lift), f"strip={path}"],
                                 capture_output=True, text=True, check=True).stdout
        row = out.strip().splitlines()[-1].split("|")[1:-1]
        cells = [c.strip() for c in row]
        self.assertEqual(cells[:4], ["strip", str(len(triangles)), "1.00", "1"])
        # Only the first triangle holds vertex 0, its two 1 mm legs meeting there:
        # the lift's gradient (-0.1, -0.1) stretches it sqrt(1 + 2 * 0.1^2) along
        # the diagonal and not across.
        self.assertAlmostEqual(float(cells[4]), np.sqrt(1.02), places=3)
        self.assertEqual(cells[5], "1.000")
        self.assertEqual(cells[6:], ["n/a", "1.000", "1.000", "1.000", "1.000"])  # the nearest free centroid 0.94 mm away

    def test_a_compliant_grasps_patch_is_chosen_by_its_rest_disc(self):
        # The same strip, vertex 0 lifted by pads that lag the jaw (0.7 of it): no
        # vertex moves by the jaw's displacement, the disc of 0.5 mm around the
        # origin holds vertex 0 alone, and its rim triangle stretches by the lag's lift.
        n = 8
        points = np.array([[1e-3 * i, 1e-3 * j, 0] for i in range(n) for j in range(2)])
        triangles = np.array([t for i in range(n - 1) for t in ([2 * i, 2 * i + 2, 2 * i + 1],
                                                               [2 * i + 2, 2 * i + 3, 2 * i + 1])])
        displacement = np.zeros_like(points)
        displacement[0] = [0, 0, 0.7e-4]
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "surface.vtu")
            write_vtu(path, points + displacement, displacement, triangles)
            script = os.path.join(ROOT, "analysis", "rim_strain.py")
            out = subprocess.run([sys.executable, script, "--patch", "0", "0", "0", "0.0005", f"strip={path}"],
                                 capture_output=True, text=True, check=True).stdout
            by_jaw = subprocess.run([sys.executable, script, "--displacement", "0", "0", "1e-4", f"strip={path}"],
                                    capture_output=True, text=True)
        cells = [c.strip() for c in out.strip().splitlines()[-1].split("|")[1:-1]]
        self.assertEqual(cells[3], "1")
        self.assertAlmostEqual(float(cells[4]), np.sqrt(1 + 2 * 0.07**2), places=3)
        self.assertNotEqual(by_jaw.returncode, 0)  # no vertex moves with the jaw

    def test_no_held_vertex_is_a_one_line_error(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "surface.vtu")
            write_vtu(path, REST, np.zeros_like(REST), TRIANGLES)
            r = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "rim_strain.py"),
                                "--displacement", "0", "0", "1", f"x={path}"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("surface.vtu: no vertex displaced by", r.stderr)

    def test_a_patch_without_a_rim_is_a_one_line_error(self):
        # Every vertex lifted: every triangle held, none on a rim.
        lift = np.array([0, 0, 1e-3])
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "surface.vtu")
            write_vtu(path, REST + lift, np.tile(lift, (len(REST), 1)), TRIANGLES)
            r = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "rim_strain.py"),
                                "--displacement", *map(str, lift), f"x={path}"], capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("surface.vtu: no triangle on the held patch's rim", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main()
