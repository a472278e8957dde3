#include "sweep.h"

#include <iomanip>
#include <set>
#include <sstream>

#include "model.h"
#include "strict_json.h"

namespace tb {
namespace {

struct Factor {
  std::string key, label;
  std::vector<nlohmann::json> values;
  std::vector<std::string> value_names;  ///< how each value appears in scenario names
  bool reference = false;
};

std::vector<std::string> split(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  std::string part;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  return parts;
}

/// Sets `value` at the dotted path `parts` of `j`, creating objects on the way.
void set_at(nlohmann::json& j, const std::vector<std::string>& parts, size_t from, const nlohmann::json& value) {
  nlohmann::json* at = &j;
  for (size_t i = from; i + 1 < parts.size(); ++i) {
    if (!at->contains(parts[i])) (*at)[parts[i]] = nlohmann::json::object();
    at = &(*at)[parts[i]];
    if (!at->is_object()) throw std::invalid_argument("'" + parts[i] + "' is not an object");
  }
  (*at)[parts.back()] = value;
}

/// The case name of a model entry ("name", else "model"); "" if it has neither as a
/// string (parse_scenario reports such an entry).
std::string case_of(const nlohmann::json& m) {
  for (const char* key : {"name", "model"})
    if (m.is_object() && m.contains(key) && m[key].is_string()) return m[key].get<std::string>();
  return "";
}

/// The scenario's "models" array, or an error naming the sweep and the scenario.
const nlohmann::json& models_of(const nlohmann::json& scenario, const std::string& where) {
  if (!scenario.is_object() || !scenario.contains("models") || !scenario["models"].is_array())
    throw ScenarioError(where + ": the scenario swept has no \"models\" array");
  return scenario["models"];
}

bool model_declares(const nlohmann::json& model_entry, const std::string& parameter) {
  const ModelInfo& info = find_model(model_entry.at("model").get<std::string>());
  for (const auto& p : info.parameters)
    if (p.name == parameter) return true;
  return false;
}

/// Sets the factor's value in a copy of the scenario JSON.
void apply(nlohmann::json& scenario, const Factor& f, const nlohmann::json& value, const std::string& where,
           const char* what = "sweep key") {
  const std::vector<std::string> parts = split(f.key);
  try {
    if (parts.size() >= 3 && parts[0] == "models") {
      // models.<case or *>.<path within the model entry>
      nlohmann::json& models = scenario.at("models");
      bool matched = false;
      for (auto& m : models) {
        const std::string case_name = case_of(m);
        const bool wildcard = parts[1] == "*";
        if (!wildcard && case_name != parts[1]) continue;
        if (wildcard && (parts.size() != 4 || parts[2] != "parameters" || !model_declares(m, parts[3]))) continue;
        set_at(m, parts, 2, value);
        matched = true;
      }
      if (!matched) throw std::invalid_argument("no case matches '" + parts[1] + "'");
    } else {
      set_at(scenario, parts, 0, value);
    }
  } catch (const ScenarioError&) {
    throw;
  } catch (const std::exception& e) {
    throw ScenarioError(where + ": " + what + " '" + f.key + "': " + e.what());
  }
}

std::vector<Factor> parse_factors(StrictObject& o) {
  const nlohmann::json& list = o.raw("factors");
  if (!list.is_array() || list.empty()) o.fail("factors", "must be a non-empty array");
  std::vector<Factor> factors;
  std::set<std::string> labels;
  for (size_t i = 0; i < list.size(); ++i) {
    StrictObject fo = o.item("factors", i);
    Factor f;
    f.key = fo.text("key", std::nullopt);
    const auto parts = split(f.key);
    if (parts.empty() || f.key.find("..") != std::string::npos) fo.fail("key", "must be a dotted path");
    f.label = fo.text("label", parts.back());
    f.reference = fo.text("role", "models", {"models", "reference"}) == "reference";
    const nlohmann::json& values = fo.raw("values");
    if (!values.is_array() || values.empty()) fo.fail("values", "must be a non-empty array");
    for (const auto& v : values) f.values.push_back(v);
    // Scalars name themselves; arrays and objects need "value_names".
    const nlohmann::json& names = fo.raw("value_names");
    if (!names.is_null() && (!names.is_array() || names.size() != values.size()))
      fo.fail("value_names", "must be an array of one name per value");
    for (size_t k = 0; k < f.values.size(); ++k) {
      const nlohmann::json& v = f.values[k];
      std::string name;
      if (!names.is_null()) {
        if (!names[k].is_string()) fo.fail("value_names", "entries must be strings");
        name = names[k].get<std::string>();
      } else if (v.is_string()) {
        name = v.get<std::string>();
      } else if (v.is_number() || v.is_boolean()) {
        name = v.dump();
      } else {
        fo.fail("value_names", "needed: a value is an array or object");
      }
      if (name.empty() || name.find_first_of("/ ") != std::string::npos)
        fo.fail("value_names", "'" + name + "' cannot be part of a folder name");
      f.value_names.push_back(name);
    }
    if (!labels.insert(f.label).second) fo.fail("label", "'" + f.label + "' is used by two factors");
    fo.finish();
    factors.push_back(std::move(f));
  }
  return factors;
}

}  // namespace

std::vector<SweepPoint> expand_sweep(const nlohmann::json& sweep, const nlohmann::json& base,
                                     const std::string& base_name, const std::string& reference,
                                     const std::string& where) {
  const nlohmann::json declarations = sweep.is_array() ? sweep : nlohmann::json::array({sweep});
  std::vector<SweepPoint> points;
  std::set<std::string> names;
  auto add = [&](SweepPoint p) {
    if (names.insert(p.name).second) points.push_back(std::move(p));
  };
  for (size_t d = 0; d < declarations.size(); ++d) {
    StrictObject o(declarations[d], where + ".sweep" + (sweep.is_array() ? "[" + std::to_string(d) + "]" : ""));
    o.in_schema("experiment.sweep");
    const bool grid = o.text("mode", "one_at_a_time", {"one_at_a_time", "grid"}) == "grid";
    std::vector<std::string> keep;
    if (o.has("cases"))
      for (const auto& c : o.raw("cases")) {
        if (!c.is_string()) o.fail("cases", "entries must be case names");
        keep.push_back(c.get<std::string>());
      }
    const std::vector<Factor> factors = parse_factors(o);
    o.finish();
    if (reference.empty())
      for (const auto& f : factors)
        if (f.reference) o.fail("factors", "a reference factor needs the experiment's \"reference\" case");

    // Every point is a scenario to load (and to run): a declaration making more than
    // kMaxSweepPoints is refused before any is made.
    double points_declared = 1;
    for (const auto& f : factors)
      points_declared = grid ? points_declared * static_cast<double>(f.values.size())
                             : points_declared + static_cast<double>(f.values.size());
    if (points_declared > kMaxSweepPoints) {
      std::ostringstream msg;
      msg << std::setprecision(3) << "would make " << points_declared << " scenarios, more than " << kMaxSweepPoints
          << " (fewer factors or values, or one_at_a_time instead of grid)";
      o.fail("factors", msg.str());
    }
    if (!base.is_object()) throw ScenarioError(where + ": the scenario swept is not a JSON object");

    // The base scenario, restricted to the kept cases.
    nlohmann::json restricted = base;
    if (!keep.empty()) {
      nlohmann::json models = nlohmann::json::array();
      for (const auto& m : models_of(base, o.where())) {
        const std::string case_name = case_of(m);
        for (const auto& k : keep)
          if (k == case_name) models.push_back(m);
      }
      if (models.size() != keep.size()) o.fail("cases", "names a case the base scenario does not have");
      restricted["models"] = models;
    }

    auto point = [&](const std::vector<std::pair<const Factor*, size_t>>& settings) {
      SweepPoint p;
      p.name = base_name;
      p.scenario = restricted;
      p.values = nlohmann::json::object();
      p.keys = nlohmann::json::object();
      for (const auto& [f, k] : settings) {
        apply(p.scenario, *f, f->values[k], where);
        p.name += "__" + f->label + "=" + f->value_names[k];
        p.values[f->label] = f->values[k];
        p.keys[f->label] = f->key;
        p.reference_only = p.reference_only || f->reference;
      }
      if (p.reference_only) {
        nlohmann::json models = nlohmann::json::array();
        for (const auto& m : models_of(p.scenario, o.where()))
          if (case_of(m) == reference) models.push_back(m);
        p.scenario["models"] = models;
      }
      p.scenario["name"] = p.name;
      return p;
    };

    if (!grid) {
      add(point({}));
      for (const Factor& f : factors)
        for (size_t k = 0; k < f.values.size(); ++k) {
          // A level equal to the base's value is the base: run once.
          nlohmann::json probe = restricted;
          apply(probe, f, f.values[k], where);
          if (probe == restricted) continue;
          add(point({{&f, k}}));
        }
    } else {
      std::vector<size_t> index(factors.size(), 0);
      while (true) {
        std::vector<std::pair<const Factor*, size_t>> settings;
        for (size_t i = 0; i < factors.size(); ++i) settings.push_back({&factors[i], index[i]});
        add(point(settings));
        size_t i = 0;
        while (i < factors.size() && ++index[i] == factors[i].values.size()) index[i++] = 0;
        if (i == factors.size()) break;
      }
    }
  }
  return points;
}

void set_scenario_key(nlohmann::json& scenario, const std::string& key, const nlohmann::json& value,
                      const std::string& where) {
  Factor f;
  f.key = key;
  apply(scenario, f, value, where, "--set");
}

}  // namespace tb
