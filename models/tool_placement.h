// Where each tool of a LoadCase holds a model's meshes, and where each interior
// probe sits in a model's volume: the one translation, shared by every model so
// that the same tool holds the same surface in each. Called in setup; errors name
// the tool's scenario key.
//
// A tool holds the fine-surface vertices it catches (a grasp: those within its
// radius of its point; a plate: those in its box). A model realises that on its
// own meshes:
//  - on the fine volume, whose nodes include the surface's: those nodes, held as
//    Dirichlet values (K_ff u_f = f_f - K_fp u_p);
//  - on a coarse volume: the coarse nodes nearest those vertices (each vertex's
//    nearest node, not clamped), held as Dirichlet values: the coarse mesh can
//    only be held at its own nodes, so a tool smaller than the coarse spacing
//    becomes a point-like hold;
//  - on the PBD surface: the vertices themselves, pinned (inverse mass 0, eq. 33).
#pragma once

#include <string>
#include <vector>

#include "elastic_body.h"
#include "load_case.h"
#include "mesh_types.h"

namespace tb {

/// The fine-surface vertices `tool` holds, ascending. Throws std::invalid_argument
/// naming the tool's key when it holds none (with the nearest vertex's distance)
/// or when one of them is in the support box. A sphere holds none: it is checked
/// instead (a positive radius, a finite centre, and at its first centre no surface
/// vertex deeper inside it than kSphereStartTolerance times its radius and its
/// centre not inside the body), and the list is empty.
std::vector<int> tool_vertices(const Tool& tool, const SurfaceMesh& surface, const SupportBox& support);

/// The prescribed group of `tool` on a volume whose node surface_to_volume[v] is
/// surface vertex v. Components: all three, or the plate's normal axis alone.
PrescribedGroup fine_volume_group(const Tool& tool, const std::vector<int>& vertices,
                                  const std::vector<int>& surface_to_volume);

/// The prescribed group of `tool` on a coarse volume: the nearest coarse node of
/// each held vertex, unique, clamped ones left out (an error naming the key if none
/// is left).
///   V_surface  #V by 3, clamped  #coarse nodes flags
PrescribedGroup coarse_volume_group(const Tool& tool, const std::vector<int>& vertices, const Points& V_surface,
                                    const TetMesh& coarse, const std::vector<char>& clamped);

/// The contact area of a set of surface vertices: the sum of their vertex areas, a
/// vertex's area one third of the summed area of its triangles (the barycentric
/// dual area; all vertices' areas sum to the surface's area): the patch up to about
/// halfway to the first vertex out of contact.
/// The same measure for every model: the FEM's active nodes, PBD's and the
/// hybrid's vertices on the sphere at the end of the frame. No allocation per call.
class ContactArea {
 public:
  explicit ContactArea(const SurfaceMesh& surface);
  ///   vertices  surface vertex indices in contact (any order, distinct)
  double area(const std::vector<int>& vertices) const;

 private:
  Eigen::VectorXd vertex_area_;  ///< a third of each vertex's triangles' area
};

/// The pads of a compliant grasp on a volume whose node surface_to_volume[v] is
/// surface vertex v: per held vertex, its node and the spring stiffness
/// pad_stiffness times its vertex area (ContactArea), N/m, in the order of
/// `vertices`: the lumped discretisation on P1 triangles of the pad traction
/// kappa (d - u) (exact for a uniform u); with smooth_pads, times
/// (1 - (r / radius)^2)^2, a vertex on the rim left out. Throws
/// std::invalid_argument naming the tool for another kind, a vertex with no node, or
/// smooth pads that hold no vertex.
std::vector<NodeSpring> pad_springs(const Tool& tool, const std::vector<int>& vertices, const SurfaceMesh& surface,
                                    const std::vector<int>& surface_to_volume);

/// Where each probe point sits in `volume`: its containing tet (within a relative
/// tolerance of 1e-6 of the mesh size), or with `nearest` the nearest tet,
/// extrapolated (a coarse mesh whose hull lies inside the surface). Throws
/// std::invalid_argument naming the probe, the mesh and the distance when a probe
/// is outside and `nearest` is false.
///   probes  #P by 3
std::vector<TetEmbedding> place_probes(const Points& probes, const TetMesh& volume, const std::string& mesh_name,
                                       bool nearest);

/// out (#P by 3) = the displacement u (3 #V of `volume`) at each probe's embedding.
void interpolate_probes(const std::vector<TetEmbedding>& probes, const Tetrahedra& T, const Eigen::VectorXd& u,
                        Points& out);

}  // namespace tb
