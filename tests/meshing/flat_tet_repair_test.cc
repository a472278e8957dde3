// The repair of flat tets spanned by an interior point almost on another node
// (meshing/flat_tet_repair.h): what TetGen -Y leaves on the liver refined to
// 140 000 surface vertices, rebuilt here on a single tet split at such a point.
#include "flat_tet_repair.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mesh_checks.h"
#include "mesh_error.h"

namespace tb {
namespace {

/// The unit tet (nodes 0-3, the "surface") split into four at an interior node 4
/// placed `offset` from node 0 along each axis: the three tets holding nodes 0
/// and 4 are flat at 1e-14, needles at 1e-3, well shaped at 0.25.
TetMesh unit_tet_split_near_a_corner(double offset) {
  TetMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, offset, offset, offset;
  m.T.resize(4, 4);
  m.T << 4, 1, 2, 3,  // opposite node 0: the one that stays
      0, 4, 2, 3,     //
      0, 1, 4, 3,     //
      0, 1, 2, 4;
  orient_and_check_tets("split", m, FlatTets::Keep);
  return m;
}

class FlatTetRepairNearACorner : public ::testing::TestWithParam<double> {};

TEST_P(FlatTetRepairNearACorner, TheInteriorPointIsMergedIntoTheCornerAndItsTetsGo) {
  TetMesh m = unit_tet_split_near_a_corner(GetParam());
  const double volume_before = total_volume(m);
  EXPECT_EQ(merge_near_coincident_interior_points(m, 4).merged, 1);
  ASSERT_EQ(m.V.rows(), 4);
  ASSERT_EQ(m.T.rows(), 1);
  EXPECT_EQ(m.V.row(0).norm(), 0.0);  // the corner kept its place; the interior point went
  EXPECT_NEAR(total_volume(m), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(volume_before, 1.0 / 6.0, 1e-8);
  EXPECT_EQ(orient_and_check_tets("split", m, FlatTets::Error), 0);  // positive, none flat
}
// 1e-14: three flat tets (volume 2e-15, the bound 5e-14); 1e-3: three needles,
// not flat (1.7e-4), their shortest edge 1/800 of their longest.
INSTANTIATE_TEST_SUITE_P(FlatOrNeedle, FlatTetRepairNearACorner, ::testing::Values(1e-14, 1e-3));

TEST(FlatTetRepair, AWellPlacedInteriorPointIsLeftAlone) {
  TetMesh m = unit_tet_split_near_a_corner(0.25);  // the centroid: no flat tet
  EXPECT_EQ(merge_near_coincident_interior_points(m, 4).merged, 0);
  EXPECT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.T.rows(), 4);
}

TEST(FlatTetRepair, AFlatTetOfSurfaceNodesIsLeftForTheCheckToReport) {
  // Four coplanar surface nodes (index < fixed_nodes): nothing may move.
  TetMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1e-9, 1e-9, 0;
  m.T.resize(1, 4);
  m.T << 0, 1, 2, 3;
  EXPECT_EQ(merge_near_coincident_interior_points(m, 4).merged, 0);
  EXPECT_EQ(m.T.rows(), 1);
  EXPECT_THROW(orient_and_check_tets("flat", m, FlatTets::Error), MeshError);
}

/// Base height of the thin tet in the refused-merge test, and what the merge would
/// make of it.
class FlatTetRepairRefused : public ::testing::TestWithParam<double> {};

TEST_P(FlatTetRepairRefused, AMergeThatWouldInvertOrFlattenATetIsNotMadeAndItsFlatTetIsLeftForTheCheck) {
  // Node 4 sits 2e-12 above corner 0, spanning a flat tet with two nodes 1 mm away;
  // a thin tet (5, 6, 7, 4), not flat (its base is 2 m^2), has its base at height
  // GetParam(): moving node 4 onto node 0 would turn it inside out (base above node 0)
  // or leave it positive but flat (base 3e-13 below: volume 2e-13, the bound 2.7e-13).
  const double base = GetParam();
  TetMesh m;
  m.V.resize(8, 3);
  m.V << 0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1,  //
      0, 0, 2e-12,                                  // interior, near node 0
      -1, -1, base, 1, -1, base, 0, 1, base;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 4,  // flat: spans nodes 0 and 4
      5, 6, 7, 4;     // thin, positive and not flat while node 4 is where it is
  orient_and_check_tets("fold.ele", m, FlatTets::Keep);
  const TetMesh before = m;
  const InteriorPointMerges done = merge_near_coincident_interior_points(m, 4);
  EXPECT_EQ(done.merged, 0);
  EXPECT_EQ(done.refused, 1);
  EXPECT_EQ(done.flat_tets_collapsed, 0);  // onto node 1, 2 or the thin tet's: inverted or flat too
  EXPECT_EQ(m.V, before.V);
  EXPECT_EQ(m.T, before.T);
  try {
    orient_and_check_tets("fold.ele", m, FlatTets::Error);
    ADD_FAILURE() << "the flat tet left went unreported";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), "fold.ele: 1 tetrahedra with zero volume");
  }
}
INSTANTIATE_TEST_SUITE_P(InvertOrFlatten, FlatTetRepairRefused, ::testing::Values(1e-12, -3e-13));

