// Where a point sits relative to a tet mesh or a closed surface.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// Barycentric coordinates of p in tet (a, b, c, d).
Eigen::Vector4d barycentric(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& d, const Eigen::Vector3d& p);

/// The tet containing p (the lowest index when on a shared face, so the result is
/// deterministic), else the nearest tet. A tet contains p when every barycentric
/// weight is >= -tolerance.
TetEmbedding locate_point(const TetMesh& mesh, const Eigen::Vector3d& p, double tolerance = 1e-9);

/// locate_point for many points: the tets bucketed in a grid by their bounding
/// boxes (inflated by what the tolerance admits), so a query tests the few tets of
/// its cell, in ascending order; the same answer as locate_point. The mesh must
/// outlive the locator.
class TetLocator {
 public:
  explicit TetLocator(const TetMesh& mesh, double tolerance = 1e-9);
  TetEmbedding locate(const Eigen::Vector3d& p) const;

 private:
  Eigen::Array3i cell_of(const Eigen::Array3d& p) const;
  const TetMesh& mesh_;
  double tolerance_;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double cell_ = 1;
  int64_t count_[3] = {1, 1, 1};
  std::vector<int64_t> start_;  // bin b holds tets_[start_[b], start_[b + 1])
  std::vector<int> tets_;
};

/// The point of triangle (a, b, c) nearest p.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

/// Distance from p to triangle (a, b, c).
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c);

/// Whether the segment from p to q meets triangle (a, b, c): Moeller and Trumbore
/// (1997), the line p + t (q - p) through the triangle at barycentrics (1 - u - v, u, v),
/// with t in [0, 1] and u, v, 1 - u - v >= 0. False for a segment parallel to the
/// triangle's plane (then it meets no interior point transversally).
bool segment_meets_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Generalized winding number of a closed surface at p: 1 inside, 0 outside
/// (for an outward-oriented surface), 1/2 on it.
/// The solid angle triangle (a, b, c) subtends at p, signed by its orientation
/// (Van Oosterom and Strackee 1983), in steradians.
double triangle_solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& p);

double winding_number(const SurfaceMesh& surface, const Eigen::Vector3d& p);

}  // namespace tb
