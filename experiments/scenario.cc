#include "scenario.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>

#include "strict_json.h"
#include "sweep.h"

namespace tb {
namespace fs = std::filesystem;

namespace {
nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
}  // namespace

nlohmann::json Experiment::to_json() const {
  nlohmann::json j;
  j["name"] = name;
  j["description"] = description;
  j["reference"] = reference;
  j["scenarios"] = nlohmann::json::array();
  for (const Scenario& s : scenarios) {
    nlohmann::json cases = nlohmann::json::array();
    for (const ModelRun& run : s.models) cases.push_back(run.case_name);
    nlohmann::json entry = {{"name", s.name}, {"file", s.file}, {"cases", cases}};
    if (!s.sweep_base.empty())
      entry["sweep"] = {{"base", s.sweep_base}, {"values", s.sweep_values}, {"keys", s.sweep_keys}};
    j["scenarios"].push_back(entry);
  }
  return j;
}

nlohmann::json Scenario::to_json() const {
  nlohmann::json j;
  j["name"] = name;
  j["description"] = description;
  j["file"] = file;
  j["mesh"] = mesh.to_json();
  j["material"] = {{"youngs_modulus", material.youngs_modulus},
                   {"poisson_ratio", material.poisson_ratio},
                   {"density", material.density}};
  j["support"] = {{"min", vec(support.min)}, {"max", vec(support.max)}};
  if (support_lowest_fraction >= 0) j["support"]["lowest_fraction"] = support_lowest_fraction;
  j["load"] = {
      {"at", load_placement}, {"point", vec(load.point)}, {"force", vec(load.force)}, {"ramp_frames", ramp_frames}};
  if (load_placement != "point") j["load"]["point_given"] = vec(load_point_given);
  j["frames"] = {{"max", max_frames},
                 {"static", static_frames},
                 {"steady_tolerance", steady_tolerance},
                 {"divergence_factor", divergence_factor}};
  j["observe"] = {{"vertices", observed}, {"top_tolerance", top_tolerance}};
  j["output"] = {{"series_every", series_every}};
  return j;
}

nlohmann::json Scenario::to_json_with_models() const {
  nlohmann::json j = to_json();
  j["models"] = nlohmann::json::array();
  for (const ModelRun& run : models)
    j["models"].push_back({{"case", run.case_name},
                           {"model", run.model},
                           {"parameters", run.parameters.to_json()},
                           {"parameters_given", run.parameters_given}});
  if (!sweep_base.empty()) j["sweep"] = {{"base", sweep_base}, {"values", sweep_values}, {"keys", sweep_keys}};
  return j;
}

void resolve_on_mesh(Scenario& s, const SurfaceMesh& surface) {
  const Points& V = surface.V;
  if (V.rows() == 0) throw std::invalid_argument(s.name + ": the fine surface has no vertices");
  if (s.support_lowest_fraction >= 0) {
    const double zmin = V.col(2).minCoeff(), zmax = V.col(2).maxCoeff();
    s.support.min = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
    s.support.max = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    s.support.max.z() = zmin + s.support_lowest_fraction * (zmax - zmin);
  }
  if (s.load_placement == "highest_surface_vertex") {
    Eigen::Index top = 0;
    V.col(2).maxCoeff(&top);  // the lowest index among equally high vertices
    s.load.point = V.row(top).transpose();
  } else if (s.load_placement == "nearest_surface_vertex") {
    s.load_point_given = s.load.point;
    Eigen::Index nearest = 0;
    (V.rowwise() - s.load.point.transpose()).rowwise().squaredNorm().minCoeff(&nearest);
    s.load.point = V.row(nearest).transpose();
  }
}

LoadCase Scenario::load_case() const {
  LoadCase c;
  c.support = support;
  c.loads.push_back(load.disc_radius > 0 ? Load::surface_traction(load.point, load.disc_radius, "load")
                                         : Load::point_force(load.point, "load"));
  return c;
}

void Scenario::loads_at(int frame, FrameLoads& out) const {
  out.values.resize(1);
  out.values[0] = load.force;
  if (ramp_frames > 0 && frame < ramp_frames) out.values[0] *= static_cast<double>(frame + 1) / ramp_frames;
}

namespace {

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ScenarioError(path + ": cannot open file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw ScenarioError(path + ": malformed JSON: " + e.what());
  }
}

Scenario parse_scenario(const nlohmann::json& j, const std::string& file) {
  const std::string base = fs::path(file).parent_path().string();
  const std::string where = fs::path(file).filename().string();
  StrictObject o(j, where);
  Scenario s;
  s.file = file;
  s.name = o.text("name", std::nullopt);
  if (s.name.empty() || s.name.find('/') != std::string::npos) o.fail("name", "must be a non-empty folder name");
  s.description = o.text("description", "");
  s.mesh = parse_mesh_recipe(o.raw("mesh"), base, where + ".mesh");

  StrictObject m = o.object("material", true);
  // Fallbacks are the defaults of the fields they fill (Material in models/model.h,
  // Scenario in scenario.h): each default is stated once.
  s.material.youngs_modulus = m.number("youngs_modulus", s.material.youngs_modulus, 1e-12, 1e15);
  if (s.material.youngs_modulus <= 0) m.fail("youngs_modulus", "must be positive");
  s.material.poisson_ratio = m.number("poisson_ratio", s.material.poisson_ratio, -0.999, 0.4999);
  s.material.density = m.number("density", s.material.density, 1e-12, 1e9);
  m.finish();

  // Support: a box, or the lowest fraction of the surface's height (resolved on
  // the mesh by resolve_on_mesh).
  StrictObject sup = o.object("support");
  if (sup.has("lowest_fraction")) {
    if (sup.has("min") || sup.has("max")) sup.fail("lowest_fraction", "give either min/max or lowest_fraction");
    s.support_lowest_fraction = sup.number("lowest_fraction", std::nullopt, 0, 1);
  } else {
    s.support.min = sup.vec3("min", std::nullopt);
    s.support.max = sup.vec3("max", std::nullopt);
    if ((s.support.min.array() > s.support.max.array()).any()) sup.fail("min", "exceeds max");
  }
  sup.finish();

  // Load point: as given, the highest surface vertex, or the surface vertex
  // nearest a given point (resolved on the mesh by resolve_on_mesh).
  StrictObject l = o.object("load");
  s.load_placement = l.text("at", s.load_placement, {"point", "highest_surface_vertex", "nearest_surface_vertex"});
  if (s.load_placement == "highest_surface_vertex") {
    if (l.has("point")) l.fail("point", "not used with at = highest_surface_vertex");
  } else {
    s.load.point = l.vec3("point", std::nullopt);
  }
  s.load.force = l.vec3("force", std::nullopt);
  s.ramp_frames = l.integer("ramp_frames", s.ramp_frames, 0, 1000000);
  s.load.disc_radius = l.number("disc_radius", s.load.disc_radius, 0, 1e9);  // m; 0: the paper's point load
  l.finish();

  StrictObject f = o.object("frames", true);
  s.max_frames = f.integer("max", s.max_frames, 1, 100000000);
  s.static_frames = f.integer("static", s.static_frames, 1, 1000000);
  s.steady_tolerance = f.number("steady_tolerance", s.steady_tolerance, 0, 1);
  s.divergence_factor = f.number("divergence_factor", s.divergence_factor, 1e-6, 1e9);
  f.finish();

  StrictObject obs = o.object("observe", true);
  s.observed = obs.text("vertices", s.observed, {"top", "all"});
  s.top_tolerance = obs.number("top_tolerance", s.top_tolerance, 0, 1e9);
  obs.finish();

  StrictObject out = o.object("output", true);
  s.series_every = out.integer("series_every", s.series_every, 0, 100000000);
  out.finish();

  const nlohmann::json& models = o.raw("models");
  if (!models.is_array() || models.empty()) o.fail("models", "must be a non-empty array");
  for (size_t i = 0; i < models.size(); ++i) {
    StrictObject mo(models[i], where + ".models[" + std::to_string(i) + "]");
    ModelRun run;
    run.model = mo.text("model", std::nullopt);
    run.case_name = mo.text("name", run.model);
    const ModelInfo* info = nullptr;
    try {
      info = &find_model(run.model);
    } catch (const std::invalid_argument& e) {
      mo.fail("model", e.what());
    }
    try {
      run.parameters_given = mo.raw("parameters");
      if (run.parameters_given.is_null()) run.parameters_given = nlohmann::json::object();
      run.parameters = resolve_parameters(info->parameters, run.parameters_given, mo.where() + ".parameters");
    } catch (const std::invalid_argument& e) {
      throw ScenarioError(e.what());
    }
    mo.finish();
    for (const auto& other : s.models)
      if (other.case_name == run.case_name) mo.fail("name", "'" + run.case_name + "' is used twice");
    s.models.push_back(std::move(run));
  }
  o.finish();
  return s;
}

/// Everything a scenario runs, without its name: the resolved scenario and each
/// case's model and resolved parameters.
nlohmann::json what_runs(const Scenario& s) {
  nlohmann::json j = s.to_json();
  j.erase("name");
  j.erase("description");
  j["models"] = nlohmann::json::array();
  for (const ModelRun& run : s.models)
    j["models"].push_back({{"case", run.case_name}, {"model", run.model}, {"parameters", run.parameters.to_json()}});
  return j;
}

}  // namespace

