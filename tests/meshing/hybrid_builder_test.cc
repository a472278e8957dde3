// The hybrid mesh of paper 1.2 on the cube, a non-convex solid and the liver.
#include "hybrid_builder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <numeric>
#include <random>
#include <set>

#include "atomic_file.h"
#include "cube_generator.h"
#include "mesh_checks.h"
#include "mesh_error.h"
#include "mesh_io.h"
#include "mesh_recipe.h"
#include "mirror_symmetric_volume.h"
#include "point_location.h"
#include "scenario.h"
#include "test_support.h"
#include "vertex_selection.h"
#include "winding_number_tree.h"

namespace tb {
namespace {

using testing::scenario_mesh;

/// The mesh recipe of a committed scenario file.
MeshRecipe scenario_recipe(const std::string& name) {
  return load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/" + name + ".json").scenarios.at(0).mesh;
}

TEST(CubeSurface, PaperCounts) {
  SurfaceMesh s = make_cube_surface({});
  EXPECT_EQ(s.V.rows(), 682);
  EXPECT_EQ(s.F.rows(), 1360);
  EXPECT_EQ(check_and_orient_surface("cube", s).flipped_triangles, 0);  // generated outward
  EXPECT_NEAR(enclosed_volume(s), 1e-3, 1e-15);
  // Top centre is a vertex; the mesh is mirror-symmetric about x = 0 and y = 0.
  EXPECT_EQ(((s.V.rowwise() - Eigen::RowVector3d(0, 0, 0.1)).rowwise().norm().array() < 1e-15).count(), 1);
  for (int axis : {0, 1}) {
    Points mirrored = s.V;
    mirrored.col(axis) *= -1;
    for (Eigen::Index v = 0; v < s.V.rows(); ++v)
      EXPECT_LT((s.V.rowwise() - mirrored.row(v)).rowwise().norm().minCoeff(), 1e-15);
    // Triangles map to triangles under the mirror.
    std::set<std::array<int, 3>> tris;
    for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
      std::array<int, 3> k{s.F(t, 0), s.F(t, 1), s.F(t, 2)};
      std::sort(k.begin(), k.end());
      tris.insert(k);
    }
    auto image = [&](int v) {
      Eigen::Index i;
      (s.V.rowwise() - mirrored.row(v)).rowwise().norm().minCoeff(&i);
      return static_cast<int>(i);
    };
    for (Eigen::Index t = 0; t < s.F.rows(); ++t) {
      std::array<int, 3> k{image(s.F(t, 0)), image(s.F(t, 1)), image(s.F(t, 2))};
      std::sort(k.begin(), k.end());
      EXPECT_TRUE(tris.count(k)) << "triangle " << t << " has no mirror image about axis " << axis;
    }
  }
}

TEST(HybridBuilder, CubeMatchesThePaperScale) {
  const HybridMesh& h = scenario_mesh("cube-pull");
  // Paper: fine 3028 nodes / 17044 tets; coarse 153 / 411.
  EXPECT_GT(h.fine_volume.V.rows(), 2500);
  EXPECT_LT(h.fine_volume.V.rows(), 3600);
  EXPECT_GT(h.fine_volume.T.rows(), 14000);
  EXPECT_LT(h.fine_volume.T.rows(), 20000);
  EXPECT_GT(h.coarse_volume.V.rows(), 120);
  EXPECT_LT(h.coarse_volume.V.rows(), 180);
  EXPECT_GT(h.coarse_volume.T.rows(), 300);
  EXPECT_LT(h.coarse_volume.T.rows(), 650);
  EXPECT_NEAR(total_volume(h.fine_volume), 1e-3, 1e-5);
  EXPECT_NEAR(total_volume(h.coarse_volume), 1e-3, 1e-5);
  // Every surface vertex is a fine-volume node, in order.
  for (size_t v = 0; v < h.fine_surface_to_volume.size(); ++v)
    EXPECT_EQ(h.fine_volume.V.row(h.fine_surface_to_volume[v]), h.fine_surface.V.row(static_cast<Eigen::Index>(v)));
  // Control points are surface vertices and coincide with a coarse node.
  int bottom = 0;
  for (const auto& cp : h.control_points) {
    const Eigen::RowVector3d p = h.fine_surface.V.row(cp.surface_vertex);
    Eigen::RowVector3d q = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 4; ++k) q += cp.coarse.weights(k) * h.coarse_volume.V.row(h.coarse_volume.T(cp.coarse.tet, k));
    EXPECT_LT((p - q).norm(), 1e-15);
    EXPECT_EQ(cp.coarse.weights.maxCoeff(), 1.0);
    bottom += p.z() == 0.0;
  }
  EXPECT_GT(bottom, 10) << "the clamped bottom face needs control points";
}

