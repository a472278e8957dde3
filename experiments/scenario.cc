#include "scenario.h"

#include <filesystem>
#include <fstream>

#include "strict_json.h"

namespace tb {
namespace fs = std::filesystem;

PointLoad Scenario::load_at(int frame) const {
  PointLoad l = load;
  if (ramp_frames > 0 && frame < ramp_frames) l.force *= static_cast<double>(frame + 1) / ramp_frames;
  return l;
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
  s.source = j;
  s.name = o.text("name", std::nullopt);
  if (s.name.empty() || s.name.find('/') != std::string::npos) o.fail("name", "must be a non-empty folder name");
  o.text("description", "");
  s.mesh = parse_mesh_recipe(o.raw("mesh"), base, where + ".mesh");

  StrictObject m = o.object("material", true);
  s.material.youngs_modulus = m.number("youngs_modulus", 3000, 1e-12, 1e15);
  if (s.material.youngs_modulus <= 0) m.fail("youngs_modulus", "must be positive");
  s.material.poisson_ratio = m.number("poisson_ratio", 0.45, -0.999, 0.4999);
  s.material.density = m.number("density", 1000, 1e-12, 1e9);
  m.finish();

  StrictObject sup = o.object("support");
  s.support.min = sup.vec3("min", std::nullopt);
  s.support.max = sup.vec3("max", std::nullopt);
  if ((s.support.min.array() > s.support.max.array()).any()) sup.fail("min", "exceeds max");
  sup.finish();

  StrictObject l = o.object("load");
  s.load.point = l.vec3("point", std::nullopt);
  s.load.force = l.vec3("force", std::nullopt);
  s.ramp_frames = l.integer("ramp_frames", 0, 0, 1000000);
  s.load.disc_radius = l.number("disc_radius", 0, 0, 1e9);  // m; 0: the paper's point load
  l.finish();

  StrictObject f = o.object("frames", true);
  s.max_frames = f.integer("max", 2000, 1, 100000000);
  s.static_frames = f.integer("static", 20, 1, 1000000);
  s.steady_tolerance = f.number("steady_tolerance", 1e-6, 0, 1);
  s.divergence_factor = f.number("divergence_factor", 10, 1e-6, 1e9);
  f.finish();

  StrictObject obs = o.object("observe", true);
  s.observed = obs.text("vertices", "top", {"top", "all"});
  s.top_tolerance = obs.number("top_tolerance", 1e-9, 0, 1e9);
  obs.finish();

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
      run.parameters = resolve_parameters(info->parameters, mo.raw("parameters"), mo.where() + ".parameters");
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

}  // namespace

Experiment load_experiment(const std::string& path) {
  const nlohmann::json j = read_json(path);
  Experiment e;
  if (j.is_object() && j.contains("scenarios")) {
    StrictObject o(j, fs::path(path).filename().string());
    e.name = o.text("name", std::nullopt);
    o.text("description", "");
    const nlohmann::json& list = o.raw("scenarios");
    if (!list.is_array() || list.empty()) o.fail("scenarios", "must be a non-empty array of scenario file paths");
    o.finish();
    for (const auto& item : list) {
      if (!item.is_string()) o.fail("scenarios", "entries must be file paths (strings)");
      const std::string file = (fs::path(path).parent_path() / item.get<std::string>()).lexically_normal().string();
      e.scenarios.push_back(parse_scenario(read_json(file), file));
    }
  } else {
    Scenario s = parse_scenario(j, path);
    e.name = s.name;
    e.scenarios.push_back(std::move(s));
  }
  return e;
}

}  // namespace tb
