// Refinement levels of the reference-convergence study: the 1-to-4
// split keeps the surface's vertices first and bitwise, and the mesh recipe's
// refine_levels key scales the volume bound.
#include "surface_subdivision.h"

#include <gtest/gtest.h>

#include <set>

#include "cube_generator.h"
#include "mesh_checks.h"
#include "mesh_recipe.h"
#include "strict_json.h"

namespace tb {
namespace {

int edge_count(const SurfaceMesh& s) {
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index t = 0; t < s.F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = s.F(t, k), b = s.F(t, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  return static_cast<int>(edges.size());
}

TEST(SurfaceSubdivision, KeepsTheVerticesFirstAndBitwiseAndSplitsEachTriangleInFour) {
  const SurfaceMesh cube = make_cube_surface({0.1, 0.1, 10, 10, 12});
  for (int levels = 1; levels <= 2; ++levels) {
    SurfaceMesh s = subdivide_surface(cube, levels);
    ASSERT_GE(s.V.rows(), cube.V.rows());
    EXPECT_TRUE((s.V.topRows(cube.V.rows()).array() == cube.V.array()).all()) << "original vertices moved";
    EXPECT_EQ(s.F.rows(), cube.F.rows() << (2 * levels));
    // Closed and consistently outward (nothing to flip), same enclosed volume.
    EXPECT_EQ(check_and_orient_surface("subdivided", s).flipped_triangles, 0);
    EXPECT_NEAR(enclosed_volume(s), enclosed_volume(cube), 1e-15);
  }
  // One level adds one vertex per edge.
  const SurfaceMesh once = subdivide_surface(cube, 1);
  EXPECT_EQ(once.V.rows(), cube.V.rows() + edge_count(cube));
  // The top centre stays a vertex (the load point) and the new vertices lie on
  // the finer grid: x = 0.1 (i / 20 - 1/2) to round-off.
  for (Eigen::Index v = cube.V.rows(); v < once.V.rows(); ++v)
    for (int c = 0; c < 2; ++c) {
      const double i = (once.V(v, c) / 0.1 + 0.5) * 20;
      EXPECT_NEAR(i, std::round(i), 1e-9);
    }
  EXPECT_EQ(subdivide_surface(cube, 0).V, cube.V);
  EXPECT_THROW(subdivide_surface(cube, -1), std::invalid_argument);
}

MeshRecipe recipe(const nlohmann::json& j) { return parse_mesh_recipe(j, ".", "test.json: mesh"); }

TEST(SurfaceSubdivision, RecipeRefineLevelsScalesTheVolumeBoundAndKeepsTheUnrefinedHash) {
  const nlohmann::json base = {
      {"type", "cube"}, {"nx", 2}, {"ny", 2}, {"nz", 2}, {"fine_tetgen", {{"max_volume", 1e-4}}}};
  nlohmann::json refined = base;
  refined["refine_levels"] = 1;
  nlohmann::json zero = base;
  zero["refine_levels"] = 0;
  EXPECT_EQ(mesh_content_hash(recipe(zero)), mesh_content_hash(recipe(base)));  // old cache entries stay valid
  EXPECT_NE(mesh_content_hash(recipe(refined)), mesh_content_hash(recipe(base)));
  MeshReport report;
  const HybridMesh coarse = build_mesh(recipe(base), report);
  const HybridMesh fine = build_mesh(recipe(refined), report);
  EXPECT_TRUE(
      (fine.fine_surface.V.topRows(coarse.fine_surface.V.rows()).array() == coarse.fine_surface.V.array()).all());
  EXPECT_EQ(fine.fine_surface.F.rows(), 4 * coarse.fine_surface.F.rows());
  // The surface's vertices are the volume's first nodes, and every tet obeys the
  // scaled bound 1e-4 / 8.
  EXPECT_TRUE((fine.fine_volume.V.topRows(fine.fine_surface.V.rows()).array() == fine.fine_surface.V.array()).all());
  for (Eigen::Index t = 0; t < fine.fine_volume.T.rows(); ++t) {
    const auto& T = fine.fine_volume.T;
    const auto& V = fine.fine_volume.V;
    EXPECT_LE(tet_volume(V.row(T(t, 0)), V.row(T(t, 1)), V.row(T(t, 2)), V.row(T(t, 3))), 1e-4 / 8 * (1 + 1e-9));
  }
  EXPECT_GT(fine.fine_volume.T.rows(), 4 * coarse.fine_volume.T.rows());
}

TEST(SurfaceSubdivision, RecipeRefineLevelsOutOfRangeIsAnError) {
  for (const nlohmann::json& bad : {nlohmann::json(-1), nlohmann::json(7), nlohmann::json(1.5), nlohmann::json("2")}) {
    nlohmann::json j = {{"type", "cube"}, {"refine_levels", bad}};
    try {
      recipe(j);
      ADD_FAILURE() << "refine_levels " << bad.dump() << " accepted";
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("refine_levels"), std::string::npos) << e.what();
    }
  }
  try {
    recipe({{"type", "cube"}, {"refine_levels", 1}, {"symmetric_fine_volume", true}});
    ADD_FAILURE() << "refine_levels with symmetric_fine_volume accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("symmetric_fine_volume"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tb
