// The coarse tet mesh of paper 1.2 from selected fine vertices: their Delaunay
// mesh (TetGen) with tets outside the surface removed, then slivers repaired with
// every coarse node kept on a selected fine vertex. A Delaunay mesh of
// points on a curved surface is full of nearly flat tets (a coarse mesh of a
// sphere had one with a smallest dihedral angle of 0.0003 degrees), whose
// stiffness is nearly singular.
#pragma once

#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

struct CoarseMeshOptions {
  /// Tets whose smallest dihedral angle is below this are slivers to repair;
  /// 0 keeps the Delaunay mesh as it is.
  double min_dihedral_deg = 5;
  int max_rounds = 40;  ///< re-meshings of a perturbed selection at most
};

/// A coarse mesh and, per node, the fine vertex it sits on.
struct CoarseMesh {
  TetMesh mesh;
  std::vector<int> node_vertex;  ///< #mesh.V: index into the candidate points V of each node
  CoarseRepairReport repair;
};

/// Builds the coarse mesh on the fine vertices `selected` (indices into V):
/// Delaunay mesh, tets with centroid outside `surface` removed, then, while a tet
/// is below options.min_dihedral_deg,
///  1. flat boundary tets are removed when the boundary stays a 2-manifold and
///     every node stays in a tet (remove_flat_boundary_slivers);
///  2. for each remaining sliver, one of its nodes moves to the fine vertex of
///     the same priority class within `spacing` (corners, class 0, never move)
///     that best improves the tets around it; if none does, an interior node of
///     the sliver is left out; and the selection is meshed again.
/// The best mesh met (fewest slivers, then largest smallest angle) is returned.
/// Deterministic.
///   V         #V by 3 candidate positions (the fine volume's nodes)
///   priority  #V selection classes (0 corner, 1 crease, 2 smooth surface, 3 interior)
///   selected  indices into V
CoarseMesh build_coarse_mesh(const Points& V, const std::vector<int>& priority, std::vector<int> selected,
                             double spacing, const SurfaceMesh& surface, const CoarseMeshOptions& options,
                             const std::string& source);

/// Removes tets below `min_dihedral_deg` that have two faces on the boundary (and
/// the edge joining their other two nodes inside), or one face on the boundary
/// (and the opposite node inside), repeatedly, worst first. Such a removal keeps
/// the boundary a 2-manifold and every node in a tet. Returns how many went.
int remove_flat_boundary_slivers(TetMesh& mesh, double min_dihedral_deg);

}  // namespace tb