TEST(SymmetricCubeVolume, EveryTetHasItsMirrorImagesAndTheSurfaceComesFirst) {
  const HybridMesh& h = scenario_mesh("cube-pull", true, true);
  const TetMesh& m = h.fine_volume;
  // Tets as sets of lattice-rounded vertex positions, so a mirror image is found by value.
  auto key = [&](int v, int sx, int sy) {
    return std::array<long long, 3>{std::llround(sx * m.V(v, 0) * 1e12), std::llround(sy * m.V(v, 1) * 1e12),
                                    std::llround(m.V(v, 2) * 1e12)};
  };
  auto tet_key = [&](Eigen::Index t, int sx, int sy) {
    std::set<std::array<long long, 3>> k;
    for (int j = 0; j < 4; ++j) k.insert(key(m.T(t, j), sx, sy));
    return k;
  };
  std::set<std::set<std::array<long long, 3>>> tets;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) tets.insert(tet_key(t, 1, 1));
  ASSERT_EQ(tets.size(), static_cast<size_t>(m.T.rows()));
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    ASSERT_TRUE(tets.count(tet_key(t, -1, 1))) << "tet " << t << " has no mirror image about x = 0";
    ASSERT_TRUE(tets.count(tet_key(t, 1, -1))) << "tet " << t << " has no mirror image about y = 0";
  }
  for (Eigen::Index v = 0; v < h.fine_surface.V.rows(); ++v) EXPECT_EQ(m.V.row(v), h.fine_surface.V.row(v));
  EXPECT_NEAR(total_volume(m), 1e-3, 1e-15);
  EXPECT_GT(min_dihedral_angle_deg(m), 5.0);
}

TEST(SymmetricCubeVolume, OddDivisionsAreAnError) {
  const CubeSpec spec{0.1, 0.1, 9, 10, 12};
  try {
    tetrahedralize_symmetric_cube(make_cube_surface(spec), spec, TetgenOptions{}, "cube");
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("even nx and ny"), std::string::npos) << e.what();
  }
}

