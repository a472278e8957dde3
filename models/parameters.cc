#include "parameters.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tb {

ParameterSpec ParameterSpec::number(std::string name, double default_value, double min, double max,
                                    std::string description) {
  if (!(min <= default_value && default_value <= max))
    throw std::logic_error("parameter '" + name + "': default outside its range");
  ParameterSpec s;
  s.name = std::move(name);
  s.description = std::move(description);
  s.default_number = default_value;
  s.min = min;
  s.max = max;
  return s;
}

ParameterSpec ParameterSpec::whole_number(std::string name, int default_value, int min, int max,
                                          std::string description) {
  ParameterSpec s = number(std::move(name), default_value, min, max, std::move(description));
  s.integer = true;
  return s;
}

ParameterSpec ParameterSpec::choice(std::string name, std::vector<std::string> choices, std::string default_choice,
                                    std::string description) {
  if (std::find(choices.begin(), choices.end(), default_choice) == choices.end())
    throw std::logic_error("parameter '" + name + "': default is not one of its choices");
  ParameterSpec s;
  s.name = std::move(name);
  s.description = std::move(description);
  s.choices = std::move(choices);
  s.default_choice = std::move(default_choice);
  return s;
}

double Parameters::number(const std::string& name) const {
  auto it = numbers_.find(name);
  if (it == numbers_.end()) throw std::logic_error("undeclared numeric parameter '" + name + "'");
  return it->second;
}

const std::string& Parameters::choice(const std::string& name) const {
  auto it = choices_.find(name);
  if (it == choices_.end()) throw std::logic_error("undeclared choice parameter '" + name + "'");
  return it->second;
}

nlohmann::json Parameters::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : numbers_) j[k] = v;
  for (const auto& [k, v] : choices_) j[k] = v;
  return j;
}

Parameters resolve_parameters(const std::vector<ParameterSpec>& specs, const nlohmann::json& given,
                              const std::string& where) {
  if (!given.is_null() && !given.is_object()) throw std::invalid_argument(where + ": must be an object");
  Parameters p;
  for (const auto& s : specs) {
    if (!s.is_choice())
      p.set_number(s.name, s.default_number);
    else
      p.set_choice(s.name, s.default_choice);
  }
  if (given.is_null()) return p;
  for (const auto& [key, value] : given.items()) {
    const ParameterSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.name == key) spec = &s;
    if (spec) p.mark_given(key);
    if (!spec) {
      std::ostringstream known;
      for (const auto& s : specs) known << (&s == &specs.front() ? "" : ", ") << s.name;
      throw std::invalid_argument(where + ": unknown parameter '" + key + "' (known: " + known.str() + ")");
    }
    if (spec->is_choice()) {
      if (!value.is_string()) throw std::invalid_argument(where + "." + key + ": must be a string");
      const std::string v = value.get<std::string>();
      bool ok = false;
      std::ostringstream allowed;
      for (const auto& c : spec->choices) {
        ok = ok || c == v;
        allowed << (&c == &spec->choices.front() ? "" : ", ") << c;
      }
      if (!ok) throw std::invalid_argument(where + "." + key + ": '" + v + "' is not one of " + allowed.str());
      p.set_choice(key, v);
    } else {
      if (!value.is_number()) throw std::invalid_argument(where + "." + key + ": must be a number");
      const double v = value.get<double>();
      if (!std::isfinite(v) || v < spec->min || v > spec->max) {
        std::ostringstream msg;
        msg << where << "." << key << ": " << v << " is outside [" << spec->min << ", " << spec->max << "]";
        throw std::invalid_argument(msg.str());
      }
      if (spec->integer && v != std::floor(v)) throw std::invalid_argument(where + "." + key + ": must be an integer");
      p.set_number(key, v);
    }
  }
  return p;
}

}  // namespace tb
