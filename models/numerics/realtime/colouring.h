// Greedy graph colourings of a tet mesh for Gauss-Seidel sweeps that run a colour
// in parallel: the vertices (no two vertices of one tet share a colour; Vertex
// Block Descent) or the tets (no two tets sharing a vertex share a colour; the
// XPBD tet constraints). Deterministic: items in index order, each the smallest
// colour its already-coloured neighbours leave free (Welsh and Powell 1967 without
// the degree ordering).
#pragma once

#include "mesh_types.h"
#include <utility>
#include <vector>

namespace tb {

/// Colour classes, each a list of item indices in increasing order.
using Colouring = std::vector<std::vector<int>>;

/// The tets around each vertex (CSR): those of vertex v are around[offset[v]] to
/// around[offset[v + 1] - 1], each (tet, the vertex's place 0..3 in it), in
/// increasing tet order.
struct VertexTets {
  std::vector<int> offset;                  ///< #V + 1
  std::vector<std::pair<int, int>> around;  ///< 4 #T
};
VertexTets vertex_tets(const Tetrahedra& T, int vertex_count);

/// The listed vertices (`active`, each in [0, #V)) coloured so that no two in one
/// class share a tet of T (#T by 4). #V: the vertex count.
Colouring colour_vertices(const Tetrahedra& T, int vertex_count, const std::vector<int>& active);

/// Every tet of T (#T by 4) coloured so that no two in one class share a vertex;
/// a vertex not in `moving` (#V flags) does not count as shared (its position is
/// never written). #V: the vertex count.
Colouring colour_tets(const Tetrahedra& T, int vertex_count, const std::vector<char>& moving);

}  // namespace tb
