// Choosing the coarse nodes among the fine base mesh's vertices (paper 1.2, after
// Mueller's hierarchical PBD [10]): a greedy coverage selection in which every
// base vertex ends up within `spacing` of a selected one.
#pragma once

#include <vector>

#include "mesh_types.h"

namespace tb {

/// Per surface vertex, how much of the shape it carries: 0 corner (3 or more
/// feature edges), 1 crease (1-2 feature edges), 2 smooth. A feature edge is one
/// whose two triangles' normals differ by more than feature_angle_deg.
///   returns #V_surface priorities
std::vector<int> surface_feature_priority(const SurfaceMesh& surface, double feature_angle_deg);

/// Greedy coverage: visit vertices by (priority, index) and select one unless a
/// selected vertex lies within `spacing`. Deterministic.
///   V         #V by 3 candidate positions
///   priority  #V classes, lower first
///   returns   selected indices into V, in selection order
std::vector<int> select_covering_vertices(const Points& V, const std::vector<int>& priority, double spacing);

/// The spacing whose selection has the count closest to target_count (bisection).
double spacing_for_target_count(const Points& V, const std::vector<int>& priority, int target_count);

}  // namespace tb
