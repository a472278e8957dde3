// The paper's cube (section 2.1) as a structured, mirror-symmetric triangle surface.
#pragma once

#include "mesh_types.h"

namespace tb {

/// Box x in [-side/2, side/2], y likewise, z in [0, height], each face a grid of
/// quads split along diagonals that alternate by quadrant, so the mesh is
/// mirror-symmetric about x = 0 and y = 0 and the top centre is a vertex (for even
/// nx, ny). 10 x 10 x 12 gives 682 vertices / 1360 triangles. Outward-oriented.
struct CubeSpec {
  double side = 0.1;
  double height = 0.1;
  int nx = 10, ny = 10, nz = 12;
};
SurfaceMesh make_cube_surface(const CubeSpec& spec);

/// Coordinate of lattice line i of n across a centred side: side (i / n - 1/2).
/// Exactly 0 at i = n / 2. Shared with meshing/mirror_symmetric_volume.cc, whose
/// cut-plane points must coincide bitwise with the surface's.
double centred_grid_coordinate(double side, int n, int i);

}  // namespace tb
