// Self-intersection detection and (explicitly requested) repair, with CGAL 5.5.
// Kept in one translation unit because CGAL's mesh-processing headers are heavy.
#pragma once

#include "mesh_types.h"

namespace tb {

/// Number of pairs of triangles that intersect other than at a shared edge/vertex.
int count_self_intersections(const SurfaceMesh& surface);

/// CGAL::Polygon_mesh_processing::experimental::remove_self_intersections; returns
/// the repaired surface (vertex order kept where the repair did not touch it).
/// Throws MeshError(source, ...) if self-intersections remain.
SurfaceMesh repair_self_intersections(const SurfaceMesh& surface, const std::string& source);

}  // namespace tb
