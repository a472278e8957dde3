// Strict reading of scenario JSON: every key is declared where it is read, and
// finish() rejects the rest, so a misspelt key is an error, not a silent default.
// Messages name the file and the key path, and for a document merged from several
// files (a scenario that extends another) the file that set the key.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mesh_error.h"

namespace tb {

/// Thrown for any invalid scenario: what() is "<file>: <key path>: <problem>", one
/// line (one_line, mesh_error.h: a value quoted from the file may hold a newline).
class ScenarioError : public std::runtime_error {
 public:
  explicit ScenarioError(const std::string& message) : std::runtime_error(one_line(message)) {}
};

/// A JSON file parsed, nested at most 64 levels deep (the loaders and nlohmann's
/// dump() recurse per level: a million '[' would overflow the stack). Throws
/// ScenarioError "<path>: cannot open file" or "<path>: malformed JSON: <nlohmann's
/// message, with the line and column>".
nlohmann::json read_json_file(const std::string& path);

/// A JSON value quoted in a message: its text, cut to `max_chars`.
std::string shown(const nlohmann::json& value, size_t max_chars = 120);

/// Which file set each value of a JSON document merged from several files: JSON
/// pointer ("/mesh/surface", "/models/3/name") -> path of the file. `file` is the
/// file that was read (the last of its `extends` chain).
struct KeyOrigins {
  std::string file;
  std::map<std::string, std::string> set_by;

  /// Records `file` as the origin of `value` at `pointer` and of everything inside
  /// it, forgetting what was recorded inside `pointer` before.
  void record(const std::string& pointer, const nlohmann::json& value, const std::string& file);
  /// The file that set `pointer`, or `file` if none is recorded.
  const std::string& origin(const std::string& pointer) const;
};

/// `pointer` + "/" + key, escaped as a JSON pointer.
std::string json_pointer_child(const std::string& pointer, const std::string& key);

class StrictObject {
 public:
  /// `where` is the file and key path, e.g. "cube-pull.json: material". With
  /// `origins`, `pointer` is this object's JSON pointer in the merged document.
  StrictObject(const nlohmann::json& j, std::string where, std::shared_ptr<const KeyOrigins> origins = nullptr,
               std::string pointer = "");
  /// Checks every key read against the object `name` of file_schema()
  /// (file_schema.h); sub-objects follow ("<name>.<key>", "<name>.<key>[]").
  StrictObject& in_schema(const std::string& name);
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
  /// Element `index` of the array `key` (read with raw()) as a strict object,
  /// named "<where>.<key>[<index>]".
  StrictObject item(const std::string& key, size_t index);
  /// The directory of the file that set `key` (relative paths in a value are
  /// relative to it); `fallback` if no origins are known.
  std::string directory_of(const std::string& key, const std::string& fallback) const;
  /// Throws if any key was never read.
  void finish() const;
  const std::string& where() const { return where_; }
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  /// " (set in <file name>)" when `key` (this object itself if empty) came from
  /// another file than the one read; else "".
  std::string set_in(const std::string& key) const;

 private:
  const nlohmann::json* value(const std::string& key);
  nlohmann::json j_;
  std::string where_;
  std::set<std::string> read_;
  std::shared_ptr<const KeyOrigins> origins_;
  std::string pointer_;
  std::string schema_;  ///< file_schema()'s object; empty: unchecked
};

}  // namespace tb
