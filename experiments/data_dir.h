// Third-party data (the liver meshes, README "Data") is not kept in the
// repository. A scenario names such a file "data:<path inside the data directory>"
// (docs/scenario_schema.md), and it is read from the data directory:
//   --data-dir DIR, else $TISSUEBENCH_DATA, else ../shared beside the repository.
// The default is resolved against the repository's source directory compiled into
// the binary, not against the working directory or the scenario file: a run from
// any folder, and a scenario file written anywhere (a test's temporary folder, a
// copy being edited), find the same data.
#pragma once

#include <string>

namespace tb {

/// What marks a data reference in a scenario file: "data:meshes/liver.msh".
constexpr const char* kDataPrefix = "data:";

struct DataDir {
  std::string path;       ///< absolute, normalised
  std::string chosen_by;  ///< "--data-dir", "TISSUEBENCH_DATA" or "the default, ../shared beside the repository"
};

/// The data directory: `flag` if not empty, else $TISSUEBENCH_DATA if set and not
/// empty, else <source directory>/../shared.
DataDir data_dir(const std::string& flag = "");

/// The repository's source directory compiled into the binary (absolute,
/// normalised): what the default data directory and the committed results (`tissuebench
/// score --answers`, results/observation_points) are found beside, from any folder.
std::string source_dir();

/// Whether a file value is a data reference ("data:..."), not a path.
bool is_data_reference(const std::string& value);

/// The file a data reference names inside `dir`. Throws ScenarioError, one line
/// prefixed by `where` (file and key), if the reference is malformed (absolute,
/// or leaving the directory with "..") or names no file there: the message names
/// the file, the data directory and how it was chosen, and where to obtain it.
std::string resolve_data_file(const std::string& reference, const DataDir& dir, const std::string& where);

}  // namespace tb
