// The fine volume stored along a Z curve (volume_ordering.h): the same tets, the
// surface's vertices first and unmoved, nodes near in space near in memory.
#include "volume_ordering.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <climits>
#include <set>
#include <stdexcept>

#include "cube_generator.h"
#include "mesh_checks.h"
#include "tetgen_driver.h"

namespace tb {
namespace {

/// Each tet as its four node positions, the tet's node order kept (orientation).
std::set<std::array<double, 12>> tets_by_position(const TetMesh& m) {
  std::set<std::array<double, 12>> out;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    std::array<double, 12> p{};
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d) p[static_cast<size_t>(3 * a + d)] = m.V(m.T(t, a), d);
    out.insert(p);
  }
  return out;
}

/// Mean over tets of the largest minus the smallest index among the tet's nodes
/// from `first` on (the spread a sweep's writes have in memory).
double mean_interior_index_span(const TetMesh& m, int first) {
  double sum = 0;
  int counted = 0;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    int lo = INT_MAX, hi = -1;
    for (int a = 0; a < 4; ++a)
      if (m.T(t, a) >= first) lo = std::min(lo, m.T(t, a)), hi = std::max(hi, m.T(t, a));
    if (hi > lo) sum += hi - lo, ++counted;
  }
  return counted ? sum / counted : 0;
}

TEST(VolumeOrdering, SameTetsSurfaceFirstAndNodesTogether) {
  const SurfaceMesh surface = make_cube_surface({});
  const TetMesh built = tetrahedralize_surface(surface, {}, "cube");
  const int fixed = static_cast<int>(surface.V.rows());
  TetMesh ordered = built;
  order_along_z_curve(ordered, fixed);

  ASSERT_EQ(ordered.V.rows(), built.V.rows());
  ASSERT_EQ(ordered.T.rows(), built.T.rows());
  EXPECT_EQ(ordered.V.topRows(fixed), built.V.topRows(fixed));  // the surface's vertices untouched
  EXPECT_EQ(tets_by_position(ordered), tets_by_position(built));  // the same tets, same orientation
  TetMesh checked = ordered;
  EXPECT_EQ(orient_and_check_tets("ordered cube", checked), 0);  // every tet still positively oriented
  EXPECT_NEAR(total_volume(ordered), total_volume(built), 1e-15);
  // Every node still used once in the node list (a permutation of the positions).
  std::set<std::array<double, 3>> a, b;
  for (Eigen::Index v = 0; v < built.V.rows(); ++v) {
    a.insert({built.V(v, 0), built.V(v, 1), built.V(v, 2)});
    b.insert({ordered.V(v, 0), ordered.V(v, 1), ordered.V(v, 2)});
  }
  EXPECT_EQ(a, b);
  // What it is for: a tet's interior nodes lie closer together in memory (TetGen's
  // insertion order scatters them over the body).
  const double before = mean_interior_index_span(built, fixed), after = mean_interior_index_span(ordered, fixed);
  EXPECT_LT(after, 0.5 * before) << before << " -> " << after;  // measured 71.7 -> 20.6
  // Consecutive tets are neighbours in space: centroid steps shorter on average.
  auto mean_step = [](const TetMesh& m) {
    double sum = 0;
    Eigen::RowVector3d previous = Eigen::RowVector3d::Zero();
    for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
      const Eigen::RowVector3d c = (m.V.row(m.T(t, 0)) + m.V.row(m.T(t, 1)) + m.V.row(m.T(t, 2)) + m.V.row(m.T(t, 3))) / 4;
      if (t > 0) sum += (c - previous).norm();
      previous = c;
    }
    return sum / static_cast<double>(m.T.rows() - 1);
  };
  EXPECT_LT(mean_step(ordered), 0.5 * mean_step(built));
}

TEST(VolumeOrdering, DeterministicAndIdempotent) {
  const SurfaceMesh surface = make_cube_surface({});
  const TetMesh built = tetrahedralize_surface(surface, {}, "cube");
  TetMesh once = built, again = built;
  order_along_z_curve(once, static_cast<int>(surface.V.rows()));
  order_along_z_curve(again, static_cast<int>(surface.V.rows()));
  EXPECT_EQ(once.V, again.V);
  EXPECT_EQ(once.T, again.T);
  TetMesh twice = once;
  order_along_z_curve(twice, static_cast<int>(surface.V.rows()));
  EXPECT_EQ(twice.V, once.V);
  EXPECT_EQ(twice.T, once.T);
}

TEST(VolumeOrdering, MortonKeyInterleavesTheBits) {
  EXPECT_EQ(morton_key(1, 0, 0), 1u);
  EXPECT_EQ(morton_key(0, 1, 0), 2u);
  EXPECT_EQ(morton_key(0, 0, 1), 4u);
  EXPECT_EQ(morton_key(3, 0, 0), 9u);  // bits 0 and 1 of x to 0 and 3
  EXPECT_EQ(morton_key(0x1fffff, 0, 0), 0x1249249249249249ULL);
  EXPECT_EQ(morton_key(0x1fffff, 0x1fffff, 0x1fffff), 0x7fffffffffffffffULL);
  EXPECT_EQ(morton_key(0x200000, 0, 0), 0u);  // only the 21 low bits count
}

TEST(VolumeOrdering, FixedCountOutsideTheMeshIsAnError) {
  TetMesh m = tetrahedralize_surface(make_cube_surface({}), {}, "cube");
  EXPECT_THROW(order_along_z_curve(m, -1), std::invalid_argument);
  EXPECT_THROW(order_along_z_curve(m, static_cast<int>(m.V.rows()) + 1), std::invalid_argument);
  TetMesh all_fixed = m;
  order_along_z_curve(all_fixed, static_cast<int>(m.V.rows()));  // only the tets move
  EXPECT_EQ(all_fixed.V, m.V);
  EXPECT_EQ(tets_by_position(all_fixed), tets_by_position(m));
}

}  // namespace
}  // namespace tb
