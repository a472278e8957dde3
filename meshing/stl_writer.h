// Writing a triangle surface as ASCII STL, for tools that read STL only (CAD,
// slicers, some simulators). STL has no shared vertices: each triangle repeats its
// corners, and read_surface (mesh_io.h) merges coincident corners back.
#pragma once

#include <string>

#include "mesh_types.h"

namespace tb {

/// Writes `mesh` (V #V by 3, F #F by 3, counter-clockwise from outside) as ASCII
/// STL: one facet per row of F with its unit normal (zero for a degenerate
/// triangle) and its corners at 17 significant digits, so read_surface gives back V
/// bitwise (in first-use order) and F. `solid_name` names the solid (no spaces).
/// Written atomically (atomic_file.h); throws std::runtime_error naming the path on
/// failure or on an index outside V.
void write_stl(const std::string& path, const SurfaceMesh& mesh, const std::string& solid_name = "surface");

}  // namespace tb
