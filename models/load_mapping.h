// Where a point load acts on each mesh a model uses: the one place that maps a load
// point to the nodes that carry it, for every model (DESIGN.md "Load"):
//  - a volume (FEM): the containing tet, the force spread by its barycentric
//    weights (eq. 10 for a point force, f^e = N^e(x)^T F);
//  - a volume the point may lie just outside (the hybrid's coarse mesh, whose
//    hull sits inside a curved fine surface): the nearest tet, with unclamped
//    barycentric weights, as control points are embedded (paper 1.2);
//  - a surface (PBD, eq. 31): the nearest vertex (the paper), or the nearest
//    surface point, the force spread over its triangle's vertices by barycentric
//    weights (consistent with the FEM's P1 load on the same surface).
// Models look a point up once and keep the answer while the point stays the same
// (PerLoadPoint), so a frame does no search and no allocation.
#pragma once

#include <Eigen/Core>
#include <string>

#include "mesh_types.h"

namespace tb {

/// Up to four nodes and the weights that spread a point force over them: node k
/// receives weights(k) * F. Unused slots have weight 0 (and repeat a used node).
struct LoadStencil {
  Eigen::Vector4i nodes = Eigen::Vector4i::Zero();
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  double distance = 0;  ///< m, from the load point to the element it was mapped into (0 inside)
};

/// The tet of `mesh` containing `point` (within a relative tolerance of 1e-6 of the
/// mesh size) and its barycentric weights. Throws std::invalid_argument naming the
/// point, `mesh_name` and the distance when the point is outside.
LoadStencil containing_tet(const TetMesh& mesh, const Eigen::Vector3d& point, const std::string& mesh_name);

/// The tet of `mesh` containing `point`, else the nearest one, with unclamped
/// barycentric weights (a point just outside is extrapolated, as control points
/// are). `distance` says how far outside it was.
LoadStencil nearest_tet(const TetMesh& mesh, const Eigen::Vector3d& point);

/// The vertex of V nearest to `point` (lowest index on ties), weight 1.
///   V  #V by 3 positions
LoadStencil nearest_vertex(const Points& V, const Eigen::Vector3d& point);

/// The point of `surface` nearest `point`: its triangle's three vertices and the
/// point's barycentric weights there (each in [0, 1], summing to 1); `distance`
/// from `point` to the surface. Lowest triangle index on ties.
LoadStencil nearest_surface_point(const SurfaceMesh& surface, const Eigen::Vector3d& point);

/// A lookup redone only when the load point changes (the runner applies the same
/// point every frame).
template <class Result>
class PerLoadPoint {
 public:
  template <class Find>
  const Result& get(const Eigen::Vector3d& point, Find&& find) {
    if (!valid_ || point != point_) {
      result_ = find(point);
      point_ = point;
      valid_ = true;
    }
    return result_;
  }
  /// The last result (nullptr before the first lookup).
  const Result* last() const { return valid_ ? &result_ : nullptr; }

 private:
  Result result_{};
  Eigen::Vector3d point_ = Eigen::Vector3d::Zero();
  bool valid_ = false;
};

}  // namespace tb
