#include "scenario.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>

#include "point_location.h"
#include "strict_json.h"
#include "sweep.h"
#include "tool_placement.h"

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
  if (!transient_reference.empty()) j["transient_reference"] = transient_reference;
  if (!law_references.empty()) j["law_references"] = law_references;
  if (!overrides.empty()) j["overrides"] = overrides;
  j["scenarios"] = nlohmann::json::array();
  for (const Scenario& s : scenarios) {
    nlohmann::json cases = nlohmann::json::array();
    for (const ModelRun& run : s.models) cases.push_back(run.case_name);
    nlohmann::json entry = {{"name", s.name}, {"file", s.file}, {"cases", cases}};
    if (!s.role.empty()) entry["role"] = s.role;
    if (!s.not_run.empty()) {
      entry["not_run"] = nlohmann::json::array();
      for (const auto& [case_name, reason] : s.not_run)
        entry["not_run"].push_back({{"case", case_name}, {"reason", reason}});
    }
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
  if (has_load) {
    j["load"] = {
        {"at", load_placement}, {"point", vec(load.point)}, {"force", vec(load.force)}, {"ramp_frames", ramp_frames}};
    if (load_placement != "point") j["load"]["point_given"] = vec(load_point_given);
  }
  for (const ScenarioLoad& l : loads) j["loads"].push_back(tb::to_json(l));
  for (const ScenarioTool& t : tools) j["tools"].push_back(tb::to_json(t));
  if (!probes_source.empty()) {
    j["probes"] = probes_source;  // points from a third-party table: its name and frame, not a copy
  } else if (probes.rows() > 0) {
    j["probes"] = nlohmann::json::array();
    for (Eigen::Index p = 0; p < probes.rows(); ++p) j["probes"].push_back(vec(probes.row(p).transpose()));
  }
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
  for (size_t i = 0; i < models.size(); ++i)
    if (models[i].max_frames > 0) j["models"][i]["max_frames"] = models[i].max_frames;
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
  if (has_load)
    c.loads.push_back(load.disc_radius > 0 ? Load::surface_traction(load.point, load.disc_radius, "load")
                                           : Load::point_force(load.point, "load"));
  for (const ScenarioLoad& l : loads) c.loads.push_back(l.load);
  for (const ScenarioTool& t : tools) c.tools.push_back(t.tool);
  return c;
}

int Scenario::changing_frames() const {
  int n = has_load ? ramp_frames : 0;
  const auto frames_of = [](const Schedule& s) { return s.path.empty() ? s.ramp_frames : s.path.back().first + 1; };
  for (const ScenarioLoad& l : loads) n = std::max(n, frames_of(l.schedule));
  for (const ScenarioTool& t : tools) n = std::max(n, frames_of(t.schedule));
  return n;
}

void check_on_mesh(const Scenario& s, const SurfaceMesh& surface) {
  const std::string where = fs::path(s.file).filename().string() + ": ";
  for (const ScenarioTool& t : s.tools) try {
      tool_vertices(t.tool, surface, s.support);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + e.what());
    }
  std::ostringstream outside;
  int count = 0;
  for (Eigen::Index p = 0; p < s.probes.rows(); ++p) {
    const Eigen::Vector3d x = s.probes.row(p).transpose();
    if (winding_number(surface, x) >= 0.5) continue;
    double d = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < surface.F.rows(); ++f)
      d = std::min(d, point_triangle_distance(x, surface.V.row(surface.F(f, 0)), surface.V.row(surface.F(f, 1)),
                                              surface.V.row(surface.F(f, 2))));
    outside << (count++ ? "; " : "") << "probes[" << p << "] (" << x.x() << ", " << x.y() << ", " << x.z() << ") by "
            << d << " m";
  }
  if (count > 0)
    throw std::invalid_argument(where + "probes: " + std::to_string(count) +
                                " point(s) outside the body: " + outside.str());
}

void Scenario::loads_at(int frame, FrameLoads& out) const {
  out.values.resize((has_load ? 1 : 0) + loads.size());
  size_t k = 0;
  if (has_load) {
    out.values[k] = load.force;
    if (ramp_frames > 0 && frame < ramp_frames) out.values[k] *= static_cast<double>(frame + 1) / ramp_frames;
    ++k;
  }
  for (const ScenarioLoad& l : loads) out.values[k++] = l.schedule.at(frame);
  out.tool_values.resize(tools.size());
  for (size_t t = 0; t < tools.size(); ++t) out.tool_values[t] = tools[t].schedule.at(frame);
}

