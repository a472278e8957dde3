"""analysis/observation_points.py: interpolation onto observation points from any
surface or tet mesh (exact at the vertices of the paper cube's own mesh, linear fields
reproduced on a mesh refined from it, the right distance from a curved surface, each bad
input one line), the committed results/observation_points (what the script writes, the
liver's and the beads' without coordinates), and the scorer against the committed
leaderboard column.

Run by CTest (analysis_tests), or alone:
  /usr/bin/python3 -m unittest discover -s tests/analysis -p "test_observation_points.py"
"""
import csv
import filecmp
import json
import os
import sys
import tempfile
import unittest

import numpy as np
from scipy.spatial import Delaunay

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import converged_fields  # noqa: E402
import metrics  # noqa: E402
import observation_points as op  # noqa: E402
import results_index  # noqa: E402
import truth_cube  # noqa: E402
from vtu_plot import read_vtu  # noqa: E402

PAPER_MESH = os.path.join(ROOT, "results", "paper", "cube-pull", "mesh")  # the suite cube's mesh too
SUITE = os.path.join(ROOT, "results", "suite")
POINTS = os.path.join(ROOT, "results", "observation_points")
STUDY_RUNS = os.path.join(ROOT, "results", "suite_reference_convergence", "suite_reference_convergence")


def paper_surface():
    V, F, _ = read_vtu(os.path.join(PAPER_MESH, "fine_surface.vtu"))
    return V, F


def split_in_four(V, F, U):
    """Each triangle split in four at its edges' midpoints (shared between neighbours),
    a midpoint's value the average of its edge's ends."""
    edges = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(V) + inverse.ravel().reshape(3, -1).T  # the midpoints of edges 01, 12, 20 of each triangle
    V2 = np.vstack([V, V[unique].mean(axis=1)])
    U2 = np.vstack([U, U[unique].mean(axis=1)])
    a, b, c = F.T
    m01, m12, m20 = mid.T
    F2 = np.vstack([np.c_[a, m01, m20], np.c_[m01, b, m12], np.c_[m20, m12, c], np.c_[m01, m12, m20]])
    return V2, F2, U2


def icosphere(levels):
    """A unit icosphere: the icosahedron split in four `levels` times, vertices on the sphere."""
    t = (1 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], dtype=float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    for _ in range(levels):
        V, F, _ = split_in_four(V, F, V)
        V /= np.linalg.norm(V, axis=1, keepdims=True)
    return V, F


def brute_force_distance(points, V, F):
    """Distance of each point from the surface, every triangle tried."""
    P = np.repeat(points, len(F), axis=0)
    A, B, C = (np.tile(V[F[:, k]], (len(points), 1)) for k in range(3))
    Q, _ = op.closest_on_triangles(P, A, B, C)
    return np.linalg.norm(Q - P, axis=1).reshape(len(points), len(F)).min(axis=1)


def closest_by_projection(p, a, b, c):
    """The closest point of triangle abc to p, another way: the projection on its plane if it
    falls inside, else the closest of the three edges' closest points."""
    n = np.cross(b - a, c - a)
    q = p - np.dot(p - a, n) / np.dot(n, n) * n
    inside = [np.dot(np.cross(y - x, q - x), n) >= 0 for x, y in ((a, b), (b, c), (c, a))]
    if all(inside):
        return q
    on_edges = [x + np.clip(np.dot(p - x, y - x) / np.dot(y - x, y - x), 0, 1) * (y - x)
                for x, y in ((a, b), (b, c), (c, a))]
    return min(on_edges, key=lambda e: np.linalg.norm(p - e))


