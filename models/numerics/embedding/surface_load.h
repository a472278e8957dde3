// Loads as weighted points: the paper's point force (eq. 10 for a point force,
// f^e = N^e(x)^T F), or a force spread as a uniform traction over a disc on the
// surface (a load whose discrete solution converges under mesh refinement, where
// the point force's grows without bound: docs/reference_convergence.md). On a
// volume they become weighted points in tets, which an assembly spreads with the
// tet's shape functions of any degree (nodal_weights_p1 for P1); on a surface,
// weighted points on triangles (surface_nodal_weights).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "load_mapping.h"
#include "mesh_types.h"

namespace tb {

/// One point of a load in a volume: the fraction `weight` of the total force acts
/// at `position` (rest configuration), which lies in tet at.tet (barycentric
/// weights at.weights).
struct LoadPoint {
  TetEmbedding at;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double weight = 0;
};

/// One point of a load on a surface: the fraction `weight` of the total force acts
/// at `position`, on triangle `triangle`.
struct SurfaceLoadPoint {
  int triangle = -1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double weight = 0;
};

/// The point force: one point of weight 1 in the tet containing `point` (the
/// lowest index when on a shared face, as containing_tet in load_mapping.h).
/// Throws std::invalid_argument naming the point if it is outside the volume.
std::vector<LoadPoint> point_load_points(const TetMesh& volume, const Eigen::Vector3d& point);

/// Quadrature of the disc load (fixed, so the load does not depend on the mesh).
struct DiscQuadrature {
  int radial = 32;    ///< Gauss-Legendre points in the radius (weight r dr)
  int angular = 128;  ///< equispaced angles (j + 1/2) 2 pi / angular: mirror-symmetric sets
};

/// The disc load on a surface: the force spread as a uniform traction over the
/// disc of `radius` around `centre` in the surface's tangent plane there (normal:
/// the area-weighted normal of the surface triangles touching `centre`). Each
/// quadrature point off the surface (by more than 1e-9 of the bounding-box
/// diagonal) is moved to the nearest point of the surface. The weights sum to 1,
/// so the total force is exact on any mesh, and so is its moment about `centre`
/// (for a flat surface) with P1 and P2 shape functions.
///   surface  #V by 3 V, #F by 3 F
/// Throws std::invalid_argument saying which if the radius is not finite and
/// positive, if `centre` is not on the surface (farther than 1e-9 of the
/// bounding-box diagonal), or if the disc leaves the surface (a quadrature point
/// farther than 1% of the radius from it, e.g. past an edge of the cube).
std::vector<SurfaceLoadPoint> disc_surface_points(const SurfaceMesh& surface, const Eigen::Vector3d& centre,
                                                  double radius, const DiscQuadrature& quadrature = {});

/// The disc load in a volume whose boundary is `surface`: disc_surface_points,
/// each given to the tet owning the surface triangle there.
///   volume             the fine tets; the surface's vertices are its nodes
///   surface_to_volume  #V node of each surface vertex in volume
std::vector<LoadPoint> disc_load_points(const TetMesh& volume, const SurfaceMesh& surface,
                                        const std::vector<int>& surface_to_volume, const Eigen::Vector3d& centre,
                                        double radius, const DiscQuadrature& quadrature = {});

/// The P1 nodal weights of weighted points in a volume: point j gives
/// weight_j * at.weights(k) to node T(at.tet, k).
NodalWeights nodal_weights_p1(const TetMesh& volume, const std::vector<LoadPoint>& points);

/// The nodal weights of weighted surface points: each point's weight shared by its
/// triangle's vertices by its barycentric coordinates there.
NodalWeights surface_nodal_weights(const SurfaceMesh& surface, const std::vector<SurfaceLoadPoint>& points);

/// Gauss-Legendre points and weights on [0, 1] (n >= 1), exact for polynomials
/// of degree 2n - 1.
void gauss_legendre_01(int n, std::vector<double>& points, std::vector<double>& weights);

}  // namespace tb