Experiment load_experiment(const std::string& path) {
  const nlohmann::json j = read_json(path);
  Experiment e;
  if (j.is_object() && j.contains("scenarios")) {
    StrictObject o(j, fs::path(path).filename().string());
    e.name = o.text("name", std::nullopt);
    e.description = o.text("description", "");
    e.reference = o.text("reference", "");
    const nlohmann::json& list = o.raw("scenarios");
    if (!list.is_array() || list.empty()) o.fail("scenarios", "must be a non-empty array of scenario file paths");
    const nlohmann::json& sweep = o.raw("sweep");
    o.finish();
    for (const auto& item : list) {
      if (!item.is_string()) o.fail("scenarios", "entries must be file paths (strings)");
      const std::string file = (fs::path(path).parent_path() / item.get<std::string>()).lexically_normal().string();
      const nlohmann::json base = read_json(file);
      if (sweep.is_null()) {
        e.scenarios.push_back(parse_scenario(base, file));
        continue;
      }
      // Each base scenario expanded into the sweep's points (sweep.h).
      const std::string base_name = base.is_object() && base.contains("name") && base["name"].is_string()
                                        ? base["name"].get<std::string>()
                                        : fs::path(file).stem().string();
      std::vector<nlohmann::json> seen;  // what each point runs: a level equal to another point's runs once
      for (SweepPoint& point : expand_sweep(sweep, base, base_name, e.reference, fs::path(path).filename().string())) {
        Scenario s;
        try {
          s = parse_scenario(point.scenario, file);
        } catch (const ScenarioError& err) {
          throw ScenarioError(fs::path(path).filename().string() + ": sweep point '" + point.name + "': " + err.what());
        }
        const nlohmann::json runs = what_runs(s);
        if (std::find(seen.begin(), seen.end(), runs) != seen.end()) continue;  // e.g. a default stated explicitly
        seen.push_back(runs);
        s.sweep_base = base_name;
        s.sweep_values = std::move(point.values);
        s.sweep_keys = std::move(point.keys);
        e.scenarios.push_back(std::move(s));
      }
    }
    for (size_t i = 0; i < e.scenarios.size(); ++i)
      for (size_t k = 0; k < i; ++k)
        if (e.scenarios[i].name == e.scenarios[k].name)
          o.fail("scenarios", "two scenarios are named '" + e.scenarios[i].name + "'");
  } else {
    // A scenario file run alone is an experiment of one scenario; it may name its
    // reference case too.
    nlohmann::json scenario = j;
    if (scenario.is_object() && scenario.contains("reference")) {
      if (!scenario["reference"].is_string())
        throw ScenarioError(fs::path(path).filename().string() + ": reference: must be a case name (string)");
      e.reference = scenario["reference"].get<std::string>();
      scenario.erase("reference");
    }
    Scenario s = parse_scenario(scenario, path);
    e.name = s.name;
    e.description = s.description;
    e.scenarios.push_back(std::move(s));
  }
  if (!e.reference.empty())
    for (const Scenario& s : e.scenarios) {
      bool found = false;
      for (const ModelRun& run : s.models) found = found || run.case_name == e.reference;
      if (!found)
        throw ScenarioError(path + ": reference: scenario '" + s.name + "' has no case named '" + e.reference + "'");
    }
  return e;
}

}  // namespace tb
