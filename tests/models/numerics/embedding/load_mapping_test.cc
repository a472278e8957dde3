// Loads mapped to nodes (load_mapping.h): the surface load of eq. (31) with
// load_spread surface_triangle (the nearest surface point's triangle and
// barycentric weights), a body force's nodal masses, and weights combined.
#include "load_mapping.h"

#include <gtest/gtest.h>

namespace tb {
namespace {

SurfaceMesh two_triangles() {
  SurfaceMesh s;
  s.V.resize(4, 3);
  s.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  s.F.resize(2, 3);
  s.F << 0, 1, 2, 1, 3, 2;
  return s;
}

TEST(NearestSurfacePoint, WeightsAreTheBarycentricCoordinatesOfTheProjectedPoint) {
  const SurfaceMesh s = two_triangles();
  const NodalWeights l = nearest_surface_point(s, {0.2, 0.3, -0.002});  // 2 mm under triangle 0
  EXPECT_EQ(l.nodes.head<3>(), Eigen::Vector3i(0, 1, 2));
  EXPECT_NEAR(l.weights(0), 0.5, 1e-12);
  EXPECT_NEAR(l.weights(1), 0.2, 1e-12);
  EXPECT_NEAR(l.weights(2), 0.3, 1e-12);
  EXPECT_EQ(l.weights(3), 0.0);
  EXPECT_NEAR(l.distance, 0.002, 1e-12);
  // The weights reproduce the projected point.
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) q += l.weights(k) * s.V.row(l.nodes(k)).transpose();
  EXPECT_LT((q - Eigen::Vector3d(0.2, 0.3, 0)).norm(), 1e-12);
}

TEST(NearestSurfacePoint, APointAtAVertexPutsTheWholeForceThere) {
  const NodalWeights l = nearest_surface_point(two_triangles(), {1, 1, 0.01});
  double at_vertex_3 = 0;
  for (int k = 0; k < 4; ++k) at_vertex_3 += l.nodes(k) == 3 ? l.weights(k) : 0;
  EXPECT_DOUBLE_EQ(at_vertex_3, 1.0);
  EXPECT_NEAR(l.distance, 0.01, 1e-12);
}

TEST(NearestSurfacePoint, OutsideEveryTriangleTheNearestEdgePointIsUsed) {
  const NodalWeights l = nearest_surface_point(two_triangles(), {0.5, -0.5, 0});  // beyond edge 0-1
  EXPECT_NEAR(l.distance, 0.5, 1e-12);
  EXPECT_NEAR(l.weights.sum(), 1.0, 1e-12);
  EXPECT_GE(l.weights.minCoeff(), 0.0);
}

TEST(NearestSurfacePoint, ADegenerateTriangleGetsItsNearestCornerAndNoNaN) {
  SurfaceMesh s;
  s.V.resize(3, 3);
  s.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // collinear: zero area
  s.F.resize(1, 3);
  s.F << 0, 1, 2;
  const NodalWeights l = nearest_surface_point(s, {1.9, 0.1, 0});
  EXPECT_TRUE(l.weights.allFinite());
  EXPECT_NEAR(l.weights.sum(), 1.0, 1e-12);
  EXPECT_THROW(nearest_surface_point(SurfaceMesh{}, {0, 0, 0}), std::invalid_argument);
}

TEST(NodalMasses, AreAQuarterOfEachTetsMassAtEachOfItsNodes) {
  TetMesh m;  // two tets sharing a face: volumes 1/6 and 1/3
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -2;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 3, 0, 2, 1, 4;
  const NodalWeights w = nodal_masses(m, 600.0);
  ASSERT_EQ(w.size(), 5);
  EXPECT_NEAR(w.weights(3), 600.0 / 6 / 4, 1e-12);      // only in the first tet
  EXPECT_NEAR(w.weights(4), 600.0 / 3 / 4, 1e-12);      // only in the second
  EXPECT_NEAR(w.weights(0), 600.0 * 0.5 / 4, 1e-12);    // in both
  EXPECT_NEAR(w.weights.sum(), 600.0 * 0.5, 1e-12);     // the whole mass
  EXPECT_EQ(w.nodes, Eigen::VectorXi::LinSpaced(5, 0, 4));
}

TEST(CombineNodalWeights, SumsScaledPartsOncePerNodeInOrderOfFirstAppearance) {
  NodalWeights a, b;
  a.nodes = Eigen::Vector3i(4, 2, 4);
  a.weights = Eigen::Vector3d(0.5, 0.25, 0.25);
  a.distance = 0.1;
  b.nodes = Eigen::Vector2i(2, 7);
  b.weights = Eigen::Vector2d(1, 1);
  const NodalWeights c = combine({a, b}, {2.0, -1.0});
  EXPECT_EQ(c.nodes, Eigen::Vector3i(4, 2, 7));
  EXPECT_EQ(c.weights, Eigen::Vector3d(1.5, -0.5, -1.0));
  EXPECT_EQ(c.distance, 0.1);
  EXPECT_THROW(combine({a}, {1.0, 2.0}), std::invalid_argument);
}

}  // namespace
}  // namespace tb