class SurfaceInterpolation(unittest.TestCase):
    def test_ericsons_closest_point_against_projection(self):
        rng = np.random.default_rng(5)
        A, B, C = rng.normal(size=(3, 2000, 3))
        C[:500] = A[:500] + 50 * (B[:500] - A[:500]) + 0.01 * C[:500]  # long and thin
        P = 2 * rng.normal(size=(2000, 3))
        Q, W = op.closest_on_triangles(P, A, B, C)
        expected = np.array([closest_by_projection(*x) for x in zip(P, A, B, C)])
        np.testing.assert_allclose(Q, expected, rtol=0, atol=1e-9)
        self.assertTrue(np.all(W >= 0) and np.allclose(W.sum(axis=1), 1))

    def test_at_the_paper_cubes_vertices_the_vertex_values_exactly(self):
        V, F = paper_surface()
        U = np.random.default_rng(1).normal(size=V.shape)
        values, distance = op.surface_values_at(V, V, F, U)
        np.testing.assert_array_equal(values, U)
        np.testing.assert_array_equal(distance, np.zeros(len(V)))

    def test_a_mesh_refined_from_it_reproduces_a_linear_field(self):
        V, F = paper_surface()
        A, b = np.array([[0.3, -0.1, 0.2], [0.05, 0.4, -0.2], [-0.3, 0.1, 0.5]]), np.array([1e-3, -2e-3, 5e-4])
        V2, F2, U2 = split_in_four(V, F, V @ A.T + b)
        rng = np.random.default_rng(2)
        tri = rng.integers(0, len(F), 300)
        w = rng.dirichlet(np.ones(3), 300)
        on_surface = np.einsum("ij,ijk->ik", w, V[F[tri]])  # points on the paper mesh's facets
        points = np.vstack([V, on_surface])
        values, distance = op.surface_values_at(points, V2, F2, U2)
        np.testing.assert_allclose(values, points @ A.T + b, rtol=0, atol=1e-15)
        self.assertLess(distance.max(), 1e-15)

    def test_points_off_a_curved_surface_get_the_right_distance(self):
        V, F = icosphere(3)
        U = V * 0.01  # a radial displacement
        A, B, C = (V[F[:, k]] for k in range(3))
        centroid = (A + B + C) / 3
        normal = np.cross(B - A, C - A)
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        # Above and below each facet's centroid: its own facet is the nearest (a convex surface).
        for h in (0.05, -1e-3):
            _, distance = op.surface_values_at(centroid + h * normal, V, F, U)
            np.testing.assert_allclose(distance, abs(h), rtol=1e-9)
        # Points on the sphere itself, off the facets, and any others: the closest facet, as trying every one.
        rng = np.random.default_rng(3)
        directions = rng.normal(size=(200, 3))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        points = np.vstack([directions, directions * 1.01, directions * 0.97])
        values, distance = op.surface_values_at(points, V, F, U)
        np.testing.assert_allclose(distance, brute_force_distance(points, V, F), rtol=1e-12, atol=1e-15)
        # On the sphere the facets lie inside it, by at most their sagitta.
        self.assertLess(distance[:200].max(), 1 - np.linalg.norm(centroid, axis=1).min() + 1e-12)
        np.testing.assert_allclose(np.linalg.norm(values[:200], axis=1), 0.01, rtol=0.01)

    def assert_one_line_error(self, pattern, *args, **kwargs):
        with self.assertRaisesRegex(ValueError, pattern) as caught:
            op.surface_values_at(*args, **kwargs)
        self.assertNotIn("\n", str(caught.exception))

    def test_bad_input_is_a_one_line_error_naming_the_problem(self):
        V, F = paper_surface()
        U = np.zeros_like(V)
        p = V[:3].copy()
        nan_point = p.copy()
        nan_point[2, 1] = np.nan
        self.assert_one_line_error("points: point 2 is not finite", nan_point, V, F, U)
        self.assert_one_line_error(r"points: expected #N by 3, got shape \(3,\)", V[0], V, F, U)
        self.assert_one_line_error(r"F: expected #N by 3, got shape \(1360, 4\)", p, V, np.c_[F, F[:, 0]], U)
        self.assert_one_line_error(r"U: shape \(3, 3\)", p, V, F, U[:3])
        self.assert_one_line_error("empty mesh", p, V, np.zeros((0, 3), int), U)
        self.assert_one_line_error("points: none given", np.zeros((0, 3)), V, F, U)
        self.assert_one_line_error("F: index 682 out of range for 682 vertices", p, V, F + 1, U)
        bad_u = U.copy()
        bad_u[F[5, 1]] = np.inf
        self.assert_one_line_error(f"U: vertex {F[5, 1]} is not finite", p, V, F, bad_u)
        far = p.copy()
        far[1] = [0.0, 0.0, 100.0]  # metres where millimetres were meant
        self.assert_one_line_error("point s9 is 99.9 m from the surface", far, V, F, U, names=["s7", "s9", "s11"])
        self.assert_one_line_error("names: 2 names for 3 points", p, V, F, U, names=["a", "b"])

    def test_patch_faces_keep_the_observed_face(self):
        V, F = paper_surface()
        ids, _, _ = metrics.read_displacements(os.path.join(SUITE, "suite-cube-pull-disc", "reference",
                                                            "top_surface.csv"))
        top = op.patch_faces(F, ids)
        self.assertEqual(len(top), 2 * 10 * 10)  # the 10 x 10 top grid, two triangles a square
        np.testing.assert_array_equal(V[top][:, :, 2], np.full((200, 3), V[:, 2].max()))


