// Reading and writing meshes. Every reader throws MeshError naming the file and
// the problem (unreadable, truncated, malformed, NaN, index out of range); none
// checks topology; see mesh_checks.h for that.
#pragma once

#include <string>
#include <vector>

#include "mesh_checks.h"
#include "mesh_types.h"

namespace tb {

/// Reads a triangle surface; the format follows the extension:
///   .obj  triangles and polygons (fan-triangulated); vt/vn/groups/materials ignored
///   .off  OFF, polygons fan-triangulated
///   .stl  ASCII or binary (a binary header may begin with "solid"); coincident
///         vertices are merged
///   .ply  ascii, binary_little_endian or binary_big_endian
///   .vtu  ASCII VTK unstructured grid of triangles (what write_surface_vtu writes)
/// Coordinates are multiplied by unit_scale (e.g. 0.01 for centimetres).
SurfaceMesh read_surface(const std::string& path, double unit_scale = 1.0);

/// Reads a tetrahedral volume; the format follows the extension:
///   .msh  Gmsh version 1, 2 or 4.1 ASCII; tetrahedra kept, other element types ignored
///         (4.1: node tags may be sparse and in any order; nodes keep the file's order)
///   .ele  TetGen (.node beside it, same stem)
///   .node TetGen (.ele beside it, same stem)
///   .vtu  ASCII VTK unstructured grid; tetrahedra kept
/// Node ids may be any integers; unused nodes are kept.
TetMesh read_volume(const std::string& path, double unit_scale = 1.0, FlatTets flat = FlatTets::Error);

/// Reads the triangles of a TetGen .face file (indices mapped to 0-based using the
/// .node file's first index).
Triangles read_tetgen_faces(const std::string& face_path, int first_index);

/// A named per-point field for VTK output: #V by 1 (scalar) or #V by 3 (vector).
struct PointField {
  std::string name;
  Eigen::MatrixXd values;
};

/// Writes a surface as an ASCII .vtu (ParaView opens it), with point fields.
void write_surface_vtu(const std::string& path, const SurfaceMesh& mesh, const std::vector<PointField>& fields = {});
/// Writes a tet volume as an ASCII .vtu, with point fields.
void write_volume_vtu(const std::string& path, const TetMesh& mesh, const std::vector<PointField>& fields = {});
/// Writes points only (e.g. control points) as an ASCII .vtu of vertex cells.
void write_points_vtu(const std::string& path, const Points& points, const std::vector<PointField>& fields = {});
/// Writes a surface as Wavefront OBJ.
void write_obj(const std::string& path, const SurfaceMesh& mesh);
/// Writes a tet volume as Gmsh 4.1 ASCII .msh: one volume entity holding every node
/// (tags 1..#V in order) and every tet (type 4); read_volume reads it back exactly.
void write_gmsh41(const std::string& path, const TetMesh& mesh);

}  // namespace tb
