// The one exception type for bad mesh input: it names the file and the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace tb {

/// `text` as one printable line: control characters (a newline or carriage return
/// read from a file, say) written as escapes (\n, \r, \xNN), and a text longer than
/// `max_chars` cut there with a note of how much was left out. Every error the
/// project reports about an input goes through it (MeshError, ScenarioError), so a
/// message is one line however the input is broken (docs/robustness.md).
std::string one_line(const std::string& text, size_t max_chars = 2000);

/// Thrown for any problem with mesh input. what() reads "<file>: <problem>", the
/// one line the CLI prints before exiting non-zero.
class MeshError : public std::runtime_error {
 public:
  MeshError(const std::string& file, const std::string& problem)
      : std::runtime_error(one_line((file.empty() ? std::string("<mesh>") : file) + ": " + problem)) {}
};

}  // namespace tb
