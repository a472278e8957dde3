// The problem package of the open benchmark (docs/benchmark_format.md, "The problem
// package"): one scenario as files a simulator outside this tree reads, without
// this code or its scenario schema: the fine surface (OBJ, STL) and tet volume (VTU,
// Gmsh 4.1) the runner builds, the material and the law the answer is computed
// with, the clamped vertices, each load's and tool's value at every frame, the
// observation points where a prediction is scored, and the schemas of problem.json
// and of a submission. No converged answer is written.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mesh_types.h"
#include "observation_points.h"
#include "scenario.h"

namespace tb {

/// The format problem.json declares; a reader refuses any other.
inline constexpr const char* kProblemFormat = "tissuebench-problem/1";
/// The format a submission declares (submission.schema.json).
inline constexpr const char* kSubmissionFormat = "tissuebench-submission/1";

/// The repository's docs/schemas: problem.schema.json and submission.schema.json.
std::string default_schema_dir();

/// The frames of a package: every frame until the last load or tool value change,
/// and at least the scenario's static frames (the frames its reference case
/// solves, the last of which holds the converged answer).
int package_frames(const Scenario& scenario);

/// The frame interval, s: the time_step of the scenario's transient reference
/// (its fem_dynamic case), else of its first case that has one, else 0.01 (the
/// models' default, models/parameters.h).
double package_time_step(const Scenario& scenario);

/// problem.json's content for `scenario` (resolved on its mesh: resolve_on_mesh)
/// on `mesh`, with `points` observed; the file names it refers to are the
/// package's. Deterministic: the same inputs give the same bytes.
nlohmann::json problem_json(const Scenario& scenario, const HybridMesh& mesh, const ObservationPoints& points);

/// Writes every file of the package into the existing, empty folder `dir`:
/// problem.json, surface.obj, surface.stl, volume.vtu, volume.msh,
/// support_vertices.csv, load_<k>.csv, tool_<k>.csv, observation_points.csv,
/// observation_interior.csv (if there are interior points), and copies of
/// `schema_dir`'s problem.schema.json and submission.schema.json. Throws
/// std::runtime_error naming the file on failure (a missing schema, a mesh
/// without a fine volume).
void write_problem_files(const Scenario& scenario, const HybridMesh& mesh, const ObservationPoints& points,
                         const std::string& dir, const std::string& schema_dir);

/// write_problem_files into a fresh staging folder beside `dir` (staged_folder.h);
/// returns it. On failure the staging folder is removed and the error rethrown.
std::string stage_problem_package(const Scenario& scenario, const HybridMesh& mesh, const ObservationPoints& points,
                                  const std::string& dir, const std::string& schema_dir);

/// write_problem_files into a staging folder beside `dir`, then moved into place
/// (staged_folder.h): `dir` is the previous folder, or the whole new package.
void write_problem_package(const Scenario& scenario, const HybridMesh& mesh, const ObservationPoints& points,
                           const std::string& dir, const std::string& schema_dir);

struct ExportOptions {
  std::string out_dir;         ///< the packages go to <out_dir>/<scenario name>/
  std::string only_scenario;   ///< a scenario's name or role; empty: every scenario
  std::string mesh_cache_dir;  ///< build_mesh_cached's cache; empty: none
  std::string observation_points_dir = default_observation_points_dir();
  std::string schema_dir = default_schema_dir();
  std::function<void(const std::string&)> progress;  ///< a line of progress; unset: silent
};

/// `tissuebench export`: for each selected scenario of `experiment` builds its
/// meshes as the runner does (build_mesh_cached, resolve_on_mesh, check_on_mesh),
/// reads its role's observation points (a scenario without a role: its own,
/// scenario_observation_points) and stages its package; once every one is staged,
/// moves them into place, so a failure leaves none written. Returns the folders
/// written. Throws std::runtime_error, one line naming the experiment file or the
/// file at fault: an unknown --scenario, an unwritable folder, missing points.
std::vector<std::string> export_problem_packages(const Experiment& experiment, const std::string& experiment_file,
                                                 const ExportOptions& options);

}  // namespace tb