namespace {

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

/// A scenario file with its "extends" chain merged, and which file set each value.
struct Document {
  nlohmann::json json;
  std::shared_ptr<KeyOrigins> origins;
};

/// Deep merge: an object merges into an object key by key; any other value
/// (array, scalar) replaces what the base has; null removes the base's key.
void merge_into(nlohmann::json& base, const nlohmann::json& over, const std::string& pointer, const std::string& file,
                KeyOrigins& origins) {
  for (const auto& [key, value] : over.items()) {
    const std::string at = json_pointer_child(pointer, key);
    if (value.is_null()) {
      base.erase(key);
      origins.record(at, value, file);
    } else if (value.is_object() && base.contains(key) && base[key].is_object()) {
      merge_into(base[key], value, at, file, origins);
    } else {
      base[key] = value;
      origins.record(at, value, file);
    }
  }
}

/// Reads a scenario file; if it says "extends": "<path relative to it>", the base
/// is read first (recursively) and this file's keys are merged over it.
Document read_scenario_document(const std::string& path, std::vector<std::string> chain = {}) {
  const std::string canonical = fs::weakly_canonical(path).string();
  if (std::find(chain.begin(), chain.end(), canonical) != chain.end()) {
    std::string names;
    for (const auto& c : chain) names += file_name(c) + " -> ";
    throw ScenarioError(file_name(chain.front()) + ".extends: a cycle: " + names + file_name(path));
  }
  chain.push_back(canonical);
  nlohmann::json j = read_json_file(path);
  if (!j.is_object() || !j.contains("extends")) {
    Document d{std::move(j), std::make_shared<KeyOrigins>()};
    d.origins->file = path;
    d.origins->record("", d.json, path);
    return d;
  }
  const nlohmann::json& extends = j["extends"];
  if (!extends.is_string() || extends.get<std::string>().empty())
    throw ScenarioError(file_name(path) + ".extends: must be the path of a scenario file, relative to this one");
  const std::string base = (fs::path(path).parent_path() / extends.get<std::string>()).lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(base, ec))
    throw ScenarioError(file_name(path) + ".extends: '" + extends.get<std::string>() + "': no such file (" + base +
                        ")");
  Document d = read_scenario_document(base, chain);
  j.erase("extends");
  merge_into(d.json, j, "", path, *d.origins);
  d.origins->file = path;
  return d;
}

/// A name the results tree can use as one folder: not empty, not '.' or '..', no '/'.
bool is_folder_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos;
}

/// The case name a model entry gives (parse_scenario's rule: "name", else "model"); "" if neither is a string.
std::string case_name_of(const nlohmann::json& entry) {
  for (const char* key : {"name", "model"})
    if (entry.is_object() && entry.contains(key) && entry[key].is_string()) return entry[key].get<std::string>();
  return "";
}

/// The cases a scenario runs in an experiment: the experiment's "models", then the
/// scenario file's own "models", then the entry's "models_add", in that order. A
/// case name given by two of them is an error naming both.
void combine_models(Document& doc, const nlohmann::json& experiment_models, const nlohmann::json& added,
                    const std::string& experiment_file, const std::string& entry_where) {
  if (experiment_models.is_null() && added.is_null()) return;
  if (!doc.json.is_object()) return;  // parse_scenario reports it
  const nlohmann::json own = doc.json.contains("models") ? doc.json["models"] : nlohmann::json::array();
  if (!own.is_array()) return;  // parse_scenario reports it
  const std::string own_file = doc.origins->origin("/models");
  nlohmann::json combined = nlohmann::json::array();
  std::vector<std::string> from;  // the file of each combined entry
  std::map<std::string, std::string> named_by;
  auto add = [&](const nlohmann::json& list, const std::string& file, const std::string& source) {
    if (list.is_null()) return;
    for (const auto& entry : list) {
      const std::string name = case_name_of(entry);
      if (!name.empty()) {
        auto [it, fresh] = named_by.emplace(name, source);
        if (!fresh)
          throw ScenarioError(entry_where + ": case '" + name + "' is given twice: by " + it->second + " and by " +
                              source + " (case names must differ)");
      }
      combined.push_back(entry);
      from.push_back(file);
    }
  };
  add(experiment_models, experiment_file, file_name(experiment_file) + " models");
  add(own, own_file, file_name(own_file) + " models");
  add(added, experiment_file, entry_where + ".models_add");
  doc.json["models"] = combined;
  doc.origins->record("/models", combined, own_file);
  for (size_t i = 0; i < combined.size(); ++i)
    doc.origins->record(json_pointer_child("/models", std::to_string(i)), combined[i], from[i]);
}

