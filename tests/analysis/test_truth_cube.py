"""analysis/truth_cube.py on synthetic bead grids: the resolution estimate finds a
quantised axis and the noise added, the layer shear is taken out of both fields
alike, the implied top displacement of a linear field is exact, and the frame is
the runner's (experiments/truth_cube.h)."""
import os
import sys
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import truth_cube  # noqa: E402


def grid():
    ijk = np.array([(i, j, k) for i in range(1, 8) for j in range(1, 8) for k in range(1, 8)])
    rest = np.stack([(ijk[:, 0] - 4) * 10.0, (ijk[:, 1] - 4) * 10.0, ijk[:, 2] * 10.0], axis=1)  # model frame, mm
    return ijk, rest


class TruthCubeAnalysis(unittest.TestCase):
    def test_resolution_finds_the_quantised_axis_and_bounds_the_noise(self):
        ijk, rest = grid()
        rng = np.random.default_rng(3)
        strains = (0.05, 0.125, 0.1825)
        positions = [rest + rng.normal(0, 0.1, rest.shape)]
        for s in strains:
            u = np.stack([0.3 * s * rest[:, 0], 0.3 * s * rest[:, 1], -s * rest[:, 2]], axis=1)
            positions.append(rest + u + rng.normal(0, 0.1, rest.shape))
        positions = np.stack(positions, axis=1)
        positions[:, :, 1] = np.round((positions[:, :, 1] - 0.125) / 0.25) * 0.25 + 0.125  # y on a 0.25 mm grid
        positions = np.round(positions, 2)
        steps, quantisation, residuals = truth_cube.measurement_resolution(positions)
        self.assertEqual(steps, [0.01, 0.25, 0.01])
        self.assertAlmostEqual(quantisation, np.sqrt((2 * 0.01 ** 2 + 0.25 ** 2) / 12), places=9)
        # Noise 0.1 mm per coordinate at rest and deformed: about 0.14 mm per displacement
        # component in x and z; the fit removes the smooth field and keeps the noise.
        for total, per_axis in residuals:
            self.assertGreater(per_axis[0], 0.12)
            self.assertLess(per_axis[0], 0.16)
            self.assertGreater(per_axis[2], 0.12)
            self.assertLess(per_axis[2], 0.16)
            self.assertGreater(per_axis[1], per_axis[0])  # the quantised axis is noisier

    def test_layer_shear_is_taken_out_of_both_fields_alike(self):
        ijk, rest = grid()
        shear = np.zeros_like(rest)
        shear[:, 1] = 0.2 * ijk[:, 2]  # each layer moved sideways as a whole
        measured = rest + shear
        self.assertAlmostEqual(truth_cube.layer_shear_rms(rest, measured, ijk),
                               np.sqrt(np.mean((0.2 * ijk[:, 2]) ** 2)), places=12)
        m = truth_cube.errors(rest, measured, rest.copy(), ijk)
        self.assertGreater(m["rms"], 0.5)
        self.assertAlmostEqual(m["unsheared_rms"], 0.0, places=12)

    def test_the_implied_top_displacement_of_a_linear_field_is_exact(self):
        ijk, rest = grid()
        measured = rest.copy()
        measured[:, 2] -= 0.2 * rest[:, 2]  # uniform strain: the top (z = 80 mm) moves 16 mm
        self.assertAlmostEqual(truth_cube.implied_top_displacement(rest, measured, ijk), -16.0, places=9)

    def test_the_frame_is_the_runners(self):
        frame = {"origin_mm": [1.0, 3.0, -17.0], "centre_m": [0, 0, 0.04], "axes": [1, -1, -1]}
        got = truth_cube.to_model_mm(np.array([[11.0, 13.0, -7.0]]), frame)
        np.testing.assert_allclose(got, [[10.0, -10.0, 30.0]])


if __name__ == "__main__":
    unittest.main()
