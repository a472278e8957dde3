// Where each load of a LoadCase acts on a model's meshes: the one translation from
// the scenario's loads (load_case.h) to nodal weights (numerics/embedding), shared
// by every model so that the same load means the same thing in each. Called in
// setup; errors name the load's scenario key.
#pragma once

#include <vector>

#include "load_case.h"
#include "load_mapping.h"
#include "mesh_types.h"

namespace tb {

/// How a point force meets a volume.
enum class PointInVolume {
  Containing,  ///< the tet containing it; outside the mesh is an error (the fine FEM)
  Nearest,     ///< the nearest tet, extrapolated (a coarse mesh whose hull lies inside the surface)
  NearestNode  ///< all on the nearest node (the hybrid's coarse_load nearest_node)
};

/// A volume and, when the fine surface's vertices are its nodes, that map (a
/// traction is then spread over the volume's own surface triangles).
struct VolumePlacement {
  const TetMesh* volume = nullptr;
  std::string name;                                ///< "fine volume", "coarse volume": named in errors
  const SurfaceMesh* surface = nullptr;            ///< the fine surface (traction discs are found on it)
  const std::vector<int>* surface_to_volume = nullptr;  ///< #V_surface nodes, or null: not the volume's boundary
  double density = 0;                              ///< kg/m^3, for a body force
  PointInVolume points = PointInVolume::Containing;
};

/// Nodal weights of every load of `loads` on the volume, one per load:
///  - point_force: by `points`;
///  - surface_traction: the disc on the surface, each quadrature point to the tet
///    owning its triangle when surface_to_volume is given, else to the tet
///    containing it or the nearest (a coarse mesh);
///  - body_force: the nodal masses (weights in kg: value g gives m_i g).
/// Throws std::invalid_argument naming the load's key and the problem.
std::vector<NodalWeights> place_on_volume(const std::vector<Load>& loads, const VolumePlacement& where);

/// Nodal weights of every load on a surface (PBD's eq. 31):
///  - point_force: the nearest vertex, or with `spread_on_triangles` the nearest
///    surface point's triangle;
///  - surface_traction: the disc's quadrature points on their triangles;
///  - body_force: `masses` (#V, kg): value g gives m_i g.
std::vector<NodalWeights> place_on_surface(const std::vector<Load>& loads, const SurfaceMesh& surface,
                                           bool spread_on_triangles, const Eigen::VectorXd& masses);

}  // namespace tb