/// The origins of a sweep point (the base document with the sweep's values set,
/// its cases possibly fewer): each case keeps the origin of the base's case of the
/// same name, and every value the sweep changed is the experiment file's.
void record_sweep_origins(const Document& base, Document& point, const std::string& experiment_file) {
  auto record_changes = [&](const nlohmann::json& before, const nlohmann::json& after, const std::string& prefix) {
    for (const auto& op : nlohmann::json::diff(before, after))
      if (op.at("op") != "remove")
        point.origins->record(prefix + op.at("path").get<std::string>(), op.at("value"), experiment_file);
  };
  nlohmann::json before = base.json, after = point.json;
  if (!before.is_object() || !after.is_object()) return;
  before.erase("models");
  after.erase("models");
  record_changes(before, after, "");
  if (!point.json.contains("models") || !point.json["models"].is_array() || !base.json.contains("models")) return;
  const nlohmann::json& base_models = base.json["models"];
  const nlohmann::json& models = point.json["models"];
  for (size_t i = 0; i < models.size(); ++i)
    for (size_t k = 0; k < base_models.size(); ++k)
      if (case_name_of(base_models[k]) == case_name_of(models[i])) {
        const std::string at = json_pointer_child("/models", std::to_string(i));
        point.origins->record(at, models[i], base.origins->origin(json_pointer_child("/models", std::to_string(k))));
        record_changes(base_models[k], models[i], at);
        break;
      }
}

Scenario parse_scenario(const Document& doc, const std::string& file, const DataDir& data) {
  const std::string base = fs::path(file).parent_path().string();
  const std::string where = file_name(file);
  StrictObject o(doc.json, where, doc.origins);
  o.in_schema("scenario");
  Scenario s;
  s.file = file;
  s.name = o.text("name", std::nullopt);
  if (!is_folder_name(s.name)) o.fail("name", "must be a folder name (not empty, '.' or '..', no '/')");
  s.description = o.text("description", "");
  s.mesh = parse_mesh_recipe(o.object("mesh"), base, data);

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

  // The paper's load (optional when "loads" or "tools" say what drives the body).
  // Its point: as given, the highest surface vertex, or the surface vertex
  // nearest a given point (resolved on the mesh by resolve_on_mesh).
  s.has_load = o.has("load");
  if (!s.has_load && !o.has("loads") && !o.has("tools")) o.fail("load", "missing: give load, loads or tools");
  StrictObject l = o.object("load", true);
  if (s.has_load)
    s.load_placement = l.text("at", s.load_placement, {"point", "highest_surface_vertex", "nearest_surface_vertex"});
  if (s.has_load) {
    if (s.load_placement == "highest_surface_vertex") {
      if (l.has("point")) l.fail("point", "not used with at = highest_surface_vertex");
    } else {
      s.load.point = l.vec3("point", std::nullopt);
    }
    s.load.force = l.vec3("force", std::nullopt);
    s.ramp_frames = l.integer("ramp_frames", s.ramp_frames, 0, 1000000);
    s.load.disc_radius = l.number("disc_radius", s.load.disc_radius, 0, 1e9);  // m; 0: the paper's point load
  }
  l.finish();
  s.loads = parse_loads(o);
  s.tools = parse_tools(o);
  ScenarioProbes probes = parse_probes(o, base, data, s.mesh);
  s.probes = std::move(probes.points);
  s.probes_source = std::move(probes.source);

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
    StrictObject mo = o.item("models", i);
    ModelRun run;
    run.model = mo.text("model", std::nullopt);
    run.case_name = mo.text("name", run.model);
    // Its results go to <scenario>/<name>/, beside the scenario's mesh/ folder.
    if (!is_folder_name(run.case_name) || run.case_name == "mesh")
      mo.fail("name", "'" + run.case_name + "' must be a folder name (not empty, '.', '..' or 'mesh', no '/')");
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
      throw ScenarioError(e.what() + mo.set_in(""));
    }
    run.max_frames = mo.integer("max_frames", 0, 0, 100000000);
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
    j["models"].push_back({{"case", run.case_name},
                           {"model", run.model},
                           {"parameters", run.parameters.to_json()},
                           {"max_frames", run.max_frames}});
  return j;
}

}  // namespace