/// Replaces tet t of m by the four tets joining `p` (a new node, inside t) to t's faces.
void split_tet_at(TetMesh& m, Eigen::Index t, const Eigen::RowVector3d& p) {
  const int n = static_cast<int>(m.V.rows());
  m.V.conservativeResize(n + 1, 3);
  m.V.row(n) = p;
  const Eigen::Vector4i old = m.T.row(t).transpose();
  const Eigen::Index rows = m.T.rows();
  m.T.conservativeResize(rows + 3, 4);
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector4i tet = old;
    tet(k) = n;
    m.T.row(k == 0 ? t : rows + k - 1) = tet.transpose();
  }
}

TEST(FlatTetRepair, AChainOfNearPointsEndsOnTheCornerAndTheNodesAfterThemMoveUpInOrder) {
  // A valid mesh: the unit tet split at a well-placed node 4, its tet at corner 0
  // split at node 5 (1.8e-4 from the corner), the first of those split at node 6
  // (1.6e-3 from node 5). With the tets in reverse order node 6 merges into node 5
  // first, then node 5, holding node 6's tets by then, into corner 0: that must give
  // back the unit tet split at node 4 alone, node 4 keeping its place.
  TetMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.T.resize(1, 4);
  m.T << 0, 1, 2, 3;
  const Eigen::RowVector3d centre(0.25, 0.25, 0.25);
  split_tet_at(m, 0, centre);  // tet 3 is now (0, 1, 2, 4)
  ASSERT_EQ(m.T.row(3), Eigen::RowVector4i(0, 1, 2, 4));
  const Eigen::RowVector3d near_corner = 1e-4 * (m.V.row(1) + m.V.row(2) + centre);
  split_tet_at(m, 3, near_corner);  // tet 3 is now (5, 1, 2, 4)
  const Eigen::RowVector3d near_it = (1 - 3e-3) * near_corner + 1e-3 * (m.V.row(1) + m.V.row(2) + centre);
  split_tet_at(m, 3, near_it);
  orient_and_check_tets("chain", m, FlatTets::Keep);
  ASSERT_EQ(m.T.rows(), 10);
  m.T = m.T.colwise().reverse().eval();

  const InteriorPointMerges done = merge_near_coincident_interior_points(m, 4);
  EXPECT_EQ(done.merged, 2);
  EXPECT_EQ(done.refused, 0);
  ASSERT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.V.row(4), centre);
  ASSERT_EQ(m.T.rows(), 4);
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    std::array<int, 4> n{m.T(t, 0), m.T(t, 1), m.T(t, 2), m.T(t, 3)};
    std::sort(n.begin(), n.end());
    EXPECT_EQ(n[3], 4) << "tet " << t << " should hold the centre";  // every tet joins it to a face
    EXPECT_GE(n[0], 0);
  }
  EXPECT_EQ(orient_and_check_tets("chain", m, FlatTets::Error), 0);  // positive, none flat
  EXPECT_NEAR(total_volume(m), 1.0 / 6.0, 1e-15);
}

