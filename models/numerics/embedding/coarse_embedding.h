// Fine-surface points carried by a coarse tet mesh through barycentric weights
// (paper 1.2's control points; SOFA's barycentric mapping): where they are
// embedded, and their displacement from the coarse nodes' (eq. 33: p'_i = p_i +
// sum_j w_ij u_j). Shared by the hybrid (its control points) and the embedded
// model (every surface vertex).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// Every vertex of `surface` embedded in `coarse`: its containing tet, else the
/// nearest one, with unclamped barycentric weights (so a vertex just outside the
/// coarse hull is reproduced exactly at rest).
///   returns #V embeddings, surface_vertex = v
std::vector<ControlPoint> embed_vertices(const Points& V, const TetMesh& coarse);

/// out.row(k) = sum_j points[k].coarse.weights(j) u_coarse(T(points[k].coarse.tet, j)).
///   coarse_T  #T by 4; coarse_u  3 #coarse nodes; out  #points by 3 (resized if needed)
void interpolate_embedded(const std::vector<ControlPoint>& points, const Tetrahedra& coarse_T,
                          const Eigen::VectorXd& coarse_u, Points& out);

}  // namespace tb
