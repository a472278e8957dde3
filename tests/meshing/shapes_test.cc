// The generated shapes: closed, manifold, outward, free of
// self-intersections, of the right volume, resting on z = 0, and meshable by TetGen.
#include "shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "mesh_checks.h"
#include "self_intersections.h"
#include "tetgen_driver.h"

namespace tb {
namespace {

/// The two resolutions the shapes experiment uses (experiments/shapes.json).
constexpr int kCoarse = 15, kFine = 30;

double relative_volume_error(const std::string& name, int resolution) {
  const SurfaceMesh s = make_shape_surface({name, resolution});
  return (enclosed_volume(s) - shape_exact_volume(name)) / shape_exact_volume(name);
}

class EveryShape : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryShape, IsAClosedManifoldOutwardSurfaceWithoutSelfIntersections) {
  for (int resolution : {kCoarse, kFine}) {
    SurfaceMesh s = make_shape_surface({GetParam(), resolution});
    const SurfaceMesh generated = s;
    // check_and_orient_surface throws on open, non-manifold, degenerate or duplicate
    // triangles; it reorients nothing on an outward surface.
    EXPECT_EQ(check_and_orient_surface(GetParam(), s).flipped_triangles, 0) << resolution;
    EXPECT_EQ(s.F, generated.F);
    EXPECT_GT(enclosed_volume(s), 0);
    EXPECT_EQ(count_self_intersections(s), 0) << resolution;
    // Euler characteristic: 2 for a sphere-like surface, 0 for the torus and the bar (genus 1).
    const long long chi = s.V.rows() - 3 * s.F.rows() / 2 + s.F.rows();
    EXPECT_EQ(chi, GetParam() == "torus" || GetParam() == "bar_with_hole" ? 0 : 2) << resolution;
    // Resting on z = 0, centred in x and y.
    EXPECT_EQ(s.V.col(2).minCoeff(), 0.0);
    for (int axis : {0, 1}) EXPECT_NEAR(s.V.col(axis).maxCoeff(), -s.V.col(axis).minCoeff(), 1e-12);
    const double diag = bounding_box_diagonal(s.V);
    EXPECT_GT(diag, 0.1);
    EXPECT_LT(diag, 0.2);
  }
}

TEST_P(EveryShape, IsDeterministic) {
  const SurfaceMesh a = make_shape_surface({GetParam(), kCoarse}), b = make_shape_surface({GetParam(), kCoarse});
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.F, b.F);
}

TEST_P(EveryShape, EnclosesTheExactVolumeToSecondOrder) {
  // Flat faces are exact; curved ones are polyhedra with vertices on the smooth
  // surface, whose volume error falls as h^2: doubling the resolution must cut it
  // by at least 3 (4 in the limit). The 5% bound at the coarse resolution is loose
  // on purpose (the torus tube and the dumbbell neck get 14 and 10 segments around).
  const double coarse = relative_volume_error(GetParam(), kCoarse), fine = relative_volume_error(GetParam(), kFine);
  std::cout << GetParam() << ": relative volume error " << coarse << " at resolution " << kCoarse << ", " << fine
            << " at " << kFine << "\n";
  if (GetParam() == "l_block") {
    EXPECT_LT(std::abs(coarse), 1e-12);
    EXPECT_LT(std::abs(fine), 1e-12);
    return;
  }
  if (GetParam() == "sphere" || GetParam() == "ellipsoid") {
    EXPECT_LT(coarse, 0) << "a polyhedron inscribed in a convex solid encloses less";
    EXPECT_LT(fine, 0);
  }
  if (GetParam() == "bar_with_hole") {
    EXPECT_GT(coarse, 0) << "a polygonal hole inscribed in the round one removes less";
    EXPECT_GT(fine, 0);
  }
  EXPECT_LT(std::abs(coarse), 0.05) << "at resolution " << kCoarse;
  EXPECT_GT(std::abs(coarse / fine), 3.0) << coarse << " then " << fine;
}

TEST_P(EveryShape, TetgenMeshesIt) {
  const SurfaceMesh s = make_shape_surface({GetParam(), kCoarse});
  const TetMesh m = tetrahedralize_surface(s, TetgenOptions{}, GetParam());
  EXPECT_GE(m.V.rows(), s.V.rows());
  EXPECT_NEAR(total_volume(m), enclosed_volume(s), 1e-9 * enclosed_volume(s));
}

INSTANTIATE_TEST_SUITE_P(Shapes, EveryShape, ::testing::ValuesIn(shape_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(Shapes, TopIsOneVertexAboveTheCentreWhereTheShapeHasAPeak) {
  for (const std::string name : {"sphere", "ellipsoid", "torus", "dumbbell"}) {
    const SurfaceMesh s = make_shape_surface({name, kCoarse});
    Eigen::Index top;
    s.V.col(2).maxCoeff(&top);
    EXPECT_NEAR(s.V(top, 0), 0, 1e-15) << name;
    EXPECT_NEAR(s.V(top, 1), 0, 1e-15) << name;
    EXPECT_EQ((s.V.col(2).array() > s.V(top, 2) - 1e-9).count(), 1) << name;
  }
}

TEST(Shapes, UnknownNameAndBadResolutionAreErrors) {
  try {
    make_shape_surface({"cylinder", 15});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown shape 'cylinder' (one of sphere, ellipsoid"), std::string::npos)
        << e.what();
  }
  for (int bad : {kMinShapeResolution - 1, kMaxShapeResolution + 1}) {
    try {
      make_shape_surface({"sphere", bad});
      FAIL();
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("resolution " + std::to_string(bad) + " outside"), std::string::npos)
          << e.what();
    }
  }
  // Every name in shape_names() has a description and a volume; others are errors.
  for (const auto& name : shape_names()) {
    EXPECT_FALSE(shape_description(name).empty());
    EXPECT_GT(shape_exact_volume(name), 0);
  }
  EXPECT_THROW(shape_exact_volume("cylinder"), std::invalid_argument);
  EXPECT_THROW(shape_description("cylinder"), std::invalid_argument);
}

TEST(Shapes, LowestResolutionStillGivesValidSurfaces) {
  for (const auto& name : shape_names()) {
    SurfaceMesh s = make_shape_surface({name, kMinShapeResolution});
    EXPECT_EQ(check_and_orient_surface(name, s).flipped_triangles, 0) << name;
    EXPECT_EQ(count_self_intersections(s), 0) << name;
  }
}

}  // namespace
}  // namespace tb
