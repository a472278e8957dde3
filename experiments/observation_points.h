// The observation points of a suite role (docs/benchmark_format.md), read from the
// committed results/observation_points/<role>.csv, <role>_interior.csv and
// <role>.json (analysis/observation_points.py writes them) and placed on the
// scenario as the runner builds it: where a file gives no coordinates (third-party
// geometry), the liver's `source_vertex` is a vertex of the built fine surface and
// a Truth Cube bead's `table_row` is a row of the scenario's probes (its beads at
// rest, in the bead table's order: scenario_tools.h). The converged answer the
// files also hold (ux, uy, uz) is never read here.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_types.h"
#include "scenario.h"

namespace tb {

/// Where `tissuebench export` reads the observation points by default: the
/// repository's results/observation_points.
std::string default_observation_points_dir();

/// `path` relative to the repository when inside it (a scenario file, the committed
/// points), else as given: what a package records, the same on every machine.
std::string shown_path(const std::string& path);

struct ObservationPoints {
  /// The role whose committed files gave the points (observation_role); empty for a
  /// scenario's own points.
  std::string role;
  std::vector<std::string> surface_id;     ///< #S ids, "s<vertex of the suite mesh>"
  std::vector<std::string> surface_patch;  ///< #S patch names ("top_face", "whole_surface")
  Points surface = Points(0, 3);           ///< #S by 3 rest positions, m
  std::vector<std::string> interior_id;    ///< #I ids: probes "p<n>", beads "b<table row>"
  Points interior = Points(0, 3);          ///< #I by 3 rest positions, m
  /// Where they come from: the files read, or the scenario's own observed vertices;
  /// the patch and its description.
  nlohmann::json source = nlohmann::json::object();
};

/// The role whose points and converged answer `role` takes in `dir`: its own files
/// when <role>.json is there, else, for a finer mesh's study role (<base>_10k, _35k,
/// _100k: the suite's problem on another mesh, which
/// analysis/prediction_leaderboard.py's same_problem checks), its base role's when
/// those are. The points are coordinates, or vertices and beads that a refined mesh
/// keeps (the liver's surface subdivided keeps its vertices first; the beads are the
/// scenario's probes). Otherwise `role` itself (reading then names the missing file).
std::string observation_role(const std::string& dir, const std::string& role);

/// The points of observation_role(dir, scenario.role) in `dir` (<role>.csv, <role>.json, and
/// <role>_interior.csv when the JSON counts interior points), placed on `surface`
/// (the scenario's built fine surface) and the scenario's probes. Throws
/// std::runtime_error, one line naming the file and the problem: a missing file, a
/// missing column, a malformed number, a source_vertex outside the surface, a
/// table_row outside the probes, a count unlike the JSON's.
ObservationPoints read_observation_points(const std::string& dir, const Scenario& scenario, const SurfaceMesh& surface);

/// A scenario with no role: its own observed vertices (observe.vertices: the top face
/// or the whole surface, observed_vertices in runner.h) as "s<vertex>", and its probes
/// as "p<n>".
ObservationPoints scenario_observation_points(const Scenario& scenario, const SurfaceMesh& surface);

}  // namespace tb
