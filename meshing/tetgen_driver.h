// Runs the `tetgen` program (TetGen 1.5, Debian package `tetgen`) in a temporary
// folder. The program is found from $TISSUEBENCH_TETGEN, else PATH.
#pragma once

#include <string>

#include "mesh_types.h"

namespace tb {

struct TetgenOptions {
  double radius_edge_ratio = 1.414;  ///< quality bound (-q); <= 0 disables
  double max_volume = 0;             ///< max tet volume in m^3 (-a); <= 0 means none
  double timeout_seconds = 600;
};

/// Tetrahedralizes the inside of a closed surface, keeping the surface: every
/// surface vertex is a volume node and no Steiner point is added on it (-pY).
/// The surface's vertices come first in the result, in their order.
/// Interior points TetGen put almost on another node (the flat tets they span) are
/// merged into it (flat_tet_repair.h); what was merged goes to `repair`.
/// `source` names the surface's file in error messages.
TetMesh tetrahedralize_surface(const SurfaceMesh& surface, const TetgenOptions& options, const std::string& source,
                               InteriorPointMerges* repair = nullptr);

/// Delaunay tetrahedralization of a point set (its convex hull), without the
/// zero-volume slivers that coplanar hull points can produce.
TetMesh tetrahedralize_points(const Points& points, const std::string& source);

/// The tetgen program used, or throws std::runtime_error with install advice.
std::string tetgen_program();

}  // namespace tb
