// The one exception type for bad mesh input: it names the file and the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace tb {

/// Thrown for any problem with mesh input. what() reads "<file>: <problem>", the
/// one line the CLI prints before exiting non-zero.
class MeshError : public std::runtime_error {
 public:
  MeshError(const std::string& file, const std::string& problem)
      : std::runtime_error((file.empty() ? std::string("<mesh>") : file) + ": " + problem) {}
};

}  // namespace tb
