// Scenario files (experiments/scenarios/*.json) and experiment files that group
// them (experiments/paper.json). docs/scenario_schema.md gives the schema.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "data_dir.h"
#include "mesh_recipe.h"
#include "scenario_tools.h"
#include "model.h"

namespace tb {

/// The scenario file's `load`: a point force, or with disc_radius > 0 the same total
/// force as a uniform traction on the disc of that radius around `point` on the
/// surface (load_case.h's point_force and surface_traction).
struct PointLoad {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< m, rest configuration
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< N, the full force (after the ramp)
  double disc_radius = 0;                           ///< m; 0: the paper's point load
};

/// One model to run in a scenario: `case_name` names its output folder
/// (e.g. "fem-direct"), `model` the registered model.
struct ModelRun {
  std::string case_name;
  std::string model;
  Parameters parameters;            ///< every declared parameter, resolved
  nlohmann::json parameters_given;  ///< the ones the scenario set (an object)
  /// A dynamic case's own frame budget (0: the scenario's frames.max): the dynamic
  /// reference of a transient needs only the frames that are compared.
  int max_frames = 0;
};

struct Scenario {
  std::string name;
  /// The scenario's role in its experiment (e.g. "cube_pull"): how the analysis
  /// finds it (experiment.json); empty when the experiment gives none.
  std::string role;
  std::string description;
  std::string file;
  MeshRecipe mesh;
  Material material;
  SupportBox support;
  double support_lowest_fraction = -1;   ///< >= 0: support = the lowest fraction of the height (resolve_on_mesh)
  bool has_load = true;                  ///< the file gives the paper's `load`
  PointLoad load;                        ///< the full load
  std::string load_placement = "point";  ///< "point", "highest_surface_vertex" or "nearest_surface_vertex"
  Eigen::Vector3d load_point_given = Eigen::Vector3d::Zero();  ///< nearest_surface_vertex: the point given
  int ramp_frames = 0;                                         ///< load scaled by (frame + 1) / ramp_frames until then
  std::vector<ScenarioLoad> loads;  ///< "loads": after `load`, in file order
  std::vector<ScenarioTool> tools;  ///< "tools", in file order
  Points probes = Points(0, 3);     ///< "probes": #P by 3 interior points
  nlohmann::json probes_source = nlohmann::json::object();  ///< where they come from, if not the file (scenario_tools.h)
  int max_frames = 2000;                                       ///< frame budget of dynamic models
  int static_frames = 20;                                      ///< frames of static models (timing samples)
  double steady_tolerance = 1e-6;                              ///< max per-frame change / max displacement
  double divergence_factor = 10;                               ///< |u| beyond this x bounding-box diagonal: diverged
  std::string observed = "top";                                ///< "top": vertices on the top plane; "all"
  int series_every = 0;         ///< > 0: a dynamic case writes its surface every N frames (.pvd + .vtu)
  double top_tolerance = 1e-9;  ///< m
  std::vector<ModelRun> models;
  /// Cases left out because their model does not take one of the scenario's loads
  /// or tools (an experiment with "unsupported_cases": "skip"): {case, reason}.
  std::vector<std::pair<std::string, std::string>> not_run;
  /// Set when the scenario is a point of a sweep (sweep.h): its base scenario's
  /// name, and {label: value} / {label: key path} of the factors set.
  std::string sweep_base;
  nlohmann::json sweep_values = nlohmann::json::object(), sweep_keys = nlohmann::json::object();

  /// The support and the loads as every model receives them (load_case.h); call
  /// resolve_on_mesh first when the scenario places them relative to the mesh.
  LoadCase load_case() const;
  /// Frames during which some load's or tool's value still changes (the longest
  /// ramp or path): static models run at least these, dynamic ones test for the
  /// steady state only after them.
  int changing_frames() const;
  /// Each load's and tool's value at frame `frame` (0-based), by its schedule. No
  /// allocation once `out` has its sizes.
  void loads_at(int frame, FrameLoads& out) const;
  /// Every value as resolved, defaults included (run.json "scenario_resolved");
  /// the model list is not included (each run.json holds its own model).
  nlohmann::json to_json() const;
  /// to_json() and the model list: each case's name, model, resolved and given
  /// parameters (`tissuebench resolve`).
  nlohmann::json to_json_with_models() const;
};

/// Fills what a scenario states relative to its mesh: the support box of
/// support.lowest_fraction (z up to z_min + fraction (z_max - z_min) of the fine
/// surface) and the load point of load.at. Called by the runner once the meshes
/// are built; a scenario with a plain box and point is unchanged.
void resolve_on_mesh(Scenario& scenario, const SurfaceMesh& surface);

/// Checks what the scenario places on its mesh before any case runs: each tool
/// holds at least one surface vertex and none in the support (tool_placement.h),
/// and each probe lies inside the fine surface. Throws std::invalid_argument naming
/// the scenario key (probes outside: each listed with its distance to the surface).
void check_on_mesh(const Scenario& scenario, const SurfaceMesh& surface);

struct Experiment {
  std::string name;
  std::string description;
  /// The case every other is compared with by the analysis (e.g. "fem-direct");
  /// empty: none declared.
  std::string reference;
  /// The case a dynamic case's first frames are compared with (the implicit-Euler
  /// fem_dynamic, docs/suite.md), in the scenarios that have it; empty: none.
  std::string transient_reference;
  /// Cases that solve the reference's problem under another material law
  /// (analysis/law_sensitivity.py compares them; the leaderboard never ranks them),
  /// in the scenarios that have them; empty: none.
  std::vector<std::string> law_references;
  std::vector<Scenario> scenarios;
  /// Values set in every scenario by `tissuebench run --set KEY=VALUE`, in order
  /// ([[key, value], ...]); recorded in experiment.json.
  nlohmann::json overrides = nlohmann::json::array();
  /// "unsupported_cases": "skip" (load_experiment leaves such cases out).
  bool skip_unsupported = false;

  /// What the analysis needs to know of the experiment (written as
  /// results/<name>/experiment.json): name, description, reference, and per
  /// scenario its name, file, role (if given) and cases in the order it runs them.
  nlohmann::json to_json() const;
};

/// Reads a scenario file, or an experiment file ({"name", "scenarios": [...]}),
/// following scenario files' "extends" and combining an experiment's "models"
/// with each scenario's (docs/scenario_schema.md). Data references are read from
/// `data`. Throws ScenarioError naming the file and key.
/// `tissuebench run FILE --model NAME` where NAME is a registered model that no case
/// of the experiment runs: a case NAME of that model, with its default parameters,
/// added to every scenario (where it takes the loads and tools, if the experiment
/// skips unsupported cases), so a model is scored on a whole suite. Returns false
/// (and changes nothing) when some case already has that name or model.
bool add_model_everywhere(Experiment& experiment, const std::string& model);

/// `tissuebench run FILE --skip-scenario NAME ...`: the scenarios of these names left
/// out of the experiment (its index then lists the others only; e.g. the suite's
/// gates leave out its larger sizes). Throws ScenarioError naming a name that is no
/// scenario of the experiment, or when no scenario is left.
void leave_out_scenarios(Experiment& experiment, const std::vector<std::string>& names);

/// `overrides` ([[dotted key, value], ...]) are set in every scenario after its
/// `extends` and the experiment's models are applied (set_scenario_key, sweep.h).
Experiment load_experiment(const std::string& path, const DataDir& data = data_dir(),
                           const nlohmann::json& overrides = nlohmann::json::array());

}  // namespace tb