namespace {

/// `tissuebench run --set`: each [key, value] set in the scenario document, recorded
/// as given on the command line (the document's origin of the key).
void apply_overrides(Document& doc, const nlohmann::json& overrides, const std::string& where) {
  for (const auto& kv : overrides) {
    const std::string key = kv.at(0).get<std::string>();
    set_scenario_key(doc.json, key, kv.at(1), where);
    if (key.rfind("models.", 0) == 0) continue;  // a case's origin stays its file's
    std::string pointer;
    for (char c : key) pointer += c == '.' ? '/' : c;
    doc.origins->record("/" + pointer, kv.at(1), "--set " + key);
  }
}

/// An experiment with "unsupported_cases": "skip" runs each of its cases only on
/// the scenarios whose loads and tools its model, with the case's parameters, takes
/// (check_supported; a benchmark suite lists
/// every model once); the others are recorded with the reason, for the analysis.
/// The reference may not be left out.
void leave_out_unsupported(Scenario& s, const std::string& reference, const std::string& where) {
  const LoadCase load_case = s.load_case();
  std::vector<ModelRun> kept;
  for (ModelRun& run : s.models) {
    try {
      check_supported(find_model(run.model), run.parameters, load_case);
      kept.push_back(std::move(run));
    } catch (const std::invalid_argument& unsupported) {
      if (run.case_name == reference)
        throw ScenarioError(where + ": scenario '" + s.name + "': the reference case '" + reference +
                            "' cannot run it: " + unsupported.what());
      s.not_run.emplace_back(run.case_name, unsupported.what());
    }
  }
  s.models = std::move(kept);
}

}  // namespace

