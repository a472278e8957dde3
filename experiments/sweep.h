// Parameter sweeps over a base scenario. An experiment file may declare
//   "sweep": {"mode": "one_at_a_time" | "grid",
//             "cases": ["fem-direct", "hybrid"],        (optional: keep only these)
//             "factors": [{"key": "models.*.parameters.iterations", "values": [5, 20],
//                          "label": "iterations",        (optional: the key's last part)
//                          "value_names": ["5", "20"],   (optional; needed for array values)
//                          "role": "models" | "reference"}]}
// or a list of such objects. A key is a dotted path into the scenario JSON; the
// segment after "models" names a case (or "*" for every case whose model declares
// the parameter). One at a time: the base, then each factor's values with the
// others at the base. Grid: every combination. A "reference" factor keeps only the
// experiment's reference case, to be compared with the base scenario's models (a
// finer FEM on the same surface).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tb {

/// The most scenarios one sweep declaration may make of a base scenario (grid: the
/// product of its factors' value counts; one at a time: one plus their sum).
inline constexpr int kMaxSweepPoints = 10000;

/// One expanded scenario of a sweep.
struct SweepPoint {
  std::string name;         ///< "<base>" or "<base>__<label>=<value>[__...]"
  nlohmann::json scenario;  ///< the scenario JSON with the values set
  nlohmann::json values;    ///< {label: value} set at this point ({} at the base)
  nlohmann::json keys;      ///< {label: key path}
  bool reference_only = false;
};

/// Expands the experiment's "sweep" declaration (object or array) over one base
/// scenario JSON named `base_name`. `reference` is the experiment's reference case
/// (needed by "reference" factors). Throws ScenarioError naming `where` and the key.
std::vector<SweepPoint> expand_sweep(const nlohmann::json& sweep, const nlohmann::json& base,
                                     const std::string& base_name, const std::string& reference,
                                     const std::string& where);

/// Sets `value` at the dotted `key` of one scenario JSON, with a sweep factor's
/// rules (`models.<case or *>.<path>` for cases): `tissuebench run --set`. Throws
/// ScenarioError naming `where` and the key.
void set_scenario_key(nlohmann::json& scenario, const std::string& key, const nlohmann::json& value,
                      const std::string& where);

}  // namespace tb
