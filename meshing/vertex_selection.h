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

/// Greedy coverage: visit vertices by (priority, rank) and select one unless a
/// selected vertex lies within `spacing`. The rank within a priority class is the
/// index (seed 0) or a permutation drawn from `seed` (seed_rank): the selection's
/// dependence on visiting order is then a factor one can vary. Deterministic.
///   V         #V by 3 candidate positions
///   priority  #V classes, lower first
///   returns   selected indices into V, in selection order
std::vector<int> select_covering_vertices(const Points& V, const std::vector<int>& priority, double spacing,
                                          unsigned seed = 0);

/// The spacing whose selection has the count closest to target_count (bisection).
double spacing_for_target_count(const Points& V, const std::vector<int>& priority, int target_count, unsigned seed = 0);

/// The visiting rank of each of n vertices: the identity for seed 0, else a
/// permutation from a Fisher-Yates shuffle driven by splitmix64 (the same on every
/// platform, unlike std::shuffle).
std::vector<int> seed_rank(int n, unsigned seed);

}  // namespace tb
