// The edges of a triangle surface with the triangles that share them, the common
// ground of the stretch constraints (one per edge) and the bending constraints
// (one per interior edge).
#pragma once

#include <array>
#include <map>
#include <utility>
#include <vector>

#include "mesh_types.h"

namespace tb::pbd {

/// Each edge (min, max vertex) with its triangles as (a, b, opposite): a -> b as
/// the triangle traverses the edge, in the triangles' order; the edges in
/// (min, max) order, so that the constraint order is deterministic.
using EdgeTriangles = std::map<std::pair<int, int>, std::vector<std::array<int, 3>>>;
EdgeTriangles edge_triangles(const SurfaceMesh& surface);

}  // namespace tb::pbd
