// The order a tet volume's nodes and tets are stored in. TetGen numbers its Steiner
// points in insertion order, scattered over the body, so two threads sweeping
// disjoint tets of one colour still write nodes that share cache lines, and the
// second core reads positions the first just wrote: the volumetric XPBD sweep ran
// 1.08x faster on two threads than on one on the paper cube, 1.14x at 88 000 tets.
// Stored along a Z curve (nodes by position, tets by centroid), a thread's share of
// a colour is a compact region whose nodes lie together in memory: 1.5x and 1.7x
// (docs/realtime_nonlinear.md, "Two threads and the node order").
#pragma once

#include <cstdint>

#include "mesh_types.h"

namespace tb {

/// x, y, z (their 21 low bits) interleaved into a Z-order (Morton 1966) key: bit i of
/// x to bit 3 i, of y to 3 i + 1, of z to 3 i + 2 (Warren and Salmon 1993, sec. 3).
uint64_t morton_key(uint32_t x, uint32_t y, uint32_t z);

/// Renumbers m's nodes from `fixed` on along a Z-order (Morton) curve of their
/// positions, keeping nodes 0..fixed-1 where they are (the fine surface's vertices,
/// which the rest of the pipeline indexes as the volume's first nodes), and its tets
/// along the Z curve of their centroids (ties by the old index). Deterministic; the
/// tets keep their node order (orientation). Morton 1966; bits interleaved as in
/// Warren and Salmon 1993, "A parallel hashed oct-tree N-body algorithm", sec. 3
/// (21 bits per axis over the bounding box's largest side).
void order_along_z_curve(TetMesh& m, int fixed);

}  // namespace tb
