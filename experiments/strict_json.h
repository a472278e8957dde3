// Strict reading of scenario JSON: every key is declared where it is read, and
// finish() rejects the rest, so a misspelt key is an error, not a silent default
// (STYLE.md 5). Messages name the file and the key path.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace tb {

/// Thrown for any invalid scenario: what() is "<file>: <key path>: <problem>".
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StrictObject {
 public:
  /// `where` is the file and key path, e.g. "cube-pull.json: material".
  StrictObject(const nlohmann::json& j, std::string where);
  bool has(const std::string& key) const;
  /// A number in [min, max]; `fallback` if absent (required if no fallback).
  double number(const std::string& key, std::optional<double> fallback, double min, double max);
  int integer(const std::string& key, std::optional<int> fallback, int min, int max);
  bool boolean(const std::string& key, bool fallback);
  /// A string; if `choices` is non-empty it must be one of them.
  std::string text(const std::string& key, std::optional<std::string> fallback,
                   const std::vector<std::string>& choices = {});
  Eigen::Vector3d vec3(const std::string& key, std::optional<Eigen::Vector3d> fallback);
  /// A sub-object (required unless `optional`: then an empty object if absent).
  StrictObject object(const std::string& key, bool optional = false);
  /// The raw value (marks it read); null if absent.
  const nlohmann::json& raw(const std::string& key);
  /// Throws if any key was never read.
  void finish() const;
  const std::string& where() const { return where_; }
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

 private:
  const nlohmann::json* value(const std::string& key);
  nlohmann::json j_;
  std::string where_;
  std::set<std::string> read_;
};

}  // namespace tb
