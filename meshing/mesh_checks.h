// Validity checks on meshes. Each failure throws MeshError naming the file, the
// problem and how many elements have it.
#pragma once

#include <Eigen/Geometry>  // cross(), in the inline tet_volume
#include <string>

#include "mesh_types.h"

namespace tb {

/// What check_and_orient_surface found and fixed.
struct SurfaceCheckReport {
  int flipped_triangles = 0;  ///< triangles reoriented to make the surface consistent and outward
};

/// Checks that a surface is a closed, 2-manifold, orientable triangle mesh with
/// finite coordinates and no degenerate or duplicate triangles, then orients it
/// consistently with outward normals (positive enclosed volume), in place.
/// Does not look for self-intersections (see find_self_intersections).
SurfaceCheckReport check_and_orient_surface(const std::string& file, SurfaceMesh& mesh);

/// What to do with tets of zero volume (relative to the mesh size).
enum class FlatTets {
  Error,  ///< a mesh read from a file: an error naming the file and the count
  Drop,   ///< a Delaunay mesh of points (coplanar hull points give slivers): remove them
  Keep,   ///< left in place, unoriented, for a repair that follows (flat_tet_repair.h)
};

/// The volume at or below which a tet counts as flat: 1e-14 of the cube of the
/// mesh's bounding-box diagonal (round-off on coordinates of that size).
inline double flat_tet_volume_bound(double bounding_box_diagonal) {
  return 1e-14 * bounding_box_diagonal * bounding_box_diagonal * bounding_box_diagonal;
}

/// Checks tets: indices in range, finite coordinates, zero-volume tets per
/// `flat`; swaps two nodes of each negatively oriented tet. In place.
/// Returns how many tets were reoriented.
int orient_and_check_tets(const std::string& file, TetMesh& mesh, FlatTets flat = FlatTets::Error);

/// Signed volume enclosed by a closed, outward-oriented surface (divergence theorem).
double enclosed_volume(const SurfaceMesh& mesh);
/// Signed volume of one tet: det[b-a, c-a, d-a] / 6. Inline: the real-time steppers
/// call it per tet each frame (tet_time_stepping.h, all_positive).
inline double tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}
/// Sum of tet volumes.
double total_volume(const TetMesh& mesh);
/// Smallest of the six dihedral angles of tet (a, b, c, d), in degrees (0 if flat).
double tet_min_dihedral_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& d);
/// Smallest dihedral angle of tet t of `mesh`, in degrees.
double tet_min_dihedral_deg(const TetMesh& mesh, Eigen::Index t);
/// Smallest dihedral angle over all tets, in degrees (180 for no tets).
double min_dihedral_angle_deg(const TetMesh& mesh);
/// Number of tets whose smallest dihedral angle is below `degrees`.
int count_tets_below_dihedral(const TetMesh& mesh, double degrees);
/// Length of the bounding-box diagonal.
double bounding_box_diagonal(const Points& V);

}  // namespace tb