TEST(HybridBuilder, NonConvexSolidHasNoCoarseTetOutside) {
  // An L-shaped prism (the notch x > 1, y > 1 missing), written by hand.
  const char* obj =
      "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
      "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\n"
      "f 1 3 2\nf 1 4 3\nf 1 6 4\nf 4 6 5\n"        // bottom (facing -z)
      "f 7 8 9\nf 7 9 10\nf 7 10 12\nf 10 11 12\n"  // top
      "f 1 2 8\nf 1 8 7\nf 2 3 9\nf 2 9 8\nf 3 4 10\nf 3 10 9\n"
      "f 4 5 11\nf 4 11 10\nf 5 6 12\nf 5 12 11\nf 6 1 7\nf 6 7 12\n";
  const testing::TempFolder dir("L");
  const std::string path = dir / "L.obj";
  write_file_atomically(path, obj);
  SurfaceMesh L = read_surface(path, 0.05);
  check_and_orient_surface(path, L);
  HybridBuildOptions o;
  o.target_coarse_nodes = 12;  // the 12 corners: their Delaunay mesh fills the notch
  const HybridMesh h = build_hybrid_from_surface(L, o, "L");
  ASSERT_GT(h.coarse_volume.T.rows(), 0);
  for (Eigen::Index t = 0; t < h.coarse_volume.T.rows(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += h.coarse_volume.V.row(h.coarse_volume.T(t, k)).transpose() / 4;
    EXPECT_GT(winding_number(L, c), 0.5) << "coarse tet " << t << " lies outside the L";
  }
  EXPECT_NEAR(total_volume(h.coarse_volume), enclosed_volume(L), 0.02 * enclosed_volume(L));
}

TEST(HybridBuilder, LiverWithGivenCoarseMesh) {
  MeshRecipe r = scenario_recipe("liver-pull");
  r.build_fine_volume = false;
  MeshReport report;
  // Self-intersections are an error unless repair is asked for.
  r.repair_self_intersections = false;
  EXPECT_THROW(build_mesh(r, report), MeshError);
  r.repair_self_intersections = true;
  const HybridMesh h = build_mesh(r, report);
  EXPECT_EQ(report.self_intersections_found, 7);
  EXPECT_EQ(h.coarse_volume.V.rows(), 181);
  EXPECT_EQ(h.coarse_volume.T.rows(), 596);
  const double d = max_embedding_distance(h);
  EXPECT_TRUE(std::isfinite(d));
  EXPECT_LT(d, 0.005);  // every fine vertex within 5 mm of its coarse tet
  EXPECT_GT(h.control_points.size(), 50u);
  for (const auto& cp : h.control_points) {
    EXPECT_GE(cp.coarse.tet, 0);
    EXPECT_NEAR(cp.coarse.weights.sum(), 1.0, 1e-12);
  }
}

TEST(HybridBuilder, SameInputSameFilesByteForByte) {
  const testing::TempFolder root("det");
  for (const char* run : {"a", "b"}) {
    MeshReport report;
    const HybridMesh h = build_mesh(scenario_recipe("cube-pull"), report);
    write_mesh_folder(root / run, h, report);
  }
  for (const std::string f : {"fine_volume.vtu", "coarse_volume.vtu", "control_points.csv", "summary.json"})
    EXPECT_EQ(read_file(root / ("a/" + f)), read_file(root / ("b/" + f))) << f;
}

TEST(TetgenDriver, DelaunayOfCoplanarHullPointsDropsSlivers) {
  // The 8 corners of a unit cube and its 6 face centres: coplanar groups of hull
  // points, for which a Delaunay mesh may contain zero-volume tets.
  Points P(14, 3);
  int i = 0;
  for (int x : {0, 1})
    for (int y : {0, 1})
      for (int z : {0, 1}) P.row(i++) << x, y, z;
  P.bottomRows(6) << 0.5, 0.5, 0, 0.5, 0.5, 1, 0.5, 0, 0.5, 0.5, 1, 0.5, 0, 0.5, 0.5, 1, 0.5, 0.5;
  const TetMesh m = tetrahedralize_points(P, "points");
  EXPECT_NEAR(total_volume(m), 1.0, 1e-12);
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    EXPECT_GT(tet_volume(m.V.row(m.T(t, 0)), m.V.row(m.T(t, 1)), m.V.row(m.T(t, 2)), m.V.row(m.T(t, 3))), 1e-12);
}

TEST(VertexSelection, GridSearchSelectsWhatComparingWithEverySelectedVertexDoes) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> U(-1, 1);
  Points V(3000, 3);
  for (Eigen::Index i = 0; i < V.size(); ++i) V.data()[i] = U(rng);
  V.row(7) = V.row(3);  // a duplicate
  std::vector<int> priority(3000);
  for (size_t i = 0; i < priority.size(); ++i) priority[i] = static_cast<int>(i % 3);
  for (double spacing : {1e-3, 0.05, 0.2, 0.7, 5.0}) {
    // The definition: visit by (priority, index), keep v unless a kept vertex is closer than spacing.
    std::vector<int> order(3000), expected;
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return priority[a] < priority[b]; });
    for (int v : order) {
      bool covered = false;
      for (int w : expected) covered = covered || (V.row(v) - V.row(w)).squaredNorm() < spacing * spacing;
      if (!covered) expected.push_back(v);
    }
    EXPECT_EQ(select_covering_vertices(V, priority, spacing), expected) << "spacing " << spacing;
  }
}

