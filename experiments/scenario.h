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
  Parameters parameters;
};

struct Scenario {
  std::string name;
  std::string file;
  nlohmann::json source;  ///< the scenario as read, written beside every result
  MeshRecipe mesh;
  Material material;
  SupportBox support;
  PointLoad load;                  ///< the full load
  int ramp_frames = 0;             ///< load scaled by (frame + 1) / ramp_frames until then
  int max_frames = 2000;           ///< frame budget of dynamic models
  int static_frames = 20;          ///< frames of static models (timing samples)
  double steady_tolerance = 1e-6;  ///< max per-frame change / max displacement
  double divergence_factor = 10;   ///< |u| beyond this x bounding-box diagonal: diverged
  std::string observed = "top";    ///< "top": vertices on the top plane; "all"
  double top_tolerance = 1e-9;     ///< m
  std::vector<ModelRun> models;

  /// The load of frame `frame` (0-based): ramped, then constant.
  PointLoad load_at(int frame) const;
};

struct Experiment {
  std::string name;
  std::vector<Scenario> scenarios;
};

/// Reads a scenario file, or an experiment file ({"name", "scenarios": [paths]}).
/// Throws ScenarioError naming the file and key.
Experiment load_experiment(const std::string& path);

}  // namespace tb
