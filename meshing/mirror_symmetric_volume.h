// A tet mesh of the paper's cube that is itself mirror-symmetric about x = 0 and
// y = 0, so that a symmetric load gives a symmetric FEM solution to round-off
// (TetGen's mesh of the whole cube is symmetric only at the surface). TetGen
// meshes the quarter x >= 0, y >= 0, closed by structured grids on the two cut
// planes, and the quarter is reflected three times; the copies share the cut
// planes' vertices exactly.
#pragma once

#include <string>

#include "cube_generator.h"
#include "mesh_types.h"
#include "tetgen_driver.h"

namespace tb {

/// `surface` is make_cube_surface(spec) (nx and ny even, so that x = 0 and y = 0
/// are grid lines). The result keeps the surface's vertices first, in order, as
/// tetrahedralize_surface does. Throws MeshError naming `source` if the surface
/// does not split cleanly into mirror-image quarters.
TetMesh tetrahedralize_symmetric_cube(const SurfaceMesh& surface, const CubeSpec& spec, const TetgenOptions& options,
                                      const std::string& source);

}  // namespace tb