class VolumeInterpolation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.X, cls.T, _ = read_vtu(os.path.join(PAPER_MESH, "fine_volume.vtu"))

    def test_nodes_and_a_linear_field_inside_to_rounding(self):
        X, T = self.X, self.T
        A = np.array([[0.2, 0.1, 0.0], [0.0, -0.3, 0.1], [0.4, 0.0, 0.2]])
        U = X @ A.T
        rng = np.random.default_rng(4)
        points = np.vstack([X[::50], rng.uniform([-0.05, -0.05, 0], [0.05, 0.05, 0.1], size=(200, 3))])
        values, distance = op.volume_values_at(points, X, T, U)
        np.testing.assert_allclose(values[:len(X[::50])], U[::50], rtol=0, atol=1e-18)
        np.testing.assert_allclose(values, points @ A.T, rtol=0, atol=1e-16)
        np.testing.assert_array_equal(distance, 0)

    def test_outside_the_nearest_tet_clamped_and_its_distance(self):
        X, T = self.X, self.T
        U = X * 0.1
        points = np.array([[0.01, -0.02, 0.1004], [0.0502, 0.013, 0.05]])  # above the top, beside a side
        values, distance = op.volume_values_at(points, X, T, U)
        np.testing.assert_allclose(distance, [4e-4, 2e-4], rtol=1e-9)
        foot = np.array([[0.01, -0.02, 0.1], [0.05, 0.013, 0.05]])
        np.testing.assert_allclose(values, foot * 0.1, rtol=0, atol=1e-16)
        with self.assertRaisesRegex(ValueError, "point b3 is 0.05 m from the volume"):
            op.volume_values_at([[0, 0, 0.15]], X, T, U, names=["b3"])
        with self.assertRaisesRegex(ValueError, "T: expected #N by 4"):
            op.volume_values_at(points, X, T[:, :3], U)


def committed_column():
    """{(role, case): the rel L2 vs converged column} of results/tables/suite_scores.csv."""
    with open(os.path.join(ROOT, "results", "tables", "suite_scores.csv"), newline="") as f:
        return {(r["role"], r["case"]): r["rel L2 vs converged"] for r in csv.DictReader(f)}