Experiment load_experiment(const std::string& path, const DataDir& data, const nlohmann::json& overrides) {
  const nlohmann::json j = read_json_file(path);
  const std::string where = file_name(path);
  Experiment e;
  e.overrides = overrides;
  if (j.is_object() && j.contains("scenarios")) {
    StrictObject o(j, where);
    o.in_schema("experiment");
    e.name = o.text("name", std::nullopt);
    if (!is_folder_name(e.name)) o.fail("name", "must be a folder name (not empty, '.' or '..', no '/')");
    e.description = o.text("description", "");
    e.reference = o.text("reference", "");
    e.transient_reference = o.text("transient_reference", "");
    const nlohmann::json& law_references = o.raw("law_references");
    if (!law_references.is_null()) {
      if (!law_references.is_array() || law_references.empty())
        o.fail("law_references", "must be a non-empty array of case names");
      for (const nlohmann::json& name : law_references) {
        if (!name.is_string() || name.get<std::string>().empty())
          o.fail("law_references", "entries must be case names (non-empty strings)");
        const std::string case_name = name.get<std::string>();
        if (case_name == e.reference || case_name == e.transient_reference)
          o.fail("law_references", "'" + case_name + "' is the experiment's reference or transient_reference");
        if (std::find(e.law_references.begin(), e.law_references.end(), case_name) != e.law_references.end())
          o.fail("law_references", "'" + case_name + "' is listed twice");
        e.law_references.push_back(case_name);
      }
    }
    const nlohmann::json& list = o.raw("scenarios");
    if (!list.is_array() || list.empty())
      o.fail("scenarios",
             "must be a non-empty array of scenario files (paths, or {\"file\", \"role\", \"models_add\"})");
    const nlohmann::json& models = o.raw("models");
    if (!models.is_null() && (!models.is_array() || models.empty()))
      o.fail("models", "must be a non-empty array of cases (as a scenario's \"models\")");
    const nlohmann::json& sweep = o.raw("sweep");
    const bool skip_unsupported = o.text("unsupported_cases", "error", {"error", "skip"}) == "skip";
    e.skip_unsupported = skip_unsupported;
    o.finish();
    std::vector<std::string> roles;
    for (size_t i = 0; i < list.size(); ++i) {
      // An entry: a path, or {"file", "role", "models_add"}.
      std::string relative, role;
      nlohmann::json added;
      const std::string entry_where = where + ".scenarios[" + std::to_string(i) + "]";
      if (list[i].is_string()) {
        relative = list[i].get<std::string>();
      } else if (list[i].is_object()) {
        StrictObject eo = o.item("scenarios", i);
        relative = eo.text("file", std::nullopt);
        role = eo.text("role", "");
        if (!role.empty()) {
          if (role.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos ||
              !std::islower(static_cast<unsigned char>(role[0])))
            eo.fail("role", "'" + role + "' must be lower case letters, digits and _, starting with a letter");
          if (std::find(roles.begin(), roles.end(), role) != roles.end())
            eo.fail("role", "'" + role + "' is given to two scenarios");
          roles.push_back(role);
        }
        added = eo.raw("models_add");
        if (!added.is_null() && (!added.is_array() || added.empty()))
          eo.fail("models_add", "must be a non-empty array of cases (as a scenario's \"models\")");
        eo.finish();
      } else {
        o.fail("scenarios", "entries must be file paths or {\"file\", \"role\", \"models_add\"} objects");
      }
      const std::string file = (fs::path(path).parent_path() / relative).lexically_normal().string();
      std::error_code ec;
      if (relative.empty() || !fs::is_regular_file(file, ec))
        throw ScenarioError(entry_where + ": '" + relative + "': no such scenario file (" + file + ")");
      Document doc = read_scenario_document(file);
      combine_models(doc, models, added, path, entry_where);
      apply_overrides(doc, overrides, entry_where);
      if (sweep.is_null()) {
        e.scenarios.push_back(parse_scenario(doc, file, data));
        e.scenarios.back().role = role;
        continue;
      }
      // Each base scenario expanded into the sweep's points (sweep.h).
      const nlohmann::json& base = doc.json;
      const std::string base_name = base.is_object() && base.contains("name") && base["name"].is_string()
                                        ? base["name"].get<std::string>()
                                        : fs::path(file).stem().string();
      std::vector<nlohmann::json> seen;  // what each point runs: a level equal to another point's runs once
      for (SweepPoint& point : expand_sweep(sweep, base, base_name, e.reference, where)) {
        Document at_point{std::move(point.scenario), std::make_shared<KeyOrigins>(*doc.origins)};
        record_sweep_origins(doc, at_point, path);
        Scenario s;
        try {
          s = parse_scenario(at_point, file, data);
        } catch (const ScenarioError& err) {
          throw ScenarioError(where + ": sweep point '" + point.name + "': " + err.what());
        }
        const nlohmann::json runs = what_runs(s);
        if (std::find(seen.begin(), seen.end(), runs) != seen.end()) continue;  // e.g. a default stated explicitly
        seen.push_back(runs);
        s.role = role;
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
    for (const std::string& law_reference : e.law_references) {
      bool found = false;
      for (const Scenario& s : e.scenarios)
        for (const ModelRun& run : s.models) found = found || run.case_name == law_reference;
      if (!found) o.fail("law_references", "no scenario has a case named '" + law_reference + "'");
    }
    if (skip_unsupported)
      for (Scenario& s : e.scenarios) leave_out_unsupported(s, e.reference, where);
  } else {
    // A scenario file run alone is an experiment of one scenario; it may name its
    // reference case too.
    Document doc = read_scenario_document(path);
    apply_overrides(doc, overrides, where);
    if (doc.json.is_object() && doc.json.contains("reference")) {
      if (!doc.json["reference"].is_string()) throw ScenarioError(where + ": reference: must be a case name (string)");
      e.reference = doc.json["reference"].get<std::string>();
      doc.json.erase("reference");
    }
    Scenario s = parse_scenario(doc, path, data);
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

bool add_model_everywhere(Experiment& e, const std::string& model) {
  for (const Scenario& s : e.scenarios)
    for (const ModelRun& run : s.models)
      if (run.case_name == model || run.model == model) return false;
  const auto& registered = registered_models();
  const auto info = std::find_if(registered.begin(), registered.end(), [&](const ModelInfo& m) { return m.name == model; });
  if (info == registered.end()) return false;  // not a model: the runner says no case matches
  for (Scenario& s : e.scenarios) {
    ModelRun run;
    run.case_name = run.model = model;
    run.parameters_given = nlohmann::json::object();
    run.parameters = resolve_parameters(info->parameters, run.parameters_given, "--model " + model);
    s.models.push_back(run);
    if (e.skip_unsupported) leave_out_unsupported(s, e.reference, "--model " + model);
  }
  return true;
}

void leave_out_scenarios(Experiment& e, const std::vector<std::string>& names) {
  std::vector<std::string> distinct;  // a name given twice is left out once
  for (const std::string& name : names)
    if (std::find(distinct.begin(), distinct.end(), name) == distinct.end()) distinct.push_back(name);
  for (const std::string& name : distinct) {
    const auto found = std::find_if(e.scenarios.begin(), e.scenarios.end(), [&](const Scenario& s) { return s.name == name; });
    if (found == e.scenarios.end())
      throw ScenarioError("--skip-scenario " + name + ": no scenario of experiment '" + e.name + "' has that name");
    e.scenarios.erase(found);
  }
  if (e.scenarios.empty()) throw ScenarioError("--skip-scenario: no scenario of experiment '" + e.name + "' is left");
}

}  // namespace tb