TEST(TetLocator, FindsWhatLocatePointFinds) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-0.06, 0.06), Z(-0.01, 0.11);
  for (const TetMesh* m : {&h.coarse_volume, &h.fine_volume}) {
    const TetLocator locator(*m);
    std::vector<Eigen::Vector3d> points;
    for (int trial = 0; trial < 400; ++trial) points.emplace_back(U(rng), U(rng), Z(rng));
    for (Eigen::Index v = 0; v < m->V.rows(); v += 7) points.push_back(m->V.row(v).transpose());  // on shared faces
    for (const Eigen::Vector3d& p : points) {
      const TetEmbedding a = locate_point(*m, p), b = locator.locate(p);
      ASSERT_EQ(a.tet, b.tet) << p.transpose();
      EXPECT_EQ(a.weights, b.weights);
      EXPECT_EQ(a.distance, b.distance);
    }
  }
}

TEST(WindingNumberTree, ClassifiesLikeTheExactSum) {
  // The L-shaped solid (non-convex) and the paper's cube, at random points in and
  // around them: the tree's far field differs from the exact sum by little, and
  // never on the wrong side of 1/2 away from the surface.
  const SurfaceMesh& cube = testing::scenario_mesh("cube-pull", false).fine_surface;
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> U(-0.08, 0.08), Z(-0.03, 0.13);
  const WindingNumberTree tree(cube);
  double worst = 0;
  int near_surface = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d p(U(rng), U(rng), Z(rng));
    const double exact = winding_number(cube, p), fast = tree(p);
    worst = std::max(worst, std::abs(exact - fast));
    if (std::abs(exact - 0.5) < 0.45) {
      ++near_surface;  // within a triangle or so of the surface
      continue;
    }
    EXPECT_EQ(exact > 0.5, fast > 0.5) << p.transpose();
  }
  EXPECT_LT(worst, 0.05);  // a tenth of the margin to 1/2 (measured 0.013)
  EXPECT_LT(near_surface, 30);
  RecordProperty("max_abs_difference", std::to_string(worst));
}

TEST(TetgenDriver, MissingProgramIsAClearError) {
  setenv("TISSUEBENCH_TETGEN", "/nonexistent/tetgen", 1);
  try {
    tetrahedralize_surface(make_cube_surface({}), {}, "cube");
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no such program"), std::string::npos) << e.what();
  }
  unsetenv("TISSUEBENCH_TETGEN");
}

// A volume TetGen returns with a flat tet (here a stand-in program that writes one)
// is refused in one line that names the surface the user gave, not TetGen's
// temporary output (gone by the time the message is read).
TEST(TetgenDriver, AFlatTetInTetgensVolumeNamesTheInputSurface) {
  const testing::TempFolder dir("fake-tetgen");
  const std::string fake = dir / "tetgen";
  write_file_atomically(fake,
                        "#!/bin/sh\n"
                        "stem=\"${2%.smesh}\"\n"
                        "printf '4 3 0 0\\n0 0 0 0\\n1 1 0 0\\n2 0 1 0\\n3 1 1 0\\n' > \"$stem.1.node\"\n"
                        "printf '1 4 0\\n0 0 1 2 3\\n' > \"$stem.1.ele\"\n");
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  setenv("TISSUEBENCH_TETGEN", fake.c_str(), 1);
  try {
    tetrahedralize_surface(make_cube_surface({}), {}, "organ.obj");
    ADD_FAILURE() << "a flat tet accepted";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), "organ.obj: tetgen -pYzQq1.414 gave an unusable volume: 1 tetrahedra with zero volume");
  }
  unsetenv("TISSUEBENCH_TETGEN");
}

}  // namespace
}  // namespace tb