class Scoring(unittest.TestCase):
    """The scorer on predictions read from the committed case files onto the points by
    surface_values_at: the committed leaderboard column, to its three digits, and
    converged_fields' error of the same case to rounding."""

    @classmethod
    def setUpClass(cls):
        cls.column = committed_column()
        cls.fields = converged_fields.read()

    def check(self, role, scenario, case, V, F, U):
        surface = op.read_role(role)["surface"]
        values, _ = op.surface_values_at(surface["rest"], V, F, U, names=surface["id"])
        score = op.score_observations(role, values)["rel_l2_converged"]
        case_dict = results_index.load_case(os.path.join(SUITE, scenario, case))
        self.assertAlmostEqual(score, self.fields[converged_fields.base_role(role)].error(case_dict), places=13)
        self.assertEqual(f"{score:.3g}", self.column[(role, case)], (role, case))

    def test_on_the_paper_mesh_the_committed_column(self):
        V, F = paper_surface()
        for role, scenario, cases in (
                ("cube_pull_disc", "suite-cube-pull-disc", ("reference", "condensed", "xpbd-neo")),
                ("cube_push_disc", "suite-cube-push-disc", ("reference", "fem-corotational", "xpbd-neo"))):
            for case in cases:
                ids, _, u = metrics.read_displacements(os.path.join(SUITE, scenario, case, "top_surface.csv"))
                U = np.full_like(V, np.nan)  # the observed patch alone is known
                U[ids] = u
                self.check(role, scenario, case, V, op.patch_faces(F, ids), U)

    def test_on_another_mesh_the_refined_role(self):
        # The 10k cube's top face, triangulated anew from its own vertices: the points are the paper mesh's.
        for case in ("reference", "pd"):
            _, rest, u = metrics.read_displacements(os.path.join(SUITE, "suite-cube-pull-disc-10k", case,
                                                                 "top_surface.csv"))
            self.check("cube_pull_disc_10k", "suite-cube-pull-disc-10k", case, rest, Delaunay(rest[:, :2]).simplices, u)

    def test_probes_against_the_converged_run(self):
        interior = op.read_role("flap_gravity")["interior"]
        surface = op.read_role("flap_gravity")["surface"]
        mine = np.loadtxt(os.path.join(SUITE, "suite-flap-gravity", "reference", "probes.csv"), delimiter=",",
                          skiprows=1, ndmin=2)[:, 4:7]
        score = op.score_observations("flap_gravity", surface["u"], mine)
        self.assertEqual(score["rel_l2_converged"], 0.0)
        self.assertAlmostEqual(score["probe_error_mm"], np.linalg.norm(mine[0] - interior["u"][0]) * 1000, places=12)
        self.assertEqual(score["converged_run"], "P1 L2")

    def test_beads_against_the_measurement(self):
        table = os.path.join(truth_cube.data_dir(None), "data", "truthcube", "uniaxial_positions.csv")
        if not os.path.isfile(table):
            self.skipTest(f"{table}: not here (third-party data, README 'Data')")
        surface = op.read_role("truth_cube_5")["surface"]
        beads = np.loadtxt(os.path.join(SUITE, "suite-truth-cube-05", "reference", "probes.csv"), delimiter=",",
                           skiprows=1, ndmin=2)[:, 1:4]
        score = op.score_observations("truth_cube_5", surface["u"], beads)
        self.assertEqual(f"{score['bead_rms_mm']:.3g}", "0.984")  # the committed bead RMS of the reference
        self.assertGreater(score["probe_error_mm"], 0)

    def test_a_role_without_a_converged_answer_and_bad_values(self):
        surface = op.read_role("liver_smooth_pads")["surface"]
        score = op.score_observations("liver_smooth_pads", np.zeros((len(surface["id"]), 3)))
        self.assertTrue(np.isnan(score["rel_l2_converged"]))
        self.assertIn("no converged answer", score["note"])
        with self.assertRaisesRegex(ValueError, "values: 3 rows, .*cube_pull_disc.csv has 121 points"):
            op.score_observations("cube_pull_disc", np.zeros((3, 3)))
        with self.assertRaisesRegex(ValueError, "no observation points for role 'cube_pul'"):
            op.score_observations("cube_pul", np.zeros((3, 3)))


