// Model parameters, declared once (name, default, range, description) and resolved
// strictly from a scenario: unknown names, wrong types and out-of-range values are
// errors that name where they came from (docs/design.md: declare each parameter once, strict configuration).
#pragma once

#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tb {

/// One parameter: a number in [min, max] (an integer when `integer`) or, when
/// `choices` is non-empty, a string that must be one of them. Build one with the
/// named functions below, so every field is said by name:
///   ParameterSpec::number("time_step", 0.01, 1e-6, 1.0, "time step per frame, s")
///   ParameterSpec::choice("solver", {"direct", "iterative"}, "direct", "...")
struct ParameterSpec {
  std::string name;
  std::string description;
  double default_number = 0;
  double min = 0, max = 0;
  bool integer = false;
  std::vector<std::string> choices;
  std::string default_choice;

  static ParameterSpec number(std::string name, double default_value, double min, double max, std::string description);
  static ParameterSpec whole_number(std::string name, int default_value, int min, int max, std::string description);
  static ParameterSpec choice(std::string name, std::vector<std::string> choices, std::string default_choice,
                              std::string description);
  bool is_choice() const { return !choices.empty(); }
};

/// A fully resolved parameter set: every declared parameter has a value.
class Parameters {
 public:
  double number(const std::string& name) const;
  int integer(const std::string& name) const { return static_cast<int>(number(name)); }
  const std::string& choice(const std::string& name) const;
  nlohmann::json to_json() const;
  void set_number(const std::string& name, double v) { numbers_[name] = v; }
  void set_choice(const std::string& name, const std::string& v) { choices_[name] = v; }
  /// Whether the scenario gave this parameter (resolve_parameters), rather than its default.
  bool given(const std::string& name) const { return given_.count(name) > 0; }
  void mark_given(const std::string& name) { given_.insert(name); }

 private:
  std::map<std::string, double> numbers_;
  std::map<std::string, std::string> choices_;
  std::set<std::string> given_;
};

/// Defaults overridden by `given` (a JSON object). `where` prefixes error messages,
/// e.g. "paper.json: scenarios[0].models[1].parameters". Throws std::invalid_argument.
Parameters resolve_parameters(const std::vector<ParameterSpec>& specs, const nlohmann::json& given,
                              const std::string& where);

}  // namespace tb
