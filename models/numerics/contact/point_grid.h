// A uniform grid over a fixed set of points (the rest positions of a surface): the
// spatial query that keeps contact with a sphere a pass over the points near it,
// not over all of them (docs/equations.md, "Contact with a rigid sphere").
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh_types.h"

namespace tb {

class PointGrid {
 public:
  /// Buckets the rows of `points` (#P by 3) in cubic cells of side `cell` (m, > 0).
  PointGrid(const Points& points, double cell);

  /// Appends to `out` (cleared first) every point whose cell meets the box around
  /// the ball of `radius` about `centre`: a superset of the points within `radius`,
  /// ascending. When that box spans more cells than there are points, every point
  /// (a scan is then cheaper). No allocation once `out` has capacity for every point.
  void query(const Eigen::Vector3d& centre, double radius, std::vector<int>& out) const;

  double cell() const { return cell_; }
  size_t size() const { return static_cast<size_t>(count_); }

 private:
  double cell_;
  Eigen::Vector3d origin_;
  Eigen::Array3i dims_;
  int count_ = 0;
  std::vector<int> start_;   ///< per cell (x fastest), its first entry in points_; one past the end last
  std::vector<int> points_;  ///< point indices, cell by cell, ascending within a cell
};

}  // namespace tb
