// Resource limits stated before a run starts (docs/robustness.md): the size of a
// scenario's meshes and the memory of each of its cases, estimated from the mesh
// recipe and the model parameters before any mesh is built, against a limit (the
// machine's available memory, or `tissuebench run --max-memory`). A scenario that
// would not fit stops with one line: what it needs, the limit, the key to change.
#pragma once

#include <string>

#include "scenario.h"

namespace tb {

/// A scenario's meshes as its recipe will build them, estimated without meshing.
struct MeshSizeEstimate {
  double surface_vertices = 0;  ///< exact before refinement (cube, shape, file), x 4^refine_levels
  double surface_volume = 0;    ///< m^3 enclosed, after unit_scale
  /// TetGen's fine tets: the larger of 2 volume / max_volume (max_volume x 8^-refine_levels)
  /// and 7 surface vertices (fits the committed runs within 1.3x: cube 17 821 tets,
  /// liver 14 415, 100k-vertex cube 632 101; results/*/run.json "mesh").
  double fine_tets = 0;
  double fine_nodes = 0;  ///< fine_tets / 4 (the committed runs: 4.2-6.4 tets per node)
  /// The recipe key that sets the size, for the message (e.g. "mesh.refine_levels").
  std::string size_key;
};

/// Reads the surface file of a files recipe (its vertex count and volume) or makes
/// the shape's or the cube's surface; no volume meshing. Throws what the readers throw.
MeshSizeEstimate estimate_mesh_size(const MeshRecipe& recipe);

/// Bytes a run of `run` needs on meshes of `size` (the process, the meshes and the
/// model's own matrices); `what` is set to the part that dominates, in words.
double estimate_case_bytes(const ModelRun& run, const MeshSizeEstimate& size, std::string& what);

/// MemAvailable of /proc/meminfo, in bytes; 0 where unknown.
double available_memory_bytes();

/// Throws std::runtime_error, one line naming the file, the scenario, the case, the
/// estimate, the limit (`limit_source`: "--max-memory" or "available memory") and the
/// key to change, when a case of `experiment` that `only_scenario` / `only_case`
/// select (empty: all) would need more than `limit_bytes`.
void check_memory(const Experiment& experiment, const std::string& only_scenario, const std::string& only_case,
                  double limit_bytes, const std::string& limit_source);

}  // namespace tb
