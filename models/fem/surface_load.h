// Where the fine FEM applies a load: the paper's point force (eq. 10 for a point
// force, f^e = N^e(x)^T F) or a force spread as a uniform traction over a disc on
// the surface (issue 13: a load whose discrete solution converges under mesh
// refinement, where the point force's grows without bound). Both become a list
// of weighted points in tets, which an assembly spreads with the tet's shape
// functions, of any degree.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// One point of a load: the fraction `weight` of the total force acts at
/// `position` (rest configuration), which lies in tet `tet` of the fine volume.
struct LoadPoint {
  int tet = -1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double weight = 0;
};

/// The point force: one point of weight 1 in the tet containing `point` (the
/// lowest index when on a shared face, as ElasticSolver::locate_load).
/// Throws std::invalid_argument naming the point if it is outside the volume.
std::vector<LoadPoint> point_load_points(const TetMesh& volume, const Eigen::Vector3d& point);

/// Quadrature of the disc load (fixed, so the load does not depend on the mesh).
struct DiscQuadrature {
  int radial = 32;    ///< Gauss-Legendre points in the radius (weight r dr)
  int angular = 128;  ///< equispaced angles (j + 1/2) 2 pi / angular: mirror-symmetric sets
};

/// The disc load: the force spread as a uniform traction over the disc of
/// `radius` around `centre` in the surface's tangent plane there (normal: the
/// area-weighted normal of the surface triangles touching `centre`). Each
/// quadrature point off the surface (by more than 1e-9 of the bounding-box
/// diagonal) is moved to the nearest point of the surface; each is given to
/// the tet owning the surface triangle there. The weights sum to 1, so the total
/// force is exact on any mesh, and so is its moment about `centre` (for a flat
/// surface) with P1 and P2 shape functions.
///   volume             the fine tets; the surface's vertices are its nodes
///   surface            #V by 3 V, #F by 3 F, the volume's boundary
///   surface_to_volume  #V node of each surface vertex in volume
/// Throws std::invalid_argument naming `load.disc_radius` if the radius is not
/// finite and positive, if `centre` is not on the surface (farther than 1e-9 of
/// the bounding-box diagonal), or if the disc leaves the surface (a quadrature
/// point farther than 1% of the radius from it, e.g. past an edge of the cube).
std::vector<LoadPoint> disc_load_points(const TetMesh& volume, const SurfaceMesh& surface,
                                        const std::vector<int>& surface_to_volume, const Eigen::Vector3d& centre,
                                        double radius, const DiscQuadrature& quadrature = {});

/// Gauss-Legendre points and weights on [0, 1] (n >= 1), exact for polynomials
/// of degree 2n - 1.
void gauss_legendre_01(int n, std::vector<double>& points, std::vector<double>& weights);

}  // namespace tb