class CommittedPoints(unittest.TestCase):
    def test_the_committed_files_are_what_the_script_writes(self):
        with tempfile.TemporaryDirectory() as out:
            done = op.make(SUITE, out)
            self.assertEqual(sorted(os.listdir(out)), sorted(os.listdir(POINTS)))
            _, mismatch, errors = filecmp.cmpfiles(out, POINTS, os.listdir(out), shallow=False)
            self.assertEqual(mismatch + errors, [])
        roles = [r for r, _, _ in op.suite_roles(SUITE)[0]]
        self.assertEqual(sorted(done), sorted(roles))
        self.assertEqual([r for r in roles if not done[r]], ["liver_smooth_pads"])

    def test_a_refined_role_shares_its_base_roles_points(self):
        for role in ("cube_pull_disc_10k", "cube_push_disc_10k"):
            with open(os.path.join(POINTS, f"{role}.csv")) as a, \
                    open(os.path.join(POINTS, f"{converged_fields.base_role(role)}.csv")) as b:
                self.assertEqual(a.read(), b.read())

    def test_third_party_geometry_is_named_by_index(self):
        # The liver's surface points by source_vertex, the beads by table row: no coordinate.
        for role in ("liver_grasp_gravity", "liver_smooth_pads"):
            files = op.read_role(role)
            self.assertIsNone(files["surface"]["rest"], role)
            with open(os.path.join(POINTS, f"{role}.csv")) as f:
                self.assertEqual(f.readline().strip().split(",")[:4], ["id", "patch", "source_vertex", "file_vertex"])
            # The probe: the scenario's own point (its file's, as the run resolved it).
            reference = os.path.dirname(os.path.join(ROOT, files["meta"]["surface_points_from"]))
            with open(os.path.join(reference, "run.json")) as f:
                probes = json.load(f)["scenario_resolved"]["probes"]
            np.testing.assert_array_equal(files["interior"]["rest"], probes)
        for strain in ("5", "12_5", "18_25"):
            interior = op.read_role(f"truth_cube_{strain}")["interior"]
            self.assertIsNone(interior["rest"])
            np.testing.assert_array_equal(interior["table_row"], np.arange(343))

    def test_the_livers_file_vertices_are_its_clamped_and_grasped_vertices(self):
        # The map from the runner's repaired liver surface to the data file's vertices
        # (REPAIRED_SURFACES), checked on the committed reference: exactly the vertices the
        # file puts in the support's box stay still, exactly those within the grasp's radius
        # move with the jaw.
        files = op.read_role("liver_grasp_gravity")
        surface, meta = files["surface"], files["meta"]
        with self.assertRaisesRegex(results_index.ResultsError, "point s2025 is a vertex the repair .* made"):
            op.surface_coordinates("liver_grasp_gravity")
        path = os.path.join(truth_cube.data_dir(None), meta["source"]["surface"].split(":", 1)[1])
        if not os.path.isfile(path):
            self.skipTest(f"{path}: not here (third-party data, README 'Data')")
        known = surface["file_vertex"] >= 0
        rest = op.read_obj_vertices(path)[surface["file_vertex"][known]] * meta["source"]["unit_scale"]
        reference = os.path.dirname(os.path.join(ROOT, meta["surface_points_from"]))
        ids, _, u = metrics.read_displacements(os.path.join(reference, "top_surface.csv"))
        np.testing.assert_array_equal(ids, surface["source_vertex"])
        u = u[known]
        with open(os.path.join(reference, "run.json")) as f:
            scenario = json.load(f)["scenario_resolved"]
        box, grasp = scenario["support"], scenario["tools"][0]
        clamped = np.all((rest >= box["min"]) & (rest <= box["max"]), axis=1)
        held = np.linalg.norm(rest - grasp["point"], axis=1) <= grasp["radius"]
        np.testing.assert_array_equal(np.all(u == 0, axis=1), clamped)
        np.testing.assert_array_equal(np.all(u == grasp["schedule"]["value"], axis=1), held)
        self.assertGreater(np.count_nonzero(clamped), 100)
        self.assertGreater(np.count_nonzero(held), 20)

    def test_the_livers_converged_values_are_the_committed_study_csvs(self):
        # Nothing beyond what the committed CSVs already hold: the finest run's displacements by index.
        files = op.read_role("liver_grasp_gravity")
        folder = os.path.join(ROOT, files["meta"]["converged"]["folder"])
        ids, rest, u = metrics.read_displacements(os.path.join(folder, "top_surface.csv"))
        self.assertIsNone(rest)
        row = {v: k for k, v in enumerate(ids)}
        np.testing.assert_array_equal(files["surface"]["u"], u[[row[v] for v in files["surface"]["source_vertex"]]])
        probes = np.loadtxt(os.path.join(folder, "probes.csv"), delimiter=",", skiprows=1, ndmin=2)
        np.testing.assert_array_equal(files["interior"]["u"], probes[:, 4:7])
        text = json.dumps(files["meta"])
        self.assertNotIn('"x"', text)

    def test_each_role_says_its_patch_and_its_converged_run(self):
        patches = {}
        for role, _, _ in op.suite_roles(SUITE)[0]:
            meta = op.read_role(role)["meta"]
            patches[role] = meta["patch"]
            if meta["converged"] is not None:
                self.assertRegex(meta["converged"]["run"], r"^P[12] L[0-2]$")
        self.assertEqual(patches["cube_pull_disc"], "top_face")
        self.assertEqual(patches["flap_gravity"], "whole_surface")
        self.assertEqual(patches["liver_grasp_gravity"], "whole_surface")


if __name__ == "__main__":
    unittest.main()
