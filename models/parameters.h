// Model parameters, declared once (name, default, range, description) and resolved
// strictly from a scenario: unknown names, wrong types and out-of-range values are
// errors that name where they came from (STYLE.md 4 and 5).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tb {

/// One parameter: a number in [min, max] or, when `choices` is non-empty, a string
/// that must be one of them.
struct ParameterSpec {
  std::string name;
  double default_number = 0;
  double min = 0, max = 0;
  std::string description;
  std::vector<std::string> choices = {};
  std::string default_choice = {};
  bool integer = false;
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

 private:
  std::map<std::string, double> numbers_;
  std::map<std::string, std::string> choices_;
};

/// Defaults overridden by `given` (a JSON object). `where` prefixes error messages,
/// e.g. "paper.json: scenarios[0].models[1].parameters". Throws std::invalid_argument.
Parameters resolve_parameters(const std::vector<ParameterSpec>& specs, const nlohmann::json& given,
                              const std::string& where);

}  // namespace tb
