// Scenario files (experiments/scenarios/*.json) and experiment files that group
// them (experiments/paper.json). See README "Scenario files" for the schema.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_recipe.h"
#include "model.h"

namespace tb {

/// One model to run in a scenario: `case_name` names its output folder
/// (e.g. "fem-direct"), `model` the registered model.
struct ModelRun {
  std::string case_name;
  std::string model;
  Parameters parameters;            ///< every declared parameter, resolved
  nlohmann::json parameters_given;  ///< the ones the scenario set (an object)
};

struct Scenario {
  std::string name;
  std::string description;
  std::string file;
  MeshRecipe mesh;
  Material material;
  SupportBox support;
  double support_lowest_fraction = -1;   ///< >= 0: support = the lowest fraction of the height (resolve_on_mesh)
  PointLoad load;                        ///< the full load
  std::string load_placement = "point";  ///< "point", "highest_surface_vertex" or "nearest_surface_vertex"
  Eigen::Vector3d load_point_given = Eigen::Vector3d::Zero();  ///< nearest_surface_vertex: the point given
  int ramp_frames = 0;                                         ///< load scaled by (frame + 1) / ramp_frames until then
  int max_frames = 2000;                                       ///< frame budget of dynamic models
  int static_frames = 20;                                      ///< frames of static models (timing samples)
  double steady_tolerance = 1e-6;                              ///< max per-frame change / max displacement
  double divergence_factor = 10;                               ///< |u| beyond this x bounding-box diagonal: diverged
  std::string observed = "top";                                ///< "top": vertices on the top plane; "all"
  int series_every = 0;         ///< > 0: a dynamic case writes its surface every N frames (.pvd + .vtu)
  double top_tolerance = 1e-9;  ///< m
  std::vector<ModelRun> models;
  /// Set when the scenario is a point of a sweep (sweep.h): its base scenario's
  /// name, and {label: value} / {label: key path} of the factors set.
  std::string sweep_base;
  nlohmann::json sweep_values = nlohmann::json::object(), sweep_keys = nlohmann::json::object();

  /// The load of frame `frame` (0-based): ramped, then constant.
  PointLoad load_at(int frame) const;
  /// Every value as resolved, defaults included (run.json "scenario_resolved");
  /// the model list is not included (each run.json holds its own model).
  nlohmann::json to_json() const;
};

/// Fills what a scenario states relative to its mesh: the support box of
/// support.lowest_fraction (z up to z_min + fraction (z_max - z_min) of the fine
/// surface) and the load point of load.at. Called by the runner once the meshes
/// are built; a scenario with a plain box and point is unchanged.
void resolve_on_mesh(Scenario& scenario, const SurfaceMesh& surface);

struct Experiment {
  std::string name;
  std::string description;
  /// The case every other is compared with by the analysis (e.g. "fem-direct");
  /// empty: none declared.
  std::string reference;
  std::vector<Scenario> scenarios;

  /// What the analysis needs to know of the experiment (written as
  /// results/<name>/experiment.json): name, description, reference, and per
  /// scenario its cases in the order the file lists them.
  nlohmann::json to_json() const;
};

/// Reads a scenario file, or an experiment file ({"name", "scenarios": [paths]}).
/// Throws ScenarioError naming the file and key.
Experiment load_experiment(const std::string& path);

}  // namespace tb
