// Building the hybrid mesh of paper section 1.2 (figure 1).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "coarse_mesh.h"
#include "mesh_types.h"
#include "tetgen_driver.h"

namespace tb {

struct HybridBuildOptions {
  TetgenOptions fine_tetgen;         ///< the fine base mesh (also the FEM reference)
  int target_coarse_nodes = 150;     ///< coarse node count to aim for (paper: 153)
  double coarse_spacing = 0;         ///< if > 0, used instead of target_coarse_nodes
  double feature_angle_deg = 30;     ///< creases and corners are selected first
  CoarseMeshOptions coarse_quality;  ///< sliver repair of the coarse mesh
  unsigned selection_seed = 0;       ///< visiting order within a priority class (vertex_selection.h)
  /// Points whose nearest fine-surface vertex is selected first, before corners
  /// (e.g. the load point: a coarse node where the force acts).
  std::vector<Eigen::Vector3d> include_points;
  /// If set, builds the fine volume from the surface (surface vertices first, in
  /// order) instead of tetrahedralize_surface with fine_tetgen.
  std::function<TetMesh(const SurfaceMesh&)> fine_volume_builder;
};

/// Paper 1.2: fine surface -> fine base tet mesh (TetGen) -> coverage selection of
/// base vertices -> TetGen of the selected points -> coarse tets whose centroid is
/// outside the surface removed (non-convex shapes) -> slivers repaired
/// (build_coarse_mesh) -> control points = selected vertices on the surface.
/// `surface` must be closed, manifold and outward.
HybridMesh build_hybrid_from_surface(const SurfaceMesh& surface, const HybridBuildOptions& options,
                                     const std::string& source);

/// How control points are chosen when the coarse volume is given.
enum class ControlPointRule {
  NearestToCoarseSurfaceNodes,  ///< the fine vertex nearest each coarse boundary node
  AllSurfaceVertices,           ///< every fine-surface vertex (fully embedded surface)
};

/// The given-coarse path (the liver): every fine-surface vertex embedded in its
/// containing (else nearest) coarse tet; control points by `rule`. When
/// `fine_tetgen` is non-null the fine volume is also built (for the FEM reference).
HybridMesh build_hybrid_with_coarse(const SurfaceMesh& surface, const TetMesh& coarse, ControlPointRule rule,
                                    const TetgenOptions* fine_tetgen, const std::string& source);

/// Largest distance from a fine-surface vertex to the coarse tet it is embedded in.
double max_embedding_distance(const HybridMesh& mesh);

/// Nodes of a tet mesh on its boundary (those of faces owned by one tet), ascending.
std::vector<int> boundary_nodes(const TetMesh& m);

}  // namespace tb