TEST(FlatTetRepair, AFlatTetWithoutANearCoincidentPairLosesItsInteriorPointToTheBestNeighbour) {
  // Two tets on the face (1, 2, 3), the upper one split at that face's centroid
  // (node 5, an interior point): one of its four tets is flat, its shortest edge
  // 0.58 of its longest, so the first pass has nothing to merge. The point's
  // collapse into a node of its link gives back the two tets.
  TetMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.6, 0.6, 0.6;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 3, 4, 1, 2, 3;
  orient_and_check_tets("bipyramid", m, FlatTets::Keep);
  const double volume = total_volume(m);
  split_tet_at(m, 1, (m.V.row(1) + m.V.row(2) + m.V.row(3)) / 3);
  ASSERT_EQ(m.T.rows(), 5);
  TetMesh checked = m;
  ASSERT_THROW(orient_and_check_tets("bipyramid", checked, FlatTets::Error), MeshError);

  const InteriorPointMerges done = merge_near_coincident_interior_points(m, 5);
  EXPECT_EQ(done.merged, 0);
  EXPECT_EQ(done.refused, 0);
  EXPECT_EQ(done.flat_tets_collapsed, 1);
  EXPECT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.T.rows(), 2);
  EXPECT_EQ(orient_and_check_tets("bipyramid", m, FlatTets::Error), 0);  // positive, none flat
  EXPECT_NEAR(total_volume(m), volume, 1e-15);
}

/// The smallest volume over longest edge cubed among m's tets (a shape measure:
/// 0.118 for the regular tet).
double smallest_shape(const TetMesh& m) {
  double smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    Eigen::Matrix<double, 4, 3> p;
    for (int k = 0; k < 4; ++k) p.row(k) = m.V.row(m.T(t, k));
    double longest = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, (p.row(i) - p.row(j)).norm());
    smallest = std::min(smallest, tet_volume(p.row(0), p.row(1), p.row(2), p.row(3)) / std::pow(longest, 3));
  }
  return smallest;
}

TEST(FlatTetRepair, TheFlatTetsPointGoesToTheNeighbourLeavingTheBestShapedTetsNotTheFirstValidOne) {
  // Above the unit tet's face (1, 2, 3), two apexes 4 and 5; the region between is
  // coned from node 6, an interior point at that face's centroid, which spans a flat
  // tet with the face. Every node of 6's link is a valid target, but they leave
  // different tets: into node 1 (the first in order) or node 5, a tet of shape
  // 0.0029; into node 2, 3 or 4, none worse than 0.0206.
  TetMesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.9, 0.3, 0.3, 0.2, 0.4, 0.9, 1.0 / 3, 1.0 / 3, 1.0 / 3;
  m.T.resize(7, 4);
  m.T << 0, 1, 2, 3,  //
      1, 6, 2, 3,     // flat, oriented as its neighbours above
      6, 4, 1, 2,     //
      6, 4, 3, 1,     //
      5, 6, 3, 2,     //
      6, 5, 4, 2,     //
      5, 6, 4, 3;
  TetMesh checked = m;
  ASSERT_THROW(orient_and_check_tets("cap", checked, FlatTets::Error), MeshError);
  orient_and_check_tets("cap", m, FlatTets::Keep);
  const double volume = total_volume(m);

  const InteriorPointMerges done = merge_near_coincident_interior_points(m, 6);
  EXPECT_EQ(done.merged, 0);
  EXPECT_EQ(done.flat_tets_collapsed, 1);
  EXPECT_EQ(m.V.rows(), 6);
  EXPECT_EQ(orient_and_check_tets("cap", m, FlatTets::Error), 0);
  EXPECT_NEAR(total_volume(m), volume, 1e-15);
  EXPECT_GT(smallest_shape(m), 0.02);
}

}  // namespace
}  // namespace tb
