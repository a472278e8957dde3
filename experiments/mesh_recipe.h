// How a scenario's meshes are made: the paper's cube, a generated shape
// (meshing/shapes.h) or files, turned into a HybridMesh (meshing/). Shared by `tissuebench run` and `tissuebench mesh`.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cube_generator.h"
#include "data_dir.h"
#include "hybrid_builder.h"
#include "mesh_types.h"
#include "shapes.h"
#include "strict_json.h"

namespace tb {

/// The paper's cube fine volume: TetGen volume bound (m^3) giving 3114 nodes and
/// 17 821 tets (paper: 3028 / 17 044). The default "max_volume" of cube recipes
/// (other recipes: none), so `tissuebench mesh --cube` builds the scenarios' cube.
constexpr double kPaperCubeFineMaxVolume = 9e-8;

struct MeshRecipe {
  enum class Kind { Cube, Files, Shape } kind = Kind::Cube;
  CubeSpec cube;
  ShapeSpec shape;  ///< Shape: which generated surface, at which resolution
  /// Cube: a mirror-symmetric fine volume (meshing/mirror_symmetric_volume.h).
  /// Off by default: it also changes the hybrid's coarse selection (made from the
  /// fine volume's vertices), and the paper scenarios keep the mesh they measure.
  bool symmetric_fine_volume = false;
  std::string surface_file;  ///< Files: the fine surface (the path read)
  std::string coarse_file;   ///< Files: optional given coarse volume (the path read)
  /// Files given as data references ("data:meshes/liver.msh", data_dir.h): the
  /// reference as written, recorded in to_json() instead of the machine's path.
  std::string surface_reference, coarse_reference;
  double unit_scale = 1.0;  ///< Files: multiply coordinates (0.01 for cm)
  bool repair_self_intersections = false;
  ControlPointRule control_points = ControlPointRule::NearestToCoarseSurfaceNodes;
  HybridBuildOptions build;       ///< fine TetGen bounds, coarse target
  bool build_fine_volume = true;  ///< Files + coarse: also mesh the fine volume (FEM reference)
  /// Uniform refinement (reference convergence): the surface's triangles
  /// are split in four this many times, keeping its vertices first and bitwise
  /// (meshing/surface_subdivision.h), and the fine TetGen max_volume is scaled by
  /// 8^-refine_levels. 0: the surface as generated or read.
  int refine_levels = 0;

  /// Every value, defaults included, in the scenario file's schema (run.json).
  nlohmann::json to_json() const;
};

/// What building reported, written to summary.json / run.json.
struct MeshReport {
  int self_intersections_found = 0;
  bool repaired = false;
  int vertices_before_repair = 0;  ///< the repair may remove and re-add vertices
  int flipped_triangles = 0;
  /// Doubts about the input that do not stop the build (a unit scale that looks
  /// wrong); each is also printed to stderr when found.
  std::vector<std::string> warnings;
  nlohmann::json to_json(const HybridMesh& mesh) const;
};

/// Parses the scenario's "mesh" object strictly; relative file paths are resolved
/// against the directory of the file that set them (`base_dir` if the object knows
/// no origins), data references against `data` (a missing data file is an error).
MeshRecipe parse_mesh_recipe(StrictObject o, const std::string& base_dir, const DataDir& data);
/// The same for a bare JSON object; `where` prefixes error messages.
MeshRecipe parse_mesh_recipe(const nlohmann::json& j, const std::string& base_dir, const std::string& where,
                             const DataDir& data = data_dir());

/// Reads/generates, checks and builds. Self-intersections are an error unless the
/// recipe asks for repair. A surface whose bounding-box diagonal (after
/// unit_scale) is above 10 m or below 1 mm gets a warning in report.warnings and
/// on stderr. Throws MeshError / std::runtime_error.
HybridMesh build_mesh(const MeshRecipe& recipe, MeshReport& report);

/// Writes fine/coarse volumes, control points, the surface (VTU, OBJ) and
/// summary.json into `dir`, staged and renamed into place (staged_folder.h): an
/// interrupted write leaves the previous folder or the whole new one.
void write_mesh_folder(const std::string& dir, const HybridMesh& mesh, const MeshReport& report);

/// A hash (16 hex digits) of everything that determines the built mesh: the
/// recipe's values and the bytes of its input files.
std::string mesh_content_hash(const MeshRecipe& recipe);

/// build_mesh through a disk cache: cache_dir/<mesh_content_hash>/ holds the mesh
/// folder (write_mesh_folder) and is read back instead of meshing again. The
/// pipeline is deterministic and VTU keeps 17 digits, so a cached mesh is the
/// built one exactly. Empty cache_dir: no cache. `hit` tells which happened.
HybridMesh build_mesh_cached(const MeshRecipe& recipe, MeshReport& report, const std::string& cache_dir, bool& hit);

}  // namespace tb
