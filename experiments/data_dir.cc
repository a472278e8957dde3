#include "data_dir.h"

#include <cstdlib>
#include <filesystem>

#include "strict_json.h"

namespace tb {
namespace fs = std::filesystem;

std::string source_dir() { return fs::path(TB_SOURCE_DIR).lexically_normal().string(); }

DataDir data_dir(const std::string& flag) {
  auto absolute = [](const fs::path& p) { return fs::absolute(p).lexically_normal().string(); };
  if (!flag.empty()) return {absolute(flag), "--data-dir"};
  if (const char* env = std::getenv("TISSUEBENCH_DATA"); env && *env) return {absolute(env), "TISSUEBENCH_DATA"};
  return {absolute(fs::path(source_dir()) / ".." / "shared"), "the default, ../shared beside the repository"};
}

bool is_data_reference(const std::string& value) { return value.rfind(kDataPrefix, 0) == 0; }

std::string resolve_data_file(const std::string& reference, const DataDir& dir, const std::string& where) {
  const fs::path inside = fs::path(reference.substr(std::string(kDataPrefix).size())).lexically_normal();
  if (inside.empty() || inside.is_absolute() || *inside.begin() == "..")
    throw ScenarioError(where + ": '" + reference + "' must be data:<relative path inside the data directory>");
  const fs::path file = fs::path(dir.path) / inside;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw ScenarioError(where + ": " + inside.string() + ": not found in data directory " + dir.path + " (" +
                        dir.chosen_by + "; set it with --data-dir or TISSUEBENCH_DATA); README 'Data' says where " +
                        "to obtain it");
  return file.string();
}

}  // namespace tb
