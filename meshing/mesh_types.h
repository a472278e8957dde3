// Mesh types shared by every stage: a triangle surface, a tetrahedral volume and
// the hybrid mesh of paper section 1.2 (fine surface + coarse tets + control points).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace tb {

using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Tetrahedra = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;

/// A closed triangle surface.
///   V  #V by 3 vertex positions
///   F  #F by 3 vertex indices per triangle, counter-clockwise seen from outside
struct SurfaceMesh {
  Points V;
  Triangles F;
};

/// A tetrahedral volume.
///   V  #V by 3 node positions
///   T  #T by 4 node indices per tet, positively oriented
///      (det[v1-v0, v2-v0, v3-v0] > 0)
struct TetMesh {
  Points V;
  Tetrahedra T;
};

/// A point expressed in one tet of a mesh: p = sum_k weights[k] * V[T(tet, k)]. The
/// one point-in-tet type of the project: control points, coarse embeddings and
/// loads mapped into volumes all use it. Weights are the (unclamped) barycentric
/// coordinates, so a point just outside its tet is reproduced exactly too;
/// `distance` is 0 inside, else the distance from the point to the tet.
struct TetEmbedding {
  int tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
  double distance = 0;
};

/// A fine-surface vertex tied to the coarse volume: its position is the barycentric
/// combination of the coarse tet's nodes (eq. 33 places it there every frame).
/// When the vertex coincides with a coarse node, coarse.weights is a unit vector.
struct ControlPoint {
  int surface_vertex = -1;  ///< index into the fine surface's V
  TetEmbedding coarse;      ///< where it sits in the coarse volume
};

/// What the coarse mesh's sliver repair did (meshing/coarse_mesh.h), reported in summary.json.
struct CoarseRepairReport {
  int boundary_slivers_removed = 0;   ///< flat tets on the boundary taken out of the mesh
  int vertices_moved = 0;             ///< selected vertices swapped for a neighbouring fine vertex
  int interior_vertices_dropped = 0;  ///< interior selected vertices left out
  int remeshes = 0;                   ///< Delaunay meshes made after the first
  int slivers_left = 0;               ///< tets still below the repair's angle (0 unless it gave up)
};

/// What the fine volume's repair of near-coincident TetGen points did
/// (meshing/flat_tet_repair.h), reported in summary.json.
struct InteriorPointMerges {
  int merged = 0;   ///< interior points merged into a near-coincident node
  int refused = 0;  ///< interior points left where they are: each merge tried would invert or flatten a tet
  int flat_tets_collapsed = 0;  ///< interior points of a flat tet left, collapsed into their best neighbour
};

/// The hybrid mesh of paper section 1.2.
///   fine_volume may be empty when a coarse volume was given (liver path).
///   fine_surface_to_volume  #V_surface indices of each surface vertex in
///   fine_volume.V, or empty when fine_volume is empty.
struct HybridMesh {
  SurfaceMesh fine_surface;
  TetMesh fine_volume;
  std::vector<int> fine_surface_to_volume;
  TetMesh coarse_volume;
  std::vector<ControlPoint> control_points;
  CoarseRepairReport coarse_repair;  ///< built coarse meshes only (zeros for a given one)
  InteriorPointMerges fine_repair;  ///< built fine volumes only (zeros for a given one)
};

}  // namespace tb
