// Coarse-mesh sliver repair: a Delaunay mesh of points on a curved
// surface has nearly flat tets; the repair removes or re-meshes them while every
// coarse node stays on a selected fine vertex.
#include "coarse_mesh.h"

#include <gtest/gtest.h>

#include <set>

#include "hybrid_builder.h"
#include "mesh_checks.h"
#include "shapes.h"

namespace tb {
namespace {

/// A square p0..p3 with p2 lifted by `lift` (a nearly flat sliver when meshed as
/// one tet), over an apex below it: the sliver has two faces on the boundary and
/// the two tets to the apex hold its other two faces.
TetMesh sliver_on_a_pyramid(double lift) {
  TetMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, lift, 0, 1, 0, 0.5, 0.5, -1;
  m.T.resize(3, 4);
  m.T << 0, 1, 2, 3,  // the sliver: diagonal 0-2 on top, 1-3 below
      4, 0, 1, 3,     //
      4, 1, 2, 3;
  orient_and_check_tets("pyramid", m);
  return m;
}

TEST(RemoveFlatBoundarySlivers, TakesOutAFlatCapAndKeepsEveryNode) {
  TetMesh m = sliver_on_a_pyramid(1e-3);
  ASSERT_LT(tet_min_dihedral_deg(m, 0), 1.0);
  EXPECT_EQ(remove_flat_boundary_slivers(m, 5), 1);
  ASSERT_EQ(m.T.rows(), 2);
  std::set<int> used(m.T.data(), m.T.data() + m.T.size());
  EXPECT_EQ(used.size(), 5u);
  EXPECT_GE(min_dihedral_angle_deg(m), 5.0);
}

TEST(RemoveFlatBoundarySlivers, KeepsGoodTetsAndTetsWhoseRemovalWouldOrphanANode) {
  TetMesh m = sliver_on_a_pyramid(0.5);  // not flat: above the threshold
  EXPECT_EQ(remove_flat_boundary_slivers(m, 5), 0);
  EXPECT_EQ(m.T.rows(), 3);
  TetMesh alone = sliver_on_a_pyramid(1e-3);
  alone.T.conservativeResize(1, 4);  // the sliver alone: four boundary faces
  EXPECT_EQ(remove_flat_boundary_slivers(alone, 5), 0);
  EXPECT_EQ(alone.T.rows(), 1);
}

/// The ellipsoid at resolution 22 (1946 surface vertices): its Delaunay coarse
/// mesh (repair off) has a tet of 0.0036 degrees and 17 below 5 (measured when
/// the repair was written).
HybridMesh ellipsoid(double min_dihedral_deg) {
  HybridBuildOptions o;
  o.coarse_quality.min_dihedral_deg = min_dihedral_deg;
  return build_hybrid_from_surface(make_shape_surface({"ellipsoid", 22}), o, "ellipsoid");
}

TEST(CoarseMeshRepair, EllipsoidSliversAreGoneAndTheMeshStillFitsTheShape) {
  const HybridMesh before = ellipsoid(0), after = ellipsoid(CoarseMeshOptions{}.min_dihedral_deg);
  EXPECT_LT(min_dihedral_angle_deg(before.coarse_volume), 0.01) << "the sliver case no longer reproduces";
  EXPECT_EQ(count_tets_below_dihedral(after.coarse_volume, 5), 0);
  EXPECT_EQ(after.coarse_repair.slivers_left, 0);
  EXPECT_GT(after.coarse_repair.boundary_slivers_removed, 0);

  // Flat tets carry almost no volume: the repaired mesh's volume is within 1% of
  // the Delaunay mesh's, which (the hull of points on a convex surface) lies
  // within 6% below the volume the surface encloses (5.2% here at 150 nodes).
  const double enclosed = enclosed_volume(after.fine_surface);
  EXPECT_NEAR(total_volume(after.coarse_volume), total_volume(before.coarse_volume), 0.01 * enclosed);
  EXPECT_LE(total_volume(after.coarse_volume), enclosed);
  EXPECT_GT(total_volume(after.coarse_volume), 0.94 * enclosed);

  // Every coarse node is a fine-volume vertex; every control point sits on a node.
  std::set<std::array<double, 3>> fine;
  for (Eigen::Index v = 0; v < after.fine_volume.V.rows(); ++v)
    fine.insert({after.fine_volume.V(v, 0), after.fine_volume.V(v, 1), after.fine_volume.V(v, 2)});
  for (Eigen::Index n = 0; n < after.coarse_volume.V.rows(); ++n)
    EXPECT_TRUE(fine.count({after.coarse_volume.V(n, 0), after.coarse_volume.V(n, 1), after.coarse_volume.V(n, 2)}))
        << "coarse node " << n << " is not on a fine vertex";
  std::set<int> nodes_used(after.coarse_volume.T.data(), after.coarse_volume.T.data() + after.coarse_volume.T.size());
  EXPECT_EQ(nodes_used.size(), static_cast<size_t>(after.coarse_volume.V.rows())) << "a node in no tet";
  ASSERT_EQ(after.control_points.size(), before.control_points.size());  // moves keep a vertex's class
  for (const auto& cp : after.control_points) {
    ASSERT_GE(cp.coarse.tet, 0);
    EXPECT_EQ(cp.coarse.weights.maxCoeff(), 1.0);
    EXPECT_EQ(cp.coarse.weights.sum(), 1.0);
    Eigen::Index k;
    cp.coarse.weights.maxCoeff(&k);
    EXPECT_EQ(after.coarse_volume.V.row(after.coarse_volume.T(cp.coarse.tet, static_cast<int>(k))),
              after.fine_surface.V.row(cp.surface_vertex));
  }
}

TEST(CoarseMeshRepair, EveryShapeAtItsExperimentResolutionsHasNoSliver) {
  // experiments/shapes.json's resolutions.
  const std::vector<std::pair<std::string, std::vector<int>>> cases{{"sphere", {15, 30}},  {"ellipsoid", {15, 30}},
                                                                    {"torus", {20, 40}},   {"bar_with_hole", {15, 25}},
                                                                    {"l_block", {15, 30}}, {"dumbbell", {20, 40}}};
  for (const auto& [name, resolutions] : cases)
    for (int resolution : resolutions) {
      const HybridMesh h = build_hybrid_from_surface(make_shape_surface({name, resolution}), {}, name);
      EXPECT_EQ(count_tets_below_dihedral(h.coarse_volume, 5), 0) << name << " " << resolution;
    }
}

}  // namespace
}  // namespace tb
