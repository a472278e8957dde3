// Uniform refinement of a triangle surface that keeps its vertices: the levels of
// the reference-convergence study share the paper's surface vertices
// bitwise, so any model run on the paper's surface compares with any level by rest
// coordinates.
#pragma once

#include "mesh_types.h"

namespace tb {

/// Splits every triangle into four (its edge midpoints joined), `levels` times.
/// The input vertices come first, in their order and bitwise unchanged; each
/// level appends its edge midpoints ((a + b) / 2, one per edge, in the order the
/// edges are first met walking the triangles). Orientation is kept: child
/// triangles turn the same way as their parent.
///   surface  #V by 3 V, #F by 3 F
///   returns  #V + (new midpoints) vertices, 4^levels #F triangles
/// Throws std::invalid_argument if levels < 0.
SurfaceMesh subdivide_surface(const SurfaceMesh& surface, int levels);

}  // namespace tb
