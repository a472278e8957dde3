// The winding number of a closed surface at many points, fast (Barill, Dickson,
// Schmidt, Levin, Jacobson 2018, "Fast winding numbers for soups and clouds"): a
// tree of triangle clusters, each far cluster (distance > kFarFactor x its radius)
// replaced by its dipole (the sum of its area vectors at its area-weighted
// centre), near ones summed exactly as in winding_number(). For classifying
// points as inside (> 1/2) or outside (< 1/2) a surface, as the hybrid builder
// does for the centroids of its coarse tets: the far-field error (measured in
// tests/meshing/hybrid_builder_test.cc) is far below 1/2 except within a few
// triangle sizes of the surface, where the near field is exact.
#pragma once

#include <vector>

#include "mesh_types.h"

namespace tb {

class WindingNumberTree {
 public:
  /// `surface` must outlive the tree.
  explicit WindingNumberTree(const SurfaceMesh& surface);
  /// About 1 inside, 0 outside an outward-oriented closed surface, 1/2 on it.
  double operator()(const Eigen::Vector3d& p) const;

  /// A cluster is far from p when |p - centre| > kFarFactor x radius.
  static constexpr double kFarFactor = 4.0;

 private:
  struct Node {
    Eigen::Vector3d centre, dipole;  // area-weighted centre; sum of area vectors (N / 2 per triangle)
    double radius = 0;               // of the ball about centre holding the cluster's vertices
    int first = 0, count = 0;        // leaves: triangles order_[first, first + count)
    int children[2] = {-1, -1};
  };
  int build(int first, int count);
  double exact(int first, int count, const Eigen::Vector3d& p) const;

  const SurfaceMesh& surface_;
  std::vector<int> order_;  // triangles, grouped by cluster
  std::vector<Node> nodes_;
};

}  // namespace tb
