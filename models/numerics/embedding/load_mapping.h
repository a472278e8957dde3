// Where a load acts on the nodes of each mesh a model uses: the one place that maps
// loads to nodes, for every model (docs/architecture.md "Loads"):
//  - a volume (FEM): the containing tet, the force spread by its barycentric
//    weights (paper eq. 10 for a point force, f^e = N^e(x)^T F);
//  - a volume the point may lie just outside (the hybrid's coarse mesh, whose
//    hull sits inside a curved fine surface): the nearest tet, with unclamped
//    barycentric weights, as control points are embedded (paper 1.2);
//  - a surface (PBD, eq. 31): the nearest vertex (the paper), or the nearest
//    surface point, the force spread over its triangle's vertices by barycentric
//    weights (consistent with the FEM's P1 load on the same surface);
//  - a body force on a volume: each node's share of the mass, int N_i rho dV
//    (exact for P1: a quarter of each tet's mass to each of its nodes).
// Models map their loads once, in setup, so a frame does no search and no
// allocation.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// Where a load's value lands on the nodes of one mesh: node nodes(k) receives
/// weights(k) times the value (a force, or an acceleration for a body force, whose
/// weights are then masses). A node may appear more than once; weights may be 0.
///   nodes, weights  #K
struct NodalWeights {
  Eigen::VectorXi nodes;
  Eigen::VectorXd weights;
  double distance = 0;  ///< m, from the load point to the element it was mapped into (0 inside)
  Eigen::Index size() const { return nodes.size(); }
};

/// The nodes of tet e.tet of `mesh` with e's barycentric weights (4 entries).
NodalWeights tet_nodal_weights(const TetMesh& mesh, const TetEmbedding& e);

/// The tet of `mesh` containing `point` (within a relative tolerance of 1e-6 of the
/// mesh size) and its barycentric weights. Throws std::invalid_argument naming the
/// point, `mesh_name` and the distance when the point is outside.
NodalWeights containing_tet(const TetMesh& mesh, const Eigen::Vector3d& point, const std::string& mesh_name);

/// The tet of `mesh` containing `point`, else the nearest one, with unclamped
/// barycentric weights (a point just outside is extrapolated, as control points
/// are). `distance` says how far outside it was.
NodalWeights nearest_tet(const TetMesh& mesh, const Eigen::Vector3d& point);

/// The vertex of V nearest to `point` (lowest index on ties), weight 1, in the
/// first of 4 entries (the others repeat it with weight 0).
///   V  #V by 3 positions
NodalWeights nearest_vertex(const Points& V, const Eigen::Vector3d& point);

/// The point of `surface` nearest `point`: its triangle's three vertices and the
/// point's barycentric weights there (each in [0, 1], summing to 1; a fourth
/// entry repeats the first with weight 0); `distance` from `point` to the
/// surface. Lowest triangle index on ties.
NodalWeights nearest_surface_point(const SurfaceMesh& surface, const Eigen::Vector3d& point);

/// The consistent nodal masses of a P1 tet mesh of uniform `density`: node i
/// receives int N_i rho dV = rho sum over its tets of |tet| / 4. With a body force
/// value g (m/s^2), node i receives the force m_i g. One entry per node, in order.
NodalWeights nodal_masses(const TetMesh& mesh, double density);

/// Several weighted loads as one: sum_j scale(j) * parts[j], each node once, in
/// order of first appearance. distance: the largest of the parts'.
///   parts  #J, scale  #J
NodalWeights combine(const std::vector<NodalWeights>& parts, const std::vector<double>& scale);

}  // namespace tb
