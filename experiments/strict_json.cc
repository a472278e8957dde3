#include "strict_json.h"

#include <cmath>
#include <sstream>

namespace tb {

StrictObject::StrictObject(const nlohmann::json& j, std::string where) : j_(j), where_(std::move(where)) {
  if (!j_.is_object()) throw ScenarioError(where_ + ": must be a JSON object");
}

void StrictObject::fail(const std::string& key, const std::string& problem) const {
  throw ScenarioError(where_ + "." + key + ": " + problem);
}

bool StrictObject::has(const std::string& key) const { return j_.contains(key); }

const nlohmann::json* StrictObject::value(const std::string& key) {
  read_.insert(key);
  auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

double StrictObject::number(const std::string& key, std::optional<double> fallback, double min, double max) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!fallback) fail(key, "missing (required)");
    return *fallback;
  }
  if (!v->is_number()) fail(key, "must be a number, found " + v->dump());
  const double x = v->get<double>();
  if (!std::isfinite(x) || x < min || x > max) {
    std::ostringstream msg;
    msg << x << " is out of range [" << min << ", " << max << "]";
    fail(key, msg.str());
  }
  return x;
}

int StrictObject::integer(const std::string& key, std::optional<int> fallback, int min, int max) {
  const nlohmann::json* v = value(key);
  if (v && !v->is_number_integer()) fail(key, "must be an integer, found " + v->dump());
  read_.erase(key);
  return static_cast<int>(number(key, fallback ? std::optional<double>(*fallback) : std::nullopt, min, max));
}

bool StrictObject::boolean(const std::string& key, bool fallback) {
  const nlohmann::json* v = value(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "must be true or false, found " + v->dump());
  return v->get<bool>();
}

std::string StrictObject::text(const std::string& key, std::optional<std::string> fallback,
                               const std::vector<std::string>& choices) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!fallback) fail(key, "missing (required)");
    return *fallback;
  }
  if (!v->is_string()) fail(key, "must be a string, found " + v->dump());
  const std::string s = v->get<std::string>();
  if (!choices.empty()) {
    std::string allowed;
    for (const auto& c : choices) {
      if (c == s) return s;
      allowed += (allowed.empty() ? "" : ", ") + c;
    }
    fail(key, "'" + s + "' is not one of " + allowed);
  }
  return s;
}

Eigen::Vector3d StrictObject::vec3(const std::string& key, std::optional<Eigen::Vector3d> fallback) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!fallback) fail(key, "missing (required)");
    return *fallback;
  }
  if (!v->is_array() || v->size() != 3) fail(key, "must be an array of 3 numbers, found " + v->dump());
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    if (!(*v)[static_cast<size_t>(k)].is_number()) fail(key, "must be an array of 3 numbers, found " + v->dump());
    out(k) = (*v)[static_cast<size_t>(k)].get<double>();
    if (!std::isfinite(out(k))) fail(key, "must be finite");
  }
  return out;
}

StrictObject StrictObject::object(const std::string& key, bool optional) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!optional) fail(key, "missing (required)");
    return StrictObject(nlohmann::json::object(), where_ + "." + key);
  }
  if (!v->is_object()) fail(key, "must be an object, found " + v->dump());
  return StrictObject(*v, where_ + "." + key);
}

const nlohmann::json& StrictObject::raw(const std::string& key) {
  static const nlohmann::json null_value;
  const nlohmann::json* v = value(key);
  return v ? *v : null_value;
}

void StrictObject::finish() const {
  for (const auto& [k, v] : j_.items())
    if (!read_.count(k)) {
      std::string known;
      for (const auto& r : read_) known += (known.empty() ? "" : ", ") + r;
      throw ScenarioError(where_ + ": unknown key '" + k + "' (expected one of: " + known + ")");
    }
}

}  // namespace tb
