// The repair of flat tets spanned by an interior point almost on another node
// (meshing/flat_tet_repair.h): what TetGen -Y leaves on the liver refined to
// 140 000 surface vertices, rebuilt here on a single tet split at such a point.
#include "flat_tet_repair.h"

#include <gtest/gtest.h>

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

TEST(FlatTetRepair, AMergeThatWouldFoldATetIsNotMadeAndItsFlatTetIsLeftForTheCheck) {
  // Node 4 sits 2e-12 above corner 0, spanning a flat tet with two nodes 1 mm away;
  // a thin tet (5, 6, 7, 4), not flat (its base is 2 m^2), has its base plane
  // between them, so moving node 4 onto node 0 would turn it inside out.
  TetMesh m;
  m.V.resize(8, 3);
  m.V << 0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1,  //
      0, 0, 2e-12,                                  // interior, near node 0
      -1, -1, 1e-12, 1, -1, 1e-12, 0, 1, 1e-12;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 4,  // flat: spans nodes 0 and 4
      5, 6, 7, 4;     // thin, positive while node 4 is above its base
  orient_and_check_tets("fold.ele", m, FlatTets::Keep);
  const TetMesh before = m;
  const InteriorPointMerges done = merge_near_coincident_interior_points(m, 4);
  EXPECT_EQ(done.merged, 0);
  EXPECT_EQ(done.refused, 1);
  EXPECT_EQ(m.V, before.V);
  EXPECT_EQ(m.T, before.T);
  try {
    orient_and_check_tets("fold.ele", m, FlatTets::Error);
    ADD_FAILURE() << "the flat tet left went unreported";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), "fold.ele: 1 tetrahedra with zero volume");
  }
}

TEST(FlatTetRepair, NodesAfterAMergedOneMoveUpInOrderAndTetsFollowThem) {
  // Node 5, a second interior point, must keep its coordinates under its new index 4.
  TetMesh m = unit_tet_split_near_a_corner(1e-14);
  m.V.conservativeResize(6, 3);
  m.V.row(5) << 0.2, 0.2, 0.2;
  m.T.row(0) << 5, 1, 2, 3;  // the big tet now uses node 5; node 4 is only in flat ones
  m.T.conservativeResize(5, 4);
  m.T.row(4) << 4, 1, 2, 5;  // a sliver between the two interior points
  orient_and_check_tets("split", m, FlatTets::Keep);
  EXPECT_EQ(merge_near_coincident_interior_points(m, 4).merged, 1);
  ASSERT_EQ(m.V.rows(), 5);
  EXPECT_EQ(m.V.row(4), Eigen::RowVector3d(0.2, 0.2, 0.2));
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k) EXPECT_LT(m.T(t, k), 5);
  EXPECT_EQ(orient_and_check_tets("split", m, FlatTets::Error), 0);
}

}  // namespace
}  // namespace tb
