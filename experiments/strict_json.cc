#include "strict_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "file_schema.h"

namespace tb {

/// Deeper nesting than any scenario needs (strict_json.h, read_json_file).
constexpr int kMaxJsonDepth = 64;

nlohmann::json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || std::filesystem::is_directory(path, ec)) throw ScenarioError(path + ": cannot open file");
  try {
    return nlohmann::json::parse(in, [&](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
      if (depth > kMaxJsonDepth)
        throw ScenarioError(path + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
      return true;
    });
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond double (1e400).
    throw ScenarioError(path + ": malformed JSON: " + e.what());
  }
}

std::string shown(const nlohmann::json& value, size_t max_chars) {
  // Strings from the parser are valid UTF-8, so dump() cannot throw; replace anyway.
  std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (text.size() > max_chars) text = text.substr(0, max_chars) + "...";
  return text;
}

std::string json_pointer_child(const std::string& pointer, const std::string& key) {
  std::string escaped;
  for (char c : key) escaped += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return pointer + "/" + escaped;
}

void KeyOrigins::record(const std::string& pointer, const nlohmann::json& value, const std::string& from) {
  // Forget the pointer and everything below it ("<pointer>/..."), then record the value's tree.
  const std::string below = pointer + "/";
  set_by.erase(pointer);
  for (auto it = set_by.lower_bound(below); it != set_by.end() && it->first.rfind(below, 0) == 0;)
    it = set_by.erase(it);
  set_by[pointer] = from;
  if (value.is_object())
    for (const auto& [k, v] : value.items()) record(json_pointer_child(pointer, k), v, from);
  else if (value.is_array())
    for (size_t i = 0; i < value.size(); ++i) record(json_pointer_child(pointer, std::to_string(i)), value[i], from);
}

const std::string& KeyOrigins::origin(const std::string& pointer) const {
  auto it = set_by.find(pointer);
  return it == set_by.end() ? file : it->second;
}

StrictObject::StrictObject(const nlohmann::json& j, std::string where, std::shared_ptr<const KeyOrigins> origins,
                           std::string pointer)
    : j_(j), where_(std::move(where)), origins_(std::move(origins)), pointer_(std::move(pointer)) {
  if (!j_.is_object()) throw ScenarioError(where_ + ": must be a JSON object" + set_in(""));
}

std::string StrictObject::set_in(const std::string& key) const {
  if (!origins_) return "";
  const std::string& from = origins_->origin(key.empty() ? pointer_ : json_pointer_child(pointer_, key));
  if (from == origins_->file) return "";
  return " (set in " + std::filesystem::path(from).filename().string() + ")";
}

std::string StrictObject::directory_of(const std::string& key, const std::string& fallback) const {
  if (!origins_) return fallback;
  return std::filesystem::path(origins_->origin(json_pointer_child(pointer_, key))).parent_path().string();
}

void StrictObject::fail(const std::string& key, const std::string& problem) const {
  throw ScenarioError(where_ + "." + key + set_in(key) + ": " + problem);
}

StrictObject& StrictObject::in_schema(const std::string& name) {
  schema_ = name;
  return *this;
}

bool StrictObject::has(const std::string& key) const { return j_.contains(key); }

const nlohmann::json* StrictObject::value(const std::string& key) {
  if (!schema_.empty()) {
    const auto it = file_schema().find(schema_);
    if (it == file_schema().end() || std::find(it->second.begin(), it->second.end(), key) == it->second.end())
      throw std::logic_error("the loader reads '" + schema_ + "." + key + "', which file_schema.cc does not declare");
  }
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
  if (!v->is_number()) fail(key, "must be a number, found " + shown(*v));
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
  if (v && !v->is_number_integer()) fail(key, "must be an integer, found " + shown(*v));
  read_.erase(key);
  return static_cast<int>(number(key, fallback ? std::optional<double>(*fallback) : std::nullopt, min, max));
}

bool StrictObject::boolean(const std::string& key, bool fallback) {
  const nlohmann::json* v = value(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "must be true or false, found " + shown(*v));
  return v->get<bool>();
}

std::string StrictObject::text(const std::string& key, std::optional<std::string> fallback,
                               const std::vector<std::string>& choices) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!fallback) fail(key, "missing (required)");
    return *fallback;
  }
  if (!v->is_string()) fail(key, "must be a string, found " + shown(*v));
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
  if (!v->is_array() || v->size() != 3) fail(key, "must be an array of 3 numbers, found " + shown(*v));
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    if (!(*v)[static_cast<size_t>(k)].is_number()) fail(key, "must be an array of 3 numbers, found " + shown(*v));
    out(k) = (*v)[static_cast<size_t>(k)].get<double>();
    if (!std::isfinite(out(k))) fail(key, "must be finite");
  }
  return out;
}

StrictObject StrictObject::object(const std::string& key, bool optional) {
  const nlohmann::json* v = value(key);
  if (!v) {
    if (!optional) fail(key, "missing (required)");
    StrictObject absent(nlohmann::json::object(), where_ + "." + key);
    if (!schema_.empty()) absent.in_schema(schema_ + "." + key);
    return absent;
  }
  if (!v->is_object()) fail(key, "must be an object, found " + shown(*v));
  StrictObject child(*v, where_ + "." + key, origins_, json_pointer_child(pointer_, key));
  if (!schema_.empty()) child.in_schema(schema_ + "." + key);
  return child;
}

StrictObject StrictObject::item(const std::string& key, size_t index) {
  const nlohmann::json& list = raw(key);
  if (!list.is_array() || index >= list.size()) fail(key, "has no element " + std::to_string(index));
  StrictObject element(list[index], where_ + "." + key + "[" + std::to_string(index) + "]", origins_,
                       json_pointer_child(json_pointer_child(pointer_, key), std::to_string(index)));
  if (!schema_.empty()) element.in_schema(schema_ + "." + key + "[]");
  return element;
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
      throw ScenarioError(where_ + ": unknown key '" + k + "'" + set_in(k) + " (expected one of: " + known + ")");
    }
}

}  // namespace tb
